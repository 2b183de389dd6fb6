"""Why a problem has no plan: a minimal set of goal conjuncts and constraints, found with real
Fast Downward calls and located in the problem file (``vslsp plan`` names it)."""

import json
from dataclasses import replace

import pytest
from helpers.cli import vslsp
from helpers.symbolic import PDDL, far

from vslsp.symbolic import parse_pddl, solve
from vslsp.symbolic.model.formula import conjunction
from vslsp.symbolic.validation.conflict import Conflict, explain

DOMAIN = (PDDL / "domain.pddl").read_text()

#: a may be pulled only after b, b only after a: neither ever; c's constraint is harmless.
CYCLE = """; two orders in a cycle, one harmless constraint
(define (problem cycle)
  (:domain vsl-sp)
  (:objects a b c - block)
  (:init (far a) (far b) (far c))
  (:goal (and (not (far a))
              (not (far c))))
  (:constraints (and
    (sometime-before (not (far a))
                     (not (far b)))   ; a after b
    (at-most-once (far c))
    (sometime-before (not (far b)) (not (far a))))))
"""

#: a must stay far, and the goal wants it near; the order on b is kept by pulling b first.
ALWAYS = """(define (problem keep-far)
  (:domain vsl-sp)
  (:objects a b - block)
  (:init (far a) (far b))
  (:goal (and (not (far b)) (not (far a))))
  (:constraints (and (sometime-before (not (far a)) (not (far b))) (always (far a)))))
"""

#: Nothing ever breaks a dish: (broken a) is out of reach with no constraint at all.
KITCHEN = """(define (domain kitchen)
  (:requirements :strips :typing :negative-preconditions :constraints)
  (:types dish)
  (:predicates (dirty ?d - dish) (clean ?d - dish) (broken ?d - dish))
  (:action wash :parameters (?d - dish) :precondition (dirty ?d)
    :effect (and (clean ?d) (not (dirty ?d)))))
"""
UNREACHABLE = """(define (problem break-a-dish)
  (:domain kitchen)
  (:objects a b - dish)
  (:init (dirty a) (dirty b))
  (:goal (and (clean a) (broken a) (clean b)))
  (:constraints (sometime-before (clean a) (clean b))))
"""


def texts(conflict: Conflict) -> list[str]:
    return [part.to_pddl() for part in conflict.parts]


def _without(problem, conflict: Conflict, dropped):
    """``problem`` with only the conflict's parts, less ``dropped``."""
    kept = [p for p in conflict.parts if p is not dropped]
    return replace(
        problem,
        goal=conjunction(p.formula for p in kept if p.kind == "goal"),
        constraints=tuple(p.formula for p in kept if p.kind == "constraint"),
    )


def solvable_without(problem, conflict: Conflict, dropped) -> bool:
    """The conflict less ``dropped`` has a plan (solve raises when it has none)."""
    solve(problem.domain, _without(problem, conflict, dropped))
    return True


def test_a_cycle_of_orders_is_named_without_the_harmless_constraint():
    domain, problem = parse_pddl(DOMAIN, CYCLE)
    conflict = explain(domain, problem)
    assert conflict is not None and conflict.minimal
    assert texts(conflict) == [
        "(not (far a))",
        "(sometime-before (not (far a)) (not (far b)))",
        "(sometime-before (not (far b)) (not (far a)))",
    ]
    assert [(p.kind, p.index) for p in conflict.parts] == [("goal", 0), ("constraint", 0), ("constraint", 2)]
    assert not conflict.without_constraints and "minimal conflict" in conflict.summary()
    for part in conflict.parts:  # each member is needed: without it the rest has a plan
        assert solvable_without(problem, conflict, part)


def test_a_goal_conjunct_against_an_always_is_named():
    domain, problem = parse_pddl(DOMAIN, ALWAYS)
    conflict = explain(domain, problem)
    assert conflict is not None and conflict.minimal
    assert texts(conflict) == ["(not (far a))", "(always (far a))"]
    for part in conflict.parts:
        assert solvable_without(problem, conflict, part)


def test_a_goal_out_of_reach_is_named_without_constraints():
    domain, problem = parse_pddl(KITCHEN, UNREACHABLE)
    conflict = explain(domain, problem)
    assert conflict is not None and conflict.minimal
    assert texts(conflict) == ["(broken a)"] and conflict.without_constraints
    assert "no constraint is involved" in conflict.summary()


def test_a_solvable_problem_has_no_conflict():
    domain, problem = parse_pddl(DOMAIN, (PDDL / "pull-in-order.pddl").read_text())
    assert explain(domain, problem) is None


