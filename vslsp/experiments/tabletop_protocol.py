"""The tabletop world's task protocol (paper, "Real-world Experiments"): the tutor's
demonstration, the robot's reproduction (Algorithm 1 part II, one operation at a time) and the
ground-truth judge, shared by the five experiments of :mod:`vslsp.experiments.real_world` (on
their base, :class:`~vslsp.experiments.tabletop.TabletopExperiment`).

The judge reads the simulator's ground truth, which perception never does: after each
operation, the moved object's pose relative to its anchor (the table, the baseline, a label, a
base, a bin, the previous domino) must match the demonstration's within :data:`POSITION_TOLERANCE`
and :data:`ANGLE_TOLERANCE` (and the stack level within :data:`LEVEL_TOLERANCE`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from vslsp.geometry.poses import wrap
from vslsp.outcomes import Diagnosis
from vslsp.sim.tabletop import PickPlaceResult, Placement
from vslsp.stages import in_stage, stage
from vslsp.vision.features import Features, extract_features
from vslsp.vision.matching import NoMatch
from vslsp.vsl.pick_place import PickPlaceDemonstration, RecordedOperation, TableView
from vslsp.vsl.recorder import Heights, Recorder
from vslsp.vsl.reproduction import (
    PlannedOperation,
    correction,
    plan_operation,
)
from vslsp.worlds.panda_table import PandaTable
from vslsp.worlds.panda_table import layouts as scenes

POSITION_TOLERANCE = 0.015  # m
ANGLE_TOLERANCE = np.radians(12.0)
LEVEL_TOLERANCE = 0.008  # m, the height of a stacked object's bottom

Move = tuple[str, Callable[[PandaTable], Placement], str | None]  # item, where (given the world), anchor


@dataclass(frozen=True, eq=False)
class TabletopDemonstration:
    """What the robot learned (``demonstration``) plus, for the judge only, the ground truth
    of each operation: the item moved, its anchor (None: the table) and its pose relative to
    the anchor afterwards (x, y, yaw, bottom height difference)."""

    demonstration: PickPlaceDemonstration
    items: tuple[str, ...]
    anchors: tuple[str | None, ...]
    relative: tuple[tuple[float, float, float, float], ...]
    slips: tuple[dict, ...] = ()  # with --tutor-slips, per operation: moved, operated, disturbed, slip
    moves: tuple = ()  # with the slip detection, per operation: its vslsp.vsl.slips.detect.Moves (for the pictures)
    actual_posts: tuple[np.ndarray, ...] = ()  # with --tutor-slips: the post-place observations as seen


@dataclass(frozen=True, eq=False)
class OperationOutcome:
    """One operation of a reproduction: the demonstrated operation ``index`` it reproduces, who
    did it (``actor``: robot or tutor), the item it concerns (ground truth), the ``diagnosis``
    (OK, NO_MATCH, AMBIGUOUS_MATCH, WRONG_OBJECT, MISPLACED, or the robot's GRASP_FAILED,
    OBJECT_SLIPPED, UNREACHABLE), the plan and the execution, the errors against
    the demonstration (ground truth), and the observation it was planned in."""

    index: int
    actor: str
    item: str
    diagnosis: Diagnosis
    planned: PlannedOperation | None = None
    result: PickPlaceResult | None = None
    errors: dict = field(default_factory=dict)
    observation: np.ndarray | None = field(default=None, repr=False)

    @property
    def ok(self) -> bool:
        return self.diagnosis is Diagnosis.OK

    def to_dict(self) -> dict:
        data = {
            "operation": self.index + 1,
            "actor": self.actor,
            "item": self.item,
            "diagnosis": self.diagnosis,
            **self.errors,
        }
        if self.planned is not None:
            data["plan"] = self.planned.to_dict()
        if self.result is not None:
            data["execution"] = {
                "ok": self.result.ok,
                "diagnosis": self.result.diagnosis,
                "held": self.result.held,
                "duration_s": round(self.result.duration_s, 3),
            }
        return data


@in_stage("perception")
def look(world: PandaTable) -> np.ndarray:
    """What the robot sees: the camera's image seen from above (:class:`TableView`), (h, w, 3)."""
    return TableView(world).rectify(world.observe())


