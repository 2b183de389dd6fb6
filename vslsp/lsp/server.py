"""``vslsp lsp``: the PDDL language server (LSP 3.17 over stdin/stdout, pygls).

Every open domain and problem is checked by the language engine (:mod:`vslsp.symbolic.language`) on
open and on every change, and its diagnostics published; a changed domain re-checks the open
problems for it. The requests (completion, hover, definition, references, rename, outline, quick
fixes) read the same analysis; ``vslsp.plan`` and ``vslsp.validate`` run ``vslsp plan/validate --json``
as a child process (the editor keeps its diagnostics while Fast Downward searches). The frames are
read by :mod:`vslsp.lsp.rpc` and each message checked by :mod:`vslsp.lsp.protocol` before pygls
takes it (docs/bad-input.md, "The language server").
"""

from __future__ import annotations

import asyncio
import logging
import os
import sys
from typing import Any, BinaryIO

from lsprotocol import types
from pygls.io_ import StdoutWriter
from pygls.lsp.server import LanguageServer

from vslsp import __version__
from vslsp.lsp import completion, fixes, navigation
from vslsp.lsp.analysis import Analyses, Checked
from vslsp.lsp.commands import PLAN_OPTIONS, findings, named, plan_arguments, run_cli, sources, told, validate_arguments
from vslsp.lsp.operators import operator_hover
from vslsp.lsp.positions import UTF16, clamped
from vslsp.lsp.protocol import PddlProtocol, RequestFailed, strict_converter
from vslsp.lsp.rpc import Framer, read_stream
from vslsp.lsp.workspace import DOMAIN, PLAN, PROBLEM, Files
from vslsp.symbolic.language import Diagnostic

logger = logging.getLogger("vslsp.lsp")
#: A document of this many characters or more is re-checked when the edits pause (its analysis takes
#: tens of milliseconds or more; the engine reads about 1 MB a second).
LARGE = 100_000
PAUSE_S = 0.3
PLAN_COMMAND = "vslsp.plan"
VALIDATE_COMMAND = "vslsp.validate"


class PddlServer(LanguageServer):
    """The server's state: the open documents (as the client names them) and their analyses."""

    def __init__(self) -> None:
        super().__init__(
            "vslsp",
            __version__,
            text_document_sync_kind=types.TextDocumentSyncKind.Incremental,
            protocol_cls=PddlProtocol,
            converter_factory=strict_converter,
        )
        self.protocol: PddlProtocol
        self.opened: dict[str, None] = {}  # in the order opened
        #: the problem and the plan last opened or edited: what vslsp.plan and vslsp.validate take by default
        self.last: dict[str, str] = {}
        self._pending: dict[str, asyncio.TimerHandle] = {}
        self._findings: dict[
            str, list[Diagnostic]
        ] = {}  # the last command's conflict or violations, by uri  # large documents' re-checks waiting for a pause
        self.files = Files(self._open_texts)
        self.analyses = Analyses(self.files)

    def _open_texts(self) -> dict[str, str]:
        return {uri: self.workspace.get_text_document(uri).source for uri in reversed(self.opened)}  # latest first

    def analysis(self, uri: str) -> Checked | None:
        return self.analyses.of(uri)

    def clamped(self, uri: str, position: types.Position) -> types.Position:
        """``position`` moved inside the document ``uri`` (a place past its end is its end: LSP 3.17)."""
        text = self.files.text(uri)
        return position if text is None else clamped(text, position, self.analyses.encoding)

    def clamped_range(self, uri: str, given: types.Range) -> types.Range:
        return types.Range(self.clamped(uri, given.start), self.clamped(uri, given.end))

    def found(self, by_uri: dict[str, list[Diagnostic]]) -> None:
        """Show a command's findings (a conflict, violations) among the documents' diagnostics until the
        next edit; the previous command's go."""
        stale = set(self._findings)
        self._findings = by_uri
        for uri in (stale | set(by_uri)) & set(self.opened):
            self.publish(uri)

    def changed(self, uri: str) -> None:
        """Re-check an edited document: at once when it is small (a few ms), else once the edits pause for
        :data:`PAUSE_S`, so that typing in a large generated problem re-checks it once, not per key. A
        command's findings describe the texts as they were: they go."""
        if self._findings:
            stale, self._findings = set(self._findings) - {uri}, {}
            for other in stale & set(self.opened):
                self.publish(other)
        pending = self._pending.pop(uri, None)
        if pending is not None:
            pending.cancel()
        if len(self.workspace.get_text_document(uri).source) < LARGE:
            self.publish(uri)
        else:
            self._pending[uri] = asyncio.get_running_loop().call_later(PAUSE_S, self.publish, uri)

    def publish(self, uri: str) -> None:
        """Check ``uri`` and publish its diagnostics; a domain also re-checks the open problems for it, a
        domain or problem the open plans."""
        targets = [uri]
        header = self.files.header(uri)
        if header.kind in (PROBLEM, PLAN):
            self.last[header.kind] = uri
        if header.kind == DOMAIN:
            targets += [p for p in self.files.problems_of(uri) if p in self.opened]
        elif header.kind == PROBLEM:  # what the problem uses may end the domain's "never used" warnings
            domain = self.files.domain_for(uri)
            targets += [domain] if domain in self.opened else []
        if header.kind in (DOMAIN, PROBLEM):
            targets += [u for u in self.opened if self.files.header(u).kind == PLAN]
        for target in targets:
            try:
                checked = self.analyses.of(target)
                diagnostics = fixes.published(self.analyses, checked) if checked is not None else []
                if checked is not None:
                    diagnostics += [fixes.to_lsp(checked, d) for d in self._findings.get(target, [])]
            except Exception:  # a bug of ours must not cost the editor its server: logged, nothing shown
                logger.exception("checking %s failed", target)
                continue
            version = self.workspace.get_text_document(target).version if target in self.opened else None
            self.text_document_publish_diagnostics(
                types.PublishDiagnosticsParams(uri=target, diagnostics=diagnostics, version=version)
            )


