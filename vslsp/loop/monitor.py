"""The execution monitor: run one plan step with its skill, observe again, check the effect.

Paper section "Results" of VSL-SP: each plan step is executed by a learned skill; after
every step the robot observes again, grounds ``far`` for every object and checks the
expected effect of the action (push: the object ends far, pull: near). A missing effect is a
failed step, which the planner answers by replanning from what is now seen. For testing that
loop, :class:`Fault` injects execution faults the way a person would disturb the robot.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

import numpy as np

from vslsp.errors import TaskFailed, UnreachableError
from vslsp.loop.perception import PerceivedState, perceive
from vslsp.sim import World
from vslsp.sim.robot import HandTrajectory
from vslsp.skills.execute import execute_skill
from vslsp.skills.library import SkillLibrary


class Action(enum.StrEnum):
    """The skills of VSL-SP and their expected effect on ``(far ?b)``."""

    PUSH = "push"
    PULL = "pull"

    @property
    def makes_far(self) -> bool:
        return self is Action.PUSH


class Fault(enum.StrEnum):
    """Execution faults for testing replanning: the tutor puts the cube back where it was after
    the action (``NUDGE``), or the step is not executed (``SKIP``)."""

    NUDGE = "nudge"
    SKIP = "skip"


@dataclass(frozen=True)
class StepResult:
    """One executed plan step: what was done, what was expected and seen, the hand's path."""

    action: str
    obj: str
    expected_far: bool
    observed_far: bool | None
    ok: bool
    error: str | None
    trajectory: HandTrajectory | None = field(default=None, repr=False)
    fault: str | None = None  # the fault injected into this step (:class:`Fault`), if any

    def to_dict(self) -> dict:
        data = {
            "action": self.action,
            "object": self.obj,
            "expected_far": self.expected_far,
            "observed_far": self.observed_far,
            "ok": self.ok,
            "error": self.error,
        }
        if self.fault is not None:
            data["fault"] = self.fault
        return data

    @property
    def expected(self) -> str:
        """The expected effect as a PDDL literal: ``(far green)`` or ``(not (far green))``."""
        return far_literal(self.obj, self.expected_far)

    @property
    def observed(self) -> str:
        """What the robot saw after the step, in the same words."""
        return f"{self.obj} not seen" if self.observed_far is None else far_literal(self.obj, self.observed_far)


def far_literal(obj: str, far: bool) -> str:
    """``(far obj)`` or ``(not (far obj))``."""
    return f"(far {obj})" if far else f"(not (far {obj}))"


EXPECTED_FAR = {action.value: action.makes_far for action in Action}


def execute_step(
    world: World, library: SkillLibrary, action: str, obj: str, state: PerceivedState, fault: Fault | str | None = None
) -> tuple[StepResult, PerceivedState]:
    """Run ``action`` on ``obj`` as perceived in ``state``; observe again and check the effect.

    ``fault`` injects an execution fault for testing replanning (:class:`Fault`).
    """
    if action not in EXPECTED_FAR:
        raise TaskFailed(f"no skill for action {action!r}; the robot knows {sorted(EXPECTED_FAR)}")
    if obj not in state.objects:
        raise TaskFailed(f"the plan acts on {obj!r} but the robot does not see it (it sees {sorted(state.objects)})")
    target = state.objects[obj]
    trajectory, error = None, None
    fault = Fault(fault) if fault is not None else None
    if fault is not Fault.SKIP:
        before = _truth_pose(world, obj)
        try:
            trajectory = execute_skill(
                world, library[action], np.array(target.table_xy), state.normal, state.line_distance(obj)
            )
        except UnreachableError as unreachable:
            error = str(unreachable)
        if fault is Fault.NUDGE and before is not None:
            world.tutor.relocate(*before)
    new_state = perceive(world)
    observed = new_state.objects.get(obj)
    observed_far = observed.far if observed is not None else None
    ok = error is None and observed_far == EXPECTED_FAR[action]
    if error is None and not ok:
        error = (
            f"expected (far {obj}) to be {EXPECTED_FAR[action]} after {action}, observed "
            f"{'nothing' if observed is None else observed_far}"
        )
    result = StepResult(
        action, obj, EXPECTED_FAR[action], observed_far, ok, error, trajectory, None if fault is None else fault.value
    )
    return result, new_state


def _truth_pose(world: World, colour: str) -> tuple[str, float, float, float] | None:
    """For fault injection only (the tutor's hand, not the robot's perception)."""
    for cube in world.spec.cubes:
        if cube.colour == colour:
            x, y, yaw = world.cube_pose(cube.name)
            return cube.name, x, y, yaw
    return None


FAULT_WHAT = {
    Fault.NUDGE.value: "the tutor put the cube back after the action",
    Fault.SKIP.value: "the step was not executed",
}


def fault_log(steps: list[StepResult], planned: set[int], ended: str) -> list[dict]:
    """Every fault injected into ``steps`` (a trial's executed steps, in order), explained:
    ``{"step" (1-based), "kind", "expected", "observed", "recovery"}``. The recovery is the
    step that followed: a new plan's first step for the steps in ``planned`` (their ``id``),
    VSL's match finding acting again for the others; ``ended`` says why none followed."""
    log = []
    for k, step in enumerate(steps):
        if step.fault is None:
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
                "kind": step.fault,
                "what": FAULT_WHAT[step.fault],
                "expected": step.expected,
                "observed": step.observed,
                "recovery": recovery,
            }
        )
    return log
