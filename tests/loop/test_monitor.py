"""Closed-loop steps: perception of a rendered scene, a skill run on what is seen, the check of
the effect its learned model expects."""

import numpy as np
import pytest

from vslsp.errors import TaskFailed
from vslsp.loop.monitor import execute_step, model_expects_far
from vslsp.loop.perception import perceive
from vslsp.sim import SceneSpec
from vslsp.symbolic import Action, Atom, Domain, Not, Predicate, When
from vslsp.worlds import World
from vslsp.worlds.icub import IcubLineWorld

FAR = Atom("far", ("?b",))
BLOCK = (("?b", "block"),)


def _domain(*actions: Action) -> Domain:
    return Domain("d", (("block", None),), (Predicate("far", BLOCK),), actions)


def test_the_robot_sees_every_cube_where_it_is_and_on_which_side():
    spec = SceneSpec.random(11, n_cubes=3)
    with IcubLineWorld.from_layout(spec) as world:
        assert isinstance(world, World)  # the loop acts on the worlds' protocol
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
    with IcubLineWorld.from_layout(spec) as world:
        state = perceive(world)
        result, after = execute_step(world, library, action, name, state, action == "push")
        assert result.ok, result.error
        assert world.is_far(name) == (action == "push")  # ground truth
        assert after.objects[name].far == (action == "push")
        assert result.trajectory is not None and len(result.trajectory.t) > 100
        # The move is sized to leave the cube clearly past the line, not on it.
        assert 0.02 < abs(after.line_distance(name)) < 0.12


def test_the_expected_effect_is_the_learned_models():
    far = {"red": True, "blue": False}
    domain = _domain(
        Action("push", BLOCK, Not(FAR), (FAR,)),
        Action("pull", BLOCK, FAR, (Not(FAR),)),
        Action("wipe", BLOCK),  # no effect on far: far stays as it was
        Action("flip", BLOCK, effects=(When(FAR, (Not(FAR),)), When(Not(FAR), (FAR,)))),  # read before
    )
    assert model_expects_far(domain, "push", ("blue",), far) is True
    assert model_expects_far(domain, "pull", ("red",), far) is False
    assert model_expects_far(domain, "wipe", ("red",), far) is True
    assert model_expects_far(domain, "wipe", ("blue",), far) is False
    assert model_expects_far(domain, "flip", ("red",), far) is False
    assert model_expects_far(domain, "flip", ("blue",), far) is True
    with pytest.raises(TaskFailed, match="no action 'lift'"):
        model_expects_far(domain, "lift", ("red",), far)


def test_a_step_is_checked_against_its_model_not_a_table(library):
    # A domain that (wrongly) models pull as leaving the cube far: the same pull that crosses the
    # line is then a failed step, its error naming the model's expectation.
    wrong = _domain(Action("pull", BLOCK, FAR, ()))
    spec = SceneSpec.random(4, n_cubes=1, far=(True,))
    name = spec.cubes[0].name
    with IcubLineWorld.from_layout(spec) as world:
        state = perceive(world)
        expected = model_expects_far(wrong, "pull", (name,), state.far())
        result, after = execute_step(world, library, "pull", name, state, expected)
        assert not world.is_far(name) and after.objects[name].far is False  # the cube crossed
        assert not result.ok and result.expected == f"(far {name})" and result.observed == f"(not (far {name}))"
        assert result.error == f"expected (far {name}) to be True after pull, observed False"


def test_a_step_without_a_skill_or_an_object_is_refused(library):
    spec = SceneSpec.random(4, n_cubes=1, far=(True,))
    with IcubLineWorld.from_layout(spec) as world:
        state = perceive(world)
        with pytest.raises(TaskFailed, match="no skill for action 'lift'"):
            execute_step(world, library, "lift", spec.cubes[0].name, state, False)
        with pytest.raises(TaskFailed, match="does not see it"):
            execute_step(world, library, "pull", "nothing", state, False)
