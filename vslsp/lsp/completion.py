"""Completion in context: predicates (and the operators allowed there) at the head of an atom, types
after ``-``, variables, constants and objects as arguments (those of the argument's type first),
requirement keywords in ``(:requirements``, sections, PDDL 3.0 operators in ``:constraints``, action
names and objects in a plan. Items replace the whole name typed so far, hyphens included."""

from __future__ import annotations

import re

from lsprotocol import types

from vslsp.lsp import context
from vslsp.lsp.analysis import Analyses, Checked
from vslsp.lsp.positions import characters, units
from vslsp.lsp.workspace import PLAN, PROBLEM
from vslsp.symbolic.language import EFFECT_OPERATORS, GOAL_OPERATORS, PDDL3_NAMES, REQUIREMENTS, Declaration
from vslsp.symbolic.language.vocabulary import ACTION_KEYWORDS, DOMAIN_SECTIONS, PROBLEM_SECTIONS

_KIND = types.CompletionItemKind
_DEFINE = re.compile(r"\(\s*define\b", re.IGNORECASE)
_OPERATORS = {
    "goal": GOAL_OPERATORS,
    "effect": EFFECT_OPERATORS,
    "init": (),
    "constraints": (*PDDL3_NAMES, *GOAL_OPERATORS),
}


def complete(analyses: Analyses, uri: str, text: str, position: types.Position) -> types.CompletionList:
    """The completion items at ``position`` of the document ``uri`` whose live text is ``text``."""
    header = analyses.files.header(uri)
    lines_before = text.split("\n")[: position.line + 1]
    line_text = lines_before[-1] if lines_before else ""
    encoding = analyses.encoding
    character = characters(line_text, position.character, encoding)
    offset = sum(len(line) + 1 for line in lines_before[:-1]) + character
    if header.kind == PLAN:
        cursor = context.plan_cursor_at(text, offset)
        items = _plan_items(analyses, uri, cursor)
    else:
        cursor = context.cursor_at(text, offset)
        checked = analyses.of(uri)
        items = _items(checked, cursor, header.kind, position) if checked is not None else []
        if not header.kind and len(cursor.heads) <= 1 and not _DEFINE.search(text):
            items = _skeletons(analyses, uri)  # a new file: a domain or a problem to start from
            if cursor.heads and text[cursor.start - 1 : cursor.start] == "(":  # the '(' typed is the skeleton's own
                cursor = context.Cursor(cursor.want, "(" + cursor.prefix, cursor.start - 1)
    start = types.Position(position.line, position.character - units(cursor.prefix, encoding))
    edit_range = types.Range(start, position)
    for item in items:
        item.text_edit = types.TextEdit(edit_range, item.insert_text or item.label)
        item.filter_text = item.filter_text or item.label
    return types.CompletionList(is_incomplete=False, items=items)


def _skeletons(analyses: Analyses, uri: str) -> list[types.CompletionItem]:
    """``(define (domain ...))`` and ``(define (problem ...))`` to fill in (snippets; the problem names
    a domain beside the file when there is one)."""
    domains = [analyses.files.header(u).name for u in analyses.files.domains_near(uri)]
    domain = domains[0] if domains else "DOMAIN"
    texts = {
        "define domain": (
            "(define (domain ${1:name})\n  (:requirements :strips :typing)\n  (:types ${2:thing})\n"
            "  (:predicates\n    (${3:ready} ?x - ${2:thing}))\n\n  (:action ${4:act}\n"
            "    :parameters (?x - ${2:thing})\n    :precondition (${3:ready} ?x)\n"
            "    :effect (not (${3:ready} ?x))))\n"
        ),
        "define problem": (
            f"(define (problem ${{1:name}})\n  (:domain ${{2:{domain}}})\n  (:objects $3)\n  (:init $4)\n"
            "  (:goal (and $0)))\n"
        ),
    }
    return [
        types.CompletionItem(
            label=label,
            kind=types.CompletionItemKind.Snippet,
            insert_text=text,
            insert_text_format=types.InsertTextFormat.Snippet,
            filter_text=f"(define {label.split()[1]}",
            detail=f"a new PDDL {label.split()[1]}",
        )
        for label, text in texts.items()
    ]


