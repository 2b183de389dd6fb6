"""The author page's PDDL work: check (the language engine), plan, validate and the state timeline.

Check is :func:`vslsp.symbolic.language.analyse` on the editor's text, as ``vslsp pddl check --json``
reports it. Plan and validate read the text with :func:`vslsp.symbolic.parse_pddl` and answer as
``vslsp plan --json`` / ``vslsp validate --json``; errors are :class:`~vslsp.errors.VslspError` with the
CLI's message (file names are the page's paths). The timeline is the plan simulated over the states
s_0..s_n: the atoms true in each, and for each PDDL 3.0 constraint its formula's truth and whether it
is kept so far ("kept"), broken for good ("broken") or still open ("open"): paper, "Implementation".
"""

from __future__ import annotations

import importlib
import importlib.util
import warnings
from typing import Any

from vslsp.errors import InputError, TaskFailed, VslspError

#: How long a plan request may search (seconds): a page waits for it.
PLAN_TIMEOUT_S = 60.0


def check(domain: str, problem: str | None, domain_file: str = "<domain>", problem_file: str = "<problem>") -> dict:
    """``pddl check --json`` on the editor's text: ``diagnostics`` (each with ``fixes``), ``exit_code``,
    ``warnings``, ``error`` (with an error), ``hovers`` (``{file: [{line, column, end_column, text}]}``:
    the declaration of each name, for hover), ``names`` (kind -> names, for completion), ``signatures``
    (kind -> name -> its declaration, for completion's details) and ``outline`` (file -> the tree of its
    declarations, :func:`vslsp.studio.navigation.outline`)."""
    from vslsp.symbolic.language import analyse

    analysis = analyse(domain, domain_file, problem or None, problem_file)
    report: dict[str, Any] = {
        "diagnostics": [_diagnostic(d) for d in analysis.diagnostics],
        "exit_code": analysis.exit_code,
        "warnings": [d.format() for d in analysis.warnings],
    }
    if analysis.errors:
        count = len(analysis.errors)
        report["error"] = f"{count} error{'' if count == 1 else 's'}; the first: {analysis.errors[0].format()}"
    index = analysis.index
    report["names"] = {
        kind: sorted(index.names(kind)) for kind in ("type", "predicate", "action", "object", "constant")
    }
    hovers: dict[str, list[dict]] = {}
    for reference in index.references:
        declaration = reference.declaration
        if declaration is None or not declaration.signature:
            continue
        span = reference.span
        if span.end_line == span.line and span.end_column > span.column:
            hovers.setdefault(span.file, []).append(
                {"line": span.line, "column": span.column, "end_column": span.end_column, "text": declaration.signature}
            )
    report["hovers"] = hovers
    report["signatures"] = {
        kind: {d.name: d.signature for d in index.of_kind(kind) if d.signature}
        for kind in ("type", "predicate", "action", "object", "constant")
    }
    from vslsp.studio.navigation import outline

    report["outline"] = {file: outline(index.in_file(file)) for file in (domain_file, problem_file)}
    return report


def complete(
    domain: str,
    problem: str | None,
    editor: str,
    at: int,
    domain_file: str = "<domain>",
    problem_file: str = "<problem>",
) -> dict:
    """Completion at offset ``at`` of the ``editor`` ("domain" or "problem"), the names the language
    engine indexed in both texts: ``{"from": the offset where the name typed starts, "items": [...]}``
    (what ``POST /api/complete`` answers and the editors' Ctrl-Space shows)."""
    from vslsp.studio.editing import complete as complete_at

    checked = check(domain, problem, domain_file, problem_file)
    text = domain if editor == "domain" else problem or ""
    return complete_at(text, at, checked, editor == "problem")


def _diagnostic(diagnostic: Any) -> dict:
    data = dict(diagnostic.to_dict())
    data.setdefault("end_line", diagnostic.span.end_line)
    data.setdefault("end_column", diagnostic.span.end_column)
    data["fixes"] = [
        {
            "title": fix.title,
            "text": fix.text,
            "line": fix.span.line,
            "column": fix.span.column,
            "end_line": fix.span.end_line,
            "end_column": fix.span.end_column,
        }
        for fix in diagnostic.fixes
    ]
    return data


def _read(domain: str, problem: str, domain_file: str, problem_file: str) -> tuple[Any, Any, list[str]]:
    from vslsp.symbolic import PddlWarning, parse_pddl

    if not problem.strip():
        raise InputError("the problem is empty; open or write a problem to plan for")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PddlWarning)
        try:
            parsed_domain, parsed_problem = parse_pddl(domain, problem)
        except InputError as error:
            message = str(error).replace("<domain>", domain_file).replace("<problem>", problem_file)
            raise InputError(message) from None
    said = [str(w.message) for w in caught if issubclass(w.category, PddlWarning)]
    return parsed_domain, parsed_problem, said


