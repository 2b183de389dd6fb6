"""Hover, go to definition, find references, rename and the outline, across a domain and its problems."""

from pathlib import Path

import pytest
from helpers.lsp import ident
from lsprotocol import types
from pygls.exceptions import JsonRpcException

from vslsp.lsp.workspace import uri_of
from vslsp.symbolic.language.vocabulary import is_reserved_name

pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest.fixture(scope="module")
def kitchen(workspace: Path) -> Path:
    return workspace / "kitchen"


def _apply(text: str, edits: list[types.TextEdit]) -> str:
    """``text`` with ``edits`` applied (from the last, so that earlier places stay)."""
    lines = text.split("\n")
    for edit in sorted(edits, key=lambda e: (e.range.start.line, e.range.start.character), reverse=True):
        start, end = edit.range.start, edit.range.end
        assert start.line == end.line
        line = lines[start.line]
        lines[start.line] = line[: start.character] + edit.new_text + line[end.character :]
    return "\n".join(lines)


async def test_hover_shows_a_predicate_s_signature_and_its_comment(editor, kitchen: Path):
    problem = kitchen / "problem.pddl"
    await editor.open(problem)
    at = editor.position_of(problem, "(clean mug)", offset=2)
    shown = await editor.client.text_document_hover_async(types.HoverParams(ident(problem), at))
    assert shown.contents.value == (
        "```pddl\n(clean ?d - dish)\n```\n\nthe dish has been washed\n\n*predicate of domain.pddl, line 10*"
    )
    assert shown.range.start.character == at.character - 1  # the whole name
    await editor.close(problem)


async def test_hover_shows_an_action_s_signature_in_the_domain_and_in_a_plan(editor, kitchen: Path):
    domain = kitchen / "domain.pddl"
    await editor.open(domain)
    at = editor.position_of(domain, "(:action pick", offset=len("(:action "))
    shown = await editor.client.text_document_hover_async(types.HoverParams(ident(domain), at))
    assert (
        shown.contents.value == "```pddl\n(:action pick :parameters (?d - dish))\n```\n\ntake a dish from the counter"
    )
    plan = kitchen / "tidy.plan"
    await editor.open(plan, "0: (pick saucer)\n1: (wash saucer)\n", language="plan")
    at = editor.position_of(plan, "wash")
    shown = await editor.client.text_document_hover_async(types.HoverParams(ident(plan), at))
    assert shown.contents.value.startswith(
        "```pddl\n(:action wash :parameters (?d - dish))\n```\n\nwash the dish in hand"
    )
    place = await editor.client.text_document_definition_async(types.DefinitionParams(ident(plan), at))
    assert place.uri == uri_of(domain) and place.range.start.line == 22
    at = editor.position_of(plan, "saucer", occurrence=2)
    place = await editor.client.text_document_definition_async(types.DefinitionParams(ident(plan), at))
    assert place.uri == uri_of(kitchen / "problem.pddl") and place.range.start.line == 4
    await editor.close(plan)
    await editor.close(domain)


async def test_definition_goes_from_a_problem_to_the_domain(editor, kitchen: Path):
    problem = kitchen / "problem.pddl"
    await editor.open(problem)
    at = editor.position_of(problem, "(on-counter saucer)", offset=1)
    place = await editor.client.text_document_definition_async(types.DefinitionParams(ident(problem), at))
    assert place.uri == uri_of(kitchen / "domain.pddl")
    assert (place.range.start.line, place.range.start.character, place.range.end.character) == (7, 5, 15)
    at = editor.position_of(problem, "mug - cup", offset=len("mug - "))  # a type
    place = await editor.client.text_document_definition_async(types.DefinitionParams(ident(problem), at))
    assert (place.uri, place.range.start.line, place.range.start.character) == (uri_of(kitchen / "domain.pddl"), 3, 10)
    await editor.close(problem)


