"""VSL's reproduction as a policy: from the tutor's recorded demonstration of the episode's trial,
it picks and places the letters of alphabet-ordering in the reproduction world, one step an
operation, until the experiment's judge says the goal holds."""

import gymnasium
import pytest
from helpers.gym_episodes import run_episode

import vslsp.gym  # noqa: F401 (registers the environments)
from vslsp.gym.policies import VslPolicy


@pytest.mark.slow
def test_the_vsl_policy_reaches_the_goal_of_alphabet_ordering():
    env = gymnasium.make("vslsp/PandaTable-v0")
    try:
        observation, _ = env.reset(seed=0)
        demonstration = env.unwrapped.demonstrate()
        assert demonstration.items == ("A", "B", "C", "D")
        policy = VslPolicy(demonstration.demonstration, env.unwrapped.camera)
        rewards, infos, _ = run_episode(env, policy, observation)
    finally:
        env.close()
    assert rewards[-1] == 1.0 and sum(rewards) == 1.0
    # one pick-and-place an operation, in the demonstrated order
    assert [info["held"] for info in infos] == ["A", "B", "C", "D"]
    assert policy.next == 4
