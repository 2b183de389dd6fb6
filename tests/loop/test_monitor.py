"""Closed-loop steps: perception of a rendered scene, a skill run on what is seen, the check."""

import numpy as np
import pytest

from vslsp.loop.monitor import StepResult, execute_step, fault_log
from vslsp.loop.perception import perceive
from vslsp.sim import SceneSpec, World


def test_the_robot_sees_every_cube_where_it_is_and_on_which_side():
    spec = SceneSpec.random(11, n_cubes=3)
    with World(spec) as world:
        state = perceive(world)
        assert sorted(state.objects) == sorted(c.colour for c in spec.cubes)
        for cube in spec.cubes:
            seen = state.objects[cube.colour]
            x, y, _ = world.cube_pose(cube.name)
            assert np.hypot(seen.table_xy[0] - x, seen.table_xy[1] - y) < 0.015
            assert seen.far == world.is_far(cube.name)
        # The line's normal seen through the camera points away from the robot, as the truth's.
        assert np.dot(state.normal, spec.landmark.normal) > 0.99


@pytest.mark.parametrize("action", ["pull", "push"])
def test_a_step_moves_the_cube_across_and_the_robot_sees_it(library, action):
    spec = SceneSpec.random(3, n_cubes=1, far=(action == "pull",))
    name = spec.cubes[0].name
    with World(spec) as world:
        state = perceive(world)
        result, after = execute_step(world, library, action, name, state)
        assert result.ok, result.error
        assert world.is_far(name) == (action == "push")  # ground truth
        assert after.objects[name].far == (action == "push")
        assert result.trajectory is not None and len(result.trajectory.t) > 100
        # The move is sized to leave the cube clearly past the line, not on it.
        assert 0.02 < abs(after.line_distance(name)) < 0.12


@pytest.mark.parametrize("fault", ["skip", "nudge"])
def test_a_faulty_step_is_noticed(library, fault):
    spec = SceneSpec.random(4, n_cubes=1, far=(True,))
    name = spec.cubes[0].name
    with World(spec) as world:
        state = perceive(world)
        result, after = execute_step(world, library, "pull", name, state, fault=fault)
        assert not result.ok
        assert result.observed_far is True and world.is_far(name)
        assert "expected (far" in result.error
        # The step says which fault it carried, in the words the report uses.
        assert result.fault == fault and result.to_dict()["fault"] == fault
        assert (result.expected, result.observed) == (f"(not (far {name}))", f"(far {name})")


def test_the_fault_log_explains_each_fault_and_what_followed_it():
    skipped = StepResult("pull", "green", False, True, False, "expected ...", fault="skip")
    again = StepResult("pull", "green", False, False, True, None)
    nudged = StepResult("push", "red", True, None, False, "expected ...", fault="nudge")
    vsl_skipped = StepResult("pull", "blue", False, True, False, "expected ...", fault="skip")
    vsl_again = StepResult("pull", "blue", False, False, True, None)
    steps = [skipped, again, nudged, vsl_skipped, vsl_again]
    log = fault_log(steps, {id(skipped), id(again), id(nudged)}, "gave up")
    assert [(e["step"], e["kind"]) for e in log] == [(1, "skip"), (3, "nudge"), (4, "skip")]
    assert log[0]["expected"] == "(not (far green))" and log[0]["observed"] == "(far green)"
    assert log[0]["recovery"] == "replanned: pull green"
    # The planned run's next step is VSL's, not a recovery of the planner's: none followed it.
    assert log[1]["observed"] == "red not seen" and log[1]["recovery"] == "none: gave up"
    assert log[2]["recovery"] == "VSL matched again: pull blue"
    assert fault_log([again], {id(again)}, "") == []
