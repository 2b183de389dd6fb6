"""Plan validation with PDDL 3.0 trajectory constraints, by simulating the plan.

Paper: "Implementation" (the demonstrated order as a constraint the plan must keep).
unified-planning's validator refuses problems with trajectory constraints, so this module
simulates the plan over the state trajectory s_0 .. s_n (s_0 the initial state, s_k the
state after step k), checks every precondition, the goal in s_n, and each constraint with
its PDDL 3.0 semantics:

- ``(always φ)``: φ in every s_i; ``(sometime φ)``: φ in some s_i; ``(at end φ)``: φ in s_n;
- ``(at-most-once φ)``: φ holds over at most one contiguous stretch of states;
- ``(sometime-before p q)``: every s_i with p has some s_j, j < i, with q;
- ``(sometime-after p q)``: every s_i with p has some s_j, j >= i, with q.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import cast

from vslsp.errors import InputError
from vslsp.files import read_text, shown
from vslsp.symbolic.budget import phase
from vslsp.symbolic.io.locate import as_written
from vslsp.symbolic.model.domain import Domain, Problem, ground_effects
from vslsp.symbolic.model.formula import (
    Always,
    And,
    AtMostOnce,
    Formula,
    SometimeBefore,
    Universe,
    conjunction,
    holds,
    substitute,
)
from vslsp.symbolic.validation.monitors import ConstraintMonitor

PlanStep = tuple[str, tuple[str, ...]]
PlanLike = Iterable[PlanStep | str]


@dataclass(frozen=True)
class Violation:
    """One way a plan fails: a step that cannot be applied (``kind == "precondition"``, ``text`` its false
    preconditions), a goal conjunct false at the end (``"goal"``), a broken constraint (``"constraint"``).

    ``step``: for a precondition the step that cannot be applied (1-based); otherwise the state where
    it broke, ``k`` meaning after step ``k`` (0: the initial state; the last step for the goal).
    """

    kind: str
    text: str
    step: int
    message: str

    def to_dict(self) -> dict:
        return {"kind": self.kind, "text": self.text, "step": self.step, "message": self.message}

    @classmethod
    def from_dict(cls, data: dict) -> Violation:
        return cls(str(data["kind"]), str(data["text"]), int(data["step"]), str(data["message"]))


@dataclass(frozen=True)
class Validation:
    """The verdict on a plan and why: ``violations`` lists every failure (the first inapplicable step,
    then each false goal conjunct, then each broken constraint); ``reason`` is the first one's message."""

    valid: bool
    reason: str
    violations: tuple[Violation, ...] = ()

    def to_dict(self) -> dict:
        return {"valid": self.valid, "reason": self.reason, "violations": [v.to_dict() for v in self.violations]}

    @classmethod
    def from_dict(cls, data: dict) -> Validation:
        violations = tuple(Violation.from_dict(v) for v in data.get("violations", ()))
        return cls(bool(data["valid"]), str(data["reason"]), violations)

    def located(self, problem_text: str, problem_name: str, plan_text: str, plan_name: str) -> list[dict]:
        """The violations as ``vslsp validate --json`` lists them: ``{"kind", "text", "instance", "file",
        "line", "column", "step", "message"}``; a step found in the PLAN text, a goal conjunct or a
        constraint in the PROBLEM text (its text as written there; line and column None if not found)."""
        positions = step_positions(plan_text) if self.violations else []
        located = []
        for violation in self.violations:
            place: dict[str, object]
            if violation.kind == "precondition":
                line, column = positions[violation.step - 1] if violation.step <= len(positions) else (None, None)
                place = {"kind": "precondition", "text": violation.text, "instance": violation.text}
                place |= {"file": plan_name, "line": line, "column": column}
            else:
                place = as_written(violation.kind, violation.text, problem_text, problem_name)
            located.append({**place, "step": violation.step, "message": violation.message})
        return located


#: Constraints whose breaking a prefix of the trajectory already decides (the rest may still hold later).
_SAFETY = (Always, AtMostOnce, SometimeBefore)


