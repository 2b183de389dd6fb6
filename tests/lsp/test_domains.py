"""A problem and its domain when several files of its folder define that domain (issue 45: a broken
draft was taken silently): the problem says which files match and which one it is checked against,
a quick fix per file writes the ``;; !domain: FILE`` comment (as the VS Code PDDL extension reads
it), and the comment decides the domain for diagnostics and for ``vslsp.plan``."""

from pathlib import Path

import pytest
from helpers.lsp import apply_edits as _apply
from helpers.lsp import code_actions as _actions
from lsprotocol import types

from vslsp.lsp.workspace import uri_of

pytestmark = pytest.mark.asyncio(loop_scope="module")

DOMAIN = """(define (domain block-sorting)
  (:requirements :strips :typing)
  (:types block bin)
  (:predicates (in ?b - block ?n - bin) (free ?b - block))
  (:action put :parameters (?b - block ?n - bin) :precondition (free ?b) :effect (and (in ?b ?n) (not (free ?b)))))
"""
PROBLEM = """(define (problem two)
  (:domain block-sorting)
  (:objects a - block left - bin)
  (:init (free a))
  (:goal (in a left)))
"""


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "domain.pddl").write_text(DOMAIN)
    (tmp_path / "draft.pddl").write_text(DOMAIN.replace("(free ?b - block)", "(loose ?b - block)"))  # broken
    (tmp_path / "old.pddl").write_text(DOMAIN.replace("(:types block bin)", "(:types block bin crate)"))
    (tmp_path / "problem.pddl").write_text(PROBLEM)
    return tmp_path


async def test_three_domains_of_one_name_are_named_and_one_is_chosen_by_a_comment(editor, folder: Path):
    problem = folder / "problem.pddl"
    (warning,) = await editor.open(problem)  # only the problem is open
    assert warning.code == "several-domains" and warning.severity == types.DiagnosticSeverity.Warning
    assert warning.message.startswith(
        "3 files define domain 'block-sorting': domain.pddl, draft.pddl, old.pddl; this problem is checked "
        "against domain.pddl: choose one with a ';; !domain: FILE' comment at the top (quick fix)"
    )
    assert warning.range.start == editor.position_of(problem, "block-sorting")
    actions = await _actions(editor, problem, warning)
    assert [a.title for a in actions] == [
        f"check against {name} (;; !domain: {name})" for name in ("domain.pddl", "draft.pddl", "old.pddl")
    ]
    chosen = _apply(editor.texts[uri_of(problem)], actions[1].edit.changes[uri_of(problem)])
    assert chosen.startswith(";; !domain: draft.pddl\n(define (problem two)")
    found = await editor.replace(problem, chosen)  # now checked against the broken draft, by choice
    assert [d.message for d in found] == ["unknown predicate 'free'"]  # as the draft declares none such
    plan = await editor.client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="vslsp.plan", arguments=[uri_of(problem)])
    )
    assert plan["exit_code"] == 2 and "draft.pddl" in plan["error"]  # the plan reads the chosen file too
    await editor.close(problem)


async def test_a_comment_that_chooses_a_missing_file_says_so(editor, folder: Path):
    problem = folder / "problem.pddl"
    found = await editor.open(problem, ";; !domain: gone.pddl\n" + PROBLEM)
    assert [(d.code, d.message) for d in found] == [
        ("chosen-domain-missing", "the ;; !domain: comment chooses gone.pddl, which is not there")
    ]  # ... and the problem is checked against the folder's first match meanwhile (no more warnings)
    await editor.close(problem)