def tutor_move(
    world: PandaTable,
    name: str,
    placement: Placement,
    recorder: Recorder[RecordedOperation, PickPlaceDemonstration] | None,
    pre_pick: np.ndarray | None = None,
) -> np.ndarray | None:
    """The tutor takes ``name`` (out of view: the pre-place observation) and puts it at
    ``placement``; the recorder, if any, records the three observations (``pre_pick`` may be
    given: the last post-place one, nothing moved since) and the heights; returns the
    post-place observation when recording."""
    world.say(f"the tutor puts {name} in place")
    if recorder and pre_pick is None:
        pre_pick = look(world)
    pick_z = world.truth(name)[2] + world.specs[name].size[2]
    world.tutor_move(name, scenes.hold_placement(0))
    pre_place = look(world) if recorder else None
    world.tutor_move(name, placement)
    if not recorder:
        return None
    height, post_place = world.specs[name].size[2], look(world)
    assert pre_pick is not None and pre_place is not None  # looked at above when recording
    recorder.record(pre_pick, post_place, pre_place, Heights(pick_z, world.truth(name)[2] + height, height))
    return post_place


def relation(world: PandaTable, name: str, anchor: str | None) -> tuple[float, float, float, float]:
    """Ground truth: ``name``'s pose seen from ``anchor`` (or the table): x, y, yaw, and the
    height of its bottom above the anchor's bottom."""
    x, y, z, yaw = world.truth(name)
    if anchor is None:
        return x, y, yaw, z
    ax, ay, az, ayaw = world.truth(anchor)
    return (*scenes.relative((ax, ay, ayaw), (x, y, yaw)), z - az)


class DemonstratedRelations(Protocol):
    """What the judge reads of a demonstration (ground truth): per operation the item moved,
    its anchor and its pose relative to the anchor afterwards (:class:`TabletopDemonstration`)."""

    @property
    def items(self) -> tuple[str, ...]: ...

    @property
    def anchors(self) -> tuple[str | None, ...]: ...

    @property
    def relative(self) -> tuple[tuple[float, float, float, float], ...]: ...


@dataclass(frozen=True)
class Relations:
    """The judge's part of a demonstration alone (:class:`DemonstratedRelations`), without the
    recorded observations: what a tutor's moves left, measured on the ground truth."""

    items: tuple[str, ...]
    anchors: tuple[str | None, ...]
    relative: tuple[tuple[float, float, float, float], ...]


def tutor_relations(world: PandaTable, moves: Iterable[Move]) -> Relations:
    """The tutor performs ``moves`` in ``world`` without recording them; the relations they leave."""
    items, anchors, relations = [], [], []
    for name, where, anchor in moves:
        tutor_move(world, name, where(world), None)
        items.append(name)
        anchors.append(anchor)
        relations.append(relation(world, name, anchor))
    return Relations(tuple(items), tuple(anchors), tuple(relations))


def relations_hold(
    world: PandaTable, demo: DemonstratedRelations, owed: Iterable[int], anchor_map: dict[str, str]
) -> bool:
    """The goal on the ground truth: the last demonstrated relation of every item that the
    ``owed`` operations move holds now."""
    last = {demo.items[k]: k for k in owed}
    return all(judge_relation(world, demo, k, anchor_map)[0] for k in last.values())


def judge_relation(
    world: PandaTable, demo: DemonstratedRelations, k: int, anchor_map: dict[str, str]
) -> tuple[bool, dict]:
    """Does operation ``k``'s demonstrated relation hold now (ground truth)? ``anchor_map``
    renames anchors (the user's intervention in the Tower of Hanoi)."""
    anchor = demo.anchors[k]
    now = relation(world, demo.items[k], anchor_map.get(anchor, anchor) if anchor else None)
    wanted = demo.relative[k]
    position = float(np.hypot(now[0] - wanted[0], now[1] - wanted[1]))
    angle = abs(wrap(now[2] - wanted[2]))
    level = abs(now[3] - wanted[3])
    ok = position <= POSITION_TOLERANCE and angle <= ANGLE_TOLERANCE and level <= LEVEL_TOLERANCE
    return ok, {
        "position_error_m": round(position, 4),
        "angle_error_deg": round(float(np.degrees(angle)), 2),
        "level_error_m": round(level, 4),
    }


