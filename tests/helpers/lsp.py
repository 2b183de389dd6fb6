"""Driving ``vslsp lsp`` from a test: a pytest-lsp client talking to the real server process over stdio,
and an editor's moves (open, change, ask) on real PDDL files."""

from __future__ import annotations

import asyncio
import shutil
import sys
from pathlib import Path

from lsprotocol import types
from pygls.protocol import default_converter
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities
from pytest_lsp.client import DEFAULT_CLIENT_FEATURES, register_lsp_features

from vslsp.lsp.workspace import uri_of

DATA = Path(__file__).parents[1] / "lsp" / "data"
SHIPPED = Path(__file__).parents[2] / "pddl"


def _published(client: LanguageClient, params: types.PublishDiagnosticsParams) -> None:
    client.diagnostics[params.uri] = params.diagnostics
    client.diagnostic_versions[params.uri] = params.version  # type: ignore[attr-defined]
    client.publications.setdefault(params.uri, []).append(params.version)  # type: ignore[attr-defined]


def make_client() -> LanguageClient:
    """pytest-lsp's test client that also keeps the document version each diagnostics were published for."""
    client = LanguageClient(converter_factory=default_converter)
    client.diagnostic_versions = {}  # type: ignore[attr-defined]
    client.publications = {}  # type: ignore[attr-defined]  # uri -> the versions published, in order
    register_lsp_features(client, {**DEFAULT_CLIENT_FEATURES, types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS: _published})
    return client


SERVER = ClientServerConfig(server_command=[sys.executable, "-m", "vslsp", "lsp"], client_factory=make_client)
#: How long a test waits for the server's diagnostics before failing (a hang guard, not a speed test).
PATIENCE_S = 60.0


def copy_examples(folder: Path) -> Path:
    """The kitchen domain and problem and the shipped PDDL files, copied into ``folder``."""
    shutil.copytree(DATA / "kitchen", folder / "kitchen")
    shutil.copytree(SHIPPED, folder / "shipped", ignore=shutil.ignore_patterns("*.py", "__pycache__"))
    return folder


async def start(client: LanguageClient, root: Path) -> types.InitializeResult:
    return await client.initialize_session(
        types.InitializeParams(
            capabilities=client_capabilities("visual-studio-code"),
            root_uri=uri_of(root),
            workspace_folders=[types.WorkspaceFolder(uri_of(root), root.name)],
        )
    )


class Editor:
    """An editor's session: open documents (from disk or given text), edits, and the diagnostics the
    server publishes for each."""

    def __init__(self, client: LanguageClient):
        self.client = client
        self.versions: dict[str, int] = {}
        self.texts: dict[str, str] = {}

    async def open(self, path: Path, text: str | None = None, language: str = "pddl") -> list[types.Diagnostic]:
        """Open ``path`` (its text on disk unless ``text``), return the diagnostics published for it."""
        uri = uri_of(path)
        text = path.read_text() if text is None else text
        self.versions[uri] = 1
        self.texts[uri] = text
        self.client.diagnostics.pop(uri, None)
        self.client.text_document_did_open(
            types.DidOpenTextDocumentParams(types.TextDocumentItem(uri, language, 1, text))
        )
        return await self.diagnostics(uri)

    async def replace(self, path: Path, text: str) -> list[types.Diagnostic]:
        """Send the whole new text of an open document as one change; its new diagnostics."""
        uri = uri_of(path)
        self.versions[uri] += 1
        self.texts[uri] = text
        self.client.diagnostics.pop(uri, None)
        self.client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                types.VersionedTextDocumentIdentifier(self.versions[uri], uri),
                [types.TextDocumentContentChangeWholeDocument(text)],
            )
        )
        return await self.diagnostics(uri)

    async def type_at(self, path: Path, line: int, character: int, inserted: str) -> list[types.Diagnostic]:
        """Insert ``inserted`` at a 0-based place (an incremental change, as editors send keystrokes)."""
        uri = uri_of(path)
        self.versions[uri] += 1
        lines = self.texts[uri].split("\n")
        lines[line] = lines[line][:character] + inserted + lines[line][character:]
        self.texts[uri] = "\n".join(lines)
        at = types.Position(line, character)
        self.client.diagnostics.pop(uri, None)
        self.client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                types.VersionedTextDocumentIdentifier(self.versions[uri], uri),
                [types.TextDocumentContentChangePartial(types.Range(at, at), inserted)],
            )
        )
        return await self.diagnostics(uri)

    async def close(self, path: Path) -> None:
        uri = uri_of(path)
        self.client.text_document_did_close(types.DidCloseTextDocumentParams(types.TextDocumentIdentifier(uri)))
        self.versions.pop(uri, None)
        self.texts.pop(uri, None)

    async def diagnostics(self, uri: str) -> list[types.Diagnostic]:
        """The diagnostics published for ``uri``'s present version (waits for them)."""
        published = self.client.diagnostic_versions  # type: ignore[attr-defined]
        for _ in range(int(PATIENCE_S / 0.01)):
            if uri in self.client.diagnostics and published.get(uri) == self.versions.get(uri):
                return list(self.client.diagnostics[uri])
            await asyncio.sleep(0.01)
        raise AssertionError(f"the server published no diagnostics for {uri}")

    def position_of(self, path: Path, needle: str, occurrence: int = 1, offset: int = 0) -> types.Position:
        """The 0-based position of the ``occurrence``-th ``needle`` in the open text (plus ``offset`` characters)."""
        text = self.texts[uri_of(path)]
        index = -1
        for _ in range(occurrence):
            index = text.index(needle, index + 1)
        index += offset
        line = text.count("\n", 0, index)
        return types.Position(line, index - (text.rfind("\n", 0, index) + 1))


def ident(path: Path) -> types.TextDocumentIdentifier:
    return types.TextDocumentIdentifier(uri_of(path))


def apply_edits(text: str, edits: list[types.TextEdit]) -> str:
    """``text`` with ``edits`` applied (as an editor applies a workspace edit to one document)."""
    lines = text.split("\n")
    for edit in sorted(edits, key=lambda e: (e.range.start.line, e.range.start.character), reverse=True):
        start, end = edit.range.start, edit.range.end
        head = "\n".join(lines[: start.line] + [lines[start.line][: start.character]])
        tail = "\n".join([lines[end.line][end.character :]] + lines[end.line + 1 :])
        lines = (head + edit.new_text + tail).split("\n")
    return "\n".join(lines)


async def code_actions(editor, path: Path, diagnostic: types.Diagnostic) -> list[types.CodeAction]:
    """The quick fixes the server offers for ``diagnostic`` of the document at ``path``."""
    found = await editor.client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=ident(path),
            range=diagnostic.range,
            context=types.CodeActionContext(diagnostics=[diagnostic], only=[types.CodeActionKind.QuickFix]),
        )
    )
    assert all(isinstance(action, types.CodeAction) for action in found)
    return list(found)
