"""Diagnostics on open and on every change, per document, with the engine's messages, severities and
ranges; a problem is checked with the domain it names (open, or beside it on disk)."""

from pathlib import Path

import pytest
from lsprotocol import types

pytestmark = pytest.mark.asyncio(loop_scope="module")

ERROR = types.DiagnosticSeverity.Error
WARNING = types.DiagnosticSeverity.Warning


def _at(diagnostic: types.Diagnostic) -> tuple[int, int, int, int]:
    r = diagnostic.range
    return (r.start.line, r.start.character, r.end.line, r.end.character)


async def test_the_shipped_domain_and_problems_open_without_errors(editor, workspace: Path):
    shipped = workspace / "shipped"
    assert await editor.open(shipped / "domain.pddl") == []
    for name in ("pull-in-order.pddl", "simple-push-pull.pddl"):
        assert await editor.open(shipped / name) == [], name
    # keep-all-near quantifies over blocks in a constraint: a requirement its domain does not declare
    found = await editor.open(shipped / "keep-all-near.pddl")
    assert [(d.severity, d.code) for d in found] == [(WARNING, "undeclared-requirement")]
    for name in ("domain.pddl", "pull-in-order.pddl", "simple-push-pull.pddl", "keep-all-near.pddl"):
        await editor.close(shipped / name)