def robot_operation(
    world: PandaTable,
    demo: TabletopDemonstration,
    k: int,
    anchor_map: dict[str, str],
    image: np.ndarray | None = None,
    pick_match=None,
    keep: bool = False,
    place_match=None,
    features: Features | None = None,
) -> OperationOutcome:
    """The robot reproduces operation ``k``: observe (unless given), match, plan, pick and
    place, take a last look and put the object right if the execution left it off its place
    (:func:`~vslsp.vsl.reproduction.correction`), then the judge's verdict and, when it
    failed, the diagnosis."""
    image = look(world) if image is None else image
    features = extract_features(image) if features is None else features
    kept = image if keep else None
    planned = plan_operation(
        demo.demonstration, k, image, TableView(world), features, pick_match=pick_match, place_match=place_match
    )
    if isinstance(planned, NoMatch):
        world.say(f"robot, operation {k + 1} ({demo.items[k]}): no match found", hold=1.0)
        return OperationOutcome(k, "robot", demo.items[k], Diagnosis.NO_MATCH, observation=kept)
    world.say(f"robot, operation {k + 1}: {demo.items[k]} (pick and place found by match finding)")
    with stage("execution"):
        result = world.pick_and_place(planned.pick, planned.place, planned.grasp_width)
    corrected = False
    if result.ok:  # a last look: an object the execution left off its place is put right, once
        with stage("perception"):
            fix = correction(demo.demonstration, k, look(world), TableView(world), planned)
        if fix is not None:
            with stage("execution"):
                result, corrected = world.pick_and_place(fix.pick, fix.place, fix.grasp_width), True
    ok, errors = judge_relation(world, demo, k, anchor_map)
    errors["corrected"] = corrected
    if ok:
        diagnosis = Diagnosis.OK
    elif not result.ok:
        diagnosis = result.diagnosis or Diagnosis.GRASP_FAILED
    elif result.held != demo.items[k]:
        diagnosis = Diagnosis.WRONG_OBJECT
    elif planned.pick_match.ambiguous or planned.place_match.ambiguous:
        diagnosis = Diagnosis.AMBIGUOUS_MATCH
    else:
        diagnosis = Diagnosis.MISPLACED
    world.say(
        f"robot, operation {k + 1}: {demo.items[k]}: {diagnosis}",
        f"{1000 * errors['position_error_m']:.1f} mm, {errors['angle_error_deg']:.1f} deg from the target"
        + (" (corrected once)" if corrected else ""),
        hold=1.0,
    )
    return OperationOutcome(k, "robot", demo.items[k], diagnosis, planned, result, errors, kept)


def tutor_operation(
    world: PandaTable,
    demo: TabletopDemonstration,
    k: int,
    anchor_map: dict[str, str],
    where: Placement,
    judged: bool = True,
) -> OperationOutcome:
    """The tutor performs operation ``k`` (putting the item at ``where``); an opening move
    (not ``judged``) may go anywhere."""
    tutor_move(world, demo.items[k], where, None)
    ok = not judged or judge_relation(world, demo, k, anchor_map)[0]
    return OperationOutcome(k, "tutor", demo.items[k], Diagnosis.OK if ok else Diagnosis.MISPLACED)


def placement_like(
    world: PandaTable, demo: TabletopDemonstration, k: int, anchor: str | None, on: str | None = None
) -> Placement:
    """Where the tutor puts operation ``k``'s item so that its demonstrated relation holds
    with ``anchor`` (ground truth; the tutor sees the scene)."""
    x, y, yaw, _ = demo.relative[k]
    if anchor is None:
        return Placement(x, y, yaw, on)
    ax, ay, _, ayaw = world.truth(anchor)
    return Placement(*scenes.compose((ax, ay, ayaw), (x, y, yaw)), on)
