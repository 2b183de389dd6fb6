"""VSL-SP's loop: action models learned from the robot's own observed executions, then a task
planned and executed in closed loop, replanning when a step's effect is missing."""

from dataclasses import replace
from pathlib import Path

import pytest

from vslsp.experiments.icub_faults import Faults
from vslsp.experiments.icub_run import IcubRun
from vslsp.experiments.icub_scripts import record
from vslsp.loop.pipeline import execute_task, explore_skill, learn_models
from vslsp.sim import LineWorld, SceneSpec
from vslsp.symbolic import Atom, LearnedTask, Not, PlanStatus, SometimeBefore, Step, learn_task, read_domain

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def domain(library):
    explorations = []
    for action, far in (("push", False), ("pull", True)):
        with LineWorld(SceneSpec.random(21, n_cubes=1, far=(far,))) as world:
            explorations.append(explore_skill(world, library, action))
    return learn_models(explorations)


def test_table_3_comes_out_of_watching_the_skills(domain):
    # push: pre (not (far ?b)), eff (far ?b); pull the reverse: learned from what the camera saw,
    # equal to the paper's Table 3 as written in pddl/domain.pddl.
    table_3 = read_domain(REPO / "pddl" / "domain.pddl")
    assert {a.name for a in domain.actions} == {"push", "pull"}
    far = Atom("far", ("?b",))
    assert domain.action("push").precondition == Not(far) and domain.action("push").effects == (far,)
    assert domain.action("pull").precondition == far and domain.action("pull").effects == (Not(far),)
    assert domain.action("push") == table_3.action("push") and domain.action("pull") == table_3.action("pull")


def _all_near_task() -> LearnedTask:
    steps = [
        [
            Step(
                "pull",
                "red",
                {"red": {"far": True}, "blue": {"far": False}},
                {"red": {"far": False}, "blue": {"far": False}},
            )
        ],
        [
            Step(
                "pull",
                "green",
                {"green": {"far": True}, "red": {"far": True}},
                {"green": {"far": False}, "red": {"far": True}},
            ),
            Step(
                "pull",
                "red",
                {"green": {"far": False}, "red": {"far": True}},
                {"green": {"far": False}, "red": {"far": False}},
            ),
        ],
    ]
    return learn_task(steps, ordered=False)


def test_a_task_is_planned_executed_and_checked_in_the_simulator(library, domain):
    spec = SceneSpec.random(5, colours=("orange", "purple"), far=(True, True))
    with LineWorld(spec) as world:
        run = execute_task(world, library, domain, _all_near_task())
        assert run.success, run.error
        assert not any(world.is_far(c.name) for c in spec.cubes)  # ground truth
        assert sorted(run.executed) == ["orange", "purple"]
        assert run.plans[-1].steps == ()  # the last plan, from the observed state, is empty


def test_a_missing_effect_makes_the_robot_replan(library, domain):
    spec = SceneSpec.random(6, colours=("blue", "yellow"), far=(True, False))
    with LineWorld(spec) as world:
        faults = Faults({0: "nudge"})  # the experiments' fault injection, through the loop's hooks
        run = execute_task(world, library, domain, _all_near_task(), act=faults.act, on_plan=faults.planned)
        assert run.replans == 1 and not run.steps[0].ok and faults.fired == {0: "nudge"}
        assert run.success, run.error
        assert not world.is_far("blue")


def _red_then_blue() -> LearnedTask:
    """The demonstrated order: red pulled near, then blue (PDDL 3 ``sometime-before``)."""
    both_far = {"red": {"far": True}, "blue": {"far": True}}
    red_near = {"red": {"far": False}, "blue": {"far": True}}
    both_near = {"red": {"far": False}, "blue": {"far": False}}
    return learn_task(
        [[Step("pull", "red", both_far, red_near), Step("pull", "blue", red_near, both_near)]], ordered=True
    )


def test_a_planner_timeout_ends_the_run_as_a_timeout_and_keeps_the_order(library, domain):
    # Out of time, the planner proved nothing: the order is not dropped (as it is when no plan
    # exists), the run ends there and says the planner's time limit was reached.
    task = _red_then_blue()
    assert task.ordered and task.constraints
    spec = SceneSpec.random(7, colours=("red", "blue"), far=(True, True))
    with LineWorld(spec) as world:
        run = execute_task(world, library, domain, task, planner_timeout=0.01)
        assert world.is_far("red") and world.is_far("blue")  # nothing executed
    assert not run.success and run.steps == [] and run.plans == []
    assert run.planning_status is PlanStatus.TIMEOUT and run.cause == "planner time limit"
    assert run.error == "no plan: the planner's time limit of 0.01 s reached (raise it with --timeout)"
    assert run.notes == []  # not replanned without the demonstrated order
    assert run.to_dict()["planning_status"] == "timeout"
    trial = IcubRun(7)  # the trial's record and the report's failure cause say so too
    record(trial, run)
    assert trial.details["planning_status"] == "timeout" and trial.error == run.error
    assert trial.cause == "planner time limit" and not trial.success


def test_an_order_no_plan_can_keep_is_dropped_and_the_goal_reached(library, domain):
    # Red near only after blue, and blue only after red (two demonstrations in opposite orders):
    # the planner proves there is no plan, so the loop keeps the goal and replans without the order.
    task = _red_then_blue()
    (red_first,) = task.constraints
    task = replace(task, constraints=(red_first, SometimeBefore(red_first.before, red_first.formula)))
    spec = SceneSpec.random(8, colours=("red", "blue"), far=(True, True))
    with LineWorld(spec) as world:
        run = execute_task(world, library, domain, task)
        assert not world.is_far("red") and not world.is_far("blue")
    assert run.success, run.error
    assert run.planning_status is None and "planning_status" not in run.to_dict()
    assert len(run.notes) == 1 and run.notes[0].startswith("no plan: ")
    assert run.notes[0].endswith("; replanning without the demonstrated order")
