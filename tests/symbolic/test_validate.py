"""The plan validator: simulation over states, preconditions, goal and every PDDL 3.0
trajectory constraint with its semantics."""

import pytest
from helpers.symbolic import PDDL, far

from vslsp.errors import InputError
from vslsp.symbolic import (
    Always,
    AtEnd,
    AtMostOnce,
    Not,
    Sometime,
    SometimeAfter,
    SometimeBefore,
    parse_pddl,
    parse_plan,
    read_pddl,
    validate,
)


def test_demonstrated_order_is_valid(pull_in_order):
    verdict = validate(*pull_in_order, ["(pull orange)", "pull green", ("pull", ("yellow",))])
    assert verdict.valid and "keeps all 2 constraints" in verdict.reason


def test_wrong_order_is_rejected_naming_sometime_before(pull_in_order):
    verdict = validate(*pull_in_order, ["pull orange", "pull yellow", "pull green"])
    assert not verdict.valid
    assert verdict.reason.startswith("constraint (sometime-before (not (far yellow)) (not (far green))) is broken")
    assert "after step 2 (pull yellow)" in verdict.reason


def test_preconditions_goal_and_names_are_checked(pull_in_order):
    assert (
        "step 1 (push orange): precondition (not (far orange)) does not hold"
        in validate(*pull_in_order, ["push orange"]).reason
    )
    assert "the goal" in validate(*pull_in_order, ["pull orange"]).reason
    assert "unknown action 'jump'" in validate(*pull_in_order, ["jump orange"]).reason
    assert "'purple' is not an object" in validate(*pull_in_order, ["pull purple"]).reason


# Trajectory: s0 {red far}, s1 after push blue {red, blue far}, s2 after pull red {blue far},
# s3 after push red {red, blue far}, s4 after pull blue {red far}.
PLAN = ["push blue", "pull red", "push red", "pull blue"]


@pytest.mark.parametrize(
    "constraint, valid, why",
    [
        (Always(far("red") | far("blue")), True, ""),
        (Always(far("red")), False, "(far red) is false after step 2 (pull red)"),
        (Sometime(far("blue") & Not(far("red"))), True, ""),
        (Sometime(Not(far("red")) & Not(far("blue"))), False, "never holds"),
        (AtMostOnce(far("blue")), True, ""),
        (AtMostOnce(far("red")), False, "becomes true again after step 3 (push red)"),
        (SometimeBefore(Not(far("red")), far("blue")), True, ""),
        (SometimeBefore(far("blue"), Not(far("red"))), False, "(far blue) holds after step 1 (push blue)"),
        (SometimeAfter(Not(far("red")), far("red")), True, ""),
        (SometimeAfter(far("blue"), Not(far("red")) & far("blue")), False, "after step 3 (push red)"),
        (AtEnd(Not(far("blue"))), True, ""),
        (AtEnd(far("blue")), False, "false at the end"),
    ],
)
def test_each_constraint_has_its_pddl3_meaning(constraint, valid, why):
    domain, problem = read_pddl(PDDL / "domain.pddl", PDDL / "simple-push-pull.pddl")
    problem = problem.without_init(far("blue")).with_goal(far("red")).with_constraint(constraint)
    verdict = validate(domain, problem, PLAN)
    assert verdict.valid == valid, verdict.reason
    assert why in verdict.reason


def test_plan_text_errors_name_line_and_column(pull_in_order):
    text = "; a plan\n(pull orange)\n\n  (pull green\n"
    with pytest.raises(InputError, match=r"^plan.txt:4:3: expected one step like \(pull green\)"):
        parse_plan(text, *pull_in_order, name="plan.txt")
    with pytest.raises(InputError, match=r"^plan.txt:1:4: pull: takes 1 argument\(s\), 2 given"):
        parse_plan("  (pull orange green)", *pull_in_order, name="plan.txt")
    assert parse_plan("(PULL Orange) ; first\n", *pull_in_order) == [("pull", ("orange",))]


