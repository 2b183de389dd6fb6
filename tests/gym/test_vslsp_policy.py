"""VSL-SP's closed loop as a policy: the robot of the episode's trial learns push's and pull's
models and the ordered task from the tutor, plans with the planner and pulls the orange, green
and yellow cubes of ``vslsp/ICubLine-v0`` near in the demonstrated order, one plan step a step."""

import gymnasium
import pytest
from helpers.gym_episodes import run_episode

import vslsp.gym  # noqa: F401 (registers the environments)
from vslsp.gym.vslsp_policy import VslSpPolicy


@pytest.mark.slow
def test_the_vslsp_policy_pulls_the_cubes_in_the_demonstrated_order():
    env = gymnasium.make("vslsp/ICubLine-v0")
    try:
        observation, _ = env.reset(seed=0)
        domain, task = env.unwrapped.demonstrate()
        assert task.ordered and len(task.constraints) == 2  # sometime-before: orange, green, yellow
        policy = VslSpPolicy(domain, task)
        rewards, infos, observation = run_episode(env, policy, observation)
        assert policy(observation, infos[-1]) is None  # the next plan is empty: the goal holds in what it sees
    finally:
        env.close()
    steps = [f"{info['skill']} {info['colour']}" for info in infos]
    assert rewards == [0.0, 0.0, 1.0]
    assert steps == ["pull orange", "pull green", "pull yellow"]
    assert [plan.lines() for plan in policy.plans] == [steps, []]
    assert policy.success and policy.replans == 0
