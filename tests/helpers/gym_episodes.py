"""An episode of a Gymnasium environment driven by a policy, for the policies' tests."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any


def run_episode(
    env: Any, policy: Callable[[Any, dict | None], Any], observation: Any
) -> tuple[list[float], list[dict], Any]:
    """Step ``env`` with ``policy``'s actions from ``observation`` until the episode ends; the
    rewards and the steps' infos. Fails when the policy stops early or acts outside the action space."""
    rewards: list[float] = []
    infos: list[dict] = []
    info: dict | None = None
    while True:
        action = policy(observation, info)
        assert action is not None, "the policy stopped before the episode ended"
        assert action in env.action_space
        observation, reward, terminated, truncated, info = env.step(action)
        rewards.append(reward)
        infos.append(info)
        if terminated or truncated:
            return rewards, infos, observation