async def test_a_typo_is_an_error_at_the_token_with_did_you_mean(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    assert await editor.open(domain) == []
    text = domain.read_text().replace("(and (on-counter ?d) (hand-empty))", "(and (on-counter ?d) (hand-emty))")
    found = await editor.replace(domain, text)
    assert [(d.severity, d.message, d.code, d.source) for d in found] == [
        (ERROR, "unknown predicate 'hand-emty' (did you mean 'hand-empty'?)", "unknown-predicate", "vslsp")
    ]
    start = editor.position_of(domain, "hand-emty")
    assert _at(found[0]) == (start.line, start.character, start.line, start.character + len("hand-emty"))
    assert await editor.replace(domain, domain.read_text()) == []  # fixed: the error goes
    await editor.close(domain)


async def test_every_error_of_a_file_at_once_and_warnings(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    text = (
        domain.read_text()
        .replace(":effect (clean ?d))", ":effect (claen ?d))")
        .replace("(:types cup plate - dish", "(:types cup plate - dish bowl - vessel")
    )
    await editor.open(domain)
    found = await editor.replace(domain, text)
    messages = {(d.severity, d.message) for d in found}
    assert (ERROR, "unknown predicate 'claen' (did you mean 'clean'?)") in messages
    assert any(s == WARNING and "vessel" in m for s, m in messages)  # the undeclared parent type
    assert any(s == WARNING and "'bowl'" in m and "never used" in m for s, m in messages)
    await editor.close(domain)


async def test_keystrokes_are_incremental_changes(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    await editor.open(domain)
    at = editor.position_of(domain, "(holding ?d))", occurrence=1)
    found = await editor.type_at(domain, at.line, at.character + 1, "x")  # (xholding ?d)
    assert [d.message for d in found] == ["unknown predicate 'xholding' (did you mean 'holding'?)"]
    found = await editor.type_at(domain, at.line, at.character + 1, "(")  # an unclosed parenthesis
    assert any(d.code == "unclosed-parenthesis" for d in found)
    await editor.close(domain)


async def test_a_problem_is_checked_against_its_open_domain_and_follows_its_edits(editor, workspace: Path):
    kitchen = workspace / "kitchen"
    domain, problem = kitchen / "domain.pddl", kitchen / "problem.pddl"
    await editor.open(domain)
    text = problem.read_text().replace("sometime-before", "sometimes-before").replace("mug - cup", "mug - cupp")
    found = await editor.open(problem, text)
    assert sorted(d.message for d in found) == [
        "undefined type 'cupp' (did you mean 'cup'?)",
        "unknown PDDL 3 operator 'sometimes-before' (did you mean 'sometime-before'?)",
    ]
    assert all(d.severity == ERROR for d in found)
    # renaming a predicate in the open domain (unsaved) re-checks the open problem
    editor.client.diagnostics.pop(editor_uri := _uri(problem), None)
    await editor.replace(domain, domain.read_text().replace("(clean ", "(washed "))
    found = await editor.diagnostics(editor_uri)
    assert "unknown predicate 'clean'" in " ".join(d.message for d in found)
    await editor.close(problem)
    await editor.close(domain)


async def test_a_problem_finds_its_domain_on_disk_or_says_it_is_missing(editor, workspace: Path, tmp_path: Path):
    alone = tmp_path / "problem.pddl"  # a folder with no domain file
    alone.write_text(
        (workspace / "kitchen" / "problem.pddl").read_text().replace("(:domain kitchen)", "(:domain kitchn)")
    )
    found = await editor.open(alone)
    assert [(d.severity, d.code) for d in found] == [(WARNING, "domain-not-found")]
    assert "no domain 'kitchn'" in found[0].message
    beside = tmp_path / "domain.pddl"  # the domain put beside it, never opened
    beside.write_text(
        (workspace / "kitchen" / "domain.pddl").read_text().replace("(domain kitchen)", "(domain kitchn)")
    )
    found = await editor.replace(alone, alone.read_text().replace("(on-counter mug)", "(on-countr mug)", 1))
    assert [d.message for d in found] == ["unknown predicate 'on-countr' (did you mean 'on-counter'?)"]
    await editor.close(alone)


def _uri(path: Path) -> str:
    from vslsp.lsp.workspace import uri_of

    return uri_of(path)


async def test_a_file_that_is_no_pddl_gets_no_diagnostics(editor, tmp_path: Path):
    notes = tmp_path / "notes.txt"
    assert await editor.open(notes, "shopping: (milk) (bread", language="plaintext") == []
    await editor.close(notes)


async def test_ranges_count_utf16_code_units_as_lsp_does(editor, workspace: Path):
    problem = workspace / "kitchen" / "problem.pddl"
    text = (
        problem.read_text()
        .replace("mug - cup", "\U0001d465mug - cup")  # a name with a character outside the BMP: 2 UTF-16 units
        .replace(
            "(:init (on-counter mug) (on-counter saucer) (hand-empty))",
            "(:init (on-counter \U0001d465mug) (hand-emty))",
        )
        .replace("(clean mug)", "(clean \U0001d465mug)")
        .replace("(on-counter mug)", "(on-counter \U0001d465mug)")
    )
    found = await editor.open(problem, text)
    (typo,) = [d for d in found if "hand-emty" in d.message]
    line = text.split("\n")[typo.range.start.line]
    before = line[: line.index("hand-emty")]
    assert typo.range.start.character == len(before.encode("utf-16-le")) // 2 == len(before) + 1
    await editor.close(problem)


async def test_a_plan_is_checked_against_the_problem_beside_it_with_fixes(editor, workspace: Path):
    kitchen = workspace / "kitchen"
    plan = kitchen / "typed.plan"
    found = await editor.open(plan, "0: (pick saucer)\n1: (wahs saucer)\n2: (put-down sauce)\n3: (wash)\n", "plan")
    assert [(d.range.start.line, d.message, d.code) for d in found] == [
        (1, "unknown action 'wahs' (did you mean 'wash'?)", "unknown-action"),
        (2, "unknown object or constant 'sauce' (did you mean 'saucer'?)", "unknown-object"),
        (3, "'wash' takes 1 argument, 0 given", "arity"),
    ]
    actions = await editor.client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=types.TextDocumentIdentifier(_uri(plan)),
            range=found[0].range,
            context=types.CodeActionContext(diagnostics=[found[0]]),
        )
    )
    assert [a.title for a in actions] == ["change to 'wash'"]
    assert await editor.replace(plan, "(pick saucer)\n(wash saucer)\n") == []
    await editor.close(plan)


async def test_a_large_problem_is_checked_after_the_edits_pause(editor, workspace: Path):
    """A generated problem of about 200 kB: quick edits are re-checked once, for the last version."""
    kitchen = workspace / "kitchen"
    dishes = [f"mug{i}" for i in range(12_000)]
    problem = kitchen / "large.pddl"
    text = (
        "(define (problem large) (:domain kitchen)\n"
        f"  (:objects {' '.join(dishes)} - cup)\n"
        "  (:init " + "\n    ".join(f"(on-counter {d})" for d in dishes) + ")\n"
        "  (:goal (clean mug0)))\n"
    )
    assert len(text) > 200_000
    assert await editor.open(problem, text) == []
    lines = text.split("\n")
    at = lines.index("    (on-counter mug5)")
    for number, typed in enumerate("xy"):  # (on-counter mug5xy): two changes in a row
        await _send_insert(editor, problem, at, len("    (on-counter mug5") + number, typed)
    found = await editor.diagnostics(_uri(problem))
    assert [(d.code, d.range.start.line) for d in found] == [("unknown-object", at)]
    assert found[0].message == "unknown object or constant 'mug5xy' (did you mean 'mug5'?)"
    assert editor.client.publications[_uri(problem)] == [1, 3]  # the version in between was never checked
    await editor.close(problem)


async def _send_insert(editor, path: Path, line: int, character: int, inserted: str) -> None:
    """An incremental change sent without waiting for its diagnostics."""
    uri = _uri(path)
    editor.versions[uri] += 1
    lines = editor.texts[uri].split("\n")
    lines[line] = lines[line][:character] + inserted + lines[line][character:]
    editor.texts[uri] = "\n".join(lines)
    at = types.Position(line, character)
    editor.client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(editor.versions[uri], uri),
            [types.TextDocumentContentChangePartial(types.Range(at, at), inserted)],
        )
    )
