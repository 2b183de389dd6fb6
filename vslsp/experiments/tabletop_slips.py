"""The tutor's slips in the five Panda tasks (issue 30): the demonstration of
:meth:`~vslsp.experiments.tabletop.TabletopExperiment.demonstrate` with ``--tutor-slips P``.

Per operation the tutor takes the item (pre-pick, then pre-place observation), puts it at its
place, and with probability P its hand nudges another item as it lets go
(:meth:`~vslsp.worlds.panda_table.PandaTable.slip_candidates`,
:meth:`~vslsp.worlds.panda_table.PandaTable.nudge`): after the pre-place observation, before the
post-place one. The relation the judge holds the reproduction to is the one the tutor meant,
taken before the slip. With the slip detection (default) VSL finds every item that moved
between the pre-pick and post-place observations (:func:`~vslsp.vsl.slips.restore.separate`, in the
top-down view), tells the operated one from the disturbed ones and records the operation from
the post-place observation the tutor meant (the disturbed items restored); without it (the
paper's VSL) from the post-place observation as it is. The next operation's pre-pick
observation is the world as it is (the disturbed item where the slip left it).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Protocol

import numpy as np

from vslsp.errors import InputError
from vslsp.experiments.tabletop_protocol import Move, TabletopDemonstration, look, relation
from vslsp.vsl.pick_place import TableModel, TableView
from vslsp.vsl.recorder import Heights, Recorder
from vslsp.vsl.slips.detect import Moves, UnseenOperation
from vslsp.vsl.slips.record import on_nudged, record_meant
from vslsp.vsl.slips.restore import separate
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
    slip ``detection``; raises :class:`~vslsp.vsl.slips.detect.UnseenOperation` when an operation
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
