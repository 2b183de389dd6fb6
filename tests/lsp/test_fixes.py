"""Quick fixes: the did-you-mean replacement (preferred) and declaring a missing predicate or type, in the
document or, from a problem, in its domain; applied, they leave the files without errors."""

from pathlib import Path

import pytest
from helpers.lsp import apply_edits as _apply
from helpers.lsp import code_actions as _actions
from lsprotocol import types

from vslsp.lsp.workspace import uri_of

pytestmark = pytest.mark.asyncio(loop_scope="module")


async def test_did_you_mean_and_declare_a_predicate_in_the_domain(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    typo = domain.read_text().replace("(and (on-counter ?d) (hand-empty))", "(and (on-counter ?d) (hand-emty))")
    (diagnostic,) = await editor.open(domain, typo)
    actions = await _actions(editor, domain, diagnostic)
    assert [(a.title, a.kind, a.is_preferred) for a in actions] == [
        ("change to 'hand-empty'", types.CodeActionKind.QuickFix, True),
        ("declare predicate 'hand-emty'", types.CodeActionKind.QuickFix, False),
    ]
    assert actions[0].diagnostics[0].message == diagnostic.message
    fixed = _apply(typo, actions[0].edit.changes[uri_of(domain)])
    assert fixed == domain.read_text()
    declared = _apply(typo, actions[1].edit.changes[uri_of(domain)])
    assert "    (hand-emty))" in declared
    assert [d for d in await editor.replace(domain, declared) if d.severity == types.DiagnosticSeverity.Error] == []
    await editor.close(domain)


async def test_a_problem_s_fix_may_declare_a_type_in_its_domain(editor, workspace: Path):
    kitchen = workspace / "kitchen"
    domain, problem = kitchen / "domain.pddl", kitchen / "problem.pddl"
    await editor.open(domain)
    typo = problem.read_text().replace("mug - cup", "mug - cupp").replace("(hand-empty))", "(hand-empty) (dirty mug))")
    found = await editor.open(problem, typo)
    by_code = {d.code: d for d in found}
    assert set(by_code) == {"undefined-type", "unknown-predicate"}
    change, declare = await _actions(editor, problem, by_code["undefined-type"])
    assert change.title == "change to 'cup'" and list(change.edit.changes) == [uri_of(problem)]
    assert declare.title == "declare type 'cupp'" and list(declare.edit.changes) == [uri_of(domain)]
    (declare_predicate,) = await _actions(editor, problem, by_code["unknown-predicate"])  # 'dirty' is close to nothing
    assert declare_predicate.title == "declare predicate 'dirty'"
    new_domain = _apply(domain.read_text(), declare.edit.changes[uri_of(domain)])
    new_domain = _apply(new_domain, declare_predicate.edit.changes[uri_of(domain)])
    assert "(dirty ?" in new_domain and " cupp" in new_domain
    editor.client.diagnostics.pop(uri_of(problem), None)
    await editor.replace(domain, new_domain)
    # both names are known now; a new type of its own makes 'mug' no dish, which the engine says
    assert {d.code for d in await editor.diagnostics(uri_of(problem))} == {"argument-type"}
    await editor.close(problem)
    await editor.close(domain)


async def test_a_misspelt_domain_name_gets_the_name_of_a_domain_beside_it(editor, workspace: Path):
    problem = workspace / "kitchen" / "problem.pddl"
    (diagnostic,) = await editor.open(problem, problem.read_text().replace("(:domain kitchen)", "(:domain kitchn)"))
    assert diagnostic.code == "domain-not-found" and diagnostic.message.endswith("(did you mean 'kitchen'?)")
    (action,) = await _actions(editor, problem, diagnostic)
    assert action.title == "change to 'kitchen'"
    assert _apply(editor.texts[uri_of(problem)], action.edit.changes[uri_of(problem)]) == problem.read_text()
    await editor.close(problem)


async def test_no_fix_where_nothing_is_wrong(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    assert await editor.open(domain) == []
    everything = types.Diagnostic(types.Range(types.Position(0, 0), types.Position(40, 0)), "")
    assert await _actions(editor, domain, everything) == []
    await editor.close(domain)
