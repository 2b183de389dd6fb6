"""VSL-SP's closed loop (paper, VSL-SP "Results") as a policy of ``vslsp/ICubLine-v0``: the
learned task planned with the learned action models and executed one plan step per call
(:func:`~vslsp.loop.pipeline.execute_task`, the loop of the iCub experiments).

Each observation is grounded (``far`` for every cube seen, :func:`~vslsp.grounding.ground_scene`);
the first is planned from (:func:`~vslsp.loop.pipeline.plan_task`: the PDDL problem of the task
in the scene, solved by the real planner; an ordered task whose order can no longer be kept is
planned without it). After each step the policy checks the step's expected effect in the new
observation (the learned model's effect: :func:`~vslsp.loop.monitor.model_expects_far`); a
missing effect ends the plan and the policy
replans from what it sees, at most ``max_replans`` times. The plan run to its end, it plans once
more: an empty plan says the goal holds in what the robot sees, and the policy stops.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from vslsp.grounding import Predicate
from vslsp.grounding.operation import ground_scene
from vslsp.gym.icub_line import COLOUR_NAMES, SKILLS
from vslsp.loop.monitor import model_expects_far
from vslsp.loop.pipeline import MAX_REPLANS, plan_task, scene_literals
from vslsp.symbolic import Domain, LearnedTask, NoPlan, PlanResult
from vslsp.symbolic.engines.planner import DEFAULT_TIMEOUT_S


class VslSpPolicy:
    """The ``task`` planned with the action models of ``domain`` (both learned:
    :meth:`vslsp.gym.icub_line.IcubLineEnv.demonstrate`) and executed step by step; call it
    with each observation (the head camera's image) and the last step's info."""

    def __init__(
        self,
        domain: Domain,
        task: LearnedTask,
        *,
        planner: str = "fast-downward",
        max_replans: int = MAX_REPLANS,
        predicates: Sequence[Predicate] | None = None,
        planner_timeout: float | None = DEFAULT_TIMEOUT_S,
    ) -> None:
        self.domain, self.task = domain, task
        self.planner, self.max_replans, self.planner_timeout = planner, max_replans, planner_timeout
        self.predicates = predicates
        self.plans: list[PlanResult] = []
        self.replans = 0
        self.notes: list[str] = []
        self.error: str | None = None  # why the policy stopped before the goal held (None: it holds, or running)
        self.success = False  # the last plan was empty: the goal holds in what the robot sees
        self._remaining: list[tuple[str, tuple[str, ...]]] = []  # the current plan's steps not yet taken
        self._last: tuple[str, str, bool] | None = None  # the step last returned: (skill, colour, expected far)

    def __call__(self, observation: np.ndarray, info: Mapping[str, Any] | None = None) -> np.ndarray | None:
        """The next action, ``[skill, colour]`` (indices into :data:`~vslsp.gym.icub_line.SKILLS`
        and :data:`~vslsp.gym.icub_line.COLOUR_NAMES`), for ``observation`` (480, 640, 3) uint8;
        ``info``: the step's before it (its ``ok``: the skill ran). None when the goal holds in
        what the robot sees or the policy gave up (:attr:`error`)."""
        if self.error is not None or self.success:
            return None
        grounding = ground_scene(observation, robot_side="bottom")
        if self._last is not None:
            action, colour, expected = self._last
            self._last = None
            far = grounding.far_by_name().get(colour)
            if (info is not None and not info.get("ok", True)) or far != expected:
                if self.replans >= self.max_replans:
                    self.error = f"gave up after {self.max_replans} replans: {action} {colour} missed its effect"
                    return None
                self.replans += 1
                self._remaining = []
        if not self._remaining:
            try:
                _, plan, self.task = plan_task(
                    self.domain,
                    self.task,
                    scene_literals(grounding, self.predicates),
                    planner=self.planner,
                    timeout=self.planner_timeout,
                    notes=self.notes,
                )
            except NoPlan as failure:
                self.error = str(failure)
                return None
            self.plans.append(plan)
            if len(self.plans) > self.max_replans + 3:
                self.error = f"the goal still does not hold after {len(self.plans) - 1} plans"
                return None
            if not plan.steps:
                self.success = True
                return None
            self._remaining = [(action, tuple(args)) for action, args in plan.steps]
        action, args = self._remaining.pop(0)
        self._last = (action, args[0], model_expects_far(self.domain, action, args, grounding.far_by_name()))
        return np.array([SKILLS.index(action), COLOUR_NAMES.index(args[0])], dtype=np.int64)