async def test_references_cover_the_domain_and_its_problem_on_disk(editor, kitchen: Path):
    domain = kitchen / "domain.pddl"
    await editor.open(domain)
    at = editor.position_of(domain, "(clean ?d - dish)", offset=1)
    found = await editor.client.text_document_references_async(
        types.ReferenceParams(
            context=types.ReferenceContext(include_declaration=True), text_document=ident(domain), position=at
        )
    )
    places = sorted((Path(f.uri).name, f.range.start.line, f.range.start.character) for f in found)
    assert places == [
        ("domain.pddl", 9, 5),  # the declaration
        ("domain.pddl", 25, 13),  # wash's effect
        ("problem.pddl", 6, 15),  # the goal
        ("problem.pddl", 6, 27),
        ("problem.pddl", 7, 34),  # the constraint
        ("problem.pddl", 7, 46),
    ]
    found = await editor.client.text_document_references_async(
        types.ReferenceParams(
            context=types.ReferenceContext(include_declaration=False), text_document=ident(domain), position=at
        )
    )
    assert len(found) == 5
    await editor.close(domain)


async def test_rename_a_predicate_across_domain_and_problem(editor, kitchen: Path):
    domain, problem = kitchen / "domain.pddl", kitchen / "problem.pddl"
    await editor.open(domain)
    await editor.open(problem)
    at = editor.position_of(problem, "(clean saucer)", offset=3)
    prepared = await editor.client.text_document_prepare_rename_async(types.PrepareRenameParams(ident(problem), at))
    assert (prepared.start.character, prepared.end.character) == (at.character - 2, at.character + 3)
    edit = await editor.client.text_document_rename_async(
        types.RenameParams(text_document=ident(problem), position=at, new_name="washed")
    )
    assert set(edit.changes) == {uri_of(domain), uri_of(problem)}
    new_domain = _apply(domain.read_text(), edit.changes[uri_of(domain)])
    new_problem = _apply(problem.read_text(), edit.changes[uri_of(problem)])
    assert "(washed ?d - dish)" in new_domain and "(clean" not in new_domain + new_problem
    assert new_problem.count("(washed ") == 4
    # the renamed files check clean together
    assert await editor.replace(domain, new_domain) == []
    assert await editor.replace(problem, new_problem) == []
    await editor.close(problem)
    await editor.close(domain)


async def test_rename_a_type_an_object_and_a_variable(editor, kitchen: Path):
    domain, problem = kitchen / "domain.pddl", kitchen / "problem.pddl"
    await editor.open(domain)
    at = editor.position_of(domain, "dish - object", offset=1)
    edit = await editor.client.text_document_rename_async(
        types.RenameParams(text_document=ident(domain), position=at, new_name="crockery")
    )
    new_domain = _apply(domain.read_text(), edit.changes[uri_of(domain)])
    assert new_domain.count("crockery") == 8 and "- dish" not in new_domain  # 2 in (:types), 3 predicates, 3 actions
    await editor.open(problem)
    at = editor.position_of(problem, "mug - cup")
    edit = await editor.client.text_document_rename_async(
        types.RenameParams(text_document=ident(problem), position=at, new_name="beaker")
    )
    assert list(edit.changes) == [uri_of(problem)]  # an object lives in its problem
    assert _apply(problem.read_text(), edit.changes[uri_of(problem)]).count("beaker") == 5
    at = editor.position_of(domain, "(holding ?d)", occurrence=2, offset=len("(holding ?"))  # in wash
    edit = await editor.client.text_document_rename_async(
        types.RenameParams(text_document=ident(domain), position=at, new_name="?dish")
    )
    new_domain = _apply(domain.read_text(), edit.changes[uri_of(domain)])
    wash = new_domain.split("(:action wash")[1].split("(:action")[0]
    assert wash.count("?dish") == 3 and "?d " not in wash and "?d)" not in wash  # parameter, precondition, effect
    assert new_domain.count("?dish") == 3  # the other actions' ?d are other variables
    await editor.close(problem)
    await editor.close(domain)


