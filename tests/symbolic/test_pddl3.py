"""PDDL 3 at the scale of public benchmarks: the lifted constraint compilation keeps exactly the
plans the constraints allow, the ADL features authors use, public problems read and planned."""

import itertools
from pathlib import Path

import pytest

from vslsp.errors import InputError
from vslsp.symbolic import (
    Always,
    AtEnd,
    AtMostOnce,
    Atom,
    Compilation,
    Equals,
    Exists,
    Not,
    PddlWarning,
    Sometime,
    SometimeAfter,
    SometimeBefore,
    When,
    forall,
    parse_pddl,
    read_pddl,
    solve,
    validate,
)
from vslsp.symbolic.engines.lifted import compile_lifted

DATA = Path(__file__).resolve().parents[1] / "data" / "pddl3"

LIGHTS = """(define (domain lights)
  (:requirements :strips :typing :negative-preconditions :equality :conditional-effects :constraints)
  (:types lamp)
  (:constants hall - lamp)
  (:predicates (on ?l - lamp) (linked ?a - lamp ?b - lamp))
  (:action switch-on
    :parameters (?l - lamp)
    :precondition (not (on ?l))
    :effect (and (on ?l) (forall (?m - lamp) (when (linked ?l ?m) (on ?m)))))
  (:action switch-off
    :parameters (?l - lamp)
    :precondition (and (on ?l) (not (= ?l hall)))
    :effect (not (on ?l))))
"""
ROOMS = """(define (problem rooms)
  (:domain lights)
  (:objects kitchen porch - lamp)
  (:init (linked kitchen porch))
  (:goal (and (on hall) (not (on porch)))))
"""


@pytest.fixture(scope="module")
def lights():
    domain, problem = parse_pddl(LIGHTS, ROOMS)
    assert problem is not None
    return domain, problem


def test_equality_conditional_effects_and_constants_are_read_written_and_planned(lights):
    domain, problem = lights
    assert domain.constants == (("hall", "lamp"),) and problem.objects == (("kitchen", "lamp"), ("porch", "lamp"))
    switch_on, switch_off = domain.actions
    assert switch_on.effects[1] == When(Atom("linked", ("?l", "?m")), (Atom("on", ("?m",)),), (("?m", "lamp"),))
    assert Not(Equals("?l", "hall")) in switch_off.precondition.args
    again, problem_again = parse_pddl(domain.to_pddl(), problem.to_pddl())
    assert again == domain and problem_again == problem
    plan = solve(domain, problem)
    assert validate(domain, problem, plan).valid
    assert not validate(domain, problem, ["switch-on hall", "switch-off hall"]).valid  # (= ?l hall) forbids it
    # the conditional effect: switching the kitchen on lights the porch too
    assert not validate(domain, problem, ["switch-on hall", "switch-on kitchen"]).valid
    assert validate(domain, problem, ["switch-on hall", "switch-on porch", "switch-off porch"]).valid


CONSTRAINTS = {
    "always": Always(Not(Atom("on", ("kitchen",)))),
    "sometime": Sometime(Atom("on", ("porch",))),
    "at-most-once": AtMostOnce(Atom("on", ("porch",))),
    "sometime-before": SometimeBefore(Atom("on", ("hall",)), Atom("on", ("porch",))),
    "sometime-after": SometimeAfter(Atom("on", ("porch",)), Not(Atom("on", ("porch",)))),
    "at-end": AtEnd(Not(Atom("on", ("kitchen",)))),
    "quantified": Sometime(Exists((("?x", "lamp"),), Atom("on", ("?x",)) & Not(Equals("?x", "hall")))),
    "one-shape": SometimeBefore(Atom("on", ("kitchen",)), Atom("on", ("porch",))),
}


@pytest.mark.parametrize("kind", sorted(CONSTRAINTS))
def test_the_lifted_compilation_accepts_exactly_the_plans_the_constraint_allows(lights, kind):
    """Every plan of up to 3 steps: valid for the constrained problem <=> valid for the compiled one."""
    domain, problem = lights
    problem = problem.with_goal(Atom("on", ("hall",))).with_constraint(CONSTRAINTS[kind])
    if kind == "one-shape":  # constraints of one shape share a parameterised monitor
        problem = problem.with_constraint(SometimeBefore(Atom("on", ("porch",)), Atom("on", ("hall",))))
    compiled_domain, compiled_problem = compile_lifted(domain, problem)
    assert not compiled_problem.constraints
    steps = [f"{a.name} {o}" for a in domain.actions for o, _ in problem.all_objects()]
    agreed = allowed = 0
    for length in range(4):
        for plan in itertools.product(steps, repeat=length):
            kept = validate(domain, problem, plan).valid
            assert kept == validate(compiled_domain, compiled_problem, plan).valid, (kind, plan)
            agreed += 1
            allowed += kept
    assert agreed == sum(len(steps) ** n for n in range(4)) and allowed > 0
    plan = solve(domain, problem)
    assert plan.compilation is Compilation.LIFTED and validate(domain, problem, plan).valid


def test_a_long_order_shares_one_monitor(lights):
    domain, _ = parse_pddl(LIGHTS)
    text = ROOMS.replace("kitchen porch - lamp", " ".join(f"l{i}" for i in range(30)) + " - lamp")
    text = text.replace("(linked kitchen porch)", "").replace("(not (on porch))", "(on l29)")
    _, problem = parse_pddl(LIGHTS, text)
    assert problem is not None
    for i in range(29):
        problem = problem.with_constraint(SometimeBefore(Atom("on", (f"l{i + 1}",)), Atom("on", (f"l{i}",))))
    problem = problem.with_goal(forall(("?l", "lamp"), Atom("on", ("?l",))))  # lamps on, in the order
    compiled_domain, _ = compile_lifted(domain, problem)
    monitors = [p.name for p in compiled_domain.predicates if p.name.startswith("vslsp-")]
    assert monitors == ["vslsp-violated", "vslsp-t1", "vslsp-c1"]
    plan = solve(domain, problem)
    assert [s for s in plan.lines() if s.startswith("switch-on l")] == [f"switch-on l{i}" for i in range(30)]
    assert validate(domain, problem, plan).valid