def plan(domain: str, problem: str, domain_file: str = "<domain>", problem_file: str = "<problem>") -> dict:
    """``vslsp plan --json`` on the text, with ``timeline`` (:func:`timeline`). No plan: TaskFailed
    (exit 1) whose ``conflict`` is set when the symbolic layer can name a minimal conflict."""
    from vslsp.symbolic import solve

    parsed_domain, parsed_problem, said = _read(domain, problem, domain_file, problem_file)
    try:
        result = solve(parsed_domain, parsed_problem, timeout=PLAN_TIMEOUT_S)
    except TaskFailed as error:
        if type(error).__name__ == "Unsolvable":  # proved unsolvable (not a timeout): explain it
            located = _conflict(parsed_domain, parsed_problem, problem, problem_file)
            error.conflict, error.reasons = located or (None, [])  # type: ignore[attr-defined]
        raise
    return {
        **result.to_dict(),
        "warnings": said,
        "timeline": timeline(parsed_domain, parsed_problem, list(result.steps)),
    }


def _conflict(domain: Any, problem: Any, text: str, problem_file: str) -> tuple[list[dict], list[str]] | None:
    """A minimal conflict of goal conjuncts and constraints, located in the problem's text, and why
    its goal atoms can never hold, where the symbolic layer explains unsolvable problems
    (``vslsp.symbolic.validation.conflict``); else None."""
    if importlib.util.find_spec("vslsp.symbolic.validation.conflict") is None:
        return None
    explainer = importlib.import_module("vslsp.symbolic.validation.conflict")
    try:
        found = explainer.explain(domain, problem, budget_s=PLAN_TIMEOUT_S, known_unsolvable=True)
    except VslspError:
        return None
    return None if found is None else (list(found.located(text, problem_file)), found.reasons(domain, problem))


def validate(
    domain: str, problem: str, plan_text: str, domain_file: str = "<domain>", problem_file: str = "<problem>"
) -> dict:
    """``vslsp validate --json`` on the text (``violations`` when the symbolic layer lists them), with
    ``timeline`` over the steps that apply."""
    from vslsp.symbolic import validate as validate_plan
    from vslsp.symbolic.validation.validate import parse_plan

    parsed_domain, parsed_problem, said = _read(domain, problem, domain_file, problem_file)
    steps = parse_plan(plan_text, parsed_domain, parsed_problem, "<plan>")
    verdict = validate_plan(parsed_domain, parsed_problem, steps)
    answer: dict[str, Any] = {**verdict.to_dict(), "warnings": said}
    located = getattr(verdict, "located", None)  # every violation, where the symbolic layer locates them
    if callable(located):
        answer["violations"] = located(problem, problem_file, plan_text, "<plan>")
    answer["timeline"] = timeline(parsed_domain, parsed_problem, steps)
    return answer


def timeline(domain: Any, problem: Any, steps: list) -> dict:
    """The states s_0..s_n of ``steps`` (stopping at the first step that does not apply) and each
    constraint's marks: ``{"steps": [...], "states": [[atom, ...], ...], "constraints": [{"text",
    "truth": [bool per state], "status": ["kept"|"broken"|"open" per state], "kept": bool}]}``."""
    from vslsp.symbolic.model.domain import ground_effects
    from vslsp.symbolic.model.formula import holds, substitute

    universe = problem.universe()
    state = frozenset(problem.init)
    states, applied = [state], []
    for name, args in steps:
        try:
            action = domain.action(name)
        except InputError:
            break
        binding = dict(zip((p for p, _ in action.parameters), args, strict=False))
        if not holds(substitute(action.precondition, binding), state, universe):
            break
        added, deleted = ground_effects(action, tuple(args), state, universe)
        state = (state - deleted) | added
        states.append(state)
        applied.append(" ".join((name, *args)))
    marks = [_marks(c, states, universe, holds) for c in problem.constraints]
    return {
        "steps": applied,
        "states": [sorted(_atom(a) for a in s) for s in states],
        "constraints": marks,
    }


def _atom(atom: Any) -> str:
    to_pddl = getattr(atom, "to_pddl", None)
    return to_pddl() if callable(to_pddl) else str(atom)


def _marks(constraint: Any, states: list, universe: Any, holds: Any) -> dict:
    """Per state: is the constraint kept on the prefix s_0..s_i, broken for good, or still open."""
    kind = type(constraint).__name__
    p = [holds(constraint.formula, s, universe) for s in states]
    other = getattr(constraint, "before", None) or getattr(constraint, "after", None)
    q = [holds(other, s, universe) for s in states] if other is not None else p
    status: list[str] = []
    broken = False
    for i in range(len(states)):
        if kind == "Always":
            broken = broken or not p[i]
            status.append("broken" if broken else "kept")
        elif kind == "AtMostOnce":
            starts = sum(1 for j in range(i + 1) if p[j] and (j == 0 or not p[j - 1]))
            broken = broken or starts > 1
            status.append("broken" if broken else "kept")
        elif kind == "SometimeBefore":
            broken = broken or (p[i] and not any(q[:i]))
            status.append("broken" if broken else "kept")
        elif kind == "Sometime":
            status.append("kept" if any(p[: i + 1]) else "open")
        elif kind == "AtEnd":
            status.append("kept" if p[i] else "open")
        else:  # SometimeAfter: every p so far has a q at or after it (so far)
            pending = any(p[j] and not any(q[j : i + 1]) for j in range(i + 1))
            status.append("open" if pending else "kept")
    return {"text": constraint.to_pddl(), "truth": p, "status": status, "kept": status[-1] == "kept"}
