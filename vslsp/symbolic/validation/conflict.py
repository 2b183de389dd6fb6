"""Why a problem has no plan: a minimal set of goal conjuncts and constraints that conflict.

Paper: "Implementation" (a problem's goal with the demonstrated order as PDDL 3.0
constraints, planned by Fast Downward). When the planner proves that no plan exists, the
user needs to know which parts of the problem cannot all be kept. A *part* is one trajectory
constraint or one conjunct of the goal. Dropping a part only relaxes the problem (fewer
states to reach, fewer trajectories ruled out), so solvability is monotone and a smallest
conflict can be found by deletion: try the problem without some parts; if it is still
unsolvable those parts are not needed, else they stay. Deletion runs in chunks that halve
(whole halves first, as in QuickXplain, then single parts), every test a real planner call
through :func:`vslsp.symbolic.engines.planner.solve`; the last round, one part at a time, is what
proves the set minimal (removing any one part makes the rest solvable).

The search is bounded by ``budget_s`` seconds of wall-clock time in all. When the bound (or a
planner that gives up without a proof) cuts it short, the set returned still has no plan but
is not proven minimal: :attr:`Conflict.minimal` says which. A set with no constraint in it
means the initial state and the actions alone cannot reach those goal conjuncts.
Preferences are soft (the reader drops them): they never take part in a conflict.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

from vslsp.errors import TaskFailed
from vslsp.symbolic.engines.outcomes import Unsolvable
from vslsp.symbolic.engines.planner import DEFAULT_MEMORY_MB, DEFAULT_PLANNER, solve
from vslsp.symbolic.io.locate import as_written
from vslsp.symbolic.model.domain import Domain, Problem
from vslsp.symbolic.model.formula import Constraint, Formula, conjunction
from vslsp.symbolic.validation.validate import conjuncts

#: The default bound on the whole search (seconds): a few dozen planner calls on problems of
#: the shipped size (each about 0.3-0.5 s).
DEFAULT_BUDGET_S = 30.0
#: No planner call is started with less time than this left.
_LEAST_CHECK_S = 0.2


@dataclass(frozen=True)
class Part:
    """One goal conjunct (``kind == "goal"``) or trajectory constraint (``"constraint"``) of a problem;
    ``index`` is its place among :func:`goal_conjuncts` or ``problem.constraints``."""

    kind: str
    index: int
    formula: Formula | Constraint

    def to_pddl(self) -> str:
        return self.formula.to_pddl()


@dataclass(frozen=True)
class Conflict:
    """Parts of a problem that together have no plan (goal conjuncts first, then constraints).

    ``minimal``: proven irreducible (removing any one part leaves a solvable problem); False
    when the time bound or an inconclusive planner run stopped the search first.
    ``checks``: the planner calls made; ``time_s``: the time the search took.
    """

    parts: tuple[Part, ...]
    minimal: bool
    checks: int
    time_s: float

    @property
    def without_constraints(self) -> bool:
        """No constraint takes part: the initial state and the actions alone cannot reach these goal conjuncts."""
        return all(part.kind == "goal" for part in self.parts)

    def summary(self) -> str:
        """One sentence on what the set means."""
        proven = (
            "a minimal conflict" if self.minimal else "a conflicting set, not proven minimal (the search was cut short)"
        )
        if not self.parts:
            return f"{proven}: the initial state itself admits no plan"
        if self.without_constraints:
            return (
                f"{proven}: no constraint is involved; the initial state and the domain's actions alone cannot reach "
                f"{'this goal conjunct' if len(self.parts) == 1 else 'these goal conjuncts together'}"
            )
        if len(self.parts) == 1:
            return f"{proven}: this constraint alone can never be kept from the initial state"
        makes = "makes" if self.minimal else "may make"
        return f"{proven}: these cannot all hold together; removing any one {makes} the rest solvable"

    def reasons(self, domain: Domain, problem: Problem) -> list[str]:
        """Why the goal conjuncts of a conflict without constraints cannot be reached, one line per
        goal atom that not even the delete relaxation reaches (the actions that would add it and the
        precondition that never holds: :mod:`vslsp.symbolic.validation.reachability`); a line saying that the
        actions' deletes are the cause when the relaxation reaches them all; [] with constraints
        involved, or when the problem is too large to ground."""
        from vslsp.symbolic.validation.reachability import relaxed_reach, why_never

        if not self.parts or not self.without_constraints:
            return []
        reach = relaxed_reach(domain, problem)
        if reach is None:
            return []
        lines = [line for part in self.parts for line in why_never(part.formula, domain, problem, reach)]  # type: ignore[arg-type]
        if lines:
            return lines
        return [
            "each of these goal atoms can be made true on its own, but no sequence of actions makes them hold together "
            "(an action needed for one undoes another)"
        ]

    def located(self, problem_text: str, problem_name: str) -> list[dict]:
        """The parts as ``vslsp plan --json`` lists them under ``"conflict"``: ``{"kind", "text",
        "instance", "file", "line", "column"}``, found in the problem file's text (``text`` as written
        there, whitespace normalised), in the order of the file."""
        items = [as_written(part.kind, part.to_pddl(), problem_text, problem_name) for part in self.parts]
        return sorted(items, key=lambda item: (item["line"] is None, item["line"] or 0, item["column"] or 0))

    def to_dict(self) -> dict:
        return {
            "parts": [{"kind": p.kind, "index": p.index, "text": p.to_pddl()} for p in self.parts],
            "minimal": self.minimal,
            "checks": self.checks,
            "time_s": self.time_s,
        }


def goal_conjuncts(problem: Problem) -> tuple[Formula, ...]:
    """The conjuncts of the problem's goal (none for the empty goal ``(and)``)."""
    return conjuncts(problem.goal)


