"""Each environment passes Gymnasium's own checker on the unwrapped environment (spaces, seeded
resets giving the same scene, deterministic steps, rendering, closing twice), a random policy
runs an episode through it, a seeded reset gives the same scene, and closing releases the
simulator."""

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import vslsp.gym  # noqa: F401 (registers the environments)

ENVIRONMENTS = ("vslsp/PandaTable-v0", "vslsp/RGBDTable-v0", "vslsp/ICubLine-v0")


@pytest.mark.slow
@pytest.mark.parametrize("env_id", ENVIRONMENTS)
def test_gymnasium_check_env_passes(env_id):
    env = gymnasium.make(env_id, render_mode="rgb_array")
    try:
        check_env(env.unwrapped)
    finally:
        env.close()


@pytest.mark.slow
@pytest.mark.parametrize("env_id", ENVIRONMENTS)
def test_a_random_policy_runs_an_episode(env_id):
    env = gymnasium.make(env_id, max_steps=3, render_mode="rgb_array")
    try:
        env.action_space.seed(7)
        observation, info = env.reset(seed=7)
        assert info["trial_seed"] == 7
        steps, done = 0, False
        while not done:
            observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
            assert observation in env.observation_space
            assert reward in (0.0, 1.0) and reward == float(info["is_success"])
            steps, done = steps + 1, terminated or truncated
        assert steps <= 3
        frame = env.render()
        assert frame.shape == (480, 640, 3) and frame.dtype == np.uint8
    finally:
        env.close()


@pytest.mark.slow
def test_the_same_seed_gives_the_same_scene_and_another_seed_another():
    env = gymnasium.make("vslsp/PandaTable-v0")
    try:
        first, _ = env.reset(seed=3)
        again, _ = env.reset(seed=3)
        other, _ = env.reset(seed=4)
    finally:
        env.close()
    assert np.array_equal(first, again)
    assert not np.array_equal(first, other)


@pytest.mark.slow
def test_close_disconnects_the_simulator():
    env = gymnasium.make("vslsp/ICubLine-v0")
    env.reset(seed=0)
    world = env.unwrapped.world
    env.close()
    assert env.unwrapped.world is None
    with pytest.raises(RuntimeError, match="is closed"):
        _ = world.live_client
    env.close()  # twice: harmless
