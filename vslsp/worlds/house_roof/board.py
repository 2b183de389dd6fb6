"""The house-and-roof world of the paper's simulation ("Simulation", Figure 4, roof placement) as
ground truth: three identical house bodies and three identical roofs at poses (x, y, θ) on a
board with a static baseline (the landmark L of Algorithm 1 line 2), rendered by compositing
the sprites of :mod:`vslsp.worlds.house_roof.sprites`.

Poses are image poses: x, y px (continuous coordinates), θ rad turning x towards y (clockwise
on screen), as the match decomposition measures it. Only the tutor, the hand's effect on the
world and the judge read these poses; perception sees the rendered images only.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache

import cv2
import numpy as np

from vslsp.geometry.poses import Pose2, relative, wrap
from vslsp.sim.live import publish
from vslsp.worlds.house_roof.sprites import board, body_sprite, covers, paste, roof_sprite

WORLD_SIZE = (960, 720)  # (W, H) px
BASELINE = ((30, 694), (930, 694))  # the static landmark, well below the objects
# A roof's pose in its body's frame (px, rad): its base edge on the body's top edge, or upside
# down on the bottom edge (a body is 60 px, a roof's anchor 10 px from its base).
TOP, BELOW = (0.0, -40.0, 0.0), (0.0, 40.0, float(np.pi))
SLOTS = {"top": TOP, "below": BELOW}
DEMONSTRATED = ("top", "top", "below")  # the tutor's three operations, as in the paper
POSITION_TOLERANCE, ANGLE_TOLERANCE = 6.0, np.radians(6.0)  # a roof this close to a slot is in it
_BODY, _ROOF = body_sprite(), roof_sprite()
_CLEARANCE = {("body", "body"): 250.0, ("body", "roof"): 180.0, ("roof", "roof"): 110.0}


@dataclass(frozen=True)
class HouseWorld:
    """The ground truth: body poses, roof poses (None while a roof is in the hand), the board's
    texture seed."""

    bodies: tuple[Pose2, ...]
    roofs: tuple[Pose2 | None, ...]
    texture: int = 0

    @classmethod
    def random(cls, seed: int, body_turn: float = np.pi) -> HouseWorld:
        """Three bodies (turned by up to ``body_turn`` rad) and three loose roofs (any angle)
        at seeded random places, with room above and below every body for its roof."""
        rng = np.random.default_rng(seed)
        placed: list[tuple[str, float, float]] = []
        poses: dict[str, list[Pose2]] = {"body": [], "roof": []}
        for kind in ("body",) * 3 + ("roof",) * 3:
            margin = 75.0 if kind == "body" else 55.0
            below = 180.0 if kind == "body" else 60.0  # a house's surroundings do not reach the baseline
            for _ in range(10000):
                x = rng.uniform(margin, WORLD_SIZE[0] - margin)
                y = rng.uniform(margin, BASELINE[0][1] - below)
                if all(
                    np.hypot(x - px, y - py) >= _CLEARANCE[(kind, other) if kind <= other else (other, kind)]
                    for other, px, py in placed
                ):
                    break
            else:  # pragma: no cover - the board has room for far more than six objects
                raise RuntimeError("no room left on the board")
            placed.append((kind, x, y))
            turn = body_turn if kind == "body" else np.pi
            poses[kind].append((float(x), float(y), float(rng.uniform(-turn, turn))))
        return cls(tuple(poses["body"]), tuple(poses["roof"]), int(rng.integers(1 << 16)))

    def render(self) -> np.ndarray:
        """The world as the camera sees it: (H, W, 3) uint8 RGB."""
        image = _empty_board(self.texture).copy()
        for pose in self.bodies:
            paste(image, _BODY, pose)
        for roof in self.roofs:
            if roof is not None:
                paste(image, _ROOF, roof)
        publish(image)  # the studio's live picture of a running trial (vslsp.sim.live), when asked for
        return image

    def with_roof(self, index: int, pose: Pose2 | None) -> HouseWorld:
        roofs = list(self.roofs)
        roofs[index] = pose
        return replace(self, roofs=tuple(roofs))

    def roof_at(self, point: tuple[float, float]) -> int | None:
        """The roof under image ``point`` (the top-most), or None."""
        for index in reversed(range(len(self.roofs))):
            pose = self.roofs[index]
            if pose is not None and covers(_ROOF, pose, point):
                return index
        return None

    def slot_of(self, roof: Pose2) -> tuple[int, str, float, float]:
        """The body and slot (top/below) nearest to a roof pose, with the position (px) and
        angle (rad) errors."""
        best: tuple[int, str, float, float] | None = None
        for index, body in enumerate(self.bodies):
            rel = relative(body, roof)
            for name, slot in SLOTS.items():
                error = (float(np.hypot(rel[0] - slot[0], rel[1] - slot[1])), abs(wrap(rel[2] - slot[2])))
                if best is None or error[0] < best[2]:
                    best = (index, name, *error)
        assert best is not None  # a world has three bodies
        return best

    def houses(self) -> dict[int, list[str]]:
        """Body index -> the slots its roofs are in (within tolerance); roofs elsewhere are left out."""
        result: dict[int, list[str]] = {i: [] for i in range(len(self.bodies))}
        for roof in self.roofs:
            if roof is not None:
                body, slot, position, angle = self.slot_of(roof)
                if position <= POSITION_TOLERANCE and angle <= ANGLE_TOLERANCE:
                    result[body].append(slot)
        return result

    def goal_reached(self, demonstrated: tuple[str, ...] = DEMONSTRATED) -> bool:
        """Every body carries exactly one roof and the slots are the demonstrated ones."""
        houses = self.houses()
        return all(len(s) == 1 for s in houses.values()) and sorted(s[0] for s in houses.values()) == sorted(
            demonstrated
        )

    def to_dict(self) -> dict:
        return {
            "bodies": [pose_dict(p) for p in self.bodies],
            "roofs": [None if p is None else pose_dict(p) for p in self.roofs],
            "texture": self.texture,
        }


@lru_cache(maxsize=4)
def _empty_board(texture: int) -> np.ndarray:
    """The board with its baseline and nothing on it (H, W, 3), kept: worlds are re-rendered often."""
    image = board(WORLD_SIZE, texture)
    cv2.line(image, BASELINE[0], BASELINE[1], (12, 12, 12), 10)
    image.flags.writeable = False
    return image


def pose_dict(pose: Pose2) -> dict:
    return {"x": round(pose[0], 2), "y": round(pose[1], 2), "theta": round(pose[2], 5)}