def build_server() -> PddlServer:
    """A server with every feature registered (not yet started)."""
    server = PddlServer()

    @server.feature(types.INITIALIZED)
    def initialized(ls: PddlServer, params: types.InitializedParams) -> None:
        ls.analyses.encoding = str(ls.workspace.position_encoding or UTF16)

    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: PddlServer, params: types.DidOpenTextDocumentParams) -> None:
        ls.opened[params.text_document.uri] = None
        ls.publish(params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: PddlServer, params: types.DidChangeTextDocumentParams) -> None:
        ls.changed(params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: PddlServer, params: types.DidSaveTextDocumentParams) -> None:
        ls.publish(params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: PddlServer, params: types.DidCloseTextDocumentParams) -> None:
        uri = params.text_document.uri
        ls.opened.pop(uri, None)
        pending = ls._pending.pop(uri, None)
        if pending is not None:
            pending.cancel()
        ls.analyses.forget(uri)
        ls.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))
        for other in list(ls.opened):  # problems and plans read the closed file from disk now
            if ls.files.header(other).kind in (PROBLEM, PLAN):
                ls.publish(other)

    @server.feature(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["(", ":", "?", "-"]))
    def complete(ls: PddlServer, params: types.CompletionParams) -> types.CompletionList:
        uri = params.text_document.uri
        return completion.complete(ls.analyses, uri, ls.files.text(uri) or "", ls.clamped(uri, params.position))

    @server.feature(types.TEXT_DOCUMENT_HOVER)
    def hover(ls: PddlServer, params: types.HoverParams) -> types.Hover | None:
        uri = params.text_document.uri
        position = ls.clamped(uri, params.position)
        if ls.files.header(uri).kind == PLAN:
            step = navigation.in_plan(ls.analyses, uri, ls.files.text(uri) or "", position)
            return navigation.described(*step) if step else None
        found = _at(ls, uri, position)
        shown = navigation.hover(*found) if found else None
        if shown is None and found is not None:  # a PDDL 3.0 operator: its meaning
            shown = operator_hover(ls.files.text(uri) or "", position, found[2] - 1)
        return shown

    @server.feature(types.TEXT_DOCUMENT_DEFINITION)
    def definition(ls: PddlServer, params: types.DefinitionParams) -> types.Location | None:
        uri = params.text_document.uri
        position = ls.clamped(uri, params.position)
        if ls.files.header(uri).kind == PLAN:
            step = navigation.in_plan(ls.analyses, uri, ls.files.text(uri) or "", position)
            return navigation.location(step[0], step[1].span) if step else None
        found = _at(ls, uri, position)
        return navigation.definition(*found) if found else None

    @server.feature(types.TEXT_DOCUMENT_REFERENCES)
    def references(ls: PddlServer, params: types.ReferenceParams) -> list[types.Location]:
        found = _at(ls, params.text_document.uri, params.position)
        if not found:
            return []
        return navigation.references(ls.analyses, *found, params.context.include_declaration)

    @server.feature(types.TEXT_DOCUMENT_PREPARE_RENAME)
    def prepare_rename(ls: PddlServer, params: types.PrepareRenameParams) -> types.Range | None:
        found = _at(ls, params.text_document.uri, params.position)
        return navigation.rename_range(*found) if found else None

    @server.feature(types.TEXT_DOCUMENT_RENAME)
    def rename(ls: PddlServer, params: types.RenameParams) -> types.WorkspaceEdit | None:
        found = _at(ls, params.text_document.uri, params.position)
        try:
            return navigation.rename(ls.analyses, *found, params.new_name) if found else None
        except ValueError as refused:  # a name PDDL does not allow: the editor shows the message
            raise RequestFailed(str(refused)) from None

    @server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    def symbols(ls: PddlServer, params: types.DocumentSymbolParams) -> list[types.DocumentSymbol]:
        checked = ls.analysis(params.text_document.uri)
        return navigation.outline(checked) if checked is not None else []

    @server.feature(
        types.TEXT_DOCUMENT_CODE_ACTION, types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix])
    )
    def code_action(ls: PddlServer, params: types.CodeActionParams) -> list[types.CodeAction]:
        uri = params.text_document.uri
        checked = ls.analysis(uri)
        return fixes.code_actions(checked, ls.clamped_range(uri, params.range)) if checked is not None else []

    @server.command(PLAN_COMMAND)
    async def plan(ls: PddlServer, *arguments: Any) -> dict[str, Any]:
        """``vslsp.plan`` with ``[]`` (the problem last opened or edited), ``[PROBLEM]``, ``[DOMAIN, PROBLEM]``
        or ``[{"domain", "problem", "planner", "compilation", "timeout", "memory"}]`` (URIs or paths):
        ``vslsp plan --json``'s object, also shown to the user as a message."""
        given = named(arguments, ("domain", "problem"), ls.last)
        options = {k: given[k] for k in PLAN_OPTIONS if given.get(k) is not None}
        failure = {"plan": None, "planner": options.get("planner", "fast-downward")}
        found, result = sources(ls.files, given, ("domain", "problem"), failure)
        if not result:
            result = await run_cli(plan_arguments, found, options, failure)
        ls.window_show_message(told(PLAN_COMMAND, result))
        ls.found(findings(result, ls.files.text))
        return result

    @server.command(VALIDATE_COMMAND)
    async def validate(ls: PddlServer, *arguments: Any) -> dict[str, Any]:
        """``vslsp.validate`` with ``[]`` (the problem and plan last opened or edited), ``[PROBLEM, PLAN]``,
        ``[DOMAIN, PROBLEM, PLAN]`` or ``[{"domain", "problem", "plan"}]``: ``vslsp validate --json``'s object,
        also shown as a message."""
        given = named(arguments, ("domain", "problem", "plan"), ls.last)
        found, result = sources(ls.files, given, ("domain", "problem", "plan"), {"valid": None})
        if not result:
            result = await run_cli(validate_arguments, found, {}, {"valid": None})
        ls.window_show_message(told(VALIDATE_COMMAND, result))
        ls.found(findings(result, ls.files.text))
        return result

    return server


