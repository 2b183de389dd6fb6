"""VSL-SP's loop: action models learned from the robot's own observed executions, then a task
planned and executed in closed loop, replanning when a step's effect is missing."""

from pathlib import Path

import pytest

from vslsp.loop.pipeline import execute_task, explore_skill, learn_models
from vslsp.sim import SceneSpec, World
from vslsp.symbolic import Atom, Not, Step, Task, learn_task, read_domain

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def domain(library):
    explorations = []
    for action, far in (("push", False), ("pull", True)):
        with World(SceneSpec.random(21, n_cubes=1, far=(far,))) as world:
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


def _all_near_task() -> Task:
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
    with World(spec) as world:
        run = execute_task(world, library, domain, _all_near_task())
        assert run.success, run.error
        assert not any(world.is_far(c.name) for c in spec.cubes)  # ground truth
        assert sorted(run.executed) == ["orange", "purple"]
        assert run.plans[-1].steps == ()  # the last plan, from the observed state, is empty


def test_a_missing_effect_makes_the_robot_replan(library, domain):
    spec = SceneSpec.random(6, colours=("blue", "yellow"), far=(True, False))
    with World(spec) as world:
        run = execute_task(world, library, domain, _all_near_task(), faults={0: "nudge"})
        assert run.replans == 1 and not run.steps[0].ok
        assert run.success, run.error
        assert not world.is_far("blue")
