"""PDDL on the planner's path (``plan``, ``validate``): messages that name the problem in PDDL's words,
a parse budget that covers the whole read, and files read within their bound (issue 27, items 3, 10)."""

from __future__ import annotations

import signal

import pytest
from helpers.cli import REPO, vslsp

from vslsp.errors import InputError
from vslsp.symbolic import budget
from vslsp.symbolic.io import pddl
from vslsp.symbolic.io.pddl_errors import PddlWarning

DOMAIN, PROBLEM = REPO / "pddl" / "domain.pddl", REPO / "pddl" / "pull-in-order.pddl"


def _problem(body: str) -> str:
    return f"(define (problem p) (:domain vsl-sp)\n  (:objects a - block)\n  (:init)\n{body})\n"


@pytest.mark.parametrize(
    "problem, message",
    [
        (
            "(define (problem p) (:domain vsl-sp)\n  (:objects a - cube)\n  (:init)\n  (:goal (far a)))\n",
            "undef_type.pddl:2:17: undefined type 'cube'",
        ),
        (
            "(define (problem p) (:domain vsl-sp)\n  (:objects far - block)\n  (:init)\n  (:goal (far far)))\n",
            "the name 'far' is given to two things",
        ),
        (
            _problem("  (:goal (far a))\n  (:constraints (always))"),
            "undef_type.pddl:5:17: (always ...) takes 1 formula, 0 given",  # as pddl check says it
        ),
        (
            _problem("  (:goal (far a))\n  (:constraints (sometime-before (far a)))"),
            "(sometime-before ...) takes 2 formulas, 1 given",
        ),
    ],
    ids=["undefined-type", "used-name", "always", "sometime-before"],
)
@pytest.mark.parametrize("command", ["plan", "validate"])
def test_reader_errors_are_said_in_pddl_words_not_unified_plannings(capsys, tmp_path, problem, message, command):
    path = tmp_path / "undef_type.pddl"
    path.write_text(problem)
    plan = tmp_path / "plan.txt"
    plan.write_text("(push a)\n")
    code, _, err = vslsp(capsys, command, DOMAIN, path, *([plan] if command == "validate" else []))
    assert code == 2 and message in err, err
    assert "error_used_name" not in err and "ExpressionManager" not in err


def test_cr_only_line_endings_after_a_comment_read_as_lines(capsys, tmp_path):
    path = tmp_path / "cr.pddl"
    path.write_bytes(DOMAIN.read_bytes().replace(b"\n", b"\r"))
    code, out, err = vslsp(capsys, "plan", path, PROBLEM)
    assert code == 0 and "the file is empty" not in err, err


def test_formulas_nested_too_deeply_say_so_with_their_place(capsys, tmp_path):
    body = "(far ?b)"
    for _ in range(60):
        body = f"(and {body} (far ?b))"
    path = tmp_path / "deep.pddl"
    path.write_text(DOMAIN.read_text().replace(":precondition (far ?b)", f":precondition {body}"))
    code, _, err = vslsp(capsys, "plan", path, PROBLEM)
    assert code == 2 and "parentheses nest 41 deep here" in err and "refers to itself" not in err, err


@pytest.mark.filterwarnings("ignore")
def test_the_parse_budget_covers_the_whole_read(monkeypatch, tmp_path):
    # 25k (either ...) predicates: the checks before unified-planning's reader count against the budget too.
    predicates = " ".join(f"(p{i} ?a - (either t1 t2))" for i in range(25_000))
    path = tmp_path / "either.pddl"
    path.write_text(
        "(define (domain d) (:requirements :strips :typing) (:types t0 - object t1 t2 - t0) "
        f"(:predicates {predicates}) (:action a :parameters (?x - t1) :precondition (p0 ?x) :effect (not (p0 ?x))))\n"
    )
    monkeypatch.setattr(budget, "PHASE_BUDGET_S", 0.5)
    with pytest.raises(InputError, match=r"either.pddl: reading took more than 0.5 s"):
        pddl.read_pddl(path)


def test_a_lost_alarm_still_stops_the_read():
    # An exception raised in a finalizer is only printed: the budget's first alarm can be lost there.
    with pytest.raises(budget.OverBudget):
        with budget.time_budget(0.01):
            try:
                signal.pause()
            except budget.OverBudget:
                pass  # lost; the block then ends as if nothing happened
    with pytest.raises(budget.OverBudget):
        with budget.time_budget(0.01):
            try:
                signal.pause()
            except budget.OverBudget:
                pass  # lost; the read goes on
            signal.pause()  # the alarm repeats


def test_many_preferences_are_read(tmp_path):
    preferences = " ".join(f"(preference q{i} (far a))" for i in range(19_000))
    path = tmp_path / "prefs.pddl"
    path.write_text(_problem(f"  (:goal (far a))\n  (:constraints (and {preferences}))"))
    with pytest.warns(PddlWarning, match="19000 preferences ignored"):
        _, problem = pddl.read_pddl(DOMAIN, path)
    assert problem is not None and not problem.constraints
