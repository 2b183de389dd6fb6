"""Execution faults of the iCub experiments (``--faults``): the tutor disturbs the robot the way
a person would, to exercise the loop's monitoring and replanning (paper, VSL-SP "Results").

The loop (:mod:`vslsp.loop`) knows nothing of faults: a trial's :class:`Faults` acts out its
steps (:meth:`Faults.act`, the loop's :data:`~vslsp.loop.monitor.Act` hook), follows its plans
(:meth:`Faults.planned`, the loop's ``on_plan``), and afterwards marks the steps it disturbed
(:class:`FaultyStep`) for the trial's record, which :func:`fault_log` explains.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass, fields

from vslsp.loop.monitor import StepResult, run_skill
from vslsp.loop.perception import PerceivedState
from vslsp.sim import LineWorld, Observation
from vslsp.sim.robot import HandTrajectory
from vslsp.skills.library import SkillLibrary
from vslsp.symbolic import PlanResult
from vslsp.worlds import World


class Fault(enum.StrEnum):
    """Execution faults for testing replanning: the tutor puts the cube back where it was after
    the action (``NUDGE``), or the step is not executed (``SKIP``)."""

    NUDGE = "nudge"
    SKIP = "skip"


FAULT_WHAT = {
    Fault.NUDGE.value: "the tutor put the cube back after the action",
    Fault.SKIP.value: "the step was not executed",
}


@dataclass(frozen=True)
class FaultyStep(StepResult):
    """An executed step that carried a fault (its kind, a :class:`Fault` value)."""

    fault: str = Fault.SKIP.value

    def to_dict(self) -> dict:
        return {**super().to_dict(), "fault": self.fault}


class Faults:
    """The faults scheduled in one execution: ``schedule`` maps the index of an executed step
    (0-based, over the execution) to the fault injected there. A fault scheduled past the end of
    the first plan moves to its last step, so that every scheduled fault fires."""

    def __init__(self, schedule: Mapping[int, str] | None = None) -> None:
        self.schedule = {int(step): Fault(kind) for step, kind in (schedule or {}).items()}
        self.steps = 0  # the steps acted out so far
        self.fired: dict[int, Fault] = {}  # step index -> the fault injected there

    def planned(self, plan: PlanResult, steps: int) -> None:
        """The loop's ``on_plan``: the first plan (``steps`` run before it: 0) bounds the schedule."""
        if steps == 0 and plan.steps:
            self.schedule = {min(step, len(plan.steps) - 1): fault for step, fault in self.schedule.items()}

    def upcoming(self) -> str | None:
        """The fault the next step will carry (its kind), if any."""
        fault = self.schedule.get(self.steps)
        return None if fault is None else fault.value

    def act(
        self, world: World[Observation], library: SkillLibrary, action: str, obj: str, state: PerceivedState
    ) -> HandTrajectory | None:
        """The loop's :data:`~vslsp.loop.monitor.Act`: the skill run, disturbed when this step is
        scheduled a fault (skipped, or its cube put back after the action)."""
        index, fault = self.steps, self.schedule.get(self.steps)
        self.steps += 1
        if fault is None:
            return run_skill(world, library, action, obj, state)
        self.fired[index] = fault
        if fault is Fault.SKIP:
            return None
        before = _truth_pose(world, obj)
        try:
            return run_skill(world, library, action, obj, state)
        finally:
            if before is not None:
                assert isinstance(world, LineWorld)  # the iCub line world: the tutor's hand
                world.tutor.relocate(*before)

    def fault_of(self, index: int) -> str | None:
        """The fault step ``index`` (0-based) carried, if any."""
        fault = self.fired.get(index)
        return None if fault is None else fault.value

    def mark(self, index: int, step: StepResult) -> StepResult:
        """``step`` (the execution's ``index``-th, 0-based) as a :class:`FaultyStep` when it carried a fault."""
        fault = self.fault_of(index)
        if fault is None:
            return step
        return FaultyStep(**{f.name: getattr(step, f.name) for f in fields(StepResult)}, fault=fault)


def _truth_pose(world: World[Observation], colour: str) -> tuple[str, float, float, float] | None:
    """For fault injection only (the tutor's hand, not the robot's perception)."""
    assert isinstance(world, LineWorld)  # the iCub line world: cubes with their truth
    for cube in world.spec.cubes:
        if cube.colour == colour:
            x, y, yaw = world.cube_pose(cube.name)
            return cube.name, x, y, yaw
    return None


def fault_of(step: StepResult) -> str | None:
    """The fault ``step`` carried (its kind), if any."""
    return step.fault if isinstance(step, FaultyStep) else None


def fault_log(steps: list[StepResult], planned: set[int], ended: str) -> list[dict]:
    """Every fault injected into ``steps`` (a trial's executed steps, in order), explained:
    ``{"step" (1-based), "kind", "expected", "observed", "recovery"}``. The recovery is the
    step that followed: a new plan's first step for the steps in ``planned`` (their ``id``),
    VSL's match finding acting again for the others; ``ended`` says why none followed."""
    log = []
    for k, step in enumerate(steps):
        kind = fault_of(step)
        if kind is None:
            continue
        after = steps[k + 1] if k + 1 < len(steps) and (id(steps[k + 1]) in planned) == (id(step) in planned) else None
        if step.ok:
            recovery = "none needed: the effect held"
        elif after is None:
            recovery = f"none: {ended}"
        elif id(step) in planned:
            recovery = f"replanned: {after.action} {after.obj}"
        else:
            recovery = f"VSL matched again: {after.action} {after.obj}"
        log.append(
            {
                "step": k + 1,
                "kind": kind,
                "what": FAULT_WHAT[kind],
                "expected": step.expected,
                "observed": step.observed,
                "recovery": recovery,
            }
        )
    return log
