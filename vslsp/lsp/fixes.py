"""Diagnostics as LSP publishes them and the quick fixes the engine attaches to them (did-you-mean
replacements first, then declaring a missing predicate or type, which may edit the domain from a
problem)."""

from __future__ import annotations

from lsprotocol import types

from vslsp.lsp.analysis import Analyses, Checked
from vslsp.symbolic.language import ERROR, Diagnostic

SOURCE = "vslsp"


def to_lsp(checked: Checked, diagnostic: Diagnostic) -> types.Diagnostic:
    """The engine's diagnostic as LSP's: the same message as ``vslsp pddl check`` (did-you-mean included)."""
    hint = f" (did you mean '{diagnostic.suggestion}'?)" if diagnostic.suggestion else ""
    severity = types.DiagnosticSeverity.Error if diagnostic.severity == ERROR else types.DiagnosticSeverity.Warning
    return types.Diagnostic(
        range=checked.lines(checked.uri).range(diagnostic.span),
        message=diagnostic.message + hint,
        severity=severity,
        code=diagnostic.code,
        source=SOURCE,
    )


def published(analyses: Analyses, checked: Checked) -> list[types.Diagnostic]:
    """The document's diagnostics, less "never used" warnings about what its problems name."""
    found = checked.diagnostics()
    if not any(d.code.startswith("unused-") for d in found):
        return [to_lsp(checked, d) for d in found]
    used = analyses.names_in_problems(checked)
    lines = checked.lines(checked.uri)
    return [
        to_lsp(checked, d)
        for d in found
        if not (d.code.startswith("unused-") and _text(lines.line(d.span.line), d).lower() in used)
    ]


def _text(line: str, diagnostic: Diagnostic) -> str:
    return line[diagnostic.span.column - 1 : diagnostic.span.end_column - 1]


def code_actions(checked: Checked, wanted: types.Range) -> list[types.CodeAction]:
    """A quick fix for each fix of each diagnostic of the document that touches ``wanted``."""
    actions: list[types.CodeAction] = []
    for diagnostic in checked.diagnostics():
        shown = to_lsp(checked, diagnostic)
        if not _touches(shown.range, wanted):
            continue
        for number, fix in enumerate(diagnostic.fixes):
            uri = checked.uri_of(fix.span.file)
            edit = types.TextEdit(checked.lines(uri).range(fix.span), fix.text)  # the domain or the problem
            actions.append(
                types.CodeAction(
                    title=fix.title,
                    kind=types.CodeActionKind.QuickFix,
                    diagnostics=[shown],
                    edit=types.WorkspaceEdit(changes={uri: [edit]}),
                    is_preferred=number == 0 and diagnostic.suggestion is not None,
                )
            )
    return actions


def _touches(a: types.Range, b: types.Range) -> bool:
    start_a, end_a = (a.start.line, a.start.character), (a.end.line, a.end.character)
    start_b, end_b = (b.start.line, b.start.character), (b.end.line, b.end.character)
    return start_a <= end_b and start_b <= end_a