def test_the_time_bound_returns_a_conflicting_set_not_proven_minimal():
    domain, problem = parse_pddl(DOMAIN, CYCLE)
    conflict = explain(domain, problem, budget_s=0, known_unsolvable=True)
    assert conflict is not None and not conflict.minimal and conflict.checks == 0
    assert len(conflict.parts) == 5  # nothing tested, nothing dropped: all the problem's parts
    assert "not proven minimal" in conflict.summary()


def test_plan_names_the_conflict_with_positions(capsys, tmp_path):
    (tmp_path / "domain.pddl").write_text(DOMAIN)
    (tmp_path / "cycle.pddl").write_text(CYCLE)
    problem = tmp_path / "cycle.pddl"
    code, out, _ = vslsp(capsys, "plan", tmp_path / "domain.pddl", problem, "--json")
    data = json.loads(out)
    assert code == 1 and data["plan"] is None and data["conflict_minimal"] is True
    assert data["status"] == "unsolvable_proven"
    assert [(c["kind"], c["text"], c["line"], c["column"]) for c in data["conflict"]] == [
        ("goal", "(not (far a))", 6, 15),
        ("constraint", "(sometime-before (not (far a)) (not (far b)))", 9, 5),  # two lines, as written
        ("constraint", "(sometime-before (not (far b)) (not (far a)))", 12, 5),
    ]
    assert {c["file"] for c in data["conflict"]} == {str(problem)}
    code, out, err = vslsp(capsys, "plan", tmp_path / "domain.pddl", problem)
    assert code == 1 and "proved by Fast Downward" in err
    assert f"{problem}:9:5: constraint (sometime-before (not (far a)) (not (far b)))" in err
    assert f"{problem}:6:15: goal (not (far a))" in err
    code, out, _ = vslsp(capsys, "plan", tmp_path / "domain.pddl", problem, "--json", "--conflict-budget", "0")
    assert code == 1 and json.loads(out)["conflict"] is None


def test_a_plan_found_has_no_conflict(capsys):
    code, out, _ = vslsp(capsys, "plan", PDDL / "domain.pddl", PDDL / "pull-in-order.pddl", "--json")
    assert code == 0 and "conflict" not in json.loads(out)


@pytest.mark.slow
def test_conflicts_of_random_unsolvable_problems_are_minimal():
    """On random problems over three blocks: every conflict found has no plan, and each of its
    parts is needed (the planner finds a plan for the conflict less any one part)."""
    import random

    from vslsp.errors import TaskFailed
    from vslsp.symbolic import Always, AtMostOnce, Not, Sometime, SometimeAfter, SometimeBefore, Unsolvable

    domain, base = parse_pddl(DOMAIN, (PDDL / "simple-push-pull.pddl").read_text())
    rng, explained = random.Random(11), 0

    def lit():
        atom = far(rng.choice(("red", "green", "blue")))
        return atom if rng.random() < 0.5 else Not(atom)

    kinds = (Always, Sometime, AtMostOnce, lambda f: SometimeBefore(f, lit()), lambda f: SometimeAfter(f, lit()))
    for _ in range(100):
        if explained == 4:
            break
        problem = base.with_goal(lit() & lit() & lit())
        for _ in range(3):
            problem = problem.with_constraint(rng.choice(kinds)(lit()))
        try:
            solve(domain, problem)
            continue
        except Unsolvable:
            pass
        except TaskFailed:
            continue
        conflict = explain(domain, problem, known_unsolvable=True)
        assert conflict is not None and conflict.minimal and conflict.parts
        with pytest.raises(Unsolvable):
            solve(domain, _without(problem, conflict, None))
        for part in conflict.parts:
            assert solvable_without(problem, conflict, part)
        explained += 1
    assert explained == 4


def test_a_constraint_broken_in_the_initial_state_is_named_alone():
    domain, problem = parse_pddl(DOMAIN, ALWAYS.replace("(always (far a))", "(always (not (far b)))"))
    conflict = explain(domain, problem)
    assert conflict is not None and conflict.minimal
    assert texts(conflict) == ["(always (not (far b)))"]
    assert "this constraint alone can never be kept" in conflict.summary()


def test_without_time_to_prove_the_problem_unsolvable_nothing_is_explained():
    from vslsp.errors import TaskFailed

    domain, problem = parse_pddl(DOMAIN, CYCLE)
    with pytest.raises(TaskFailed, match="cannot explain: the planner did not prove the problem unsolvable"):
        explain(domain, problem, budget_s=0)
