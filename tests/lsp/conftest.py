"""A real ``vslsp lsp`` process per test module, driven over stdio by pytest-lsp's client, on copies of
the kitchen domain (tests/lsp/data) and the shipped PDDL (helpers: tests/helpers/lsp.py)."""

from pathlib import Path

import pytest
import pytest_lsp
from helpers.lsp import SERVER, Editor, copy_examples, start
from pytest_lsp import LanguageClient


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return copy_examples(tmp_path_factory.mktemp("workspace"))


@pytest_lsp.fixture(config=SERVER, scope="module")
async def client(lsp_client: LanguageClient, workspace: Path):
    lsp_client.initialize_result = await start(lsp_client, workspace)  # type: ignore[attr-defined]
    yield
    await lsp_client.shutdown_session()


@pytest.fixture(scope="module")
def editor(client: LanguageClient) -> Editor:
    return Editor(client)
