"""VSL as a policy in a Gymnasium environment (docs/gym.md): the tutor's demonstration of
alphabet-ordering recorded in the world of a seed, then reproduced in a new scene of
``vslsp/PandaTable-v0`` one pick-and-place a step, until the experiment's judge rewards the goal.
Run it with

    python examples/gym/vsl_policy.py [SEED]
"""

from __future__ import annotations

import sys

import gymnasium

import vslsp.gym  # noqa: F401 (registers vslsp/PandaTable-v0, vslsp/RGBDTable-v0, vslsp/ICubLine-v0)
from vslsp.gym.policies import VslPolicy


def run(seed: int = 0) -> float:
    """One episode of the VSL policy; its return (1.0: the letters stand in their row)."""
    env = gymnasium.make("vslsp/PandaTable-v0", task="alphabet-ordering")
    try:
        observation, info = env.reset(seed=seed)
        demonstration = env.unwrapped.demonstrate()  # Algorithm 1 part I, in the trial's own world
        policy = VslPolicy(demonstration.demonstration, env.unwrapped.camera)
        total, done, step = 0.0, False, None
        while not done:
            action = policy(observation, step)  # Algorithm 1 part II: match, plan, one pick-and-place
            if action is None:
                break
            observation, reward, terminated, truncated, step = env.step(action)
            print(f"picked {step['held']}, reward {reward}")
            total, done = total + reward, terminated or truncated
        return total
    finally:
        env.close()


if __name__ == "__main__":
    print(f"return {run(int(sys.argv[1]) if len(sys.argv) > 1 else 0)}")
