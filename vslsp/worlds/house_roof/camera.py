"""The camera over the house-roof board in a reproduction, as a perturbation (:mod:`vslsp.perturbations`)
changes it: moved, turned, nearer or farther, under other light, with sensor noise; with a grey
occluder standing over part of one object and distractor shapes on the board that the
demonstration did not have.

Unperturbed it is the demonstration's camera: straight above the board, one pixel per board
pixel, and :meth:`BoardCamera.see` is the board's own render. Moved, its calibration (the board
to image homography, :attr:`BoardCamera.homography`) is known to the robot, as a researcher's
calibrated camera is: :meth:`BoardCamera.on_board` maps its image back to board coordinates.
"""

from __future__ import annotations

import cv2
import numpy as np

from vslsp.perturbations import Drawn, images, viewpoint
from vslsp.worlds.house_roof.board import BASELINE, WORLD_SIZE, HouseWorld
from vslsp.worlds.house_roof.sprites import Sprite, body_sprite, paste, roof_sprite

#: The camera's height above the board in board pixels (1.2 m at 1 mm per pixel), and its focal
#: length in pixels (the same: one image pixel per board pixel straight below).
DISTANCE_PX = 1200.0
#: Board pixels per metre (the board is 96 x 72 cm).
PX_PER_M = 1000.0
#: How far (px) the camera's view reaches past the board on each side: the demonstration's image is
#: the board, and a camera moved 15 cm and turned 15 deg, or brought 1.4 times nearer, still sees
#: the board whole (a camera that lost part of the board would fail for want of the picture).
SENSOR_MARGIN_PX = 360
#: A distractor keeps this far (px) from every body and roof centre (a body's roof slots lie 40 px
#: off it, a roof reaches 34 px), and from the baseline and the other distractors.
DISTRACTOR_CLEARANCE = 110.0
#: The distractors' shapes and colours (RGB): none is a house's blue or a roof's orange-brown.
DISTRACTORS = (("disc", (40, 160, 60)), ("square", (230, 200, 40)), ("star", (150, 60, 170)))


class BoardCamera:
    """The camera of one reproduction (its ``drawn`` perturbation), over the world it starts
    from (``world``: where the occluder stands and the distractors lie, fixed for the trial)."""

    def __init__(self, drawn: Drawn, world: HouseWorld) -> None:
        self.drawn = drawn
        levels = drawn.levels
        self.moved = bool(levels.camera or levels.scale != 1.0)
        width, height = WORLD_SIZE
        self.homography = viewpoint.board_homography(width, height, DISTANCE_PX, drawn, PX_PER_M)
        self.occluded = _object_box(world, drawn.occluded) if levels.occlusion else None
        rng = np.random.default_rng(drawn.layout_seed)
        self.distractors = _distractors(world, int(levels.clutter), rng) if levels.clutter else ()
        self.taken = 0  # images taken so far (each draws its own noise)

    def see(self, world: HouseWorld) -> np.ndarray:
        """What the camera sees of ``world``: (H, W, 3) uint8 RGB."""
        image = world.render()
        if self.drawn.none:
            return image
        image = image.copy()
        for shape, colour, centre, size, turn in self.distractors:
            _draw_distractor(image, shape, colour, centre, size, turn)
        rng = self.drawn.noise_rng(10_000 + self.taken)
        if self.occluded is not None:
            image = images.occlude(
                image, self.occluded, self.drawn.levels.occlusion / 100.0, self.drawn.occluded_from, rng
            )
        if self.moved:
            image = viewpoint.view(image, self.homography, SENSOR_MARGIN_PX)
        image = images.apply(image, self.drawn, self.taken)
        self.taken += 1
        return image

    def on_board(self, image: np.ndarray) -> np.ndarray:
        """The camera's ``image`` in board coordinates, through its calibration (itself when the
        camera did not move)."""
        return viewpoint.to_board(image, self.homography, SENSOR_MARGIN_PX) if self.moved else image

    def to_dict(self) -> dict:
        """The report's account of the camera: what the perturbation drew and did."""
        found = self.drawn.to_dict()
        if self.occluded is not None:
            found["occluded_box_px"] = [round(v, 1) for v in self.occluded]
        if self.distractors:
            found["distractors"] = [
                {"shape": shape, "at_px": [round(c, 1) for c in centre]} for shape, _, centre, _, _ in self.distractors
            ]
        return found


def _object_box(world: HouseWorld, share: float) -> tuple[float, float, float, float]:
    """The pixel box of the object at ``share`` of the world's objects (bodies, then roofs)."""
    body, roof = body_sprite(), roof_sprite()
    objects = [(body, pose) for pose in world.bodies] + [(roof, pose) for pose in world.roofs if pose is not None]
    sprite, pose = objects[min(int(share * len(objects)), len(objects) - 1)]
    mask = np.zeros((WORLD_SIZE[1], WORLD_SIZE[0], 3), np.uint8)
    paste(mask, Sprite(np.full_like(sprite.colour, 255), sprite.alpha, sprite.anchor), pose)
    rows, cols = np.nonzero(mask[..., 0] > 127)
    return (float(cols.min()), float(rows.min()), float(cols.max() + 1), float(rows.max() + 1))


def _distractors(world: HouseWorld, count: int, rng: np.random.Generator) -> tuple:
    """``count`` distractors at free places of the board: shape, colour, centre, size, turn."""
    taken = [(p[0], p[1]) for p in (*world.bodies, *world.roofs) if p is not None]
    found: list[tuple] = []
    for k in range(count):
        shape, colour = DISTRACTORS[k % len(DISTRACTORS)]
        for _ in range(10_000):
            x, y = rng.uniform(50.0, WORLD_SIZE[0] - 50.0), rng.uniform(50.0, BASELINE[0][1] - 60.0)
            if all(np.hypot(x - a, y - b) >= DISTRACTOR_CLEARANCE for a, b in taken):
                break
        else:  # pragma: no cover - the board has room for far more
            continue
        taken.append((x, y))
        found.append(
            (shape, colour, (float(x), float(y)), float(rng.uniform(44.0, 60.0)), float(rng.uniform(0, np.pi)))
        )
    return tuple(found)


def _draw_distractor(image: np.ndarray, shape: str, colour: tuple, centre: tuple, size: float, turn: float) -> None:
    cx, cy = centre
    if shape == "disc":
        cv2.circle(image, (int(round(cx)), int(round(cy))), int(size / 2), colour, -1, cv2.LINE_AA)
        cv2.circle(image, (int(round(cx)), int(round(cy))), int(size / 4), (250, 250, 250), 3, cv2.LINE_AA)
        return
    corners = 4 if shape == "square" else 10
    angles = turn + np.arange(corners) * 2 * np.pi / corners
    radii = np.full(corners, size / np.sqrt(2) if shape == "square" else size / 2)
    if shape == "star":
        radii[1::2] *= 0.45
    points = np.column_stack([cx + radii * np.cos(angles), cy + radii * np.sin(angles)])
    cv2.fillPoly(image, [np.round(points).astype(np.int32)], colour, cv2.LINE_AA)
    cv2.polylines(image, [np.round(points).astype(np.int32)], True, (20, 20, 20), 2, cv2.LINE_AA)
