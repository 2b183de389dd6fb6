"""Authoring a domain and a problem step by step, as in a notebook; learned and hand-built
models are the same objects."""

import pytest
from helpers.symbolic import PDDL

from vslsp.errors import InputError
from vslsp.symbolic import (
    Action,
    Domain,
    Predicate,
    Problem,
    forall,
    read_pddl,
    solve,
    sometime_before,
    validate,
)

far = Predicate("far", (("?b", "block"),))


def tabletop() -> Domain:
    return (
        Domain("vsl-sp")
        .with_type("block")
        .with_predicate(far)
        .with_action(Action("push", (("?b", "block"),), ~far("?b"), (far("?b"),)))
        .with_action(Action("pull", (("?b", "block"),), far("?b"), (~far("?b"),)))
    )


def test_authored_models_equal_the_shipped_files():
    domain = tabletop()
    problem = (
        Problem("pull-in-order", domain)
        .with_objects("block", "orange", "green", "yellow")
        .with_init(far("orange"), far("green"), far("yellow"))
        .with_goal(~far("orange") & ~far("green") & ~far("yellow"))
        .with_constraint(sometime_before(~far("green"), ~far("orange")))
        .with_constraint(sometime_before(~far("yellow"), ~far("green")))
    )
    shipped_domain, shipped_problem = read_pddl(PDDL / "domain.pddl", PDDL / "pull-in-order.pddl")
    assert domain == shipped_domain
    assert problem.init == shipped_problem.init and problem.constraints == shipped_problem.constraints
    assert problem.objects == shipped_problem.objects


def test_edit_plan_and_validate_in_a_notebook():
    domain = tabletop()
    problem = (
        Problem("p", domain)
        .with_objects("block", "red", "green")
        .with_init(far("red"))
        .with_goal(forall(("?b", "block"), ~far("?b")))
    )
    assert solve(domain, problem).lines() == ["pull red"]
    problem = problem.with_objects("block", "blue").with_init(far("blue")).without_init(far("red"))
    assert solve(domain, problem).lines() == ["pull blue"]
    assert not validate(domain, problem, ["pull red"]).valid
    assert "(:objects red green blue - block)" in problem.to_pddl()


def test_unknown_names_are_input_errors():
    domain = tabletop()
    with pytest.raises(InputError, match="undefined type 'table'"):
        domain.with_predicate(Predicate("on", (("?b", "table"),)))
    with pytest.raises(InputError, match="does not match a declared predicate"):
        domain.with_action(Action("lift", (("?b", "block"),), far("?b"), (Predicate("up", (("?b", "block"),))("?b"),)))
    problem = Problem("p", domain).with_objects("block", "red")
    with pytest.raises(InputError, match="'green', which is not an object"):
        problem.with_init(far("green"))
    with pytest.raises(InputError, match="takes 1 arguments"):
        far("red", "green")


def test_models_round_trip_through_json():
    problem = Problem("p", tabletop()).with_objects("block", "red").with_init(far("red")).with_goal(~far("red"))
    assert Problem.from_dict(problem.to_dict()) == problem
    assert Domain.from_dict(tabletop().to_dict()) == tabletop()
