"""Planning through unified-planning: trajectory constraints compiled away, then Fast Downward.

Paper: "Implementation" and the iCub experiments (VSL-SP hands the learned domain and the
problem, with its PDDL 3.0 ordering constraints, to an off-the-shelf planner). Fast Downward
has no trajectory constraints, so unified-planning's TrajectoryConstraintsRemover (shipped,
not registered in 1.3.0's factory) compiles them into monitoring atoms on a grounded
problem first; the plan is mapped back to the lifted actions.
"""

from __future__ import annotations

import os
import tempfile
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass

from vslsp.errors import InputError, TaskFailed
from vslsp.symbolic.model import Domain, Problem

DEFAULT_PLANNER = "fast-downward"
#: vslsp's planner names that are a unified-planning engine with set parameters; any other
#: name is a unified-planning oneshot planner as installed (e.g. fast-downward-opt: A* + LM-cut).
#: The default is greedy best-first search with the FF heuristic and preferred operators:
#: LAMA's landmark preprocessing dominates on the long chains of a demonstrated order
#: (about 5x slower at 200 blocks, see benchmarks/bench_planning.py).
PLANNERS: dict[str, tuple[str, dict]] = {
    "fast-downward": ("fast-downward", {"fast_downward_search_config":
                                        "let(hff,ff(),lazy_greedy([hff],preferred=[hff]))"}),
    "fast-downward-lama": ("fast-downward", {"fast_downward_alias": "lama-first"}),
}


@dataclass(frozen=True)
class PlanResult:
    """A plan: ``steps`` are ``(action, (arg, ...))`` in lower case, e.g. ``("pull", ("orange",))``."""

    steps: tuple[tuple[str, tuple[str, ...]], ...]
    planner: str
    time_s: float

    def lines(self) -> list[str]:
        """``["pull orange", ...]``: one string per step, as in ``vslsp plan --json``."""
        return [" ".join((name, *args)) for name, args in self.steps]

    def to_pddl(self) -> str:
        """One ``(action arg ...)`` per line: the PLAN file of ``vslsp validate``."""
        return "".join(f"({line})\n" for line in self.lines())

    def to_dict(self) -> dict:
        return {"plan": self.lines(), "planner": self.planner, "time_s": self.time_s}

    @classmethod
    def from_dict(cls, data: dict) -> "PlanResult":
        steps = tuple((line.split()[0], tuple(line.split()[1:])) for line in data["plan"])
        return cls(steps, data["planner"], float(data["time_s"]))


@dataclass(frozen=True)
class PlanningTimes:
    """Where the time went: building the UP problem, compiling constraints away, searching."""

    build_s: float
    compile_s: float
    solve_s: float


def solve(domain: Domain, problem: Problem, planner: str = DEFAULT_PLANNER) -> PlanResult:
    """Plan for ``problem`` in ``domain`` with a unified-planning oneshot planner.

    Raises TaskFailed("no plan: ...") when the planner proves or reports no plan, InputError
    for an unknown planner or one that cannot take the problem.
    """
    return solve_timed(domain, problem, planner)[0]


