"""Checking a plan of a numeric or temporal problem (:mod:`vslsp.symbolic.engines.pddl21`).

The plan file is read line by line, so that each step keeps its place: ``(action arg ...)``,
``N: (action arg ...)`` as VAL writes a sequential plan, ``T: (action arg ...) [D]`` for a
temporal one (start time ``T``, duration ``D``), each also after ``N. `` as ``vslsp plan`` prints
it, ``;`` comments. unified-planning's validators
give the verdict (the sequential plan validator; the time-triggered one for temporal plans,
which checks the ``?duration`` constraints, the ``at start``/``over all``/``at end`` conditions
and mutually exclusive effects); a goal that does not hold is told conjunct by conjunct, each with
its FILE:LINE:COL in the problem.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from vslsp.errors import InputError
from vslsp.symbolic.engines.pddl21 import Read, TimedStep
from vslsp.symbolic.model.up_model import environment

_STEP = re.compile(
    r"^\s*(?:\d+\.\s+)?(?:(?P<start>\d+(?:\.\d+)?)\s*:\s*)?\(\s*(?P<atom>[^()]*?)\s*\)\s*(?:\[\s*(?P<duration>\d+(?:\.\d+)?)\s*\])?\s*$"
)
_PRINTED = re.compile(r"^\s*\d+\.\s+(?P<atom>[^()]+?)\s*$")  # "1. drive r a b", as vslsp plan prints it
#: At most this many goal conjuncts are checked one by one (each is one more validation).
MAX_GOALS_TOLD = 50


@dataclass(frozen=True)
class WrittenStep:
    """A step of the plan file with its 1-based ``line`` and ``column``."""

    step: TimedStep
    line: int
    column: int


@dataclass(frozen=True)
class Verdict:
    """Whether the plan is valid; ``violations`` as dicts with ``kind``, ``text``, ``step``, ``time``,
    ``file``, ``line``, ``column`` and ``message`` (the shape of ``vslsp validate --json``)."""

    valid: bool
    reason: str
    violations: list[dict] = field(default_factory=list)
    metric: float | None = None

    def to_dict(self) -> dict:
        return {"valid": self.valid, "reason": self.reason, "violations": self.violations, "metric": self.metric}


def read_plan(text: str, name: str, temporal: bool) -> list[WrittenStep]:
    """The steps of a plan file; InputError ``NAME:LINE:COL`` at a line that is not a step."""
    steps = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split(";", 1)[0]
        if not line.strip():
            continue
        match = _STEP.match(line) or _PRINTED.match(line)
        column = len(line) - len(line.lstrip()) + 1
        if match is None or not match.group("atom").strip():
            raise InputError(
                f"{name}:{number}:{column}: expected a step such as (action arg ...) or T: (action ...) [D]"
            )
        words = tuple(match.group("atom").lower().split())
        groups = match.groupdict()
        start = float(groups["start"]) if temporal and groups.get("start") else None
        if temporal and start is None:
            raise InputError(
                f"{name}:{number}:{column}: a temporal plan's step starts with its time: T: (action ...) [D]"
            )
        duration = float(groups["duration"]) if groups.get("duration") else None
        steps.append(WrittenStep(TimedStep(words[0], words[1:], start, duration), number, column))
    return steps


def validate(problem: Read, steps: list[WrittenStep], plan_name: str, problem_name: str) -> Verdict:
    """Check ``steps`` against ``problem``: every violation with its step (and time) and place."""
    up_plan = _up_plan(problem, steps, plan_name)
    result = _validated(problem.problem, up_plan)
    metric = _metric(result)
    if result.status.name == "VALID":
        return Verdict(True, "the plan reaches the goal", metric=metric)
    reason = result.reason.name if result.reason is not None else "INVALID"
    messages = [m.message for m in (result.log_messages or [])]
    if reason == "UNSATISFIED_GOALS":
        violations = _false_goals(problem, up_plan, problem_name)
        return Verdict(False, f"{len(violations)} goal conjunct(s) do not hold at the end", violations, metric)
    index = _failed_step(result, messages, steps)
    written = steps[index] if index is not None else None
    message = "; ".join(messages) or (
        f"its conditions or its ?duration constraint do not hold (at time {written.step.start:g})"
        if written is not None and written.step.start is not None
        else f"the plan is invalid ({reason.lower().replace('_', ' ')})"
    )
    violation = {
        "kind": "step",
        "text": written.step.to_pddl() if written else "",
        "step": index + 1 if index is not None else None,
        "time": written.step.start if written else None,
        "file": plan_name,
        "line": written.line if written else None,
        "column": written.column if written else None,
        "message": message,
    }
    what = f"step {index + 1} cannot be applied" if index is not None else "the plan is invalid"
    return Verdict(False, what, [violation], metric)


def _up_plan(problem: Read, steps: list[WrittenStep], name: str) -> Any:
    from unified_planning.plans import ActionInstance, SequentialPlan, TimeTriggeredPlan

    up_problem = problem.problem
    actions = {a.name.lower(): a for a in up_problem.actions}
    objects = {o.name.lower(): o for o in up_problem.all_objects}
    instances = []
    for written in steps:
        step = written.step
        action = actions.get(step.action)
        where = f"{name}:{written.line}:{written.column}"
        if action is None:
            raise InputError(f"{where}: no action '{step.action}' in the domain; actions: {', '.join(sorted(actions))}")
        if len(step.args) != len(action.parameters):
            raise InputError(f"{where}: {step.action} takes {len(action.parameters)} arguments, given {len(step.args)}")
        unknown = next((a for a in step.args if a not in objects), None)
        if unknown is not None:
            raise InputError(f"{where}: no object '{unknown}' in the problem")
        instances.append(ActionInstance(action, tuple(objects[a] for a in step.args)))
    if not problem.temporal:
        return SequentialPlan(instances, environment())
    timed = []
    for written, instance in zip(steps, instances):
        duration = Fraction(str(written.step.duration)) if written.step.duration is not None else None
        timed.append((Fraction(str(written.step.start)), instance, duration))
    return TimeTriggeredPlan(timed, environment())


def _validated(up_problem: Any, up_plan: Any) -> Any:
    """unified-planning's validator for the plan's kind (checks skipped: an undefined numeric
    initial value is an error it reports itself when the plan reads it)."""
    from unified_planning.shortcuts import PlanValidator

    name = (
        "up_time_triggered_validator" if type(up_plan).__name__ == "TimeTriggeredPlan" else "sequential_plan_validator"
    )
    with PlanValidator(name=name) as validator:
        validator.skip_checks = True
        return validator.validate(up_problem, up_plan)


def _metric(result: Any) -> float | None:
    values = list((result.metric_evaluations or {}).values())
    return float(values[0]) if values else None


def _failed_step(result: Any, messages: list[str], steps: list[WrittenStep]) -> int | None:
    """The 0-based index of the step that failed: the validator's "N-th action instance", or the first
    step that is its inapplicable action."""
    for message in messages:
        found = re.search(r"(\d+)-th action instance", message)
        if found:
            return int(found.group(1)) - 1
    failed = result.inapplicable_action
    if failed is None:
        return None
    name = failed.action.name.lower()
    args = tuple(str(p).lower() for p in failed.actual_parameters)
    return next((i for i, s in enumerate(steps) if (s.step.action, s.step.args) == (name, args)), None)


def _false_goals(problem: Read, up_plan: Any, problem_name: str) -> list[dict]:
    """Each goal conjunct that does not hold at the end, placed in the problem file."""
    conjuncts: list[Any] = []
    for goal in problem.problem.goals:
        conjuncts.extend(goal.args if goal.is_and() else [goal])
    violations = []
    for conjunct in conjuncts[:MAX_GOALS_TOLD]:
        single = problem.problem.clone()
        single.clear_goals()
        single.add_goal(conjunct)
        if _validated(single, up_plan).status.name == "VALID":
            continue
        line, column = _place_of(conjunct, problem.problem_text)
        violations.append(
            {
                "kind": "goal",
                "text": str(conjunct),
                "step": None,
                "time": None,
                "file": problem_name,
                "line": line,
                "column": column,
                "message": f"goal {conjunct} does not hold at the end of the plan",
            }
        )
    return violations


def _place_of(conjunct: Any, text: str) -> tuple[int | None, int | None]:
    """Where the conjunct is written in the goal (an atom found by its words), else the ``(:goal``."""
    goal = re.search(r"\(\s*:goal\b", text, re.IGNORECASE)
    offset = goal.start() if goal else 0
    words: list[str] = []
    if conjunct.is_fluent_exp():
        words = [conjunct.fluent().name, *(str(a) for a in conjunct.args)]
    elif conjunct.is_not() and conjunct.arg(0).is_fluent_exp():
        inner = conjunct.arg(0)
        words = [inner.fluent().name, *(str(a) for a in inner.args)]
    found = None
    if words:
        pattern = r"\(\s*" + r"\s+".join(re.escape(w) for w in words) + r"\s*\)"
        found = re.compile(pattern, re.IGNORECASE).search(text, offset)
    index = found.start() if found else (goal.start() if goal else None)
    if index is None:
        return None, None
    return text.count("\n", 0, index) + 1, index - text.rfind("\n", 0, index)