def validate(domain: Domain, problem: Problem, plan_steps: PlanLike) -> Validation:
    """Simulate ``plan_steps`` (``("pull", ("green",))``, ``"pull green"`` or ``"(pull green)"``).

    Every violation is listed. At a step that cannot be applied the simulation stops: the goal
    and the constraints that only the rest of a trajectory could keep (sometime, at end,
    sometime-after) are then not judged; always, at-most-once and sometime-before are, on the
    states reached. The whole run is within the validating phase's budget
    (:func:`vslsp.symbolic.budget.phase`).
    """
    with phase("validating", f"the plan for problem {problem.name}"):
        return _validate(domain, problem, plan_steps)


def _validate(domain: Domain, problem: Problem, plan_steps: PlanLike) -> Validation:
    steps = [_as_step(step) for step in getattr(plan_steps, "steps", plan_steps)]
    universe = problem.universe()
    objects = dict(problem.all_objects())
    # One state, changed in place step by step; the constraints are judged as the states come
    # (vslsp.symbolic.validation.monitors), so no trajectory is kept: memory stays that of one state.
    state = set(problem.init)
    monitors = [ConstraintMonitor(constraint, universe) for constraint in problem.constraints]
    for monitor in monitors:
        monitor.observe(state)
    violations: list[Violation] = []
    for number, (name, args) in enumerate(steps, start=1):
        stuck = _inapplicable(domain, objects, universe, number, name, args, cast(frozenset, state))
        if stuck:
            violations.append(stuck)
            break
        added, deleted = ground_effects(domain.action(name), args, cast(frozenset, state), universe)
        state -= deleted
        state |= added
        for monitor in monitors:
            monitor.observe(state)
    finished = not violations
    if finished:
        for conjunct in conjuncts(problem.goal):
            if not holds(conjunct, cast(frozenset, state), universe):
                text = conjunct.to_pddl()
                violations.append(
                    Violation("goal", text, len(steps), f"the goal {text} does not hold after the last step")
                )

    def when(i: int) -> str:
        return "in the initial state" if i == 0 else f"after step {i} ({' '.join((steps[i - 1][0], *steps[i - 1][1]))})"

    for monitor in monitors:
        if not finished and not isinstance(monitor.constraint, _SAFETY):
            continue
        broken = monitor.verdict(when)
        if broken:
            at, why = broken
            text = monitor.constraint.to_pddl()
            violations.append(Violation("constraint", text, at, f"constraint {text} is broken: {why}"))
    if violations:
        return Validation(False, violations[0].message, tuple(violations))
    count = len(problem.constraints)
    kept = (" and keeps its constraint" if count == 1 else f" and keeps all {count} constraints") if count else ""
    return Validation(True, f"the plan reaches the goal in {plural(len(steps), 'step')}{kept}")


def _inapplicable(
    domain: Domain,
    objects: dict[str, str],
    universe: Universe,
    number: int,
    name: str,
    args: tuple[str, ...],
    state: frozenset,
) -> Violation | None:
    """Why step ``number`` cannot be applied in ``state`` (its false preconditions), or None."""
    written = "(" + " ".join((name, *args)) + ")"
    label = f"step {number} ({' '.join((name, *args))})"
    try:
        action = domain.action(name)
    except InputError as error:
        return Violation("precondition", written, number, f"{label}: {error}")
    wrong = _wrong_arguments(domain, action.parameters, args, objects)
    if wrong:
        return Violation("precondition", written, number, f"{label}: {wrong}")
    precondition = substitute(action.precondition, dict(zip((p for p, _ in action.parameters), args, strict=False)))
    if holds(precondition, state, universe):
        return None
    false = [part for part in conjuncts(precondition) if not holds(part, state, universe)]
    text = conjunction(false).to_pddl()
    if len(false) == 1:
        return Violation("precondition", text, number, f"{label}: precondition {text} does not hold")
    listed = ", ".join(part.to_pddl() for part in false)
    return Violation("precondition", text, number, f"{label}: preconditions {listed} do not hold")


