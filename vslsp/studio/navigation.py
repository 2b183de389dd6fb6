"""Go to definition, find references, rename and the outline in the author page's editors, from the
language engine's index (:mod:`vslsp.symbolic.language`), as the language server gives them
(:mod:`vslsp.lsp.navigation`), on the two texts of the page instead of a workspace.

Positions are character offsets of an editor's text (code points, as Python counts) on the way in,
1-based lines and columns on the way out, with the editor (``domain`` or ``problem``) they are in.
"""

from __future__ import annotations

import re
from typing import Any

from vslsp.errors import InputError
from vslsp.symbolic.language import Declaration, Span, analyse

#: Declarations that can be renamed (every place that names one is changed).
RENAMABLE = (
    "domain",
    "problem",
    "type",
    "constant",
    "predicate",
    "function",
    "action",
    "object",
    "parameter",
    "variable",
)
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_\-]*\Z")


def _line_column(text: str, at: int) -> tuple[int, int]:
    before = text[: max(0, min(at, len(text)))]
    line = before.count("\n") + 1
    return line, len(before) - (before.rfind("\n") + 1) + 1


def _place(span: Span, editors: dict[str, str]) -> dict[str, Any]:
    editor = next((kind for kind, file in editors.items() if file == span.file), None)
    place = {"line": span.line, "column": span.column, "end_line": span.end_line, "end_column": span.end_column}
    return {"in": editor, "file": span.file, **place}


def navigate(
    domain: str,
    problem: str | None,
    editor: str,
    at: int,
    what: str,
    new_name: str | None = None,
    domain_file: str = "<domain>",
    problem_file: str = "<problem>",
) -> dict[str, Any]:
    """``what`` at offset ``at`` of ``editor``'s text:

    - ``definition``: ``{"name", "kind", "signature", "locations": [place]}`` (the declaration);
    - ``references``: ``{"name", "kind", "locations": [place, ...]}`` (the declaration first, then each use);
    - ``rename`` (with ``new_name``): ``{"name", "edits": [place + "text"]}``, every place that names it;
      a name PDDL does not allow, or a word PDDL reserves, is an InputError;
    - ``outline``: ``{"outline": [{"kind", "name", "line", "column", "children"}]}`` of ``editor``'s file.

    A place is ``{"in": "domain"|"problem", "file", "line", "column", "end_line", "end_column"}``. Where
    the cursor names nothing: ``{"name": None, "locations": []}`` (``edits`` for rename)."""
    if editor not in ("domain", "problem"):
        raise InputError(f"'in' must be domain or problem, got {editor!r}")
    analysis = analyse(domain, domain_file, problem or None, problem_file)
    files = {"domain": domain_file, "problem": problem_file}
    if what == "outline":
        return {"outline": outline(analysis.index.in_file(files[editor]))}
    text = domain if editor == "domain" else problem or ""
    if not 0 <= at <= len(text):
        raise InputError(f"'at' must be an offset in the {editor} text (0 to {len(text)}), got {at!r}")
    line, column = _line_column(text, at)
    index = analysis.index
    found = index.symbol_at(files[editor], line, column)
    if found is None and column > 1:  # the cursor just after a name still means that name
        found = index.symbol_at(files[editor], line, column - 1)
    target = found if found is None or isinstance(found, Declaration) else found.declaration
    empty_key = "edits" if what == "rename" else "locations"
    if target is None:
        return {"name": None, empty_key: []}
    places = [target.span, *(reference.span for reference in index.references_to(target))]
    if what == "definition":
        return {
            "name": target.name,
            "kind": target.kind,
            "signature": target.signature,
            "locations": [_place(target.span, files)],
        }
    if what == "references":
        return {"name": target.name, "kind": target.kind, "locations": [_place(span, files) for span in places]}
    if what == "rename":
        if target.kind not in RENAMABLE:
            raise InputError(f"a {target.kind} cannot be renamed")
        new_text = renamed(target.name, new_name, target.kind)
        return {"name": target.name, "edits": [{**_place(span, files), "text": new_text} for span in places]}
    raise InputError(f"'what' must be definition, references, rename or outline, got {what!r}")


def renamed(old: str, new_name: object, what: str = "name") -> str:
    """The text a rename of ``old`` (a ``what``: predicate, object ...) to ``new_name`` writes (``?x`` for a
    variable), or InputError for a name PDDL does not allow (a keyword of PDDL is none: ``and``, ``either``,
    ``forall``...; the language engine's one message)."""
    from vslsp.symbolic.language import is_reserved_name, reserved_name_message

    if not isinstance(new_name, str) or not new_name:
        raise InputError("give the new name")
    variable = old.startswith("?")
    bare = new_name[1:] if variable and new_name.startswith("?") else new_name
    if not _NAME.match(bare):
        raise InputError(
            f"'{new_name}' is not a PDDL name: start with a letter, then letters, digits, '-' or '_'"
            + (" (after the '?')" if variable else "")
        )
    if not variable and is_reserved_name(bare):
        raise InputError(reserved_name_message(bare, what))
    return f"?{bare}" if variable else bare


def outline(declarations: list[Declaration]) -> list[dict[str, Any]]:
    """The declarations of one file as a tree: each action with its parameters under it."""
    shown = [
        d
        for d in declarations
        if d.kind in ("domain", "problem", "type", "constant", "object", "predicate", "function", "action")
    ]
    tree = []
    for declaration in shown:
        children = []
        if declaration.kind == "action":
            children = [
                {"kind": "parameter", "name": p.name, "line": p.span.line, "column": p.span.column, "children": []}
                for p in declaration.parameters
            ]
        span = declaration.span
        tree.append(
            {
                "kind": declaration.kind,
                "name": declaration.name,
                "line": span.line,
                "column": span.column,
                "children": children,
            }
        )
    return tree
