"""Where a goal conjunct or a trajectory constraint is written in its problem file.

Paper: "Implementation" (the problem file with its goal and PDDL 3.0 constraints). The model
keeps no positions: an explanation (:mod:`vslsp.symbolic.validation.conflict`) or a validation
(:mod:`vslsp.symbolic.validation.validate`) names formulas of the model, and this module finds them in
the file text so that a user reads ``FILE:LINE:COL`` and the formula as they wrote it. A
constraint under ``(forall (?x - t) ...)`` is expanded over the objects by the reader: each
ground instance is found at the quantified constraint it came from.
"""

from __future__ import annotations

import re
from bisect import bisect_right
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

#: An s-expression: a word, or ``(offset, children)`` for a parenthesised list (offset of its ``(``).
Tree = str | tuple[int, tuple["Tree", ...]]
_TOKEN = re.compile(r";[^\n]*|\(|\)|[^\s();]+")


@dataclass(frozen=True)
class Written:
    """A goal conjunct or a constraint as the file writes it: its text (comments dropped, whitespace
    normalised, case kept) and the 1-based line and column of its ``(``."""

    text: str
    line: int
    column: int
    tree: Tree
    variables: frozenset[str] = frozenset()  # bound by a (forall ...) around constraints
    canonical: Tree = ""  # the tree in lower case, variable lists written one way (what find compares)


class Parts(tuple):
    """The parts of a section (a tuple of :class:`Written`), those without variables indexed by their
    canonical tree: a problem's thousands of goal conjuncts are each found in constant time."""

    exact: dict[object, tuple[int, Written]]
    quantified: list[tuple[int, Written]]

    def __new__(cls, parts: Sequence[Written]) -> Parts:
        made = super().__new__(cls, parts)
        made.exact, made.quantified = {}, []
        for index, part in enumerate(parts):
            if part.variables:
                made.quantified.append((index, part))
            else:
                made.exact.setdefault(_words(part.canonical), (index, part))  # the first that writes it
        return made


def as_written(kind: str, formula: str, text: str, name: str) -> dict:
    """``{"kind", "text", "instance", "file", "line", "column"}`` for a goal conjunct (``kind == "goal"``)
    or a constraint (``"constraint"``) given as the model writes it (``formula``), found in the problem
    ``text`` of file ``name``: ``text`` as written there, ``instance`` as the model holds it (a
    quantified constraint's ground instance). Not found: the model's text, line and column None."""
    found = find(formula, written_parts(text, ":goal" if kind == "goal" else ":constraints"))
    return {
        "kind": kind,
        "text": found.text if found else formula,
        "instance": formula,
        "file": name,
        "line": found.line if found else None,
        "column": found.column if found else None,
    }


def where(item: dict) -> str:
    """``FILE:LINE:COL`` of an :func:`as_written` item (``FILE`` alone when it was not found)."""
    return item["file"] if item.get("line") is None else f"{item['file']}:{item['line']}:{item['column']}"


@lru_cache(maxsize=8)
def written_parts(text: str, section: str) -> Parts:
    """The conjuncts of the problem's ``(:goal ...)`` or the constraints of its ``(:constraints ...)``
    (``section``: ``":goal"`` or ``":constraints"``), ``(and ...)`` opened, preferences left out."""
    body = _section(_parse(text), section)
    if body is None:
        return Parts(())
    lines = [0, *(match.end() for match in re.finditer("\n", text))]
    return Parts([p for tree in body for p in _parts(text, lines, tree, frozenset(), None, section == ":constraints")])


def find(formula: str, parts: Sequence[Written]) -> Written | None:
    """The part that writes ``formula`` (the model's ``to_pddl()``), or None when none does.

    A part under ``(forall (?x) ...)`` matches each instance with ?x replaced by an object.
    """
    trees = _parse(formula)
    if not trees:
        return None
    target = _canonical(_lower(trees[0]))
    if not isinstance(parts, Parts):
        parts = Parts(parts)
    hit = parts.exact.get(_words(target))
    for index, part in parts.quantified:  # the first part in the file that writes it wins
        if hit is not None and index > hit[0]:
            break
        if _match(part.canonical, target, part.variables, {}):
            return part
    return hit[1] if hit is not None else None


def normalised(text: str) -> str:
    """``text`` with comments dropped and whitespace normalised: ``(sometime-before (a) (b))``."""
    words = [t for t in _TOKEN.findall(text) if not t.startswith(";")]
    return re.sub(r"\( | \)", lambda m: m.group(0).strip(), " ".join(words))


def position(text: str, offset: int) -> tuple[int, int]:
    """1-based line and column of ``offset`` in ``text``."""
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1


