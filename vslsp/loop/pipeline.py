"""VSL-SP end to end: from observations to action models and tasks, and the closed loop.

Paper sections "Implementation" and "Results" of VSL-SP. The robot learns the symbolic
models of its skills by watching its own executions (VSL grounds ``far`` before and after),
learns the task from the tutor's demonstrations (pre-/post-action images only), states the
task in the observed scene as a PDDL problem, plans, and executes every step with the
learned skills, observing again after each one. A step whose effect is missing (the push
did not cross the line, the cube was knocked back) makes the robot replan from what it sees.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from vslsp.errors import TaskFailed
from vslsp.grounding import Predicate, unary_literals, with_builtins
from vslsp.grounding.operation import Grounding, SceneGrounding, ground
from vslsp.loop.monitor import Act, StepResult, execute_step, model_expects_far, run_skill
from vslsp.loop.perception import PerceivedState, perceive
from vslsp.sim import Observation
from vslsp.skills.library import SkillLibrary
from vslsp.symbolic import (
    Domain,
    LearnedTask,
    NoPlan,
    PlanResult,
    PlanStatus,
    Problem,
    Step,
    learn_domain,
    make_problem,
    solve,
)
from vslsp.symbolic.engines.planner import DEFAULT_TIMEOUT_S
from vslsp.worlds import World

MAX_REPLANS = 4
#: The planner's statuses that say the problem has no plan (proved, or the whole search gave up):
#: for an ordered task, the order can no longer be kept, and the loop replans without it.
NO_PLAN_EXISTS = (PlanStatus.UNSOLVABLE_PROVEN, PlanStatus.UNSOLVABLE_INCOMPLETELY)


def literals(state: PerceivedState, predicates: Sequence[Predicate] | None = None) -> dict[str, dict[str, bool]]:
    """The grounded predicates of every object seen: ``{"green": {"far": True}, ...}``; with the
    user's unary ``predicates`` too (``far`` is always there)."""
    return scene_literals(state.grounding, predicates)


def scene_literals(
    grounding: SceneGrounding, predicates: Sequence[Predicate] | None = None
) -> dict[str, dict[str, bool]]:
    """:func:`literals` of one grounded observation (the objects :func:`ground_scene` found)."""
    far = grounding.far_by_name()
    if not predicates:
        return {name: {"far": value} for name, value in far.items()}
    values = unary_literals(grounding.atoms(with_builtins(predicates)))
    return {name: values.get(name, {}) for name in far}


def to_step(
    grounding: Grounding, before: PerceivedState, after: PerceivedState, predicates: Sequence[Predicate] | None = None
) -> Step:
    """A grounded operation as the symbolic layer learns from it."""
    return Step(grounding.action, grounding.name, literals(before, predicates), literals(after, predicates))


@dataclass(frozen=True)
class Exploration:
    """The robot's own skill executions, observed and grounded (what the domain is learned from)."""

    steps: tuple[Step, ...]
    groundings: tuple[Grounding, ...]
    images: tuple[tuple[np.ndarray, np.ndarray], ...] = field(repr=False)


def explore_skill(
    world: World[Observation],
    library: SkillLibrary,
    action: str,
    obj: str | None = None,
    predicates: Sequence[Predicate] | None = None,
) -> Exploration:
    """The robot executes ``action`` on a cube and watches: VSL grounds the pre/post pair.

    The grounded execution (which object moved, ``far`` before and after) is what the
    action models are learned from (the paper's Table 3). ``obj`` defaults to the first
    object on the side the skill starts from; the robot expects it to cross the line (no model
    is learned yet).
    """
    state = perceive(world)
    start_far = action == "pull"
    name = obj or next((n for n, o in state.objects.items() if o.far == start_far), None)
    if name is None:
        raise TaskFailed(f"the robot sees no {'far' if start_far else 'near'} object to try {action} on")
    result, after = execute_step(world, library, action, name, state, not start_far)
    if not result.ok:
        raise TaskFailed(f"exploring {action} on {name}: {result.error}", cause=f"exploring {action} on {name}")
    grounding = ground(state.image, after.image)
    if grounding.action != action:
        raise TaskFailed(f"the robot executed {action} but saw {grounding.action or 'no change of far'}")
    return Exploration((to_step(grounding, state, after, predicates),), (grounding,), ((state.image, after.image),))


def learn_models(explorations: list[Exploration]) -> Domain:
    """The lifted action schemas push / pull learned from the robot's observed executions."""
    return learn_domain([step for exploration in explorations for step in exploration.steps])


@dataclass
class Execution:
    """A task executed in closed loop: every plan made, every step run, and the outcome.

    ``error`` says why it failed and ``cause`` names that in short (the report's tally);
    ``planning_status`` is how the planner's run ended when the loop stopped for want of a plan
    (a limit reached, or no plan even without the demonstrated order).
    """

    plans: list[PlanResult] = field(default_factory=list)
    problems: list = field(default_factory=list)
    steps: list[StepResult] = field(default_factory=list)
    states: list[PerceivedState] = field(default_factory=list, repr=False)
    replans: int = 0
    success: bool = False
    error: str | None = None
    notes: list[str] = field(default_factory=list)
    cause: str | None = None
    planning_status: PlanStatus | None = None

    @property
    def executed(self) -> list[str]:
        """The objects acted on successfully, in order: ``["orange", "green", ...]``."""
        return [s.obj for s in self.steps if s.ok]

    def fail(self, error: str, cause: str | None = None) -> Execution:
        """The run failed: ``error`` says why, ``cause`` names it in short (None: the error is its own)."""
        self.error, self.cause = error, cause
        return self

    def to_dict(self) -> dict:
        data = {
            "success": self.success,
            "replans": self.replans,
            "plans": [p.to_dict() for p in self.plans],
            "steps": [s.to_dict() for s in self.steps],
            "failed_steps": sum(not s.ok for s in self.steps),
            "error": self.error,
            "notes": self.notes,
        }
        if self.planning_status is not None:
            data["planning_status"] = self.planning_status.value
        return data


