"""VSL-3D's reproduction as a policy: from the tutor's recorded demonstration of the episode's
trial, it picks and places the duck, the teddy and the duckling of the table cleaning in the
reshuffled scene of ``vslsp/RGBDTable-v0``, one step an operation, until the experiment's judge
says every object lies at its demonstrated pose."""

import gymnasium
import pytest
from helpers.gym_episodes import run_episode

import vslsp.gym  # noqa: F401 (registers the environments)
from vslsp.gym.vsl3d_policy import Vsl3dPolicy


@pytest.mark.slow
def test_the_vsl3d_policy_cleans_the_table():
    env = gymnasium.make("vslsp/RGBDTable-v0")
    try:
        observation, _ = env.reset(seed=0)
        demonstrated = env.unwrapped.demonstrate()
        assert all(moved is not None for moved in demonstrated)
        policy = Vsl3dPolicy(demonstrated, env.unwrapped.camera, seed=0)
        rewards, infos, _ = run_episode(env, policy, observation)
    finally:
        env.close()
    assert rewards == [0.0, 0.0, 1.0]
    # the demonstrated order, one pick-and-place each
    assert [info["held"] for info in infos] == ["duck", "teddy", "duckling"]
    assert policy.errors == {}