def explain(
    domain: Domain,
    problem: Problem,
    planner: str = DEFAULT_PLANNER,
    budget_s: float = DEFAULT_BUDGET_S,
    known_unsolvable: bool = False,
    memory_mb: int | None = DEFAULT_MEMORY_MB,
) -> Conflict | None:
    """A minimal conflict of ``problem``'s goal conjuncts and constraints, or None when it has a plan.

    ``known_unsolvable``: the caller's planner run has just proved the whole problem unsolvable (one
    planner call saved); ``memory_mb``: each planner call's memory limit. Raises TaskFailed when the
    planner cannot tell within ``budget_s`` whether the whole problem is solvable; a failure inside
    the planner propagates as from :func:`solve`.
    """
    start = time.perf_counter()
    deadline = start + budget_s
    parts = [Part("constraint", i, c) for i, c in enumerate(problem.constraints)]
    parts += [Part("goal", i, g) for i, g in enumerate(goal_conjuncts(problem))]
    checks = 0
    decided = True  # every test so far gave a proof either way

    def unsolvable(kept: list[Part]) -> bool | None:
        """True: proved to have no plan; False: a plan; None: not known (out of time, or no proof)."""
        nonlocal checks, decided
        left = deadline - time.perf_counter()
        if left < _LEAST_CHECK_S:
            decided = False
            return None
        checks += 1
        try:
            solve(domain, _restricted(problem, kept), planner=planner, timeout=left, memory_mb=memory_mb)
        except Unsolvable:
            return True
        except TaskFailed:
            decided = False
            return None
        return False

    if not known_unsolvable:
        verdict = unsolvable(parts)
        if verdict is False:
            return None
        if verdict is None:
            raise TaskFailed(
                f"cannot explain: the planner did not prove the problem unsolvable within {budget_s:g} s "
                "(give more time)",
                cause="cannot explain",
            )
    kept = _deleted(parts, unsolvable)
    ordered = sorted(kept, key=lambda p: (p.kind != "goal", p.index))
    return Conflict(tuple(ordered), decided, checks, time.perf_counter() - start)


def _deleted(parts: list[Part], unsolvable) -> list[Part]:
    """Deletion in halving chunks; ``parts`` is known unsolvable and so is every set this keeps."""
    kept = list(parts)
    constraints = [p for p in kept if p.kind == "constraint"]
    if constraints and len(constraints) < len(kept):  # unsolvable without any constraint: the goal alone
        goals = [p for p in kept if p.kind == "goal"]
        if unsolvable(goals):
            kept = goals
    chunk = max(1, len(kept) // 2)
    while True:
        i = 0
        while i < len(kept):
            candidate = kept[:i] + kept[i + chunk :]
            if unsolvable(candidate):
                kept = candidate
            else:
                i += chunk
        if chunk == 1:
            return kept
        chunk = max(1, chunk // 2)


def _restricted(problem: Problem, kept: list[Part]) -> Problem:
    """``problem`` with only the ``kept`` constraints and goal conjuncts."""
    goal = conjunction(p.formula for p in kept if p.kind == "goal")  # type: ignore[misc]
    constraints = tuple(p.formula for p in kept if p.kind == "constraint")
    return replace(problem, goal=goal, constraints=constraints)  # type: ignore[arg-type]
