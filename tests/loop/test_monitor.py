"""Closed-loop steps: perception of a rendered scene, a skill run on what is seen, the check."""

import numpy as np
import pytest

from vslsp.loop.monitor import execute_step
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
