"""Planning through unified-planning: trajectory constraints compiled away, then Fast Downward.

Paper: "Implementation" and the iCub experiments (VSL-SP hands the learned domain and the
problem, with its PDDL 3.0 ordering constraints, to an off-the-shelf planner). Fast Downward
has no trajectory constraints: :mod:`vslsp.symbolic.engines.lifted` compiles them into the lifted
action schemas (Fast Downward grounds them itself). A planner without conditional effects
(e.g. ``fast-downward-opt``), or ``compilation="ground"``, gets unified-planning's
TrajectoryConstraintsRemover on the grounded problem instead, its plan mapped back. Every Fast
Downward planner is run by vslsp itself (:mod:`vslsp.symbolic.engines.fast_downward`, bounded in
time and memory); unified-planning gives the model, its compilers and its writer. This is the only
module that imports unified-planning's engines.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass, replace
from typing import Any

from vslsp.errors import InputError, VslspError
from vslsp.interrupts import memory_limit_mb, user_limited
from vslsp.stages import in_stage
from vslsp.symbolic.budget import phase
from vslsp.symbolic.engines.fast_downward import Run as FastDownwardRun
from vslsp.symbolic.engines.fast_downward import failure as fast_downward_failure
from vslsp.symbolic.engines.fast_downward import run as run_fast_downward
from vslsp.symbolic.engines.lifted import compile_lifted, objects_named
from vslsp.symbolic.engines.outcomes import Compilation, InternalError, NoPlan, PlanStatus, Unsolvable
from vslsp.symbolic.model.domain import Domain, Problem
from vslsp.symbolic.model.formula import Always, SometimeBefore, expand_quantifiers, holds
from vslsp.symbolic.model.up_model import environment, to_up

DEFAULT_PLANNER = "fast-downward"
#: Every planner run is bounded (docs/bad-input.md): wall-clock seconds, and megabytes of address
#: space for each of its processes. A goal whose normal form explodes (a quantified disjunction)
#: would otherwise make Fast Downward's translator take the machine's memory.
DEFAULT_TIMEOUT_S = 300.0
DEFAULT_MEMORY_MB = 4096
#: vslsp's planner names that are a unified-planning engine with set parameters; any other
#: name is a unified-planning oneshot planner as installed (e.g. fast-downward-opt: A* + LM-cut).
#: The default is greedy best-first search with the FF heuristic and preferred operators:
#: LAMA's landmark preprocessing dominates on the long chains of a demonstrated order
#: (about 5x slower at 200 blocks, see benchmarks/bench_planning.py).
PLANNERS: dict[str, tuple[str, dict]] = {
    "fast-downward": (
        "fast-downward",
        {"fast_downward_search_config": "let(hff,ff(),lazy_greedy([hff],preferred=[hff]))"},
    ),
    "fast-downward-lama": ("fast-downward", {"fast_downward_alias": "lama-first"}),
}
#: The same two, as options of Fast Downward's driver run directly (vslsp.symbolic.engines.fast_downward)
#: on the lifted compilation.
DIRECT: dict[str, list[str]] = {
    "fast-downward": ["--search", PLANNERS["fast-downward"][1]["fast_downward_search_config"]],
    "fast-downward-lama": ["--alias", "lama-first"],
}
#: Every planner that is Fast Downward, with the driver's options that its unified-planning engine
#: runs it with (up-fast-downward's ``fast-downward-opt``: A* with LM-cut). vslsp runs the driver
#: itself (:func:`vslsp.symbolic.engines.fast_downward.run`: bounded in time and memory, its processes
#: ended with this one) on the problem as unified-planning's PDDLWriter writes it for the engine, after
#: unified-planning's compilers (the ground constraint compilation, conditional effects removed).
FAST_DOWNWARD: dict[str, list[str]] = {**DIRECT, "fast-downward-opt": ["--search", "astar(lmcut())"]}
#: The Fast Downward planners whose engine plans for an artificial goal action, as up-fast-downward's
#: optimal engine does (the goal its precondition, reached last: LM-cut takes no axioms, which a
#: quantified goal would become); the action is dropped from the plan.
GOAL_ACTION = frozenset({"fast-downward-opt"})


@dataclass(frozen=True)
class PlanResult:
    """A plan: ``steps`` are ``(action, (arg, ...))`` in lower case, e.g. ``("pull", ("orange",))``."""

    steps: tuple[tuple[str, tuple[str, ...]], ...]
    planner: str
    time_s: float
    compilation: Compilation = Compilation.NONE

    def lines(self) -> list[str]:
        """``["pull orange", ...]``: one string per step, as in ``vslsp plan --json``."""
        return [" ".join((name, *args)) for name, args in self.steps]

    def to_pddl(self) -> str:
        """One ``(action arg ...)`` per line: the PLAN file of ``vslsp validate``."""
        return "".join(f"({line})\n" for line in self.lines())

    def to_dict(self) -> dict:
        return {
            "plan": self.lines(),
            "planner": self.planner,
            "time_s": self.time_s,
            "compilation": self.compilation.value,
        }

    @classmethod
    def from_dict(cls, data: dict) -> PlanResult:
        steps = tuple((line.split()[0], tuple(line.split()[1:])) for line in data["plan"])
        return cls(steps, data["planner"], float(data["time_s"]), Compilation(data.get("compilation", "none")))


@dataclass(frozen=True)
class PlanningTimes:
    """Where the time went: building the UP problem, compiling constraints away, searching."""

    build_s: float
    compile_s: float
    solve_s: float


def planners() -> list[str]:
    """The planner names :func:`solve` takes: vslsp's own, then unified-planning's installed oneshot planners."""
    return list(PLANNERS) + [name for name in _oneshot_planners(environment()) if name not in PLANNERS]


def check_planner(name: str) -> None:
    """Raise InputError (listing the available planners) unless ``name`` is one :func:`solve` takes."""
    if name in PLANNERS:
        return
    available = planners()
    if name not in available:
        raise InputError(f"unknown planner {name!r}; available: {', '.join(available)}")


def solve(
    domain: Domain,
    problem: Problem,
    planner: str = DEFAULT_PLANNER,
    compilation: Compilation | None = None,
    timeout: float | None = DEFAULT_TIMEOUT_S,
    memory_mb: int | None = DEFAULT_MEMORY_MB,
) -> PlanResult:
    """Plan for ``problem`` in ``domain`` with a unified-planning oneshot planner.

    Raises :class:`~vslsp.symbolic.engines.outcomes.NoPlan` ("no plan: ...", a TaskFailed with the run's
    :class:`~vslsp.symbolic.engines.outcomes.PlanStatus`) when the planner proves or reports no plan
    (:class:`~vslsp.symbolic.engines.outcomes.Unsolvable` when it proved it), and one naming the limit
    (status TIMEOUT or MEMOUT) when it reaches ``timeout`` (wall-clock seconds) or
    ``memory_mb`` (megabytes per process; None: unbounded); InputError for an unknown planner
    or one that cannot take the problem, :class:`~vslsp.symbolic.engines.outcomes.InternalError` when a
    planner or compiler fails inside. ``compilation``: force LIFTED or GROUND (default: lifted where the planner has
    conditional effects).
    """
    return solve_timed(domain, problem, planner, compilation, timeout, memory_mb)[0]


@in_stage("planning")
def solve_timed(
    domain: Domain,
    problem: Problem,
    planner: str = DEFAULT_PLANNER,
    compilation: Compilation | None = None,
    timeout: float | None = DEFAULT_TIMEOUT_S,
    memory_mb: int | None = DEFAULT_MEMORY_MB,
) -> tuple[PlanResult, PlanningTimes]:
    """:func:`solve`, with the time of each phase."""
    check_planner(planner)
    if problem.domain.name != domain.name:
        raise InputError(f"problem {problem.name} is for domain {problem.domain.name}, not {domain.name}")
    broken = initially_broken(problem)
    if broken:
        raise Unsolvable(broken)
    try:
        # Never more than the user's own address-space limit (ulimit -v): a child cannot be given it.
        memory_mb = memory_limit_mb(memory_mb) if memory_mb else memory_mb
        return _solve(domain, problem, planner, compilation, Limits(timeout, memory_mb))
    except VslspError:
        raise
    except Exception as error:  # a failure inside unified-planning or the planner: not "no plan"
        stage = getattr(error, "vslsp_stage", "planning")
        first = str(error).splitlines()[0] if str(error) else ""
        raise InternalError(
            f"{stage} failed inside ({type(error).__name__}: {first}); run with --debug for the traceback"
        ) from error


def initially_broken(problem: Problem) -> str | None:
    """A message when a constraint is already broken for good in the initial state, else None."""
    universe, state = problem.universe(), frozenset(problem.init)
    for constraint in problem.constraints:
        if isinstance(constraint, Always) and not holds(constraint.formula, state, universe):
            return f"{constraint.to_pddl()} is false in the initial state"
        if isinstance(constraint, SometimeBefore) and holds(constraint.formula, state, universe):
            return (
                f"{constraint.to_pddl()} can never hold: {constraint.formula.to_pddl()} is already true in the "
                "initial state, before anything else"
            )
    return None


@dataclass(frozen=True)
class Limits:
    """The bounds of one planner run: wall-clock seconds and megabytes per process (None: none)."""

    timeout: float | None
    memory_mb: int | None

    def reached(self, status: PlanStatus) -> NoPlan:
        """The failure of a run that reached its time (TIMEOUT) or memory (MEMOUT) limit (exit 1, naming it)."""
        if status is PlanStatus.TIMEOUT:
            limit = f"time limit of {self.timeout:g} s" if self.timeout else "time limit"
            return NoPlan(f"the planner's {limit} reached (raise it with --timeout)", status)
        limit = f"memory limit of {self.memory_mb} MB" if self.memory_mb else "memory"
        if self.memory_mb and user_limited(self.memory_mb):
            return NoPlan(f"the planner's {limit} reached (your own limit, ulimit -v: raise it there)", status)
        return NoPlan(f"the planner's {limit} reached (raise it with --memory)", status)


def _solve(
    domain: Domain, problem: Problem, planner: str, compilation: Compilation | None, limits: Limits
) -> tuple[PlanResult, PlanningTimes]:
    if planner in DIRECT and compilation is not Compilation.GROUND:
        return _solve_directly(domain, problem, planner, limits)
    return _solve_up(domain, problem, planner, compilation, limits)


def _solve_directly(domain: Domain, problem: Problem, planner: str, limits: Limits) -> tuple[PlanResult, PlanningTimes]:
    """Lifted compilation, our PDDL text, Fast Downward's driver: nothing grounded in Python."""
    start = time.perf_counter()
    with phase("grounding", f"problem {problem.name}"):
        compiled_domain, compiled_problem = compile_lifted(domain, problem)
        compiled = time.perf_counter()
        domain_text, problem_text = planner_texts(compiled_domain, compiled_problem)
        built = time.perf_counter()
    run = run_fast_downward(domain_text, problem_text, DIRECT[planner], limits.timeout, memory_mb=limits.memory_mb)
    solved = time.perf_counter()
    _raise_unless_solved(run, problem, limits)
    used = Compilation.LIFTED if problem.constraints else Compilation.NONE
    times = PlanningTimes(built - compiled, compiled - start, solved - built)
    return PlanResult(run.steps, planner, solved - start, used), times


