"""The tutor's slips in the five Panda tasks (issue 30): the demonstration of
:meth:`~vslsp.experiments.tabletop.TabletopExperiment.demonstrate` with ``--tutor-slips P``.

Per operation the tutor takes the item (pre-pick, then pre-place observation), puts it at its
place, and with probability P its hand nudges another item as it lets go
(:meth:`~vslsp.worlds.panda_table.PandaTable.slip_candidates`,
:meth:`~vslsp.worlds.panda_table.PandaTable.nudge`): after the pre-place observation, before the
post-place one. The relation the judge holds the reproduction to is the one the tutor meant,
taken before the slip. With the slip detection (default) VSL finds every item that moved
between the pre-pick and post-place observations (:func:`~vslsp.vsl.restore.separate`, in the
top-down view), tells the operated one from the disturbed ones and records the operation from
the post-place observation the tutor meant (the disturbed items restored); without it (the
paper's VSL) from the post-place observation as it is. The next operation's pre-pick
observation is the world as it is (the disturbed item where the slip left it).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace
from typing import TYPE_CHECKING, Protocol

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.experiments.tabletop_protocol import Move, TabletopDemonstration, look, relation
from vslsp.vision.features import extract_features
from vslsp.vsl.pick_place import TableModel, TableView
from vslsp.vsl.recorder import Heights, Recorder
from vslsp.vsl.restore import only_arrival, separate
from vslsp.vsl.slips import Moves, UnseenOperation, keypoint_area
from vslsp.worlds.panda_table import layouts as scenes
from vslsp.worlds.slips import TutorSlips

if TYPE_CHECKING:
    from vslsp.worlds.panda_table import PandaTable


class Demonstrated(Protocol):
    """A tabletop task as the tutor demonstrates it: its moves (a
    :class:`~vslsp.experiments.tabletop.TabletopExperiment`)."""

    def moves(self, rng: np.random.Generator) -> Iterator[Move]: ...


def demonstrate_with_slips(
    task: Demonstrated, world: PandaTable, rng: np.random.Generator, probability: float, detection: bool
) -> TabletopDemonstration:
    """The tutor's demonstration of ``task`` in ``world`` with the tutor's slips (probability
    ``probability`` per operation, seeded by the world's seed), recorded with or without the
    slip ``detection``; raises :class:`~vslsp.vsl.slips.UnseenOperation` when an operation
    cannot be recorded."""
    view = TableView(world)
    recorder = Recorder(TableModel(view))
    tutor = TutorSlips(probability, world.seed)
    items, anchors, relations = [], [], []
    records: list[dict] = []
    found: list[Moves | None] = []
    posts: list[np.ndarray] = []
    seen = None
    nudged: list[np.ndarray] = []  # the disturbed items' keypoints (N, 2) px where the slips left them
    for k, (name, where, anchor) in enumerate(task.moves(rng)):
        world.say(f"the tutor puts {name} in place")
        pre_pick = look(world) if seen is None else seen
        pick_z = world.truth(name)[2] + world.specs[name].size[2]
        world.tutor_move(name, scenes.hold_placement(0))
        pre_place = look(world)
        world.tutor_move(name, where(world))
        height = world.specs[name].size[2]
        heights = Heights(pick_z, world.truth(name)[2] + height, height)
        items.append(name)
        anchors.append(anchor)
        relations.append(relation(world, name, anchor))  # what the tutor meant, before any slip
        drawn = tutor.draw(k, world.slip_candidates(name))
        slip = None if drawn is None else world.nudge(drawn)
        if slip is not None:
            world.say(f"the tutor's hand nudges {slip.name}")
        seen = look(world)
        record: dict = {} if slip is None else {"slip": slip.to_dict()}
        moves, post = None, seen
        if detection:
            moves, post = separate(pre_pick, seen, pre_place)
        found.append(moves)
        posts.append(seen)
        try:
            operation = record_meant(recorder, (pre_pick, post, pre_place), heights, moves)
        except InputError as unseen:
            raise UnseenOperation(str(unseen), (*records, record)) from unseen
        if moves is not None:
            record = {**moved_record(moves, world, view, operation.place_point), **record}
            nudged = on_nudged(recorder, operation, moves, nudged)
        records.append(record)
    return TabletopDemonstration(
        recorder.demonstration(),
        tuple(items),
        tuple(anchors),
        tuple(relations),
        tuple(records),
        tuple(found),
        tuple(posts),
    )


def record_meant(recorder: Recorder, observations: tuple, heights: Heights, moves: Moves | None):
    """The operation recorded from its pre-pick, meant post-place and pre-place
    ``observations``. The rule: a slip's nudge can push a neighbour a little (a domino turned
    against the next one, a shift too small to be a move of its own), a change that the restore
    leaves beside the operated item's arrival and that widens its changed region. When the
    arrival then does not match the operated item's features, every change outside the operated
    item's own pixels (its keypoints' hull where it arrived, and a rim) is taken for the slip's
    and restored from the pre-place observation (:func:`~vslsp.vsl.restore.only_arrival`;
    domino 62). Raises InputError when the operation still cannot be recorded."""
    pre_pick, post, pre_place = observations
    try:
        return recorder.record(pre_pick, post, pre_place, heights)
    except InputError:
        if moves is None or moves.operated is None or not moves.disturbed:
            raise
        return recorder.record(pre_pick, only_arrival(pre_place, post, moves.operated), pre_place, heights)


def on_nudged(recorder: Recorder, operation, moves: Moves, nudged: list[np.ndarray]) -> list[np.ndarray]:
    """Mind what was put on an item the tutor's slip had nudged. The rule: an item put on a
    nudged one lies where it lies on it, so its place is found by the item below (that item's
    features in the pre-place observation, matched as the pick matches its object; the frame
    reported that item's size), not by the wider frame whose surroundings the slip no longer
    agrees with (the Tower of Hanoi's disk put on a disk nudged off its base's centre, which the
    new world has centred). ``nudged``: the keypoints (N, 2) px of the items
    disturbed so far, where the slips left them; an item stays nudged until the tutor takes it
    (a third of its keypoints where the operated item was seen); the operation's own disturbed
    items join. Sets the last recorded operation's frame; returns the items nudged now."""
    below = [points for points in nudged if _inside(operation.place_point, points)]
    if below:
        side = max(float(np.ptp(points, axis=0).max()) for points in below)
        features = extract_features(operation.pre_place, keypoint_area(operation.pre_place.shape, below))
        recorder.operations[-1] = replace(operation, place_frame=side, place_features=features)
    taken = moves.operated.keypoints_before if moves.operated is not None else np.zeros((0, 2))
    kept = [points for points in nudged if not _same_item(points, taken)]
    return kept + [obj.keypoints_after for obj in moves.disturbed]


def _inside(point: tuple[float, float], points: np.ndarray) -> bool:
    """Whether ``point`` (px) lies in the convex hull of ``points`` (N, 2) px."""
    hull = cv2.convexHull(np.asarray(points, np.float32))
    return cv2.pointPolygonTest(hull, (float(point[0]), float(point[1])), False) >= 0


def _same_item(points: np.ndarray, taken: np.ndarray, near: float = 3.0) -> bool:
    """Whether a third of ``points`` (N, 2) px lie within ``near`` px of ``taken`` (M, 2): the
    nudged item is the one the tutor took."""
    if not len(points) or not len(taken):
        return False
    gaps = np.min(np.hypot(*(points[:, None, :] - taken[None, :, :]).transpose(2, 0, 1)), axis=1)
    return bool(np.mean(gaps <= near) >= 1.0 / 3.0)


def moved_record(moves: Moves, world: PandaTable, view: TableView, recorded: tuple[float, float]) -> dict:
    """The operation's ``moved``, ``operated`` and ``disturbed`` items, named by the world's
    truth (the item nearest to where each was seen after the operation; the report's names, not
    perception's), and where perception saw each (px of the top-down view). The operated item
    is the one recorded (its place point ``recorded``): when its features did not identify it,
    it is what changed once the disturbed items were restored."""
    operated = item_at(world, view, recorded)
    disturbed = [item_at(world, view, obj.after) for obj in moves.disturbed]
    names = [item_at(world, view, obj.after) for obj in moves.moved]
    return {
        "moved": [operated, *disturbed],
        "operated": operated,
        "disturbed": disturbed,
        "moves": [{"object": name, **obj.to_dict()} for name, obj in zip(names, moves.moved)],
    }


def item_at(world: PandaTable, view: TableView, point: tuple[float, float]) -> str:
    """The movable item whose top's centre is nearest to ``point`` (px of the top-down view)."""

    def distance(name: str) -> float:
        x, y, z, _ = world.truth(name)
        u, v = view.table_to_pixel(x, y, z + world.specs[name].size[2])
        return float(np.hypot(u - point[0], v - point[1]))

    return min((name for name, item in world.specs.items() if item.movable), key=distance)
