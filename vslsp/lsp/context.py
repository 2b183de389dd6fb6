"""Where the cursor is in a PDDL text, for completion: which kind of name fits there.

The text before the cursor is read as the engine reads a file (its tokens, comments skipped), and the
lists still open at the cursor say the context: the head of a list inside a precondition, effect, goal
or initial state wants a predicate (or an operator), the word after ``-`` a type, an atom's arguments
a variable, constant or object, ``(:requirements`` requirement keywords, ``:constraints`` PDDL 3.0
operators. A file half typed is the normal case: nothing here needs the lists to close.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from vslsp.symbolic.language.syntax import tokenize

#: What completion offers, by want.
PREDICATE = "predicate"  # the head of an atom (with the operators allowed there)
ARGUMENT = "argument"  # an argument of an atom: variables in a domain, objects and constants in a problem
TYPE = "type"
REQUIREMENT = "requirement"
SECTION = "section"  # a (:section of the define list
ACTION_KEYWORD = "action-keyword"  # :parameters :precondition :effect
ACTION = "action"  # a plan step's action
NOTHING = "nothing"  # a new name (a declaration), a comment, outside any list

_NAME_CHARS = re.compile(r"[^\s();]*\Z")  # \Z: "$" would match before a final line break
_FORMULA_SLOTS = {":precondition": "goal", ":goal": "goal", ":effect": "effect", ":init": "init", ":condition": "goal"}
#: Lists whose items are typed names, where ``-`` is followed by a type.
_TYPED_LISTS = (":types", ":constants", ":objects", ":parameters", ":predicates", "forall", "exists", ":vars")


@dataclass
class _Frame:
    head: str = ""  # the lower-case first name of the list ("" before it is typed)
    count: int = 0  # items so far
    slot: str = ""  # the keyword (":precondition" ...) or section that precedes the list in its parent
    last_keyword: str = ""


@dataclass(frozen=True)
class Cursor:
    """The completion context: ``want`` (one of the constants above), the partial ``prefix`` typed and the
    offset where it starts, the enclosing formula (``formula``: goal, effect, init, constraints or ""),
    ``heads`` the open lists' heads from the outermost, and for an argument the atom's ``atom`` head and
    the argument's ``position`` (0-based)."""

    want: str
    prefix: str
    start: int
    formula: str = ""
    heads: tuple[str, ...] = field(default_factory=tuple)
    atom: str = ""
    position: int = 0


def cursor_at(text: str, offset: int) -> Cursor:
    """The completion context at ``offset`` (0-based, in characters) of a domain or problem ``text``."""
    before = text[:offset]
    line_start = before.rfind("\n") + 1
    if ";" in before[line_start:]:
        return Cursor(NOTHING, "", offset)  # in a comment (names never hold ';')
    prefix = _NAME_CHARS.search(before)
    word = prefix.group() if prefix else ""
    start = offset - len(word)
    tokens, _ = tokenize(before[:start], "")
    stack: list[_Frame] = []
    previous = ""
    for token in tokens:
        if token.kind == "(":
            slot = stack[-1].last_keyword if stack else ""
            if stack and stack[-1].head in _FORMULA_SLOTS or (stack and stack[-1].head == ":constraints"):
                slot = stack[-1].head
            stack.append(_Frame(slot=slot))
        elif token.kind == ")":
            if stack:
                stack.pop()
            if stack:
                stack[-1].count += 1
        elif stack:
            frame = stack[-1]
            if frame.count == 0:
                frame.head = token.key
            elif token.key.startswith(":"):
                frame.last_keyword = token.key
            frame.count += 1
        previous = token.key
    if not stack:
        return Cursor(NOTHING, word, start)
    heads = tuple(f.head for f in stack)
    frame = stack[-1]
    formula = _formula(stack)
    if word.startswith("?") and frame.count > 0:
        return Cursor(ARGUMENT, word, start, formula, heads, frame.head, frame.count - 1)
    if previous == "-" and frame.count > 0 and (frame.head in _TYPED_LISTS or _in_typed_list(stack)):
        return Cursor(TYPE, word, start, formula, heads)
    if frame.count == 0:
        parent = stack[-2].head if len(stack) >= 2 else ""
        if parent == "define":
            return Cursor(SECTION, word, start, formula, heads)
        if formula:
            return Cursor(PREDICATE, word, start, formula, heads)
        return Cursor(NOTHING, word, start, formula, heads)
    if frame.head == ":requirements":
        return Cursor(REQUIREMENT, word, start, formula, heads)
    if frame.head in (":action", ":derived") and (word.startswith(":") or not word):
        return Cursor(ACTION_KEYWORD, word, start, formula, heads)
    if formula and not frame.head.startswith(":") and frame.head not in ("forall", "exists"):
        return Cursor(ARGUMENT, word, start, formula, heads, frame.head, frame.count - 1)
    return Cursor(NOTHING, word, start, formula, heads)


def _formula(stack: list[_Frame]) -> str:
    """The formula the innermost list is part of: goal, effect, init, constraints or ""."""
    for frame in reversed(stack):
        if frame.head == ":constraints" or frame.slot == ":constraints":
            return "constraints"
        if frame.slot in _FORMULA_SLOTS:
            return _FORMULA_SLOTS[frame.slot]
        if frame.head in (":init", ":goal"):
            return _FORMULA_SLOTS[frame.head]
    return ""


def _in_typed_list(stack: list[_Frame]) -> bool:
    """Whether the innermost list is a typed list: a predicate's declaration, an action's parameters,
    a quantifier's variables."""
    if len(stack) < 2:
        return False
    inner, outer = stack[-1], stack[-2]
    return outer.head == ":predicates" or inner.slot == ":parameters" or outer.head in ("forall", "exists")


_STEP_PREFIX = re.compile(r"^\s*(?:\d+(?:\.\d+)?\s*[:.]\s*)?\(?\s*")


def plan_cursor_at(text: str, offset: int) -> Cursor:
    """The completion context in a plan (one ``(action arg ...)``, ``N: (action ...)`` or ``N. action ...``
    per line): the action name first, then its arguments."""
    before = text[:offset]
    line = before[before.rfind("\n") + 1 :]
    if ";" in line:
        return Cursor(NOTHING, "", offset)
    lead = _STEP_PREFIX.match(line)
    rest = line[lead.end() if lead else 0 :]
    words = rest.split()
    word = "" if not rest or rest[-1].isspace() else words[-1]
    start = offset - len(word)
    done = words[:-1] if word else words
    if not done:
        return Cursor(ACTION, word, start)
    return Cursor(ARGUMENT, word, start, atom=done[0].lower(), position=len(done) - 1)