def _raise_unless_solved(run: FastDownwardRun, problem: Problem, limits: Limits) -> None:
    """The failure of a Fast Downward run that found no plan, raised (nothing when it found one)."""
    if run.outcome is PlanStatus.SOLVED:
        return
    if run.outcome.limit_reached:
        raise limits.reached(run.outcome)
    if run.outcome is PlanStatus.INTERNAL_ERROR:
        raise InternalError(f"{fast_downward_failure(run)}; run with --debug for its whole log") from RuntimeError(
            run.log
        )
    if run.outcome is PlanStatus.UNSOLVABLE_PROVEN:
        raise Unsolvable(
            f"the goal cannot be reached from the initial state{_under(problem)} (proved by Fast Downward)"
        )
    raise NoPlan("Fast Downward's search gave up without a plan (it is incomplete)", run.outcome)


def planner_texts(domain: Domain, problem: Problem) -> tuple[str, str]:
    """The domain and problem text for a planner without PDDL 3.0 (quantified goals written out, no
    ``:constraints`` requirement)."""
    goal = expand_quantifiers(problem.goal, problem.universe(), "the goal")
    named = objects_named(domain)  # the compiled schemas name objects: Fast Downward wants them as constants
    domain = replace(domain, constants=(*domain.constants, *(o for o in problem.objects if o[0] in named)))
    problem = replace(problem, domain=domain, goal=goal, objects=tuple(o for o in problem.objects if o[0] not in named))
    domain_text = re.sub(r"(\(:requirements[^)]*?) :constraints\)", r"\1)", domain.to_pddl(), count=1)
    return domain_text, problem.to_pddl()


