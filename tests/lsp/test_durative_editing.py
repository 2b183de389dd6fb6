"""The language server on PDDL 2.1: numeric and temporal domains open clean, a durative action
hovers as an action, a numeric function renames across domain and problem, and a timed condition
written wrong is a diagnostic on its line."""

from pathlib import Path

import pytest
from helpers.lsp import ident
from lsprotocol import types

from vslsp.lsp.workspace import uri_of

pytestmark = pytest.mark.asyncio(loop_scope="module")

DATA = Path(__file__).resolve().parents[1] / "data" / "pddl21"


async def test_a_durative_action_hovers_and_a_timed_condition_is_checked(editor, tmp_path: Path):
    domain = tmp_path / "domain.pddl"
    text = (DATA / "rover-temporal-domain.pddl").read_text()
    domain.write_text(text)
    assert await editor.open(domain) == []
    at = editor.position_of(domain, "(:durative-action sample", offset=len("(:durative-action "))
    shown = await editor.client.text_document_hover_async(types.HoverParams(ident(domain), at))
    assert "sample" in shown.contents.value and "?r - rover" in shown.contents.value
    found = await editor.replace(domain, text.replace("(over all (road ?from ?to))", "(over al (road ?from ?to))"))
    assert any(d.range.start.line == 11 and "a durative action's condition is (at start" in d.message for d in found)
    await editor.close(domain)


async def test_a_numeric_function_renames_across_domain_and_problem(editor, tmp_path: Path):
    domain, problem = tmp_path / "domain.pddl", tmp_path / "problem.pddl"
    domain.write_text((DATA / "rover-numeric-domain.pddl").read_text())
    problem.write_text((DATA / "rover-numeric-problem.pddl").read_text())
    assert await editor.open(domain) == []
    assert await editor.open(problem) == []
    at = editor.position_of(problem, "(battery curiosity)", offset=2)
    edit = await editor.client.text_document_rename_async(
        types.RenameParams(text_document=ident(problem), position=at, new_name="charge")
    )
    assert set(edit.changes) == {uri_of(domain), uri_of(problem)}
    assert len(edit.changes[uri_of(domain)]) == 7 and len(edit.changes[uri_of(problem)]) == 1
    await editor.close(problem)
    await editor.close(domain)
