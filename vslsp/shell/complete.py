"""Tab completion for ``vslsp shell``: the names that fit where the cursor is.

Command names first; then, by the command and the place inside its parentheses: predicates
at the head of an atom (with the connectives that fit: effects take ``when``, constraints take
the PDDL 3.0 operators at their top), types after ``-``, the action's variables and the objects
of the right type as arguments, action names in ``validate`` steps and ``drop action``,
constraint numbers after ``drop constraint``. Names are whole PDDL names, hyphens included:
the shell tells readline to split words only at blanks and parentheses (:data:`DELIMITERS`).
"""

from __future__ import annotations

import glob
import os
from collections.abc import Sequence

from vslsp.shell.check import CONNECTIVES, CONSTRAINT_OPERATORS, EFFECT_WORDS, tokens, typed_list
from vslsp.shell.commands import NAMES
from vslsp.symbolic.model.domain import Domain, Problem

#: Where readline splits the line into words: never at '-' or '?', which are parts of PDDL names.
DELIMITERS = " \t\n()"

_SHOW = ("domain", "problem", "constraints")
_DROP = ("action", "constraint", "constraints", "init")
_KEYWORDS = (":parameters", ":precondition", ":effect")


def _frames(text: str) -> list[list]:
    """The lists still open at the end of ``text``, outermost (the command's words) first."""
    stack: list[list] = [[]]
    for token in tokens(text):
        if token == "(":
            stack.append([])
        elif token == ")":
            if len(stack) > 1:
                done = stack.pop()
                stack[-1].append(done)
        else:
            stack[-1].append(token)
    return stack


def complete(
    line: str, begidx: int, text: str, domain: Domain, problem: Problem, planners: Sequence[str] = ()
) -> list[str]:
    """The completions of the word ``text`` that starts at ``begidx`` of ``line``, sorted, each
    with the space that follows it."""
    opened = len(text) - len(text.lstrip("("))  # a '(' typed before the name (when '(' is no delimiter)
    before, prefix = line[: begidx + opened], text[opened:]
    frames = _frames(before)
    words = frames[0]
    if not words:
        found = list(NAMES)
    else:
        found = _arguments(words[0], frames, prefix, domain, problem, planners)
    # a finished name ends with a space (Python's readline adds none), a folder with its '/'
    return sorted({"(" * opened + n + ("" if n.endswith("/") else " ") for n in found if n.startswith(prefix)})


def _arguments(
    command: str, frames: list[list], prefix: str, domain: Domain, problem: Problem, planners: Sequence[str]
) -> list[str]:
    words, depth = frames[0][1:], len(frames) - 1
    types = [t for t, _ in domain.types] + ["object"]
    if command == "help":
        return list(NAMES) if not words else []
    if command == "show":
        return list(_SHOW) if not words else []
    if command == "plan":
        return list(planners) if not words else []
    if command in ("load", "save"):
        return [path + ("/" if os.path.isdir(path) else "") for path in glob.glob(prefix + "*")]
    if command in ("type", "objects"):
        return types if words and words[-1] == "-" and depth == 0 else []
    if command == "predicate":
        return types if depth == 1 and frames[1] and frames[1][-1] == "-" else []
    if command == "drop":
        if not words:
            return list(_DROP)
        if words[0] == "action" and len(words) == 1:
            return [a.name for a in domain.actions]
        if words[0] == "constraint" and len(words) == 1:
            return [str(n) for n in range(1, len(problem.constraints) + 1)]
        if words[0] == "init":
            return _formula(frames, "init", {}, domain, problem)
        return []
    if command == "action":
        return _action(frames, prefix, domain)
    if command == "validate":
        return _step(frames, domain, problem)
    if command in ("init", "goal", "constraint"):
        return _formula(frames, command, {}, domain, problem)
    return []


def _action(frames: list[list], prefix: str, domain: Domain) -> list[str]:
    words = frames[0][1:]
    if len(frames) == 1:
        return [k for k in _KEYWORDS if k not in words] if words else []
    section = words[-1] if words and isinstance(words[-1], str) else ""
    if section == ":parameters":
        return [t for t, _ in domain.types] + ["object"] if len(frames) == 2 and frames[1][-1:] == ["-"] else []
    given = words[words.index(":parameters") + 1] if ":parameters" in words[:-1] else []
    variables = dict(typed_list(given)) if isinstance(given, list) else {}
    return _formula(frames, "effect" if section == ":effect" else "precondition", variables, domain, None)


def _step(frames: list[list], domain: Domain, problem: Problem) -> list[str]:
    if len(frames) != 2:
        return []
    frame = frames[1]
    if not frame:
        return [a.name for a in domain.actions]
    actions = {a.name: a for a in domain.actions}
    position = len(frame) - 1
    if frame[0] not in actions or position >= len(actions[frame[0]].parameters):
        return []
    return _objects(actions[frame[0]].parameters[position][1], domain, problem)


def _objects(type_: str, domain: Domain, problem: Problem | None) -> list[str]:
    everything = problem.all_objects() if problem is not None else domain.constants
    fits = domain.subtypes(type_)
    return [o for o, t in everything if type_ == "object" or t in fits]


def _formula(
    frames: list[list], where: str, variables: dict[str, str], domain: Domain, problem: Problem | None
) -> list[str]:
    """Completions inside a formula: ``where`` is init, goal, constraint, precondition or effect."""
    inner = frames[1:]
    if not inner:
        return []
    scope = dict(variables)
    for outer in inner[:-1]:  # variables bound by enclosing quantifiers
        if outer and outer[0] in ("forall", "exists") and len(outer) >= 2 and isinstance(outer[1], list):
            scope.update(typed_list(outer[1]))
    frame = inner[-1]
    parent = inner[-2] if len(inner) > 1 else None
    if parent is not None and parent[:1] in (["forall"], ["exists"]) and len(parent) == 1:
        return [t for t, _ in domain.types] + ["object"] if frame[-1:] == ["-"] else []  # the variables' types
    predicates = {p.name: p for p in domain.predicates}
    if not frame:
        if where == "init":
            return list(predicates)
        if where == "constraint" and len(inner) == 1:
            return [o for o in CONSTRAINT_OPERATORS if o != "at"] + ["at"]
        return [*predicates, *(EFFECT_WORDS if where == "effect" else CONNECTIVES)]
    head, position = frame[0], len(frame) - 1
    if head == "at" and position == 0 and where == "constraint":
        return ["end"]
    if head == "=":
        type_ = "object"
    elif head in predicates and position < len(predicates[head].parameters):
        type_ = predicates[head].parameters[position][1]
    else:
        return []
    fits = domain.subtypes(type_)
    return [v for v, t in scope.items() if type_ == "object" or t in fits] + _objects(type_, domain, problem)
