"""vslsp.gym registers the worlds' environments with Gymnasium: ``gymnasium.make`` builds each
by its id after ``import vslsp.gym``, or by ``vslsp.gym:ID`` without it, with the spaces the
camera and the skills give (no world is built before the first reset)."""

import gymnasium
import numpy as np
import pytest

import vslsp.gym
from vslsp.errors import InputError


@pytest.mark.parametrize(
    ("env_id", "observation", "action"),
    [
        ("vslsp/PandaTable-v0", (960, 1280, 3), (6,)),
        ("vslsp/ICubLine-v0", (480, 640, 3), (2,)),
    ],
)
def test_make_builds_the_environment_with_the_camera_and_skill_spaces(env_id, observation, action):
    env = gymnasium.make(env_id)
    try:
        assert env.observation_space.shape == observation
        assert env.observation_space.dtype == np.uint8
        assert env.action_space.shape == action
        assert env.unwrapped.world is None  # built by reset
    finally:
        env.close()


def test_the_rgbd_table_observes_colour_and_depth_as_a_dict():
    env = gymnasium.make("vslsp.gym:vslsp/RGBDTable-v0")  # Gymnasium imports vslsp.gym first
    try:
        space = env.observation_space
        assert isinstance(space, gymnasium.spaces.Dict)
        assert space["rgb"].shape == (480, 640, 3) and space["depth"].shape == (480, 640)
        assert space["depth"].dtype == np.float32
        assert env.action_space.shape == (6,)
    finally:
        env.close()


def test_every_environment_is_registered():
    assert set(vslsp.gym.ENVIRONMENTS) <= set(gymnasium.registry)


def test_a_step_before_reset_asks_for_the_reset():
    env = gymnasium.make("vslsp/PandaTable-v0").unwrapped
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(env.action_space.sample())


@pytest.mark.parametrize(
    ("env_id", "options", "wrong"),
    [
        ("vslsp/PandaTable-v0", {"task": "domino"}, "task must be one of"),
        ("vslsp/ICubLine-v0", {"task": "simple-vsl-task"}, "task must be one of"),
        ("vslsp/RGBDTable-v0", {"render_mode": "ansi"}, "render_mode must be None or 'rgb_array'"),
    ],
)
def test_an_unknown_option_is_refused_with_what_to_give(env_id, options, wrong):
    with pytest.raises(InputError, match=wrong):
        gymnasium.make(env_id, **options)
