"""Planning with unified-planning + Fast Downward: the demonstrated order enforced through
compiled PDDL 3.0 constraints, dropped on request, unsolvable problems reported as no plan."""

import pytest

from vslsp.errors import InputError, TaskFailed
from vslsp.symbolic import (
    Always,
    Atom,
    NoPlan,
    Not,
    PlanResult,
    PlanStatus,
    SometimeBefore,
    Unsolvable,
    check_planner,
    solve,
    validate,
)

DEMONSTRATED = ["pull orange", "pull green", "pull yellow"]


def test_plan_respects_the_demonstrated_order(pull_in_order):
    domain, problem = pull_in_order
    plan = solve(domain, problem)
    assert plan.lines() == DEMONSTRATED and plan.planner == "fast-downward" and plan.time_s > 0
    assert plan.steps[0] == ("pull", ("orange",))


@pytest.mark.parametrize("order", [("yellow", "green", "orange"), ("green", "yellow", "orange")])
def test_order_reversed_in_the_problem_is_followed(pull_in_order, order):
    domain, problem = pull_in_order

    def near(c):
        return Not(Atom("far", (c,)))

    reordered = problem.without_constraints()
    for earlier, later in zip(order, order[1:], strict=False):
        reordered = reordered.with_constraint(SometimeBefore(near(later), near(earlier)))
    assert solve(domain, reordered).lines() == [f"pull {c}" for c in order]


def test_without_the_order_the_planner_chooses(pull_in_order):
    domain, problem = pull_in_order
    free = problem.without_constraints()
    plan = solve(domain, free)
    assert sorted(plan.lines()) == sorted(DEMONSTRATED)
    # Any order is now acceptable, including the reverse of the demonstration.
    assert validate(domain, free, DEMONSTRATED[::-1]).valid
    assert not validate(domain, problem, DEMONSTRATED[::-1]).valid


def test_planning_is_deterministic_and_other_planners_are_selectable(pull_in_order):
    domain, problem = pull_in_order
    assert solve(domain, problem).steps == solve(domain, problem).steps
    for planner in ("fast-downward-opt", "fast-downward-lama"):
        plan = solve(domain, problem, planner=planner)
        assert plan.lines() == DEMONSTRATED and plan.planner == planner


def test_unsolvable_problems_raise_no_plan(pull_in_order):
    domain, problem = pull_in_order
    with pytest.raises(TaskFailed, match=r"^no plan: .*proved by Fast Downward") as proved:
        solve(domain, problem.with_constraint(Always(Atom("far", ("green",)))))
    assert isinstance(proved.value, Unsolvable) and proved.value.status is PlanStatus.UNSOLVABLE_PROVEN
    assert proved.value.cause == "no plan"  # what a report tallies, typed: not read from the message
    with pytest.raises(TaskFailed, match=r"^no plan: \(sometime-before \(not \(far green\)\).*already true") as broken:
        solve(domain, problem.without_init(Atom("far", ("green",))))
    assert broken.value.status is PlanStatus.UNSOLVABLE_PROVEN


@pytest.mark.parametrize("planner", ["fast-downward", "fast-downward-opt"])
def test_a_planner_out_of_time_says_so_in_its_status_not_unsolvable(pull_in_order, planner):
    # fast-downward: the driver run directly; fast-downward-opt: through unified-planning's engine.
    with pytest.raises(NoPlan, match=r"^no plan: the planner's time limit of 0.01 s reached") as stopped:
        solve(*pull_in_order, planner=planner, timeout=0.01)
    assert stopped.value.status is PlanStatus.TIMEOUT and stopped.value.status.limit_reached
    assert not isinstance(stopped.value, Unsolvable) and stopped.value.cause == "planner time limit"


def test_unknown_planner_is_an_input_error(pull_in_order):
    with pytest.raises(InputError, match="unknown planner 'nope'; available: fast-downward, fast-downward-lama"):
        solve(*pull_in_order, planner="nope")
    with pytest.raises(InputError, match="unknown planner 'nope'"):
        check_planner("nope")
    check_planner("fast-downward-lama")


def test_plan_result_forms():
    plan = PlanResult((("pull", ("orange",)), ("push", ("red",))), "fast-downward", 0.5)
    assert plan.to_pddl() == "(pull orange)\n(push red)\n"
    assert PlanResult.from_dict(plan.to_dict()) == plan
