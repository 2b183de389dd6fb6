"""PDDL 3.0 files through unified-planning: the shipped files, writing and reading back, and
malformed input reported as FILE:LINE:COL."""

import re

import pytest
from helpers.symbolic import PDDL

from vslsp.errors import InputError
from vslsp.symbolic import (
    Forall,
    SometimeBefore,
    learn_domain,
    learn_task,
    make_problem,
    read_pddl,
    save,
    solve,
)

EXPERIMENTS = ("simple-push-pull", "keep-all-near", "pull-in-order")


@pytest.mark.parametrize("name", EXPERIMENTS)
def test_shipped_problems_read(name):
    domain, problem = read_pddl(PDDL / "domain.pddl", PDDL / f"{name}.pddl")
    assert problem.name == name and problem.domain == domain and domain.name == "vsl-sp"
    if name == "keep-all-near":
        assert isinstance(problem.goal, Forall)
    if name == "pull-in-order":
        assert all(isinstance(c, SometimeBefore) for c in problem.constraints) and len(problem.constraints) == 2


def test_learned_model_writes_reads_back_and_plans(tmp_path, skill_executions, pull_in_order_demonstration):
    domain = learn_domain(skill_executions)
    problem = make_problem(
        domain,
        learn_task([pull_in_order_demonstration]),
        {"orange": {"far": True}, "green": {"far": True}, "yellow": {"far": True}},
        name="learned",
    )
    domain_text, problem_text = domain.to_pddl(), problem.to_pddl()
    assert "(:requirements :strips :typing :negative-preconditions :constraints)" in domain_text
    assert "(:constraints (and\n    (sometime-before (not (far green)) (not (far orange)))\n" in problem_text
    domain_file, problem_file = save(domain_text, tmp_path / "d.pddl"), save(problem_text, tmp_path / "p.pddl")
    read_domain, read_problem = read_pddl(domain_file, problem_file)
    assert read_domain == domain and read_problem == problem
    assert solve(read_domain, read_problem).lines() == ["pull orange", "pull green", "pull yellow"]


def _broken(tmp_path, source: str, old: str, new: str) -> str:
    text = (PDDL / source).read_text()
    assert old in text
    path = save(text.replace(old, new, 1), tmp_path / source)
    with pytest.raises(InputError) as error:
        if source == "domain.pddl":
            read_pddl(path)
        else:
            read_pddl(PDDL / "domain.pddl", path)
    message = str(error.value)
    assert message.startswith(f"{path}:"), message
    return message


def _place(message: str) -> tuple[int, int]:
    line, column = re.match(r".*?:(\d+):(\d+): ", message).groups()
    return int(line), int(column)


def test_missing_parenthesis_names_the_place(tmp_path):
    message = _broken(tmp_path, "domain.pddl", "(far ?b - block))", "(far ?b - block)")
    assert _place(message) == (10, 3) and "')' is missing" in message and "opened at line 7, col 3" in message
    message = _broken(tmp_path, "pull-in-order.pddl", "(not (far yellow))))", "(not (far yellow)))")
    assert "')' is missing" in message and "(:constraints" in message


def test_unknown_predicate_names_it_and_its_place(tmp_path):
    message = _broken(tmp_path, "domain.pddl", ":effect (far ?b))", ":effect (fary ?b))")
    # placed and worded as `vslsp pddl check` says it (the name, not its parenthesis), with did-you-mean
    assert _place(message) == (13, 14) and "unknown predicate 'fary' (did you mean 'far'?)" in message
    message = _broken(tmp_path, "keep-all-near.pddl", "(far purple)", "(near purple)")
    assert _place(message) == (9, 6) and "'near'" in message


def test_type_errors_and_unknown_names(tmp_path):
    assert "undefined type 'blok'" in _broken(
        tmp_path, "domain.pddl", "(?b - block)\n    :precondition (not", "(?b - blok)\n    :precondition (not"
    )
    assert "unknown object or constant 'purple'" in _broken(
        tmp_path, "pull-in-order.pddl", "(far orange)\n", "(far purple)\n"
    )
    assert "'far' takes 1 argument, 2 given" in _broken(
        tmp_path, "pull-in-order.pddl", "(far orange)\n", "(far orange green)\n"
    )


def test_somewhere_after_names_the_pddl3_operators(tmp_path):
    message = _broken(
        tmp_path, "pull-in-order.pddl", "(sometime-before (not (far yellow))", "(somewhere-after (not (far yellow))"
    )
    assert _place(message) == (17, 6)
    assert "(sometime-before p q)" in message and "sometime-after" in message and "at-most-once" in message


def test_unreadable_file_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="cannot read"):
        read_pddl(tmp_path / "missing.pddl")


def test_unsupported_pddl3_operators_are_named(tmp_path):
    message = _broken(
        tmp_path,
        "pull-in-order.pddl",
        "(sometime-before (not (far yellow)) (not (far green)))",
        "(within 3 (not (far yellow)))",
    )
    assert "(within ...) is not supported" in message and "sometime-before" in message


def test_problem_for_another_domain_is_refused_with_its_place(tmp_path):
    path = save(
        (PDDL / "keep-all-near.pddl").read_text().replace("(:domain vsl-sp)", "(:domain blocks-world)"),
        tmp_path / "other.pddl",
    )
    with pytest.raises(InputError) as raised:
        read_pddl(PDDL / "domain.pddl", path)
    message = str(raised.value)
    assert message.startswith(f"{path}:5:12: the problem is for domain 'blocks-world'"), message
    assert "(:domain vsl-sp)" in message
