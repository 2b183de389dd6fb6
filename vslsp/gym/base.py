"""What the Gymnasium environments of vslsp's worlds share (:mod:`vslsp.gym`): a world rebuilt
by every ``reset`` from a trial's seed, the task's success as the reward, ``rgb_array``
rendering, and ``close`` releasing the simulator.

An environment's episode is the reproduction of one trial of an experiment: ``reset(seed=s)``
builds the world in which trial ``s`` of the experiment reproduces its demonstration (the same
seed, the same scene); ``reset()`` without a seed draws the trial's seed from the environment's
own generator (``np_random``), so a seeded first reset makes every later one reproducible. The
reward is 1.0 on the step after which the experiment's judge says the goal holds (on the
simulator's ground truth, which the observation never shows) and 0.0 otherwise; the episode
terminates there, or where the task can no longer succeed, and is truncated after
``max_steps`` steps.
"""

from __future__ import annotations

from typing import Any, Generic, TypeVar

import gymnasium
import numpy as np
from gymnasium.error import ResetNeeded

from vslsp.errors import InputError

ObsT = TypeVar("ObsT")
ActT = TypeVar("ActT")
WorldT = TypeVar("WorldT")

SEEDS = 2**31 - 1  # a trial's seed drawn by reset() without one lies in [0, SEEDS)
RENDER_SIZE = (640, 480)  # (width, height) px of render()'s scene view


class WorldEnv(gymnasium.Env[ObsT, ActT], Generic[ObsT, ActT, WorldT]):
    """A world of vslsp as a Gymnasium environment. Subclasses build the world of a trial's
    seed (:meth:`_build`), observe it (:meth:`_observe`), act (:meth:`_act`), judge it
    (:meth:`_success`, :meth:`_failed`) and picture it (:meth:`_render`)."""

    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 2}

    def __init__(self, render_mode: str | None = None, max_steps: int = 10) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise InputError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        if max_steps < 1:
            raise InputError(f"max_steps must be at least 1, got {max_steps!r}")
        self.render_mode = render_mode
        self.max_steps = max_steps
        self.world: WorldT | None = None
        self.trial_seed: int | None = None  # the experiment's trial whose reproduction this episode is
        self.steps = 0

    # -- the Gymnasium API ------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[ObsT, dict[str, Any]]:
        """The world of trial ``seed`` (or of a seed drawn from ``np_random``) and its first observation."""
        super().reset(seed=seed)
        trial = int(seed) if seed is not None else int(self.np_random.integers(SEEDS))
        self._close_world()
        self.trial_seed, self.steps = trial, 0
        self.world = self._build(trial)
        return self._observe(), {"trial_seed": trial}

    def step(self, action: ActT) -> tuple[ObsT, float, bool, bool, dict[str, Any]]:
        """Act; the reward is 1.0 when the task's goal holds afterwards (then the episode terminates)."""
        if self.world is None:
            raise ResetNeeded("call reset() before step()")
        info = self._act(action)
        self.steps += 1
        success = self._success()
        terminated = success or self._failed()
        truncated = not terminated and self.steps >= self.max_steps
        return self._observe(), float(success), terminated, truncated, {**info, "is_success": success}

    def render(self) -> np.ndarray | None:  # type: ignore[override]
        """``rgb_array``: a view of the scene with the robot, (480, 640, 3) uint8; None without a world."""
        if self.render_mode is None or self.world is None:
            return None
        return self._render()

    def close(self) -> None:
        """Release the world (disconnect its simulator); closing twice is harmless."""
        self._close_world()

    # -- the world ------------------------------------------------------------------------------
    def _close_world(self) -> None:
        if self.world is not None:
            world, self.world = self.world, None
            world.close()  # type: ignore[attr-defined]

    @property
    def live(self) -> WorldT:
        """The world of the current episode (a :class:`ResetNeeded` before the first reset)."""
        if self.world is None:
            raise ResetNeeded("call reset() first")
        return self.world

    def _build(self, trial: int) -> WorldT:
        raise NotImplementedError

    def _observe(self) -> ObsT:
        raise NotImplementedError

    def _act(self, action: ActT) -> dict[str, Any]:
        raise NotImplementedError

    def _success(self) -> bool:
        raise NotImplementedError

    def _failed(self) -> bool:
        """Whether the task can no longer succeed in this episode (a terminal failure)."""
        return False

    def _render(self) -> np.ndarray:
        raise NotImplementedError


def pick_place_space(x: tuple[float, float], y: tuple[float, float]) -> gymnasium.spaces.Box:
    """A pick-and-place action: (pick x, pick y, pick θ, place x, place y, place θ), x and y in
    table metres within ``x`` × ``y``, θ the gripper's closing axis (rad, [-π, π])."""
    low = np.array([x[0], y[0], -np.pi, x[0], y[0], -np.pi])
    high = np.array([x[1], y[1], np.pi, x[1], y[1], np.pi])
    return gymnasium.spaces.Box(low, high, dtype=np.float64)


def image_space(width: int, height: int) -> gymnasium.spaces.Box:
    """A camera's RGB image: (height, width, 3) uint8."""
    return gymnasium.spaces.Box(0, 255, (height, width, 3), dtype=np.uint8)