def _at(ls: PddlServer, uri: str, position: types.Position) -> tuple[Checked, int, int] | None:
    """The analysis of ``uri`` and the 1-based place of ``position`` in it."""
    checked = ls.analysis(uri)
    if checked is None:
        return None
    line, column = checked.lines(uri).place(ls.clamped(uri, position))
    return checked, line, column


def serve() -> None:
    """Run the server on this process's stdin/stdout until the client ends it; the exit code is 1 when
    ``exit`` came without ``shutdown`` (LSP 3.17), else 0."""
    logging.basicConfig(level=logging.WARNING, stream=sys.stderr, format="vslsp lsp: %(levelname)s: %(message)s")
    # stdout carries only the protocol: whatever else writes there (a print, a planner's child
    # process) goes to stderr, the editor's log.
    protocol_out = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())
    sys.stdout = sys.stderr
    code = run(build_server(), sys.stdin.fileno(), protocol_out)
    if code:
        sys.exit(code)


def run(server: PddlServer, stdin: int, stdout: BinaryIO) -> int:
    """Serve the client on the file descriptor ``stdin`` and the stream ``stdout`` until ``exit`` or
    the end of stdin; the exit code."""
    server.protocol.set_writer(StdoutWriter(stdout))
    try:
        asyncio.run(read_stream(stdin, Framer(), server.protocol.receive))
    except (BrokenPipeError, ConnectionResetError):
        logger.error("the client closed the connection")
    finally:
        server.shutdown()
    return server.protocol.exit_code or 0