def _solve_up(
    domain: Domain, problem: Problem, planner: str, compilation: Compilation | None, limits: Limits
) -> tuple[PlanResult, PlanningTimes]:
    """Through unified-planning's model and compilers (any installed planner; the ground compilation).
    A Fast Downward planner (:data:`FAST_DOWNWARD`) is then run by vslsp on the compiled problem as
    unified-planning writes it; another installed planner is run as unified-planning runs it (bounded
    in wall-clock time, not in memory)."""
    from unified_planning.engines import CompilationKind

    engine_name, params = PLANNERS.get(planner, (planner, {}))
    engine = environment().factory.engine(engine_name)  # the class: what it supports, no instance
    start = time.perf_counter()
    conditional = engine.supported_kind().has_conditional_effects()
    used = (
        Compilation.NONE
        if not problem.constraints
        else compilation or (Compilation.LIFTED if conditional else Compilation.GROUND)
    )
    map_backs = []
    with phase("grounding", f"problem {problem.name}"):
        if used is Compilation.LIFTED:
            compiled_domain, compiled_problem = compile_lifted(domain, problem)
            up_problem = to_up(compiled_domain, compiled_problem, expand=True)
        else:
            up_problem = to_up(domain, problem, expand=True)
    built = time.perf_counter()
    if used is Compilation.GROUND:
        up_problem, back = _ground_compilation(up_problem, problem)
        map_backs.append(back)
    kind = up_problem.kind  # computed afresh on each access: once is enough
    if not engine.supports(kind) and kind.has_conditional_effects():
        from unified_planning.shortcuts import Compiler

        with Compiler(problem_kind=kind, compilation_kind=CompilationKind.CONDITIONAL_EFFECTS_REMOVING) as remover:
            result = remover.compile(up_problem, CompilationKind.CONDITIONAL_EFFECTS_REMOVING)
        up_problem = result.problem
        map_backs.append(result.map_back_action_instance)
        kind = up_problem.kind
    if not engine.supports(kind):
        raise InputError(f"planner {planner} cannot solve this problem (it needs: {kind}); try {DEFAULT_PLANNER}")
    if _false_goal(up_problem):
        raise Unsolvable(f"the goal {problem.goal.to_pddl()} can never hold{_under(problem)}")
    compiled_at = time.perf_counter()
    if planner in FAST_DOWNWARD:
        instances = _fast_downward_on_up(up_problem, problem, planner, FAST_DOWNWARD[planner], limits)
    else:
        instances = _oneshot(up_problem, problem, planner, engine_name, params, limits)
    solved = time.perf_counter()
    steps = []
    for instance in instances:
        for map_back in reversed(map_backs):
            instance = map_back(instance)
        args = tuple(str(p.object().name).lower() for p in instance.actual_parameters)
        steps.append((instance.action.name.lower(), args))
    times = PlanningTimes(built - start, compiled_at - built, solved - compiled_at)
    return PlanResult(tuple(steps), planner, solved - start, used), times


