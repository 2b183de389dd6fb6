"""The tutor's slips in the iCub experiments (issue 30, item 1: ``--tutor-slips P``,
``--slip-detection on|off``).

While demonstrating an operation, with probability P the tutor also nudges another cube
(:class:`~vslsp.worlds.slips.TutorSlips`, applied by :func:`~vslsp.worlds.icub.tutor_slip`
before the post-action image). The robot watching the tutor then either

- detects every cube that moved (detection on: :func:`~vslsp.vsl.slips.colour.ground_moves`),
  takes the one moved farthest across the line for the operated one and records the rest as
  disturbed; or
- takes the change for the operation (detection off: the paper's VSL,
  :func:`~vslsp.grounding.operation.ground`, which finds one moved object and gives up when
  several moved): the baseline.

What is learned must not copy the accident. The learned action models come from the robot's own
executions (no tutor, no slip); the goal and the order come from the operated cubes only
(:func:`~vslsp.symbolic.learn_task` takes each step's acted object). And **a disturbance is no
part of the demonstration: the learner keeps each disturbed cube's predicates as they were before
the slip until the tutor operates on that cube** (so a cube the slip put across the line neither
enters the goal, nor shows up in another rule's context, nor hides the tutor's later operation on
it). keep-all-near's case, a cube pushed across the line: the demonstrated goal stays "no block is
far" (only the tutor's pulls teach it) and the report says which cube was disturbed, where, and
that it is not part of the goal.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vslsp.grounding.operation import Grounding, ground
from vslsp.grounding.spatial import identify_action
from vslsp.loop.perception import PerceivedState
from vslsp.loop.pipeline import to_step
from vslsp.sim import LineWorld
from vslsp.symbolic import Step
from vslsp.vsl.demonstration import ImagePlane
from vslsp.vsl.slips.colour import Moves, ground_moves
from vslsp.worlds.icub import tutor_slip
from vslsp.worlds.slips import Slip, TutorSlips


@dataclass
class Watcher:
    """How the robot watches the tutor in a trial run with ``--tutor-slips`` or
    ``--slip-detection``: the tutor's slips (a stream of their own, ``probability`` 0 when only
    the detection was given), the detection, and what they left: a record per demonstrated
    operation (``records``), the disturbances in words (``notes``), and the moves of each
    observation the report draws (``pictures``, by the observation's index)."""

    seed: int
    probability: float = 0.0
    detection: bool = True
    operation: int = 0
    records: list[dict] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    pictures: dict[int, Moves] = field(default_factory=dict, repr=False)
    held: dict[str, dict[str, bool]] = field(default_factory=dict)  # disturbed cubes' predicates before the slip
    slips: TutorSlips = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self.slips = TutorSlips(self.probability, self.seed)

    def start(self) -> None:
        """A new demonstration begins (a new scene): what was held of the last one's disturbed
        cubes is no part of it."""
        self.held.clear()

    def slip(self, world: LineWorld, operated: str) -> dict | None:
        """The tutor's slip in the operation on cube ``operated`` just done (drawn for every
        operation, applied when it slips): its ground-truth record, or None."""
        self.operation += 1
        others = [c.name for c in world.spec.cubes if c.name != operated]
        drawn = self.slips.draw(self.operation, others)
        if drawn is None:
            return None
        far = world.is_far(drawn.name)
        applied: Slip | None = tutor_slip(world, drawn)
        if applied is None:
            return {**_plain(drawn.to_dict()), "applied": False, "why": "no room: every way touches a lane"}
        return {**_plain(applied.to_dict()), "applied": True, "crossed_line": world.is_far(applied.name) != far}

    def ground(self, title: str, pre: np.ndarray, post: np.ndarray) -> tuple[Grounding, Moves | None]:
        """The operation's grounding (the operated cube's) and, with the detection, every move."""
        if not self.detection:
            return ground(pre, post), None
        moves = ground_moves(pre, post)
        return moves.operated, moves

    def step(
        self,
        grounding: Grounding,
        moves: Moves | None,
        before: PerceivedState,
        after: PerceivedState,
        predicates: tuple,
    ) -> Step:
        """The operation as the learner takes it: the operated cube's step, with every disturbed
        cube's predicates kept as they were before its slip until the tutor operates on it."""
        step = to_step(grounding, before, after, predicates)
        if moves is None:
            return step
        meant_before = {o: self.held.get(o, v) for o, v in step.before.items()}
        self.held.pop(grounding.name, None)
        for disturbed in moves.disturbed:
            if disturbed.name in meant_before:
                self.held.setdefault(disturbed.name, dict(meant_before[disturbed.name]))
        meant_after = {o: self.held.get(o, v) for o, v in step.after.items()}
        action = step.action
        was, now = meant_before.get(grounding.name, {}), meant_after.get(grounding.name, {})
        if "far" in was and "far" in now:
            action = identify_action(bool(was["far"]), bool(now["far"]))
        return Step(action, step.obj, meant_before, meant_after)

    def record(
        self, title: str, number: int, tutor: str, grounding: Grounding, moves: Moves | None, slip: dict | None
    ) -> None:
        """The operation's record (``tutor_operations`` of the trial) and its disturbances in words."""
        seen = (
            moves.to_dict()
            if moves is not None
            else {"moved": [grounding.name], "operated": grounding.name, "disturbed": []}
        )
        entry = {"demonstration": title, "operation": number, "tutor": tutor, **seen}
        if slip is not None:
            entry["slip"] = slip
        self.records.append(entry)
        for disturbed in moves.disturbed if moves is not None else ():
            where = f"{title}, operation {number} ({tutor})"
            if disturbed.far_pre != disturbed.far_post:
                self.notes.append(
                    f"{disturbed.name} was disturbed across the line in {where}: (far {disturbed.name}) "
                    f"{str(disturbed.far_pre).lower()} -> {str(disturbed.far_post).lower()} by a slip, not by "
                    f"an operation; not part of the goal (the learner keeps {disturbed.name} as before the slip)"
                )
            else:
                self.notes.append(
                    f"{disturbed.name} was disturbed in {where} without changing side; not part of what was learned"
                )

    def failed(self, title: str, number: int, tutor: str, slip: dict | None, error: str) -> None:
        """The operation the robot could not ground (detection off and several cubes moved)."""
        entry = {"demonstration": title, "operation": number, "tutor": tutor, "error": error}
        if slip is not None:
            entry["slip"] = slip
        self.records.append(entry)

    def details(self) -> dict:
        """The trial's record fields."""
        return {"tutor_operations": self.records, "disturbances": self.notes}


def _plain(record: dict) -> dict:
    """``record`` with its numbers as Python floats (the slips are drawn as NumPy's)."""
    return {k: float(v) if isinstance(v, float) else v for k, v in record.items()}


class OperatedPlane(ImagePlane):
    """VSL's image-plane observation model (:class:`~vslsp.vsl.demonstration.ImagePlane`) that
    records the operated object when several moved (:func:`~vslsp.vsl.slips.colour.ground_moves`):
    a disturbed one is no operation of the demonstration."""

    def ground_operation(self, pre: np.ndarray, post: np.ndarray) -> Grounding:
        """The operated object's grounding when several moved."""
        return ground_moves(pre, post, self.robot_side).operated


def summary(results: list) -> dict:
    """The run's figures of the slips: operations slipped, slips the detection saw (the slipped
    cube among the disturbed), operations whose operated cube was not the tutor's, disturbances
    across the line."""
    records = [op for r in results for op in r.details.get("tutor_operations", [])]
    slipped = [op for op in records if op.get("slip", {}).get("applied")]
    return {
        "operations_slipped": len(slipped),
        "slips_detected": sum(op["slip"]["object"] in op.get("disturbed", []) for op in slipped),
        "operated_not_the_tutors": sum(
            "operated" in op and op["operated"] != op["tutor"].split()[-1] for op in records
        ),
        "slips_across_the_line": sum(bool(op["slip"].get("crossed_line")) for op in slipped),
    }