async def test_rename_refuses_what_is_no_pddl_name_or_no_declared_name(editor, kitchen: Path):
    domain = kitchen / "domain.pddl"
    await editor.open(domain)
    at = editor.position_of(domain, "(and (on-counter", offset=1)  # the keyword 'and'
    assert await editor.client.text_document_prepare_rename_async(types.PrepareRenameParams(ident(domain), at)) is None
    at = editor.position_of(domain, "(on-counter ?d - dish)", offset=1)
    with pytest.raises(JsonRpcException, match="is not a PDDL name") as refused:
        await editor.client.text_document_rename_async(
            types.RenameParams(text_document=ident(domain), position=at, new_name="2 words")
        )
    assert refused.value.code == -32803  # RequestFailed: understood, refused
    assert refused.value.data is None and "\n" not in refused.value.message  # one line, no traceback
    for reserved in ("and", "AND", "forall", "either", "when", "sometime-before", "object"):
        with pytest.raises(
            JsonRpcException, match=r"is a word of PDDL \(.*\), so it cannot name a predicate"
        ) as refused:
            await editor.client.text_document_rename_async(
                types.RenameParams(text_document=ident(domain), position=at, new_name=reserved)
            )
        assert refused.value.code == -32803
    edit = await editor.client.text_document_rename_async(  # `at` is an ordinary predicate name
        types.RenameParams(text_document=ident(domain), position=at, new_name="at")
    )
    assert edit is not None and edit.changes
    await editor.close(domain)


async def test_reserved_names_are_the_words_of_pddl_s_syntax():
    assert all(is_reserved_name(word) for word in ("and", "Or", "not", "imply", "exists", "forall", "when", "?and"))
    assert all(is_reserved_name(word) for word in ("increase", "always", "at-most-once", "either", "define", "object"))
    assert not any(is_reserved_name(word) for word in ("at", "end", "on-counter", "clean", "anded", "pick"))


async def test_the_outline_lists_types_predicates_and_actions_with_parameters(editor, kitchen: Path):
    domain = kitchen / "domain.pddl"
    await editor.open(domain)
    symbols = await editor.client.text_document_document_symbol_async(types.DocumentSymbolParams(ident(domain)))
    (root,) = symbols
    assert (root.name, root.kind) == ("kitchen", types.SymbolKind.Module)
    children = [(c.name, c.kind) for c in root.children]
    assert [name for name, kind in children if kind == types.SymbolKind.Class] == ["cup", "plate", "dish"]
    assert [name for name, kind in children if kind == types.SymbolKind.Function] == [
        "on-counter",
        "clean",
        "holding",
        "hand-empty",
    ]
    actions = [c for c in root.children if c.kind == types.SymbolKind.Method]
    assert [a.name for a in actions] == ["pick", "wash", "put-down"]
    assert [p.name for p in actions[0].children] == ["?d"]
    assert actions[0].range.start.line == 16 and actions[0].range.end.line == 19  # the whole (:action ...)
    problem = kitchen / "problem.pddl"
    await editor.open(problem)
    (root,) = await editor.client.text_document_document_symbol_async(types.DocumentSymbolParams(ident(problem)))
    assert root.name == "tidy-up" and [c.name for c in root.children] == ["mug", "saucer"]
    await editor.close(problem)
    await editor.close(domain)


async def test_rename_the_domain_renames_the_problems_domain_line(editor, kitchen: Path):
    domain, problem = kitchen / "domain.pddl", kitchen / "problem.pddl"
    await editor.open(domain)
    at = editor.position_of(domain, "(domain kitchen)", offset=len("(domain "))
    edit = await editor.client.text_document_rename_async(
        types.RenameParams(text_document=ident(domain), position=at, new_name="galley")
    )
    assert set(edit.changes) == {uri_of(domain), uri_of(problem)}  # the problem is not even open
    assert "(define (domain galley)" in _apply(domain.read_text(), edit.changes[uri_of(domain)])
    assert "(:domain galley)" in _apply(problem.read_text(), edit.changes[uri_of(problem)])
    await editor.close(domain)


async def test_hover_says_what_a_pddl3_operator_means(editor, kitchen: Path):
    problem = kitchen / "problem.pddl"
    await editor.open(problem)
    at = editor.position_of(problem, "sometime-before", offset=3)
    shown = await editor.client.text_document_hover_async(types.HoverParams(ident(problem), at))
    assert shown.contents.value.startswith("`(sometime-before φ ψ)`: whenever φ holds, ψ has held in an earlier state")
    at = editor.position_of(problem, "(:goal (and", offset=len("(:goal ("))  # 'and' is no PDDL 3 operator
    assert await editor.client.text_document_hover_async(types.HoverParams(ident(problem), at)) is None
    await editor.close(problem)
