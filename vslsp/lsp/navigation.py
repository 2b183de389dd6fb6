"""Hover, go to definition, find references, rename and the outline, from the engine's index.

A name declared in a domain (a predicate, type, constant, action, the domain's own name) is used in
the domain and in every problem for it (open, or a ``.pddl`` file beside the domain): references and
rename cover them all. An object belongs to its problem, a parameter or quantified variable to its
action or formula.
"""

from __future__ import annotations

import re
from pathlib import Path

from lsprotocol import types

from vslsp.lsp.analysis import Analyses, Checked
from vslsp.lsp.positions import Lines, characters, units
from vslsp.symbolic.language import Declaration, Span
from vslsp.symbolic.language.vocabulary import is_reserved_name, reserved_name_message

#: Declarations visible in a domain and all its problems.
_DOMAIN_WIDE = ("domain", "type", "constant", "predicate", "function", "action")
_RENAMABLE = (*_DOMAIN_WIDE, "problem", "object", "parameter", "variable")
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_\-]*\Z")
_WORD = re.compile(r"[^\s();:.]+")
_STEP = re.compile(r"\s*(?:\d+(?:\.\d+)?\s*[:.]\s*)?\(?\s*")
_SYMBOL_KINDS = {
    "domain": types.SymbolKind.Module,
    "problem": types.SymbolKind.Module,
    "requirement": types.SymbolKind.Key,
    "type": types.SymbolKind.Class,
    "constant": types.SymbolKind.Constant,
    "object": types.SymbolKind.Constant,
    "predicate": types.SymbolKind.Function,
    "function": types.SymbolKind.Function,
    "action": types.SymbolKind.Method,
    "parameter": types.SymbolKind.Variable,
}


def declaration_at(checked: Checked, line: int, column: int) -> Declaration | None:
    """The declaration named under the cursor, whether at its declaration or at a use."""
    found = checked.symbol_at(line, column)
    if found is None or isinstance(found, Declaration):
        return found
    return found.declaration


def hover(checked: Checked, line: int, column: int) -> types.Hover | None:
    """A name's signature (``(far ?b - block)``, ``(:action push :parameters (?b - block))``) and the
    comment above its declaration."""
    found = checked.symbol_at(line, column)
    if found is None:
        return None
    declaration = found if isinstance(found, Declaration) else found.declaration
    if declaration is None:
        return None
    return described(checked, declaration, checked.lines(checked.uri).range(found.span))


def described(checked: Checked, declaration: Declaration, shown: types.Range) -> types.Hover:
    """The hover of ``declaration`` over the range ``shown``."""
    parts = [f"```pddl\n{declaration.signature}\n```"]
    if declaration.comment:
        parts.append(declaration.comment)
    if declaration.span.file != checked.file:
        parts.append(f"*{declaration.kind} of {Path(declaration.span.file).name}, line {declaration.span.line}*")
    return types.Hover(types.MarkupContent(types.MarkupKind.Markdown, "\n\n".join(parts)), shown)


def definition(checked: Checked, line: int, column: int) -> types.Location | None:
    declaration = declaration_at(checked, line, column)
    if declaration is None:
        return None
    return location(checked, declaration.span)


def occurrences(analyses: Analyses, checked: Checked, line: int, column: int) -> list[tuple[str, Span]] | None:
    """Every place that names the declaration under the cursor, its declaration first, as (uri, span);
    None when the cursor is on no declared name."""
    target = declaration_at(checked, line, column)
    if target is None:
        return None
    searched = [checked]
    if target.kind in _DOMAIN_WIDE and checked.domain_uri is not None:
        for uri in [checked.domain_uri, *analyses.files.problems_of(checked.domain_uri)]:
            other = analyses.of(uri)
            if other is not None and other is not checked and other.domain_uri == checked.domain_uri:
                searched.append(other)
    places: dict[tuple[str, int, int], tuple[str, Span]] = {}
    for analysis in searched:
        same = _same_declaration(analysis, target)
        if same is None:
            continue
        for span in [same.span, *(r.span for r in analysis.analysis.index.references_to(same))]:
            uri = analysis.uri_of(span.file)
            places.setdefault((uri, span.line, span.column), (uri, span))
    return list(places.values())


def references(
    analyses: Analyses, checked: Checked, line: int, column: int, with_declaration: bool
) -> list[types.Location]:
    found = occurrences(analyses, checked, line, column) or []
    if not with_declaration:
        found = found[1:]
    return [types.Location(uri, _lines(analyses, checked, uri).range(span)) for uri, span in found]


def rename_range(checked: Checked, line: int, column: int) -> types.Range | None:
    """The name that a rename at the cursor would change, None where there is nothing to rename."""
    found = checked.symbol_at(line, column)
    declaration = found if found is None or isinstance(found, Declaration) else found.declaration
    if found is None or declaration is None or declaration.kind not in _RENAMABLE:
        return None
    return checked.lines(checked.uri).range(found.span)


