"""The Panda table of a reproduction as a perturbation (:mod:`vslsp.perturbations`) changes it: the
camera moved, turned, nearer or farther, under other light, with sensor noise; a grey occluder
standing over part of one object in every image; distractor boxes on the table that the
demonstration did not have.

The moved camera replaces the world's own (:attr:`~vslsp.sim.tabletop.TabletopWorld.camera`): the
robot knows its calibration, as a researcher's calibrated camera is known, so the table view
(:class:`~vslsp.vsl.pick_place.TableView` of the world) and ``pixel_to_table`` go through it. The
demonstration's world is never perturbed.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from vslsp.perturbations import Drawn, images, viewpoint
from vslsp.sim.tabletop import TabletopWorld

#: Where a distractor's centre may lie (x, y m): on the table, in the table view, in reach.
CLUTTER_AREA = ((0.28, 0.76), (-0.34, 0.34))
#: The free table (m) between a distractor's footprint disc and every item's.
CLUTTER_CLEARANCE = 0.04
#: The distractors' plain colours (RGB 0-1): green, yellow, purple, cyan, red, white.
CLUTTER_COLOURS = (
    (0.16, 0.63, 0.24),
    (0.90, 0.78, 0.16),
    (0.59, 0.24, 0.67),
    (0.20, 0.70, 0.80),
    (0.85, 0.20, 0.20),
    (0.95, 0.95, 0.95),
)
#: The noise streams of the occluder's texture start here (the images' own noise: 0, 1, 2, ...).
OCCLUDER_STREAM = 10_000


class PerturbedView:
    """What ``drawn`` changes in the reproduction ``world`` (applied when made): its camera
    moved, distractors put on the table (``drawn.layout_seed``), the occluded object's image box
    fixed for the trial; :meth:`see` is what the camera then sees of an image the world renders."""

    def __init__(self, world: TabletopWorld, drawn: Drawn) -> None:
        self.drawn = drawn
        levels = drawn.levels
        camera = world.camera
        eye, target, up = viewpoint.moved_view(camera.eye, camera.target, camera.up, drawn)
        self.moved = bool(levels.camera or levels.scale != 1.0)
        if self.moved:
            world.camera = replace(camera, eye=eye, target=target, up=up)
        rng = np.random.default_rng(drawn.layout_seed)
        self.distractors = _add_distractors(world, int(levels.clutter), rng) if levels.clutter else ()
        self.occluded = _occluded(world, drawn.occluded) if levels.occlusion else None
        self.taken = 0  # images taken so far (each draws its own noise)

    def see(self, image: np.ndarray) -> np.ndarray:
        """The camera's ``image`` (H, W, 3) uint8 with the occluder over its object, under the
        drawn light and noise."""
        if self.occluded is not None:
            rng = self.drawn.noise_rng(OCCLUDER_STREAM + self.taken)
            share = self.drawn.levels.occlusion / 100.0
            image = images.occlude(image, self.occluded[1], share, self.drawn.occluded_from, rng)
        image = images.apply(image, self.drawn, self.taken)
        self.taken += 1
        return image

    def to_dict(self, world: TabletopWorld) -> dict:
        """The report's account of the perturbation: what was drawn and what was done."""
        found = self.drawn.to_dict()
        if self.moved:
            camera = world.camera
            found.setdefault("camera", {}).update(
                eye_m=[round(v, 4) for v in camera.eye], target_m=[round(v, 4) for v in camera.target]
            )
        if self.occluded is not None:
            found["occluded"] = {"item": self.occluded[0], "box_px": [round(v, 1) for v in self.occluded[1]]}
        if self.distractors:
            found["distractors"] = [
                {"at_m": [round(x, 4), round(y, 4)], "size_m": [round(s, 4) for s in size]}
                for x, y, size in self.distractors
            ]
        return found


def _occluded(world: TabletopWorld, share: float) -> tuple[str, tuple[float, float, float, float]]:
    """The item at ``share`` of the world's movable items in the camera's view (in the world's
    order; when none is, as where animals-vs-machines shows its cards one at a time, of the
    landmarks in view) and the box (px) its eight corners span in the camera's image, as it lies
    when the reproduction starts."""
    boxes = {name: _image_box(world, name) for name in world.specs}
    seen = [
        name for name, (x0, y0, x1, y1) in boxes.items() if x1 > 0 and y1 > 0 and x0 < world.WIDTH and y0 < world.HEIGHT
    ]
    names = [name for name in seen if world.specs[name].movable] or seen or list(boxes)
    name = names[min(int(share * len(names)), len(names) - 1)]
    return name, boxes[name]


def _image_box(world: TabletopWorld, name: str) -> tuple[float, float, float, float]:
    """The box (x0, y0, x1, y1 px) that item ``name``'s eight corners span in the camera's image."""
    x, y, z, yaw = world.pose(name)
    sx, sy, sz = world.specs[name].size
    c, s = np.cos(yaw), np.sin(yaw)
    corners = np.array(
        [
            (x + c * dx - s * dy, y + s * dx + c * dy, z + dz)
            for dx in (-sx / 2, sx / 2)
            for dy in (-sy / 2, sy / 2)
            for dz in (0.0, sz)
        ]
    )
    pixels = world.camera.project(corners)
    low, high = pixels.min(axis=0), pixels.max(axis=0)
    return float(low[0]), float(low[1]), float(high[0]), float(high[1])


def _add_distractors(world: TabletopWorld, count: int, rng: np.random.Generator) -> tuple:
    """``count`` small boxes of plain colours at free places of the table (not items of the
    world: the judge and the tutor never see them); their centres (m) and sizes (m)."""
    taken = [(*world.pose(name)[:2], float(np.hypot(*item.size[:2])) / 2.0) for name, item in world.specs.items()]
    found: list[tuple[float, float, tuple[float, float, float]]] = []
    for k in range(count):
        size = (float(rng.uniform(0.025, 0.045)), float(rng.uniform(0.025, 0.045)), float(rng.uniform(0.015, 0.03)))
        radius = float(np.hypot(size[0], size[1])) / 2.0
        for _ in range(10_000):
            x, y = float(rng.uniform(*CLUTTER_AREA[0])), float(rng.uniform(*CLUTTER_AREA[1]))
            if all(np.hypot(x - a, y - b) >= r + radius + CLUTTER_CLEARANCE for a, b, r in taken):
                break
        else:  # pragma: no cover - the table has room for far more
            continue
        world.add_plain_box(size, CLUTTER_COLOURS[k % len(CLUTTER_COLOURS)], x, y, float(rng.uniform(0.0, np.pi)))
        taken.append((x, y, radius))
        found.append((x, y, size))
    if found:
        world.settle()
    return tuple(found)