def _items(checked: Checked, cursor: context.Cursor, kind: str, position: types.Position) -> list[types.CompletionItem]:
    index = checked.analysis.index
    want = cursor.want
    if want == context.PREDICATE:
        items = [_declared(d, _KIND.Function) for d in index.of_kind("predicate")]
        if cursor.formula in ("goal", "effect", "init"):
            items += [_declared(d, _KIND.Function) for d in index.of_kind("function")]
        return items + _words(_OPERATORS.get(cursor.formula, ()), _KIND.Operator)
    if want == context.TYPE:
        return [_declared(d, _KIND.Class) for d in index.of_kind("type")] + _words(("object",), _KIND.Class)
    if want == context.REQUIREMENT:
        return _words(REQUIREMENTS, _KIND.Keyword)
    if want == context.SECTION:
        return _words(PROBLEM_SECTIONS if kind == PROBLEM else DOMAIN_SECTIONS, _KIND.Keyword)
    if want == context.ACTION_KEYWORD:
        return _words(ACTION_KEYWORDS, _KIND.Keyword)
    if want == context.ARGUMENT:
        line, column = position.line + 1, position.character + 1
        variables = [
            d
            for d in index.declarations
            if d.kind in ("parameter", "variable")
            and d.span.file == checked.file
            and d.scope is not None
            and d.scope.contains(line, column)
        ]
        if cursor.prefix.startswith("?"):
            return [_declared(d, _KIND.Variable) for d in _unique(variables)]
        names = [*index.of_kind("constant"), *(index.of_kind("object") if kind == PROBLEM else [])]
        wanted = _argument_types(checked, cursor)
        items = [_declared(d, _KIND.Variable) for d in _unique(variables)] if kind != PROBLEM else []
        for d in names:
            item = _declared(d, _KIND.Constant)
            fits = wanted is None or any(t in wanted for t in _ancestors(checked, d.types))
            item.sort_text = f"{0 if fits else 1}{d.name}"
            items.append(item)
        return items
    return []


def _plan_items(analyses: Analyses, uri: str, cursor: context.Cursor) -> list[types.CompletionItem]:
    """Actions of the domains beside the plan (open or in its folder); as arguments, their problems'
    objects and the constants."""
    files = analyses.files
    checked = [c for u in files.neighbours(uri) if files.header(u).kind == PROBLEM and (c := analyses.of(u))]
    checked += [c for u in files.domains_near(uri) if (c := analyses.of(u)) is not None]
    kind = "action" if cursor.want == context.ACTION else None
    items: dict[str, types.CompletionItem] = {}
    for analysis in checked:
        index = analysis.analysis.index
        found = index.of_kind("action") if kind else [*index.of_kind("object"), *index.of_kind("constant")]
        for d in found:
            items.setdefault(d.key, _declared(d, _KIND.Method if kind else _KIND.Constant))
    return list(items.values())


def _declared(declaration: Declaration, kind: types.CompletionItemKind) -> types.CompletionItem:
    documentation = types.MarkupContent(types.MarkupKind.Markdown, declaration.comment) if declaration.comment else None
    return types.CompletionItem(
        label=declaration.name, kind=kind, detail=declaration.signature, documentation=documentation
    )


def _words(words: tuple[str, ...] | list[str], kind: types.CompletionItemKind) -> list[types.CompletionItem]:
    return [types.CompletionItem(label=word, kind=kind) for word in words]


def _unique(declarations: list[Declaration]) -> list[Declaration]:
    """The innermost declaration of each name (a quantifier's variable hides a parameter's)."""
    found: dict[str, Declaration] = {}
    for d in sorted(declarations, key=lambda d: (d.scope.line, d.scope.column) if d.scope else (0, 0)):
        found[d.key] = d
    return list(found.values())


def _argument_types(checked: Checked, cursor: context.Cursor) -> tuple[str, ...] | None:
    """The type(s) the atom's predicate wants at the argument under the cursor, None when unknown."""
    predicate = checked.analysis.index.find("predicate", cursor.atom)
    if predicate is None or cursor.position >= len(predicate.parameters):
        return None
    return tuple(t.lower() for t in predicate.parameters[cursor.position].types)


def _ancestors(checked: Checked, names: tuple[str, ...]) -> list[str]:
    """``names`` and every type above them (the index's parents), in lower case."""
    chain = [n.lower() for n in names] or ["object"]
    index = 0
    while index < len(chain):
        declaration = checked.analysis.index.find("type", chain[index])
        for parent in declaration.types if declaration else ():
            if parent.lower() not in chain:
                chain.append(parent.lower())
        index += 1
    return [*chain, "object"]
