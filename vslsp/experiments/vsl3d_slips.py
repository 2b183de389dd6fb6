"""The tutor's slips in VSL-3D's demonstrations (issue 30, ``--tutor-slips P``,
``--slip-detection on|off``), shared by the table cleaning and the stacking.

:class:`DemonstrationSlips` draws per demonstrated operation whether the tutor's hand also nudges
another object on the table (:class:`~vslsp.worlds.slips.TutorSlips`, its own seeded stream:
without the option nothing is drawn and the runs are as before) and applies it in the world
(:meth:`~vslsp.worlds.rgbd_table.RgbdTable.tutor_slip`, after the operated object has been put
down and before the post-action capture). getObject runs with the slip detection on
(:func:`~vslsp.vsl.slips.clouds.get_operated_object`: every moved object found, the operated one told
from those disturbed) or off (the paper's getObject: the whole difference is the object). With
the option, each operation's record gets its ``slip`` (the ground truth, or None) and its
``demonstration`` the detection's finding: ``moved`` (every object found moving: role, where
before and after, by how much, and its name from the truth, for the report), ``operated`` and
``disturbed`` (names).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from vslsp.vsl.slips.clouds import get_operated_object
from vslsp.vsl3d.cloud import DepthCamera
from vslsp.vsl3d.pictures import draw_moves
from vslsp.vsl3d.vsl import OPERATED, MovedObject, WorldCloud
from vslsp.worlds.rgbd_table import RgbdTable
from vslsp.worlds.slips import TutorSlips


class DemonstrationSlips:
    """The slips of one trial's demonstration (``probability`` None: the option was not given,
    nothing is drawn or recorded) and getObject with the detection on or off (``detect``)."""

    def __init__(self, probability: float | None, seed: int, detect: bool = True) -> None:
        self.given = probability is not None
        self.slips = TutorSlips(probability, seed) if probability is not None else None
        self.detect = detect
        self.records: dict[int, dict | None] = {}  # per operation index: the applied slip's record
        self.found: dict[int, dict] = {}  # per operation index: getObject's record (and the detection's)

    def during(
        self,
        scene: RgbdTable,
        index: int,
        others: Sequence[str],
        clear_of: Sequence[tuple[np.ndarray, np.ndarray]],
    ) -> None:
        """The tutor may slip in operation ``index`` onto one of ``others`` (objects on the table,
        in a fixed order), keeping it clear of ``clear_of`` (lower, upper) boxes."""
        if self.slips is None:
            return
        drawn = self.slips.draw(index, list(others))
        applied = scene.tutor_slip(drawn, clear_of) if drawn is not None else None
        self.records[index] = applied.to_dict() if applied is not None else None

    def get_object(self, pre: WorldCloud, post: WorldCloud, method: str, seed: int) -> MovedObject:
        """getObject with the detection on (every moved object) or off (the paper's)."""
        return get_operated_object(pre, post, detect=self.detect, method=method, seed=seed)

    def picture(self, pre: np.ndarray, post: np.ndarray, camera: DepthCamera, scene: RgbdTable, moved: MovedObject):
        """The pre and post RGB views with the moved objects marked (as they were, without the option)."""
        if not self.given:
            return pre, post
        return draw_moves(pre, post, camera, moved, [name_of(scene, m.after) for m in moved.moves])

    def record(self, scene: RgbdTable, moved: MovedObject, demonstration: dict) -> dict:
        """``demonstration`` (getObject's record) with the detection's finding, under the option;
        ``scene`` is the post-action world (the names come from its truth, for the report only)."""
        if not self.given:
            return demonstration
        names = [name_of(scene, move.after) for move in moved.moves]
        return {
            **demonstration,
            "moved": [{"object": name, **move.to_dict()} for name, move in zip(names, moved.moves, strict=True)],
            "operated": next((n for n, m in zip(names, moved.moves, strict=True) if m.role == OPERATED), None),
            "disturbed": [n for n, m in zip(names, moved.moves, strict=True) if m.role != OPERATED],
        }

    def extra(self, index: int) -> dict:
        """The operation record's ``slip`` (the truth), under the option."""
        return {"slip": self.records.get(index)} if self.given else {}


def name_of(scene: RgbdTable, points: np.ndarray) -> str | None:
    """The object (or box) whose true bounding box (5 mm wider) holds most of ``points`` (N, 3):
    the report's name for a moved object (truth, never read by perception)."""
    best, most = None, 0
    for name in scene.bodies:
        lower, upper = scene.bounds(name)
        inside = int(np.all((points >= lower - 0.005) & (points <= upper + 0.005), axis=1).sum())
        if inside > most:
            best, most = name, inside
    return best


def place_box(x: float, y: float, half: float = 0.04) -> tuple[np.ndarray, np.ndarray]:
    """A box around the place (x, y) on the table where a later operation puts an object down."""
    return np.array([x - half, y - half, 0.0]), np.array([x + half, y + half, 0.1])