def _parse(text: str) -> list[Tree]:
    """The top-level s-expressions of ``text`` (unbalanced parentheses closed or ignored: the reader
    has checked the file already)."""
    stack: list[tuple[int, list[Tree]]] = [(-1, [])]
    for match in _TOKEN.finditer(text):
        token = match.group(0)
        if token.startswith(";"):
            continue
        if token == "(":
            stack.append((match.start(), []))
        elif token == ")":
            if len(stack) > 1:
                start, children = stack.pop()
                stack[-1][1].append((start, tuple(children)))
        else:
            stack[-1][1].append(token)
    while len(stack) > 1:
        start, children = stack.pop()
        stack[-1][1].append((start, tuple(children)))
    return stack[0][1]


def _head(tree: Tree) -> str | None:
    if isinstance(tree, str) or not tree[1] or not isinstance(tree[1][0], str):
        return None
    return tree[1][0].lower()


def _section(trees: list[Tree], keyword: str) -> tuple[Tree, ...] | None:
    for tree in trees:
        if _head(tree) == "define":
            assert not isinstance(tree, str)
            for child in tree[1]:
                if _head(child) == keyword:
                    assert not isinstance(child, str)
                    return child[1][1:]
    return None


def _parts(
    text: str, lines: list[int], tree: Tree, variables: frozenset[str], quantified: Tree | None, constraints: bool
) -> list[Written]:
    """``tree`` as parts: ``and`` opened; among ``constraints``, ``forall`` opened with its variables
    bound (a part inside it is written as the whole quantified constraint when that holds just one)."""
    head = _head(tree)
    if isinstance(tree, str) or head == "preference":
        return []
    if head == "and":
        children = tree[1][1:]
        alone = quantified if len(children) == 1 else None
        return [p for child in children for p in _parts(text, lines, child, variables, alone, constraints)]
    if constraints and head == "forall" and len(tree[1]) == 3:
        bound = _variables(tree[1][1])
        return _parts(text, lines, tree[1][2], variables | bound, quantified or tree, constraints)
    shown = quantified if quantified is not None else tree
    assert not isinstance(shown, str)
    start = shown[0]
    line = bisect_right(lines, start)  # the lines' starts, found once per section: no count from the top
    column = start - lines[line - 1] + 1
    written = normalised(text[start : _end(text, start)])
    return [Written(written, line, column, tree, variables, _canonical(_lower(tree)))]


def _variables(tree: Tree) -> frozenset[str]:
    words = [tree] if isinstance(tree, str) else [w for w in tree[1] if isinstance(w, str)]
    return frozenset(w.lower() for w in words if w.startswith("?"))


def _end(text: str, start: int) -> int:
    """The offset after the ``)`` closing the ``(`` at ``start`` (comments skipped)."""
    depth = 0
    for match in _TOKEN.finditer(text, start):
        token = match.group(0)
        if token == "(":
            depth += 1
        elif token == ")":
            depth -= 1
            if depth == 0:
                return match.end()
    return len(text)


def _words(tree: Tree) -> object:
    """``tree`` without its offsets: what two trees written at different places share when they match."""
    return tree if isinstance(tree, str) else tuple(_words(child) for child in tree[1])


def _lower(tree: Tree) -> Tree:
    return tree.lower() if isinstance(tree, str) else (tree[0], tuple(_lower(c) for c in tree[1]))


def _canonical(tree: Tree) -> Tree:
    """Quantified variable lists written one way: ``(?a ?b - t)`` as ``(?a - t ?b - t)``."""
    if isinstance(tree, str):
        return tree
    children = tuple(_canonical(c) for c in tree[1])
    if _head(tree) in ("forall", "exists") and len(children) == 3 and not isinstance(children[1], str):
        children = (children[0], (children[1][0], _typed_words(children[1][1])), children[2])
    return tree[0], children


def _typed_words(words: tuple[Tree, ...]) -> tuple[Tree, ...]:
    names: list[str] = []
    out: list[Tree] = []
    flat = [w for w in words if isinstance(w, str)]
    i = 0
    while i < len(flat):
        if flat[i] == "-" and i + 1 < len(flat):
            out.extend(w for name in names for w in (name, "-", flat[i + 1]))
            names, i = [], i + 2
        else:
            names.append(flat[i])
            i += 1
    out.extend(w for name in names for w in (name, "-", "object"))
    return tuple(out)


def _match(pattern: Tree, target: Tree, variables: frozenset[str], binding: dict[str, str]) -> bool:
    """Whether ``pattern`` is ``target`` with each of ``variables`` standing for one word throughout."""
    if isinstance(pattern, str):
        if pattern in variables and isinstance(target, str):
            return binding.setdefault(pattern, target) == target
        return pattern == target
    if isinstance(target, str) or len(pattern[1]) != len(target[1]):
        return False
    return all(_match(p, t, variables, binding) for p, t in zip(pattern[1], target[1], strict=True))