def plan_task(
    domain: Domain,
    task: LearnedTask,
    state: dict[str, dict[str, bool]],
    *,
    planner: str = "fast-downward",
    timeout: float | None = DEFAULT_TIMEOUT_S,
    notes: list[str] | None = None,
) -> tuple[Problem, PlanResult, LearnedTask]:
    """Plan ``task`` from the grounded ``state`` (:func:`literals`): the problem, its plan and the
    task planned for. When the planner finds no plan for an ordered task, the order can no longer
    be kept (a later object already changed): the task without its order is planned instead
    (said in ``notes``) and returned. Raises :class:`NoPlan` when the planner stops otherwise."""
    while True:
        problem = make_problem(domain, task, state)
        try:
            return problem, solve(domain, problem, planner, timeout=timeout), task
        except NoPlan as failure:
            if not (task.ordered and failure.status in NO_PLAN_EXISTS):
                raise
            if notes is not None:
                notes.append(f"{failure}; replanning without the demonstrated order")
            task = task.without_order()


def execute_task(
    world: World[Observation],
    library: SkillLibrary,
    domain: Domain,
    task: LearnedTask,
    *,
    planner: str = "fast-downward",
    max_replans: int = MAX_REPLANS,
    on_step: Callable[[StepResult, PerceivedState], None] | None = None,
    predicates: Sequence[Predicate] | None = None,
    before_step: Callable[[int, str, str], None] | None = None,
    planner_timeout: float | None = DEFAULT_TIMEOUT_S,
    act: Act = run_skill,
    on_plan: Callable[[PlanResult, int], None] | None = None,
) -> Execution:
    """Plan ``task`` in the scene the robot sees and execute the plan, replanning on failures.

    Every step is acted out by ``act`` (the learned skill, :func:`~vslsp.loop.monitor.run_skill`)
    and checked against the effect its learned model in ``domain`` expects
    (:func:`~vslsp.loop.monitor.model_expects_far`). The run succeeds when a plan from the last
    observed state is empty: the goal holds in what the robot sees. ``on_plan(plan, steps)`` is
    called with each plan about to be executed and the number of steps run before it,
    ``before_step(number, action, object)`` before each step (1-based over the run),
    ``on_step(result, state)`` after it.

    When the planner finds no plan for the ordered task, the order can no longer be kept (a
    later object already changed): the loop replans for the goal alone. When it stops at its
    time or memory limit (or fails), nothing is known about the order: the run ends there,
    reporting the planner's status.
    """
    run = Execution()
    state = perceive(world)
    run.states.append(state)
    while True:
        try:
            problem, plan, task = plan_task(
                domain, task, literals(state, predicates), planner=planner, timeout=planner_timeout, notes=run.notes
            )
        except NoPlan as failure:
            run.planning_status = failure.status
            return run.fail(str(failure), failure.cause)
        run.plans.append(plan)
        run.problems.append(problem)
        if len(run.plans) > max_replans + 3:
            return run.fail(f"the goal still does not hold after {len(run.plans) - 1} plans")
        if not plan.steps:
            run.success = True
            return run
        if on_plan is not None:
            on_plan(plan, len(run.steps))
        for action, args in plan.steps:
            if before_step is not None:
                before_step(len(run.steps) + 1, action, args[0])
            expected = model_expects_far(domain, action, args, state.far())
            result, state = execute_step(world, library, action, args[0], state, expected, act)
            run.steps.append(result)
            run.states.append(state)
            if on_step is not None:
                on_step(result, state)
            if not result.ok:
                break
        else:
            continue  # the whole plan ran: the next plan from the observed state should be empty
        if run.replans >= max_replans:
            return run.fail(
                f"gave up after {max_replans} replans: {run.steps[-1].error}", f"gave up after {max_replans} replans"
            )
        run.replans += 1


def describe_learned(domain: Domain | None, task: LearnedTask | None) -> dict:
    """What a trial learned, for its record: the action models (the paper's Table 3: each
    action's parameters, precondition and effects in PDDL, and the whole domain), the goal, the
    ordering constraints (PDDL 3 ``sometime-before``) and the rules they came from."""
    data: dict = {}
    if domain is not None:
        data["action_models"] = [
            {
                "action": action.name,
                "parameters": " ".join(f"{name} - {kind}" for name, kind in action.parameters),
                "precondition": action.precondition.to_pddl(),
                "effects": [effect.to_pddl() for effect in action.effects],
            }
            for action in domain.actions
        ]
        data["domain_pddl"] = domain.to_pddl()
    if task is not None:
        data["goal"] = task.goal.to_pddl()
        data["constraints"] = [constraint.to_pddl() for constraint in task.constraints]
        data["rules"] = [str(rule) for rule in task.rules]
    return data
