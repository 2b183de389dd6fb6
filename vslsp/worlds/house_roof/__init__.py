"""The house-roof board of VSL's simulation (paper, "Simulation", Figure 4): three identical house
bodies and three identical roofs on a board with a baseline, in 2-D, without a simulator.

Its seeded layout is a :class:`~vslsp.worlds.house_roof.board.HouseWorld` (the ground truth as a
value, :meth:`~vslsp.worlds.house_roof.board.HouseWorld.random`), drawn with the sprites of
:mod:`~vslsp.worlds.house_roof.sprites`; its observation the rendered (H, W, 3) RGB image; the
tutor lifts a roof (``where`` None) or puts it at a pose (x, y px, θ rad); there is no robot (the
reproduction plans the hand's path and lets the grasped roof land where it ends).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from vslsp.geometry.poses import Pose2
from vslsp.worlds.house_roof.board import ANGLE_TOLERANCE, BASELINE, POSITION_TOLERANCE, WORLD_SIZE, HouseWorld
from vslsp.worlds.slips import Slip

PIXEL_M = 0.001  # m per px of the board (96 x 72 cm): the scale a slip in metres is applied with
# How close (px) a nudged object may come to another, unless it was closer already (the
# clearances of HouseWorld.random: a free body keeps room for its roof above and below).
_NUDGE_CLEARANCE = {("body", "body"): 250.0, ("body", "roof"): 180.0, ("roof", "roof"): 110.0}

__all__ = ["HouseBoard", "HouseWorld", "roof_name"]


def roof_name(index: int) -> str:
    """The name of roof ``index`` (0, 1, 2)."""
    return f"roof-{index}"


class HouseBoard:
    """The house-roof board as a :class:`~vslsp.worlds.World`: ``state`` is the ground truth now."""

    robot = None

    def __init__(self, state: HouseWorld) -> None:
        self.state = state

    @classmethod
    def from_layout(cls, layout: HouseWorld, seed: int = 0) -> HouseBoard:
        return cls(layout)

    def observe(self) -> np.ndarray:
        """The board as the camera sees it: (H, W, 3) uint8 RGB."""
        return self.state.render()

    def tutor_move(self, name: str, where: Pose2 | None) -> None:
        """The tutor lifts roof ``name`` (``where`` None: in the hand, out of view) or puts it at ``where``."""
        self.state = self.state.with_roof(_index(name), where)

    def settle(self) -> None:
        """Nothing moves by itself on the board."""

    def truth(self, name: str) -> Pose2 | None:
        """Roof ``name``'s pose (None while in the hand)."""
        return self.state.roofs[_index(name)]

    def close(self) -> None:
        """Nothing to release: the board is an image."""

    # -- the tutor's slips (vslsp.worlds.slips) --------------------------------------------
    def slip_candidates(self, operated: str) -> list[str]:
        """What the tutor's hand may disturb while operating roof ``operated``: the loose roofs
        and the bodies without a roof (what the demonstration goes on to operate on, or to put
        a roof on), in a fixed order; a finished house is left alone (its roof would stay behind)."""
        state = self.state
        loose = [j for j, pose in enumerate(state.roofs) if pose is not None and not _slotted(state, pose)]
        roofs = [roof_name(j) for j in loose if roof_name(j) != operated]
        return roofs + [f"body-{j}" for j, slots in state.houses().items() if not slots]

    def nudge(self, slip: Slip) -> Slip | None:
        """Apply the tutor's ``slip`` (metres and degrees, at :data:`PIXEL_M` m per px; θ turns
        x towards y): the object moves by it, or the other way when that way would leave the
        board or come closer to another object than the board's clearance (unless it was that
        close already); returns the slip applied, or None when neither way is free."""
        kind, index = slip.name.split("-")
        pose = (self.state.bodies if kind == "body" else self.state.roofs)[int(index)]
        assert pose is not None  # a candidate lies on the board
        for way in slip.both_ways():
            moved = (
                pose[0] + way.dx_m / PIXEL_M,
                pose[1] + way.dy_m / PIXEL_M,
                pose[2] + float(np.radians(way.dyaw_deg)),
            )
            if self._free(kind, int(index), pose, moved):
                if kind == "body":
                    bodies = list(self.state.bodies)
                    bodies[int(index)] = moved
                    self.state = replace(self.state, bodies=tuple(bodies))
                else:
                    self.state = self.state.with_roof(int(index), moved)
                return way
        return None

    def _free(self, kind: str, index: int, old: Pose2, new: Pose2) -> bool:
        margin = 75.0 if kind == "body" else 55.0
        below = 180.0 if kind == "body" else 60.0
        if not (margin <= new[0] <= WORLD_SIZE[0] - margin and margin <= new[1] <= BASELINE[0][1] - below):
            return False
        others = [("body", j, p) for j, p in enumerate(self.state.bodies)]
        others += [("roof", j, p) for j, p in enumerate(self.state.roofs) if p is not None]
        for other, j, pose in others:
            if (other, j) == (kind, index):
                continue
            clearance = _NUDGE_CLEARANCE[(kind, other) if kind <= other else (other, kind)]
            before = float(np.hypot(old[0] - pose[0], old[1] - pose[1]))
            after = float(np.hypot(new[0] - pose[0], new[1] - pose[1]))
            if after < min(before, clearance):
                return False
        return True


def _slotted(state: HouseWorld, roof: Pose2) -> bool:
    """Whether ``roof`` lies in a body's slot (within the judge's tolerances)."""
    _, _, position, angle = state.slot_of(roof)
    return position <= POSITION_TOLERANCE and angle <= ANGLE_TOLERANCE


def _index(name: str) -> int:
    return int(name.removeprefix("roof-"))
