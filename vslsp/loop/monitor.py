"""The execution monitor: run one plan step with its skill, observe again, check the effect.

Paper section "Results" of VSL-SP: each plan step is executed by a learned skill; after
every step the robot observes again, grounds ``far`` for every object and checks the
expected effect of the action. The expectation is the learned action model's
(:func:`model_expects_far`: the grounded action's add and delete effects applied to what was
seen before), so any learned domain is monitored by its own models. A missing effect is a
failed step, which the planner answers by replanning from what is now seen.

How a step is acted out is a hook (:data:`Act`, :func:`run_skill` by default): an experiment
that disturbs the robot passes its own (:mod:`vslsp.experiments.icub_faults`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from vslsp.errors import TaskFailed, UnreachableError
from vslsp.loop.perception import PerceivedState, perceive
from vslsp.sim import Observation
from vslsp.sim.robot import HandTrajectory
from vslsp.skills.execute import execute_skill
from vslsp.skills.library import SkillLibrary
from vslsp.symbolic import Atom, Domain
from vslsp.symbolic.model.domain import ground_effects
from vslsp.worlds import World

#: Acting out a step: ``act(world, library, action, obj, state)`` runs the skill of ``action`` on
#: ``obj`` as seen in ``state`` and returns the hand's trajectory (None: the hand did not move);
#: raises :class:`~vslsp.errors.UnreachableError` when the skill cannot reach.
Act = Callable[[World[Observation], SkillLibrary, str, str, PerceivedState], HandTrajectory | None]


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

    def to_dict(self) -> dict:
        return {
            "action": self.action,
            "object": self.obj,
            "expected_far": self.expected_far,
            "observed_far": self.observed_far,
            "ok": self.ok,
            "error": self.error,
        }

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


def model_expects_far(domain: Domain, action: str, args: Sequence[str], far: dict[str, bool]) -> bool:
    """``(far obj)`` after ``action`` on ``args`` (``obj`` = ``args[0]``, the object acted on) by
    the learned model of ``action`` in ``domain``: true when its grounded effects add it, false
    when they delete it, else as it was in ``far`` (every seen object's ``far`` before the step,
    which conditional effects are read in). Raises TaskFailed when the domain has no such action."""
    names = [a.name for a in domain.actions]
    if action not in names:
        raise TaskFailed(f"the learned domain has no action {action!r} (it has {names})")
    obj = args[0]
    before = frozenset(Atom("far", (name,)) for name, value in far.items() if value)
    added, deleted = ground_effects(domain.action(action), tuple(args), before)
    atom = Atom("far", (obj,))
    return True if atom in added else False if atom in deleted else far.get(obj, False)


def run_skill(
    world: World[Observation], library: SkillLibrary, action: str, obj: str, state: PerceivedState
) -> HandTrajectory:
    """Run the learned skill of ``action`` on ``obj`` where ``state`` sees it (:data:`Act`)."""
    target = state.objects[obj]
    return execute_skill(world, library[action], np.array(target.table_xy), state.normal, state.line_distance(obj))


def execute_step(
    world: World[Observation],
    library: SkillLibrary,
    action: str,
    obj: str,
    state: PerceivedState,
    expected_far: bool,
    act: Act = run_skill,
) -> tuple[StepResult, PerceivedState]:
    """Run ``action`` on ``obj`` as perceived in ``state`` (by ``act``); observe again and check
    that ``(far obj)`` is now ``expected_far`` (:func:`model_expects_far` for a planned step)."""
    if action not in library.skills:
        raise TaskFailed(f"no skill for action {action!r}; the robot knows {sorted(library.skills)}")
    if obj not in state.objects:
        raise TaskFailed(f"the plan acts on {obj!r} but the robot does not see it (it sees {sorted(state.objects)})")
    trajectory, error = None, None
    try:
        trajectory = act(world, library, action, obj, state)
    except UnreachableError as unreachable:
        error = str(unreachable)
    new_state = perceive(world)
    observed = new_state.objects.get(obj)
    observed_far = observed.far if observed is not None else None
    ok = error is None and observed_far == expected_far
    if error is None and not ok:
        error = (
            f"expected (far {obj}) to be {expected_far} after {action}, observed "
            f"{'nothing' if observed is None else observed_far}"
        )
    return StepResult(action, obj, expected_far, observed_far, ok, error, trajectory), new_state
