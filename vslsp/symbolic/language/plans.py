"""Checking a plan file against a domain and problem: each step's action, its arguments and their
types, every mistake located at the name written, with the declared name nearest to an unknown one.

A plan holds one step per line (``;`` comments and blank lines allowed): ``(pull green)``, as VAL
and IPC planners write it (``0: (pull green)``, ``0.000: (pull green) [1]``), or as ``vslsp plan``
prints it (``1. pull green``) - the formats ``vslsp validate`` reads.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from vslsp.symbolic.language.analysis import Analysis
from vslsp.symbolic.language.diagnostics import ERROR, Diagnostic, Fix, Span, SuggestionBudget, closest
from vslsp.symbolic.language.index import Reference

_STEP = re.compile(
    r"^\s*(?:\d+(?:\.\d+)?\s*:\s*)?\(\s*([\w-]+)((?:\s+[\w-]+)*)\s*\)\s*(?:\[[\d.]+\])?\s*$"
    r"|^\s*\d+\.\s+([\w-]+)((?:\s+[\w-]+)*)\s*$"
)
_NAME = re.compile(r"[\w-]+")


@dataclass
class PlanAnalysis:
    """What :func:`analyse_plan` found: ``diagnostics`` (sorted by place), ``references`` (each action
    and object named, resolved in the analysis's index; None where unknown) and the ``steps`` read
    (lower-case action and arguments, those with no error)."""

    diagnostics: list[Diagnostic] = field(default_factory=list)
    references: list[Reference] = field(default_factory=list)
    steps: list[tuple[str, tuple[str, ...]]] = field(default_factory=list)


def analyse_plan(analysis: Analysis, text: str, file: str = "<plan>") -> PlanAnalysis:
    """Check the plan ``text`` (named ``file``) against the domain and problem of ``analysis``."""
    found = PlanAnalysis()
    index = analysis.index
    actions = index.names("action")
    objects = index.names("object") + index.names("constant")
    suggestions = SuggestionBudget()
    for number, line in enumerate(text.split("\n"), start=1):
        code = line.split(";", 1)[0].rstrip("\r")
        if not code.strip():
            continue
        match = _STEP.match(code)
        if match is None:
            column = len(code) - len(code.lstrip()) + 1
            span = Span(file, number, column, number, len(code.rstrip()) + 1)
            message = f"expected one step like (pull green) or 1. pull green, got {code.strip()!r}"
            found.diagnostics.append(Diagnostic(span, ERROR, message, "bad-step"))
            continue
        group = 1 if match.group(1) else 3
        name = match.group(group)
        span = Span(file, number, match.start(group) + 1, number, match.end(group) + 1)
        action = index.find("action", name)
        found.references.append(Reference("action", name, span, action))
        arguments = [
            (
                word.group(),
                Span(
                    file,
                    number,
                    match.start(group + 1) + word.start() + 1,
                    number,
                    match.start(group + 1) + word.end() + 1,
                ),
            )
            for word in _NAME.finditer(match.group(group + 1))
        ]
        errors = len(found.diagnostics)
        if action is None:
            suggestion = closest(name, actions, suggestions)
            fixes = (Fix(f"change to '{suggestion}'", span, suggestion),) if suggestion else ()
            found.diagnostics.append(
                Diagnostic(span, ERROR, f"unknown action '{name}'", "unknown-action", suggestion, fixes)
            )
        elif len(arguments) != len(action.parameters):
            count = len(action.parameters)
            message = f"'{action.name}' takes {count} argument{'s' if count != 1 else ''}, {len(arguments)} given"
            found.diagnostics.append(Diagnostic(span, ERROR, message, "arity"))
        for position, (word, at) in enumerate(arguments):
            declared = index.find("object", word) or index.find("constant", word)
            found.references.append(Reference("object" if declared is None else declared.kind, word, at, declared))
            if declared is None:
                suggestion = closest(word, objects, suggestions)
                fixes = (Fix(f"change to '{suggestion}'", at, suggestion),) if suggestion else ()
                message = f"unknown object or constant '{word}'"
                found.diagnostics.append(Diagnostic(at, ERROR, message, "unknown-object", suggestion, fixes))
            elif action is not None and position < len(action.parameters):
                wanted = action.parameters[position].types
                if not _below(analysis, declared.types, wanted):
                    message = (
                        f"'{word}' is of type {' or '.join(declared.types)}, but argument {position + 1} of "
                        f"'{action.name}' is of type {' or '.join(wanted)}"
                    )
                    found.diagnostics.append(Diagnostic(at, ERROR, message, "argument-type"))
        if len(found.diagnostics) == errors:
            found.steps.append((name.lower(), tuple(word.lower() for word, _ in arguments)))
    return found


def _below(analysis: Analysis, types: tuple[str, ...], wanted: tuple[str, ...]) -> bool:
    """Whether each of ``types`` is one of ``wanted`` or below one of them (an unknown type: yes)."""
    parents = analysis.type_parents
    for kind in types:
        chain, seen = [kind], {kind}
        while chain[-1] in parents:
            following = next((p for p in parents[chain[-1]] if p not in seen), None)
            if following is None:
                break
            chain.append(following)
            seen.add(following)
        if kind != "object" and kind not in parents:
            continue  # undeclared: reported in the domain or problem
        if not any(w in chain or w == "object" for w in wanted):
            return False
    return True