def _fast_downward_on_up(
    up_problem: Any, problem: Problem, planner: str, options: list[str], limits: Limits
) -> list[Any]:
    """Fast Downward's driver run by vslsp on a unified-planning problem, written as its engine writes
    it (unified-planning's PDDLWriter, requirements included); the plan read back through the writer's
    names. A problem the writer cannot write (e.g. a constant ``true`` left by a compilation) is no plan."""
    from unified_planning.exceptions import UPException
    from unified_planning.io import PDDLReader, PDDLWriter

    if planner in GOAL_ACTION:
        from up_fast_downward.utils import introduce_artificial_goal_action

        up_problem = introduce_artificial_goal_action(up_problem)[0]
    writer = PDDLWriter(up_problem, needs_requirements=True, rewrite_bool_assignments=False)
    try:
        domain_text, problem_text = writer.get_domain(), writer.get_problem()
    except UPException as error:
        raise NoPlan(f"{planner} failed: {error}", PlanStatus.INTERNAL_ERROR) from None
    run = run_fast_downward(domain_text, problem_text, options, limits.timeout, memory_mb=limits.memory_mb)
    _raise_unless_solved(run, problem, limits)
    steps = run.steps[:-1] if planner in GOAL_ACTION else run.steps
    plan_text = "".join(f"({' '.join((name, *args))})\n" for name, args in steps)
    return list(PDDLReader(environment()).parse_plan_string(up_problem, plan_text, writer.get_item_named).actions)