@pytest.mark.parametrize("name", ["blocksworld/p1", "blocksworld/p5", "sokoban/p1", "sokoban/p2"])
def test_public_constrained_problems_plan_lifted_and_validate(name):
    folder, instance = name.split("/")
    with pytest.warns(PddlWarning, match=r"lists \d constraints without \(and ...\)"):
        domain, problem = read_pddl(
            DATA / "liftedtcore" / folder / "domain.pddl", DATA / "liftedtcore" / folder / f"{instance}.pddl"
        )
    assert problem is not None and len(problem.constraints) >= 2
    plan = solve(domain, problem, timeout=60)
    assert plan.compilation is Compilation.LIFTED and validate(domain, problem, plan).valid


def test_the_ground_compilation_agrees_on_a_public_problem():
    domain, problem = read_pddl(
        DATA / "liftedtcore" / "blocksworld" / "domain.pddl", DATA / "liftedtcore" / "blocksworld" / "p1.pddl"
    )
    assert problem is not None
    plan = solve(domain, problem, compilation=Compilation.GROUND, timeout=60)
    assert plan.compilation is Compilation.GROUND and validate(domain, problem, plan).valid


def test_preferences_are_ignored_with_a_warning_and_the_hard_goal_is_planned():
    folder = DATA / "ipc2006" / "trucks-preferences-qualitative"
    with pytest.warns(PddlWarning) as warned:
        domain, problem = read_pddl(folder / "domain.pddl", folder / "instance-1.pddl")
    assert any("5 preferences ignored" in str(w.message) for w in warned)
    assert problem is not None and problem.constraints == ()
    plan = solve(domain, problem)
    assert plan.steps and validate(domain, problem, plan).valid


def test_either_in_predicates_and_late_type_declarations_are_read():
    folder = DATA / "ipc2006" / "storage-preferences-qualitative"
    with pytest.warns(PddlWarning, match=r"\(either ...\)"):
        domain, _ = read_pddl(folder / "domain.pddl")
    assert dict(domain.predicate("in").parameters)["?x"] == "surface"
    assert dict(domain.types)["area"] == "surface"


def test_sections_out_of_order_are_read_with_a_warning():
    folder = DATA / "ipc2006" / "tpp-preferences-qualitative"
    with pytest.warns(PddlWarning, match="sections were read in the order"):
        domain, _ = read_pddl(folder / "domain.pddl")
    assert domain.constants == (("level0", "level"),)


def test_at_end_is_read_and_kept(lights):
    domain, problem = lights
    text = ROOMS.replace(
        "(:goal (and (on hall) (not (on porch))))",
        "(:goal (on hall))\n  (:constraints (and (at end (on porch)) (sometime (on kitchen)))))",
    )
    _, problem = parse_pddl(LIGHTS, text[:-2] + "\n")
    assert problem is not None and AtEnd(Atom("on", ("porch",))) in problem.constraints
    plan = solve(domain, problem)
    assert validate(domain, problem, plan).valid


def test_type_cycle_is_named_with_its_place():
    text = LIGHTS.replace("(:types lamp)", "(:types lamp - bulb\n   bulb - lamp)")
    with pytest.raises(InputError, match=r"^<domain>:3:11: the types form a cycle \(lamp - bulb - lamp\)"):
        parse_pddl(text)


def test_unsupported_constructs_are_named_as_written_with_their_place():
    text = LIGHTS.replace("(:action switch-off", "(:durative-action switch-off")
    with pytest.raises(InputError, match=r"^<domain>:10:4: durative actions are not supported"):
        parse_pddl(text)
    text = LIGHTS.replace(
        "(:action switch-off\n    :parameters (?l - lamp)", "(:action switch-off\n    :parameters (?l - (either lamp))"
    )
    with pytest.raises(InputError, match=r"^<domain>:11:24: \(either ...\) types are not supported"):
        parse_pddl(text)


def test_a_file_over_the_size_limit_is_refused_up_front(tmp_path):
    big = tmp_path / "big.pddl"
    big.write_text(LIGHTS + ";" * 1_000_001)
    with pytest.raises(
        InputError, match=r"big.pddl: the PDDL file has 1.0 MB, over the limit of 1.0 MB; raise it with --max-size MB"
    ):
        read_pddl(big, max_bytes=1_000_000)
    assert read_pddl(big)[0].name == "lights"  # the default limit (100 MB) reads it


def test_undeclared_requirements_are_warned_and_counts_read_well(lights):
    text = LIGHTS.replace(":negative-preconditions :equality ", "")
    with pytest.warns(PddlWarning, match=r"the domain uses :negative-preconditions, :equality without declaring them"):
        parse_pddl(text, ROOMS)
    domain, problem = lights
    verdict = validate(
        domain,
        problem.with_goal(Atom("on", ("hall",))).with_constraint(CONSTRAINTS["sometime"]),
        ["switch-on porch", "switch-on hall"],
    )
    assert verdict.reason == "the plan reaches the goal in 2 steps and keeps its constraint"
    assert (
        validate(domain, problem.with_goal(Atom("on", ("hall",))), ["switch-on hall"]).reason
        == "the plan reaches the goal in 1 step"
    )