def conjuncts(formula: Formula) -> tuple[Formula, ...]:
    """The parts of a conjunction, nested ``(and ...)`` opened (none for ``(and)``); any other formula alone."""
    if not isinstance(formula, And):
        return (formula,)
    return tuple(dict.fromkeys(part for arg in formula.args for part in conjuncts(arg)))


def plural(count: int, noun: str) -> str:
    """``1 step``, ``2 steps``."""
    return f"{count} {noun}{'' if count == 1 else 's'}"


def _wrong_arguments(domain: Domain, parameters, args: tuple[str, ...], types: dict[str, str]) -> str | None:
    if len(args) != len(parameters):
        return f"takes {len(parameters)} argument(s), {len(args)} given"
    for (parameter, type_), arg in zip(parameters, args, strict=False):
        if arg not in types:
            return f"{arg!r} is not an object of the problem"
        if types[arg] not in domain.subtypes(type_):
            return f"{arg!r} is a {types[arg]}, but {parameter} must be a {type_}"
    return None


def _as_step(step: PlanStep | str) -> PlanStep:
    if isinstance(step, str):
        words = step.strip().strip("()").lower().split()
        if not words:
            raise InputError(f"empty plan step {step!r}")
        return words[0], tuple(words[1:])
    name, args = step
    return name.lower(), tuple(a.lower() for a in args)


#: The largest plan file read (a plan of 10 000 steps has about 300 kB).
MAX_PLAN_BYTES = 1_000_000
#: ``(pull green)``; ``0: (pull green)`` and ``0.000: (pull green) [1]`` (VAL, IPC); ``1. pull green`` (vslsp plan).
_PLAN_LINE = re.compile(
    r"^\s*(?:\d+(?:\.\d+)?\s*:\s*)?\(\s*([\w-]+)((?:\s+[\w-]+)*)\s*\)\s*(?:\[[\d.]+\])?\s*$"
    r"|^\s*\d+\.\s+([\w-]+)((?:\s+[\w-]+)*)\s*$"
)


def parse_plan(text: str, domain: Domain, problem: Problem, name: str = "<plan>") -> list[PlanStep]:
    """Steps from a PLAN text, one step per line (``;`` comments, blank lines allowed): ``(pull green)``,
    as VAL and IPC planners write it (``0: (pull green)``), or as ``vslsp plan`` prints it (``1. pull green``).

    A line that is not a step, names an unknown action or object, or has the wrong number or
    types of arguments raises InputError ``NAME:LINE:COL: what``.
    """
    steps, types = [], dict(problem.all_objects())
    for number, line in enumerate(text.splitlines(), start=1):
        code = line.split(";", 1)[0]
        if not code.strip():
            continue
        match = _PLAN_LINE.match(code.lower())
        if not match:
            column = len(code) - len(code.lstrip()) + 1
            raise InputError(
                f"{name}:{number}:{column}: expected one step like (pull green) or 1. pull green, got {code.strip()!r}"
            )
        group = 1 if match.group(1) else 3
        action_name, args = match.group(group), tuple(match.group(group + 1).split())
        column = match.start(group) + 1
        try:
            action = domain.action(action_name)
        except InputError as error:
            raise InputError(f"{name}:{number}:{column}: {error}") from None
        wrong = _wrong_arguments(domain, action.parameters, args, types)
        if wrong:
            raise InputError(f"{name}:{number}:{column}: {action_name}: {wrong}")
        steps.append((action_name, args))
    return steps


def step_positions(text: str) -> list[tuple[int, int]]:
    """The 1-based line and column where each step of a PLAN text starts, in the order of :func:`parse_plan`."""
    positions = []
    for number, line in enumerate(text.splitlines(), start=1):
        code = line.split(";", 1)[0]
        if code.strip():
            positions.append((number, len(code) - len(code.lstrip()) + 1))
    return positions


def read_plan(path: str | Path, domain: Domain, problem: Problem) -> list[PlanStep]:
    """:func:`parse_plan` on a file (regular, UTF-8, at most :data:`MAX_PLAN_BYTES`, read within that bound)."""
    text = read_text(path, "plan", MAX_PLAN_BYTES)
    return parse_plan(text, domain, problem, shown(path))