def rename(analyses: Analyses, checked: Checked, line: int, column: int, new_name: str) -> types.WorkspaceEdit | None:
    """The edits renaming the declaration under the cursor everywhere it is named (ValueError for a
    name PDDL does not allow)."""
    declaration = declaration_at(checked, line, column)
    if declaration is None or declaration.kind not in _RENAMABLE:
        return None
    variable = declaration.name.startswith("?")
    bare = new_name[1:] if variable and new_name.startswith("?") else new_name
    if not _NAME.match(bare):
        raise ValueError(
            f"'{new_name}' is not a PDDL name: start with a letter, then letters, digits, '-' or '_'"
            + (" (after the '?')" if variable else "")
        )
    if is_reserved_name(bare):
        raise ValueError(reserved_name_message(bare, declaration.kind))
    new_text = f"?{bare}" if variable else bare
    changes: dict[str, list[types.TextEdit]] = {}
    for uri, span in occurrences(analyses, checked, line, column) or []:
        changes.setdefault(uri, []).append(types.TextEdit(_lines(analyses, checked, uri).range(span), new_text))
    return types.WorkspaceEdit(changes=changes)


def outline(checked: Checked) -> list[types.DocumentSymbol]:
    """The document's declarations as a tree: the domain or problem, then its types, constants,
    predicates, actions (with their parameters) and objects."""
    lines = checked.lines(checked.uri)
    declared = [d for d in checked.analysis.index.in_file(checked.file) if d.kind in _SYMBOL_KINDS]
    roots = [d for d in declared if d.kind in ("domain", "problem")]
    actions = [d for d in declared if d.kind == "action"]

    def symbol(d: Declaration, children: list[types.DocumentSymbol] | None = None) -> types.DocumentSymbol:
        extent = d.extent if _inside(d.span, d.extent) else d.span
        return types.DocumentSymbol(
            name=d.name,
            kind=_SYMBOL_KINDS[d.kind],
            range=lines.range(extent),
            selection_range=lines.range(d.span),
            detail=d.signature if d.kind not in ("domain", "problem", "requirement") else d.kind,
            children=children,
        )

    def parameters_of(action: Declaration) -> list[types.DocumentSymbol]:
        return [symbol(d) for d in declared if d.kind == "parameter" and _inside(d.span, action.extent)]

    members = [
        symbol(d, parameters_of(d)) if d.kind == "action" else symbol(d)
        for d in declared
        if d.kind not in ("domain", "problem", "parameter")
    ]
    members += [
        symbol(d) for d in declared if d.kind == "parameter" and not any(_inside(d.span, a.extent) for a in actions)
    ]
    if len(roots) == 1:
        return [symbol(roots[0], members)]
    return [symbol(d) for d in roots] + members


def in_plan(
    analyses: Analyses, uri: str, text: str, position: types.Position
) -> tuple[Checked, Declaration, types.Range] | None:
    """The action or object named under the cursor in a plan, as the domains and problems beside the plan
    declare it (for hover and go to definition), with the word's range."""
    lines = text.split("\n")
    line = lines[position.line] if position.line < len(lines) else ""
    encoding = analyses.encoding
    cursor = characters(line, position.character, encoding)
    for match in _WORD.finditer(line):
        if match.start() <= cursor <= match.end():
            break
    else:
        return None
    first = _STEP.match(line)
    is_action = first is not None and first.end() == match.start()
    files = analyses.files
    near = [u for u in files.neighbours(uri) if files.header(u).kind in ("domain", "problem")]
    for other in near:
        checked = analyses.of(other)
        if checked is None:
            continue
        index = checked.analysis.index
        found = (
            index.find("action", match.group())
            if is_action
            else index.find("object", match.group()) or index.find("constant", match.group())
        )
        if found is not None:
            shown = types.Range(
                types.Position(position.line, units(line[: match.start()], encoding)),
                types.Position(position.line, units(line[: match.end()], encoding)),
            )
            return checked, found, shown
    return None


def _same_declaration(checked: Checked, target: Declaration) -> Declaration | None:
    """``target`` as another analysis indexed it (the same kind, name and place)."""
    for declaration in checked.analysis.index.declarations:
        if declaration.kind == target.kind and declaration.span == target.span:
            return declaration
    return None


def _inside(inner: Span, outer: Span) -> bool:
    return (
        inner.file == outer.file
        and (outer.line, outer.column) <= (inner.line, inner.column)
        and (
            inner.end_line,
            inner.end_column,
        )
        <= (outer.end_line, outer.end_column)
    )


def location(checked: Checked, span: Span) -> types.Location:
    uri = checked.uri_of(span.file)
    return types.Location(uri, checked.lines(uri).range(span))


def _lines(analyses: Analyses, checked: Checked, uri: str) -> Lines:
    """Lines of ``uri`` as analysed (a problem's text may be another analysis's)."""
    if uri in checked.texts:
        return checked.lines(uri)
    other = analyses.of(uri)
    return other.lines(uri) if other is not None else checked.lines(uri)
