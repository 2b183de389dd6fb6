"""Saving a loaded domain and problem in place: the file's own text, with only what changed rewritten.

Paper: "Implementation" (a user edits what VSL-SP learned, or a file of their own, in the shell).
A file written by hand carries comments, a layout and an order of ``:init`` atoms that the model
does not hold, so ``save`` after ``load`` starts from the loaded text, not from ``to_pddl``: each
section whose model is unchanged since loading (the name, ``:requirements``, ``:types``,
``:constants``, ``:predicates``, each ``:action`` by name, ``:objects``, ``:init``, ``:goal``,
``:constraints``) keeps its text byte for byte. In a changed list (``:predicates``, ``:init``, the
actions) the unchanged items keep theirs, a removed item's text goes and a new one is appended
after the last (the constraints too, where the file's list maps one to one onto the model's); a
changed typed list (``:types``, ``:constants``, ``:objects``) gets new names appended, or is written
anew when an entry changed; a changed goal is written anew in its place; a new section goes where
PDDL 3.0 orders it. What is written anew is laid out as ``to_pddl`` lays it out. The sections are
found in the positioned syntax tree of the language engine (:mod:`vslsp.symbolic.language.syntax`),
which knows comments.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from vslsp.symbolic.io.pddl import read_pddl
from vslsp.symbolic.language.files import MAX_PDDL_BYTES, read_text
from vslsp.symbolic.language.syntax import Group, Token, read_document
from vslsp.symbolic.model.domain import Domain, Problem
from vslsp.symbolic.model.formula import Atom

#: The order of a domain's sections before its actions, and of a problem's (PDDL 3.0 BNF).
DOMAIN_ORDER = (":requirements", ":types", ":constants", ":predicates")
PROBLEM_ORDER = (":domain", ":requirements", ":objects", ":init", ":goal", ":constraints")

#: What a requirement declared in a file implies (PDDL 1.2's :adl and :quantified-preconditions).
_IMPLIED = {
    ":adl": (
        ":strips",
        ":typing",
        ":negative-preconditions",
        ":disjunctive-preconditions",
        ":equality",
        ":conditional-effects",
        ":existential-preconditions",
        ":universal-preconditions",
        ":quantified-preconditions",
    ),
    ":quantified-preconditions": (":existential-preconditions", ":universal-preconditions"),
}


@dataclass(frozen=True)
class Loaded:
    """The files a shell session started from: their text and the models read from them."""

    domain_text: str
    domain: Domain
    problem_text: str | None = None
    problem: Problem | None = None


def load(domain_path: str | Path, problem_path: str | Path | None = None, max_bytes: int = MAX_PDDL_BYTES) -> Loaded:
    """Read a domain (and a problem) file of at most ``max_bytes`` each, keeping their text for
    :func:`domain_in_place`."""
    domain, problem = read_pddl(domain_path, problem_path, max_bytes)
    problem_text = read_text(problem_path, max_bytes=max_bytes) if problem_path is not None else None
    return Loaded(read_text(domain_path, max_bytes=max_bytes), domain, problem_text, problem)


def saved_texts(loaded: Loaded | None, domain: Domain, problem: Problem) -> tuple[str, str]:
    """The domain and problem files to save: the loaded text edited in place, else ``to_pddl``."""
    domain_text = domain_in_place(loaded.domain_text, loaded.domain, domain) if loaded else domain.to_pddl()
    if loaded is None or loaded.problem_text is None or loaded.problem is None:
        return domain_text, problem.to_pddl()
    return domain_text, problem_in_place(loaded.problem_text, loaded.problem, problem)


class _Edits:
    """Replacements of spans of one text, applied together: insertions and rewrites never overlap;
    removals that meet or overlap (neighbours taken out with their blanks) are merged first."""

    def __init__(self, text: str):
        self.text = text
        self.document = read_document(text, "<saved>")
        self.newline = "\r\n" if "\r\n" in text else "\n"
        self.comments = [(c.offset, c.offset + len(c.text)) for c in self.document.comments]
        self.changes: list[tuple[int, int, str]] = []

    def applied(self) -> str:
        text = self.text
        merged: list[tuple[int, int]] = []
        for start, end in sorted((start, end) for start, end, new in self.changes if not new and start < end):
            if merged and start <= merged[-1][1]:  # two removals that meet or overlap are one
                merged[-1] = (merged[-1][0], max(end, merged[-1][1]))
            else:
                merged.append((start, end))
        changes = [change for change in self.changes if change[2] or change[0] == change[1]]
        changes += [(start, end, "") for start, end in merged]
        # From the end back, so each span still points at the original text; of two insertions at one
        # place the one asked first ends up first.
        order = sorted(range(len(changes)), key=lambda i: (*changes[i][:2], i), reverse=True)
        for start, end, new in (changes[i] for i in order):
            text = text[:start] + new.replace("\n", self.newline) + text[end:]
        return text

    def replace(self, node: Token | Group, new: str) -> None:
        start, end = _span(node)
        self.changes.append((start, end, new.strip()))

    def insert_after(self, node: Token | Group, new: str, separator: str | None = None) -> None:
        end = _span(node)[1]
        self.changes.append((end, end, (separator or self.separator(node)) + new.strip()))

    def separator(self, node: Token | Group) -> str:
        """The blank before ``node``: a new item after it is set apart the same way."""
        start = _span(node)[0]
        line_start = self.text.rfind("\n", 0, start) + 1
        before = self.text[:start]
        blank = before[len(before.rstrip()) :]
        if blank and not self._in_comment(len(before.rstrip()) - 1):
            return blank.replace("\r", "")
        indent = self.text[line_start:start]
        return "\n" + indent if not indent.strip() else " "

    def remove(self, first: Token | Group, last: Token | Group | None = None, comments: bool = False) -> None:
        """Take ``first`` (to ``last``) out with the blank that set it apart (whole lines when it had them);
        ``comments``: with the comment lines just above it, which tell what it is."""
        text = self.text
        start, end = _span(first)[0], _span(last or first)[1]
        line_start = text.rfind("\n", 0, start) + 1
        while comments and line_start > 0 and not text[line_start:start].strip():
            above = text.rfind("\n", 0, line_start - 1) + 1
            if not text[above:line_start].lstrip().startswith(";"):
                break
            start = line_start = above
        left, right = start, end
        while left > 0 and text[left - 1] in " \t":
            left -= 1
        while right < len(text) and text[right] in " \t\r":
            right += 1
        at_line_start = left == 0 or text[left - 1] == "\n"
        if at_line_start and (right == len(text) or text[right] == "\n"):
            right = min(right + 1, len(text))
            if text[max(left - 2, 0) : left] == "\n\n" and text[right : right + 1] == "\n":
                right += 1  # blank lines on both sides: one of them goes too
            self.changes.append((left, right, ""))
        elif right < len(text) and text[right] not in "\n)":
            self.changes.append((start, right, ""))
        else:
            previous = len(text[:left].rstrip())
            self.changes.append((left if self._in_comment(previous - 1) else previous, end, ""))

    def _in_comment(self, offset: int) -> bool:
        return any(start <= offset < end for start, end in self.comments)

    def define(self) -> Group:
        for group in self.document.groups:
            if group.key == "define":
                return group
        raise ValueError("no (define ...) in the loaded text")


def _span(node: Token | Group) -> tuple[int, int]:
    if isinstance(node, Token):
        return node.offset, node.offset + len(node.text)
    last = node.close
    assert last is not None, "the loaded file's parentheses balance (it was read)"
    return node.open.offset, last.offset + 1


def _sections(define: Group) -> dict[str, Group]:
    """The sections of a ``(define ...)`` by keyword (the first of each), actions as ``:action NAME``."""
    found: dict[str, Group] = {}
    for item in define.items:
        if isinstance(item, Group) and item.key.startswith(":"):
            key = item.key
            if key == ":action" and len(item.items) > 1:
                key = f":action {item.items[1].key if isinstance(item.items[1], Token) else ''}"
            found.setdefault(key, item)
    return found


def _generated(text: str) -> dict[str, str]:
    """Each section of ``to_pddl`` text as written there (``:action NAME`` for actions)."""
    define = next(g for g in read_document(text, "<generated>").groups if g.key == "define")
    return {key: text[slice(*_span(group))] for key, group in _sections(define).items()}


def domain_in_place(text: str, before: Domain, after: Domain) -> str:
    """``text`` (read as ``before``) edited to say ``after``, with what did not change kept as written."""
    if before == after:
        return text
    edits = _Edits(text)
    define = edits.define()
    found = _sections(define)
    generated = _generated(after.to_pddl())
    _rename(edits, define, before.name, after.name)
    _requirements(edits, define, found, before, after, generated)
    anchors = {
        ":types": (before.types, after.types),
        ":constants": (before.constants, after.constants),
        ":predicates": (before.predicates, after.predicates),
    }
    for key, (old, new) in anchors.items():
        if old == new:
            continue
        if key not in found or key not in generated:
            _put_section(edits, define, found, key, generated, DOMAIN_ORDER)
        elif key == ":predicates":
            _predicates(edits, found[key], before, after)
        else:
            _typed_list(edits, found[key], old, new, generated[key], types=key == ":types")
    actions = [(k.partition(" ")[2], g) for k, g in found.items() if k.startswith(":action ")]
    last_section = [item for item in define.items if isinstance(item, Group) and item.key != ":action"][-1]
    _keyed(
        edits,
        [(_action_name(group, before), group) for _, group in actions],
        last_section,
        {a.name: a for a in before.actions},
        {a.name: a for a in after.actions},
        lambda name: generated.get(f":action {name.lower()}", after.action(name).to_pddl()),
        separator="\n\n  " if not actions else None,
        comments=True,
    )
    return edits.applied()


def _predicates(edits: _Edits, section: Group, before: Domain, after: Domain) -> None:
    items = [(item.head.text, item) for item in section.items if isinstance(item, Group) and item.head]
    written = {p.name: f"({p.name}{' ' if p.parameters else ''}{_typed(p.parameters)})" for p in after.predicates}
    old, new = {p.name: p for p in before.predicates}, {p.name: p for p in after.predicates}
    _keyed(edits, items, section.items[0], old, new, written.__getitem__)


def _action_name(group: Group, before: Domain) -> str:
    written = group.items[1].text if isinstance(group.items[1], Token) else ""
    return next((a.name for a in before.actions if a.name.lower() == written.lower()), written)


def problem_in_place(text: str, before: Problem, after: Problem) -> str:
    """``text`` (read as ``before``) edited to say ``after``, with what did not change kept as written."""
    if before == after:
        return text
    edits = _Edits(text)
    define = edits.define()
    found = _sections(define)
    generated = _generated(after.to_pddl())
    _rename(edits, define, before.name, after.name)
    if before.domain.name != after.domain.name and ":domain" in found and len(found[":domain"].items) > 1:
        edits.replace(found[":domain"].items[1], after.domain.name)
    if before.objects != after.objects:
        if ":objects" in found and ":objects" in generated:
            _typed_list(edits, found[":objects"], before.objects, after.objects, generated[":objects"])
        else:
            _put_section(edits, define, found, ":objects", generated, PROBLEM_ORDER)
    if before.init != after.init and ":init" in found:
        section = found[":init"]
        atoms = [(_atom(item), item) for item in section.items[1:] if isinstance(item, Group)]
        known = [(atom, item) for atom, item in atoms if atom is not None]
        new = {atom: atom for atom in sorted(after.init, key=lambda a: (a.predicate, a.args))}
        _keyed(edits, known, section.items[0], {a: a for a in before.init}, new, Atom.to_pddl)
    elif before.init != after.init:
        _put_section(edits, define, found, ":init", generated, PROBLEM_ORDER)
    if before.goal != after.goal:
        _put_section(edits, define, found, ":goal", generated, PROBLEM_ORDER)
    if before.constraints != after.constraints and not _constraints(edits, found, before, after):
        _put_section(edits, define, found, ":constraints", generated, PROBLEM_ORDER)
    return edits.applied()


def _constraints(edits: _Edits, found: dict[str, Group], before: Problem, after: Problem) -> bool:
    """Constraints dropped or appended (as ``drop constraint N`` and ``constraint C`` do) edited one by
    one, the others kept as written; False when that cannot be (none left, reordered, a preference)."""
    section = found.get(":constraints")
    if section is None or not after.constraints:
        return False
    items, anchor = section.items[1:], section.items[0]
    wrapper = items[0] if len(items) == 1 else None
    if isinstance(wrapper, Group) and wrapper.key == "and":
        items, anchor = wrapper.items[1:], wrapper.items[0]
    groups = [item for item in items if isinstance(item, Group) and item.key != "preference"]
    kept = [c for c in after.constraints if c in before.constraints]
    in_order = [c for c in before.constraints if c in kept] == kept == list(after.constraints[: len(kept)])
    distinct = len(set(before.constraints)) == len(before.constraints)
    if len(groups) != len(items) or len(groups) != len(before.constraints) or not in_order or not distinct:
        return False
    written = dict(zip(before.constraints, groups, strict=True))
    _keyed(
        edits,
        list(written.items()),
        anchor,
        {c: c for c in before.constraints},
        {c: c for c in after.constraints},
        lambda c: c.to_pddl(),
    )
    return True


def _atom(node: Group) -> Atom | None:
    """The ground atom a ``:init`` item writes, or None (a function's value, a timed literal)."""
    if node.head is None or not all(isinstance(i, Token) for i in node.items):
        return None
    return Atom(node.items[0].text, tuple(item.text for item in node.items[1:]))  # type: ignore[union-attr]


def _rename(edits: _Edits, define: Group, old: str, new: str) -> None:
    heading = define.items[1] if len(define.items) > 1 else None
    if old != new and isinstance(heading, Group) and len(heading.items) > 1:
        edits.replace(heading.items[1], new)


def _requirements(
    edits: _Edits, define: Group, found: dict[str, Group], before: Domain, after: Domain, generated: dict
) -> None:
    """Declare what the edit newly needs and the file does not declare yet; drop nothing declared."""
    newly = [r for r in after.requirements() if r not in before.requirements()]
    section = found.get(":requirements")
    if section is None:
        if newly:
            _put_section(edits, define, found, ":requirements", generated, DOMAIN_ORDER)
        return
    declared = {item.key for item in section.items[1:] if isinstance(item, Token)}
    declared |= {word for key in list(declared) for word in _IMPLIED.get(key, ())}
    missing = [r for r in newly if r not in declared]
    if missing:
        edits.insert_after(section.items[-1], " ".join(missing), " ")


def _put_section(
    edits: _Edits, define: Group, found: dict[str, Group], key: str, generated: dict[str, str], order: tuple
) -> None:
    """Write section ``key`` anew: in place of the old one, else where ``order`` puts it; removed when
    the model has none."""
    if key in found:
        if key in generated:
            edits.replace(found[key], generated[key])
        else:
            edits.remove(found[key])
        return
    if key not in generated:
        return
    earlier = [found[k] for k in order[: order.index(key)] if k in found]
    anchor = earlier[-1] if earlier else define.items[1]
    edits.insert_after(anchor, generated[key])


def _keyed(
    edits: _Edits,
    items: Sequence[tuple[Hashable, Group]],
    anchor: Token | Group,
    before: dict,
    after: dict,
    render: Callable[[Any], str],
    separator: str | None = None,
    comments: bool = False,
) -> None:
    """A list of items known by a key (atoms, predicates, actions): the unchanged ones kept as written,
    a changed one rewritten in place, a removed one taken out (``comments``: with the comment lines just
    above it), new ones appended after the last item kept (``anchor`` when none is)."""
    written = {key for key, _ in items}
    kept = []
    run: list[Group] = []  # removed items with nothing but blanks between them: taken out as one
    for key, node in items:
        if key not in after:
            if run and edits.text[_span(run[-1])[1] : _span(node)[0]].strip():
                edits.remove(run[0], run[-1], comments)
                run = []
            run.append(node)
            continue
        if run:
            edits.remove(run[0], run[-1], comments)
            run = []
        kept.append(node)
        if after[key] != before.get(key):
            edits.replace(node, render(key))
    if run:
        edits.remove(run[0], run[-1], comments)
    new = [render(key) for key in after if key not in written]
    if new:
        gap = separator or (edits.separator(items[-1][1]) if items else " ")
        edits.insert_after(kept[-1] if kept else anchor, gap.join(new), gap)


def _typed_list(edits: _Edits, section: Group, old: tuple, new: tuple, generated: str, types: bool = False) -> None:
    """``a b - t c - u`` extended by the names added after the old ones, in the model's order; written
    anew when an old entry changed or went."""
    if tuple(new[: len(old)]) != tuple(old) or not section.items[1:]:
        edits.replace(section, generated)
        return
    runs: list[tuple[str | None, list[str]]] = []  # consecutive names of one type
    for name, type_ in new[len(old) :]:
        type_ = None if types and type_ == "object" else type_
        if runs and runs[-1][0] == type_:
            runs[-1][1].append(name)
        else:
            runs.append((type_, [name]))
    items = section.items[1:]
    last = items[-1]
    if not _trailing_untyped(section) and isinstance(last, Token) and runs and runs[0][0] == last.text:
        edits.insert_after(items[-3], " ".join(runs.pop(0)[1]), " ")  # joins the last group, of its type
    # Names without a type are typed by the next "- TYPE": before another group they say "- object".
    parts = [
        " ".join(names) if type_ is None and number == len(runs) - 1 else f"{' '.join(names)} - {type_ or 'object'}"
        for number, (type_, names) in enumerate(runs)
    ]
    if parts and _trailing_untyped(section) and not (len(runs) == 1 and runs[0][0] is None):
        parts.insert(0, "- object")
    if parts:
        edits.insert_after(last, " ".join(parts), " ")


def _trailing_untyped(section: Group) -> bool:
    """Whether the list ends in names without ``- type`` (a typed name appended would type them too)."""
    items = section.items[1:]
    return bool(items) and not (len(items) >= 2 and isinstance(items[-2], Token) and items[-2].text == "-")


def _typed(parameters: Iterable[tuple[str, str]]) -> str:
    return " ".join(f"{name} - {type_}" for name, type_ in parameters)