def _random_problem(rng, domain, problem):
    """Three blocks, a random initial state, goal and two random PDDL 3.0 constraints."""
    blocks = ("red", "green", "blue")

    def lit():
        atom = far(rng.choice(blocks))
        return atom if rng.random() < 0.5 else Not(atom)

    kinds = (
        lambda: Always(lit() | lit()),
        lambda: Sometime(lit() & lit()),
        lambda: AtMostOnce(lit()),
        lambda: SometimeBefore(lit(), lit()),
        lambda: SometimeAfter(lit(), lit()),
    )
    problem = problem.without_init(*problem.init).with_init(*(far(b) for b in blocks if rng.random() < 0.5))
    problem = problem.with_goal(lit() & lit())
    for _ in range(2):
        problem = problem.with_constraint(rng.choice(kinds)())
    return problem


def test_planner_and_validator_agree_on_random_problems():
    """The planner's compiled constraints and the validator's semantics are the same: every
    plan found is valid, and when there is no plan, no plan of up to 4 steps is valid either."""
    import itertools
    import random

    from vslsp.errors import TaskFailed
    from vslsp.symbolic import solve

    domain, base = read_pddl(PDDL / "domain.pddl", PDDL / "simple-push-pull.pddl")
    steps = [(a, (b,)) for a in ("push", "pull") for b in ("red", "green", "blue")]
    rng, outcomes = random.Random(7), {"planned": 0, "no plan": 0}
    for _ in range(12):
        problem = _random_problem(rng, domain, base)
        try:
            plan = solve(domain, problem)
        except TaskFailed:
            outcomes["no plan"] += 1
            for length in range(5):
                for candidate in itertools.product(steps, repeat=length):
                    assert not validate(domain, problem, candidate).valid, (problem.constraints, candidate)
            continue
        outcomes["planned"] += 1
        verdict = validate(domain, problem, plan.steps)
        assert verdict.valid, (problem.goal, problem.constraints, plan.lines(), verdict.reason)
    assert outcomes["planned"] and outcomes["no plan"], outcomes  # both sides exercised


def test_every_violation_is_listed_with_its_step(pull_in_order):
    domain, problem = read_pddl(PDDL / "domain.pddl", PDDL / "simple-push-pull.pddl")
    problem = problem.without_init(far("blue")).with_goal(far("red") & far("blue") & Not(far("green")))
    problem = problem.with_constraint(Always(far("red"))).with_constraint(Sometime(far("green")))
    verdict = validate(domain, problem, PLAN)  # red pulled at step 2; blue near at the end; green never far
    assert not verdict.valid
    assert [(v.kind, v.text, v.step) for v in verdict.violations] == [
        ("goal", "(far blue)", 4),
        ("constraint", "(always (far red))", 2),
        ("constraint", "(sometime (far green))", 4),
    ]
    assert verdict.reason == verdict.violations[0].message == "the goal (far blue) does not hold after the last step"
    assert "(far red) is false after step 2 (pull red)" in verdict.violations[1].message


def test_the_first_inapplicable_step_names_its_false_preconditions_and_what_broke_before(pull_in_order):
    verdict = validate(*pull_in_order, ["pull green", "push orange", "pull yellow"])
    assert [(v.kind, v.text, v.step) for v in verdict.violations] == [
        ("precondition", "(not (far orange))", 2),
        ("constraint", "(sometime-before (not (far green)) (not (far orange)))", 1),  # already broken at step 1
    ]  # the goal and the rest are not judged: the plan stops at step 2
    kitchen_domain, kitchen = parse_pddl(
        "(define (domain k) (:requirements :strips :typing) (:types dish) (:predicates (clean ?d - dish) "
        "(wet ?d - dish) (dirty ?d - dish)) (:action dry :parameters (?d - dish) :precondition (and (dirty ?d) "
        "(clean ?d) (wet ?d)) :effect (not (wet ?d))))",
        "(define (problem p) (:domain k) (:objects a - dish) (:init (dirty a)) (:goal (and)))",
    )
    assert kitchen is not None
    (only,) = validate(kitchen_domain, kitchen, ["dry a"]).violations
    assert (only.kind, only.text, only.step) == ("precondition", "(and (clean a) (wet a))", 1)
    assert only.message == "step 1 (dry a): preconditions (clean a), (wet a) do not hold"
