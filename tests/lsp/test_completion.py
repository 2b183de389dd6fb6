"""Completion in context, asked of the server at a cursor in real domain, problem and plan texts."""

from pathlib import Path

import pytest
from helpers.lsp import ident
from lsprotocol import types

pytestmark = pytest.mark.asyncio(loop_scope="module")

CURSOR = "|"


async def _complete(editor, path: Path, text: str, language: str = "pddl") -> list[types.CompletionItem]:
    """Open ``text`` (``|`` marks the cursor) as ``path`` and ask for completion at the cursor."""
    await editor.open(path, text.replace(CURSOR, ""), language)
    at = editor.position_of(path, text.split(CURSOR)[0][-30:], offset=len(text.split(CURSOR)[0][-30:]))
    result = await editor.client.text_document_completion_async(types.CompletionParams(ident(path), at))
    await editor.close(path)
    assert isinstance(result, types.CompletionList)
    return list(result.items)


def _labels(items: list[types.CompletionItem]) -> list[str]:
    return [item.label for item in items]


async def test_predicates_and_goal_operators_at_the_head_of_a_precondition_atom(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    text = domain.read_text().replace("(and (on-counter ?d) (hand-empty))", "(and (on-counter ?d) (hand-e|")
    items = await _complete(editor, domain, text)
    labels = _labels(items)
    assert labels[:4] == ["on-counter", "clean", "holding", "hand-empty"]
    assert {"and", "or", "not", "forall", "exists", "imply"} <= set(labels)
    assert "when" not in labels and "sometime-before" not in labels
    hand_empty = items[labels.index("hand-empty")]
    assert hand_empty.detail == "(hand-empty)"
    assert hand_empty.documentation.value == "the robot's hand is free"
    # the item replaces the whole hyphenated word typed so far
    edit = hand_empty.text_edit
    assert edit.new_text == "hand-empty"
    assert edit.range.end.character - edit.range.start.character == len("hand-e")


async def test_effect_operators_in_an_effect(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    text = domain.read_text().replace(":effect (clean ?d))", ":effect (and (clean ?d) (|")
    labels = _labels(await _complete(editor, domain, text))
    assert {"clean", "holding", "and", "not", "when", "forall"} <= set(labels)
    assert "or" not in labels


async def test_types_after_a_dash(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    text = domain.read_text().replace(
        "(:action wash\n    :parameters (?d - dish)", "(:action wash\n    :parameters (?d - |"
    )
    assert set(_labels(await _complete(editor, domain, text))) == {"cup", "plate", "dish", "object"}
    text = domain.read_text().replace("(holding ?d - dish)", "(holding ?d - pl|")
    assert "plate" in _labels(await _complete(editor, domain, text))


async def test_an_action_s_variables_as_arguments_in_a_domain(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    text = domain.read_text().replace("(and (on-counter ?d) (hand-empty))", "(and (on-counter ?|")
    assert _labels(await _complete(editor, domain, text)) == ["?d"]


async def test_requirement_keywords_after_requirements(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    text = domain.read_text().replace(":negative-preconditions :constraints)", ":neg|")
    labels = _labels(await _complete(editor, domain, text))
    assert ":negative-preconditions" in labels and ":typing" in labels and ":adl" in labels


async def test_objects_in_a_problem_and_pddl3_operators_in_constraints(editor, workspace: Path):
    problem = workspace / "kitchen" / "problem.pddl"
    text = problem.read_text().replace("(:init (on-counter mug)", "(:init (on-counter |")
    items = await _complete(editor, problem, text)
    assert set(_labels(items)) == {"mug", "saucer"}
    assert items[_labels(items).index("mug")].detail == "mug - cup"
    text = problem.read_text().replace(
        "(:constraints (sometime-before (clean mug) (clean saucer)))", "(:constraints (|"
    )
    labels = _labels(await _complete(editor, problem, text))
    assert {"sometime-before", "sometime-after", "always", "at-most-once", "at end", "and"} <= set(labels)
    assert "clean" in labels  # an atom is a constraint's formula too
    text = problem.read_text().replace("(:goal (and (clean mug)", "(:goal (and (cl|")
    labels = _labels(await _complete(editor, problem, text))
    assert "clean" in labels and "sometime-before" not in labels


async def test_sections_at_the_top_of_a_problem(editor, workspace: Path):
    problem = workspace / "kitchen" / "problem.pddl"
    text = problem.read_text().replace("  (:init", "  (:|\n  (:init")
    labels = _labels(await _complete(editor, problem, text))
    assert {":objects", ":init", ":goal", ":constraints"} <= set(labels) and ":action" not in labels


async def test_action_names_then_objects_in_a_plan(editor, workspace: Path):
    plan = workspace / "kitchen" / "tidy.plan"
    items = await _complete(editor, plan, "(pick saucer)\n(wa|", language="plan")
    assert set(_labels(items)) == {"pick", "wash", "put-down"}
    assert items[_labels(items).index("wash")].detail == "(:action wash :parameters (?d - dish))"
    items = await _complete(editor, plan, "(pick saucer)\n(wash |", language="plan")
    assert set(_labels(items)) == {"mug", "saucer"}


async def test_nothing_inside_a_comment(editor, workspace: Path):
    domain = workspace / "kitchen" / "domain.pddl"
    text = domain.read_text().replace("; wash the dish in hand", "; wash the (|")
    assert await _complete(editor, domain, text) == []


async def test_constants_too_and_the_argument_s_type_first(editor, workspace: Path):
    kitchen = workspace / "kitchen"
    domain, problem = kitchen / "domain.pddl", kitchen / "problem.pddl"
    with_constant = domain.read_text().replace(
        "  (:predicates\n", "  (:constants tray - plate)\n  (:predicates\n    (full ?c - cup)\n"
    )
    await editor.open(domain, with_constant)
    text = problem.read_text().replace("(:init (on-counter mug)", "(:init (full |")
    items = await _complete(editor, problem, text)
    ranked = [item.label for item in sorted(items, key=lambda item: item.sort_text)]
    assert ranked == ["mug", "saucer", "tray"]  # a cup fits (full ?c - cup); the plates after it
    assert items[_labels(items).index("tray")].detail == "tray - plate"
    await editor.close(domain)


async def test_a_new_file_offers_a_domain_and_a_problem_to_start_from(editor, workspace: Path):
    new = workspace / "kitchen" / "new.pddl"
    items = await _complete(editor, new, "(|")
    assert [(i.label, i.kind, i.insert_text_format) for i in items] == [
        ("define domain", types.CompletionItemKind.Snippet, types.InsertTextFormat.Snippet),
        ("define problem", types.CompletionItemKind.Snippet, types.InsertTextFormat.Snippet),
    ]
    problem = items[1].text_edit.new_text
    assert problem.startswith("(define (problem ${1:name})\n  (:domain ${2:kitchen})")  # the domain beside it
    assert (items[1].text_edit.range.start.character, items[1].text_edit.range.end.character) == (0, 1)