def solve_timed(domain: Domain, problem: Problem, planner: str = DEFAULT_PLANNER) -> tuple[PlanResult, PlanningTimes]:
    """:func:`solve`, with the time of each phase."""
    from unified_planning.engines import CompilationKind, PlanGenerationResultStatus
    from unified_planning.engines.compilers.trajectory_constraints_remover import TrajectoryConstraintsRemover
    from unified_planning.exceptions import UPException, UPProblemDefinitionError
    from unified_planning.shortcuts import Compiler, OneshotPlanner

    from vslsp.symbolic.pddl import environment, to_up
    from vslsp.symbolic.validate import initially_broken

    env = environment()
    available = list(PLANNERS) + [name for name in _oneshot_planners(env) if name not in PLANNERS]
    if planner not in available:
        raise InputError(f"unknown planner {planner!r}; installed: {', '.join(available)}")
    engine_name, params = PLANNERS.get(planner, (planner, {}))
    if problem.domain.name != domain.name:
        raise InputError(f"problem {problem.name} is for domain {problem.domain.name}, not {domain.name}")
    broken = initially_broken(problem)
    if broken:
        raise TaskFailed(f"no plan: {broken}")

    start = time.perf_counter()
    up_problem = to_up(domain, problem, expand=True)
    built = time.perf_counter()
    map_backs = []
    if up_problem.trajectory_constraints:
        try:
            compiled = TrajectoryConstraintsRemover().compile(up_problem, CompilationKind.TRAJECTORY_CONSTRAINTS_REMOVING)
        except UPProblemDefinitionError as error:
            raise TaskFailed(f"no plan: {str(error).replace('PROBLEM NOT SOLVABLE: ', '')}") from None
        up_problem = compiled.problem
        map_backs.append(compiled.map_back_action_instance)
    if env.expression_manager.And(up_problem.goals).simplify().is_false():
        raise TaskFailed(f"no plan: the goal {problem.goal.to_pddl()} can never hold under the constraints")
    with OneshotPlanner(name=engine_name, params=params) as engine:
        kind = up_problem.kind  # computed afresh on each access: once is enough
        if not engine.supports(kind) and kind.has_conditional_effects():
            # Optimal Fast Downward (LM-cut) has no conditional effects; the constraint monitors have some.
            with Compiler(problem_kind=kind, compilation_kind=CompilationKind.CONDITIONAL_EFFECTS_REMOVING) as remover:
                compiled = remover.compile(up_problem, CompilationKind.CONDITIONAL_EFFECTS_REMOVING)
            up_problem = compiled.problem
            map_backs.append(compiled.map_back_action_instance)
            kind = up_problem.kind
        if not engine.supports(kind):
            raise InputError(f"planner {planner} cannot solve this problem (it needs: {kind}); "
                             f"try {DEFAULT_PLANNER}")
        engine.skip_checks = True  # supports() was just checked; UP would compute the kind again
        compiled_at = time.perf_counter()
        try:
            with _private_directory():
                result = engine.solve(up_problem)
        except UPException as error:
            raise TaskFailed(f"no plan: {planner} failed: {error}") from None
    solved = time.perf_counter()
    if result.status not in (PlanGenerationResultStatus.SOLVED_SATISFICING, PlanGenerationResultStatus.SOLVED_OPTIMALLY):
        raise TaskFailed(f"no plan: {_reason(result)}")
    steps = []
    for instance in result.plan.actions:
        for map_back in reversed(map_backs):
            instance = map_back(instance)
        steps.append((instance.action.name.lower(), tuple(str(p.object().name).lower() for p in instance.actual_parameters)))
    times = PlanningTimes(built - start, compiled_at - built, solved - compiled_at)
    return PlanResult(tuple(steps), planner, solved - start), times


_CWD_LOCK = threading.Lock()  # the working directory is the process's: one planner at a time per process


@contextmanager
def _private_directory():
    """Run in a fresh working directory: Fast Downward's driver writes ``output.sas`` into the
    current one, so two planners started from the same folder (test workers, experiment
    workers) would read and delete each other's file. Threads of one process take turns."""
    with _CWD_LOCK, tempfile.TemporaryDirectory(prefix="vslsp-plan-") as folder:
        previous = os.getcwd()
        os.chdir(folder)
        try:
            yield
        finally:
            os.chdir(previous)


def _reason(result) -> str:
    from unified_planning.engines import PlanGenerationResultStatus as Status

    reasons = {
        Status.UNSOLVABLE_PROVEN: "the goal cannot be reached from the initial state under the constraints "
                                  f"(proved by {result.engine_name})",
        Status.UNSOLVABLE_INCOMPLETELY: f"{result.engine_name} explored every reachable state and found none "
                                        "that reaches the goal under the constraints",
        Status.TIMEOUT: "the planner ran out of time",
        Status.MEMOUT: "the planner ran out of memory",
        Status.UNSUPPORTED_PROBLEM: "the planner does not support this problem",
    }
    return reasons.get(result.status, f"the planner stopped with status {result.status.name}")


def _oneshot_planners(env) -> list[str]:
    from unified_planning.engines.mixins import OneshotPlannerMixin

    names = []
    for name in env.factory.engines:
        try:
            if issubclass(env.factory.engine(name), OneshotPlannerMixin):
                names.append(name)
        except Exception:  # an engine whose package is broken is simply not offered
            continue
    return names