def _oneshot(
    up_problem: Any, problem: Problem, planner: str, engine_name: str, params: dict, limits: Limits
) -> list[Any]:
    """Another installed unified-planning oneshot planner, run as unified-planning runs it."""
    from unified_planning.exceptions import UPException
    from unified_planning.shortcuts import OneshotPlanner

    with OneshotPlanner(name=engine_name, params=params) as engine:
        engine.skip_checks = True  # supports() was just checked; UP would compute the kind again
        try:
            result = engine.solve(up_problem, timeout=limits.timeout)
        except UPException as error:
            raise NoPlan(f"{planner} failed: {error}", PlanStatus.INTERNAL_ERROR) from None
    status = plan_status(result.status)
    if status.limit_reached:
        raise limits.reached(status)
    if status is PlanStatus.UNSOLVABLE_PROVEN:
        raise Unsolvable(_reason(result, problem))
    if status is not PlanStatus.SOLVED:
        raise NoPlan(_reason(result, problem), status)
    return list(result.plan.actions)


def _false_goal(up_problem: Any) -> bool:
    """Whether the goal simplifies to false (a compiled constraint that can never be kept)."""
    return bool(environment().expression_manager.And(up_problem.goals).simplify().is_false())


def _ground_compilation(up_problem: Any, problem: Problem) -> tuple[Any, Any]:
    """unified-planning's TrajectoryConstraintsRemover (it grounds the problem in Python first)."""
    from unified_planning.engines import CompilationKind
    from unified_planning.engines.compilers.trajectory_constraints_remover import TrajectoryConstraintsRemover
    from unified_planning.exceptions import UPProblemDefinitionError

    try:
        compiled = TrajectoryConstraintsRemover().compile(up_problem, CompilationKind.TRAJECTORY_CONSTRAINTS_REMOVING)
    except UPProblemDefinitionError as error:
        raise Unsolvable(str(error).replace("PROBLEM NOT SOLVABLE: ", "")) from None
    except Exception as error:  # unified-planning 1.3.0's grounder: "list.remove(x)" on some static preconditions
        error.vslsp_stage = "the ground constraint compilation (unified-planning's grounder)"  # type: ignore[attr-defined]
        raise
    return compiled.problem, compiled.map_back_action_instance


def plan_status(status: Any) -> PlanStatus:
    """The :class:`PlanStatus` of a unified-planning ``PlanGenerationResultStatus`` (both kinds of
    solved are SOLVED; an intermediate or unknown status is INTERNAL_ERROR)."""
    if status.name in ("SOLVED_SATISFICING", "SOLVED_OPTIMALLY"):
        return PlanStatus.SOLVED
    return PlanStatus.__members__.get(status.name, PlanStatus.INTERNAL_ERROR)


def _under(problem: Problem) -> str:
    """The words ' under the constraints' when the problem has any (for a message about its goal)."""
    return " under the constraints" if problem.constraints else ""


def _reason(result: Any, problem: Problem) -> str:
    from unified_planning.engines import PlanGenerationResultStatus as Status

    reasons = {
        Status.UNSOLVABLE_PROVEN: f"the goal cannot be reached from the initial state{_under(problem)} "
        f"(proved by {result.engine_name})",
        Status.UNSOLVABLE_INCOMPLETELY: f"{result.engine_name} explored every reachable state and found none "
        f"that reaches the goal{_under(problem)}",
        Status.UNSUPPORTED_PROBLEM: "the planner does not support this problem",
    }
    return reasons.get(result.status, f"the planner stopped with status {result.status.name}")


def _oneshot_planners(env: Any) -> list[str]:
    from unified_planning.engines.mixins import OneshotPlannerMixin

    names = []
    for name in env.factory.engines:
        try:
            if issubclass(env.factory.engine(name), OneshotPlannerMixin):
                names.append(name)
        except Exception:  # an engine whose package is broken is simply not offered
            continue
    return names
