"""Positions in the code units agreed at initialize: Neovim asks for UTF-8 first, and then every range
the server sends and every position it reads counts UTF-8 bytes (VS Code's UTF-16 is in
test_diagnostics.py)."""

from pathlib import Path

import pytest
import pytest_lsp
from helpers.lsp import SERVER
from lsprotocol import types
from pytest_lsp import LanguageClient, client_capabilities

from vslsp.lsp.workspace import uri_of

pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest_lsp.fixture(config=SERVER, scope="module")
async def client(lsp_client: LanguageClient, workspace: Path):
    result = await lsp_client.initialize_session(
        types.InitializeParams(capabilities=client_capabilities("neovim"), root_uri=uri_of(workspace))
    )
    assert result.capabilities.position_encoding == types.PositionEncodingKind.Utf8
    yield
    await lsp_client.shutdown_session()


async def test_ranges_and_completion_count_utf8_bytes(editor, workspace: Path):
    problem = workspace / "kitchen" / "problem.pddl"
    text = (
        problem.read_text()
        .replace("mug - cup", "tasse\u0301 - cup")  # a combining accent: 1 character, 2 bytes
        .replace("(:init (on-counter mug)", "(:init (on-counter tasse\u0301) (hand-emty)")
        .replace("(clean mug)", "(clean tasse\u0301)")
        .replace("(on-counter mug)", "(on-counter tasse\u0301)")
    )
    found = await editor.open(problem, text)
    (typo,) = [d for d in found if "hand-emty" in d.message]
    line = text.split("\n")[typo.range.start.line]
    before = line[: line.index("hand-emty")]
    assert typo.range.start.character == len(before.encode("utf-8")) == len(before) + 1
    assert typo.range.end.character - typo.range.start.character == len("hand-emty")
    # completion at the end of "(hand-e" after the accented name: the edit replaces exactly "hand-e"
    at = types.Position(typo.range.start.line, typo.range.start.character + len("hand-e"))
    result = await editor.client.text_document_completion_async(
        types.CompletionParams(types.TextDocumentIdentifier(uri_of(problem)), at)
    )
    (item,) = [i for i in result.items if i.label == "hand-empty"]
    assert (item.text_edit.range.start.character, item.text_edit.range.end.character) == (
        typo.range.start.character,
        at.character,
    )
    await editor.close(problem)
