"""The iCub line world of VSL-SP (paper, VSL-SP "Implementation" and "Results") as a Gymnasium
environment, ``vslsp/ICubLine-v0``.

An episode is the robot's part of one trial of an iCub experiment: ``reset(seed=s)`` builds
the test scene of trial ``s``, ``pull-in-order`` by default (the orange, green and yellow cubes
all far, to be pulled near in that order) or ``keep-all-near`` (one to three cubes, some far; no
cube may stay far).

- observation: the head camera's RGB image, (480, 640, 3) uint8, the arm parked;
- action: a skill on a cube, MultiDiscrete ``[2, 6]``: the skill (0 push, 1 pull:
  :data:`SKILLS`) and the cube's colour (:data:`COLOUR_NAMES`); the robot finds the cube in
  its head camera's view and runs the skill's DMP on it
  (:func:`~vslsp.loop.monitor.execute_step`, the step ``ok`` when the cube ends on the side the
  skill takes it to: :data:`TAKES_FAR`); a colour it does not see does nothing;
- reward: 1.0 once the experiment's goal holds on the simulator's truth (``pull-in-order``:
  every cube near, each become near in the demonstrated order; ``keep-all-near``: no cube far),
  which terminates the episode; in ``pull-in-order`` a cube become near out of order ends it
  as failed.

:meth:`IcubLineEnv.demonstrate` lets the robot learn ``pull-in-order`` as the experiment's trial
does (its skills' models from its own executions, the task and its order from the tutor's
demonstration), what VSL-SP's policy (:class:`vslsp.gym.vslsp_policy.VslSpPolicy`) plans with.
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np
from gymnasium.error import ResetNeeded

from vslsp.errors import InputError, TaskFailed
from vslsp.experiments.icub_run import IcubRun
from vslsp.experiments.icub_scripts import ORDERED_COLOURS, explore, keep_all_near_scene, watch
from vslsp.experiments.seeds import reproduction_seed
from vslsp.gym.base import RENDER_SIZE, WorldEnv, image_space
from vslsp.loop.monitor import execute_step
from vslsp.loop.perception import perceive
from vslsp.sim import COLOURS
from vslsp.sim.video import scene_camera
from vslsp.skills.library import SKILL_NAMES, SkillLibrary, default_library_path
from vslsp.symbolic import Domain, LearnedTask, learn_task
from vslsp.worlds.icub import IcubLineWorld, line_layout

TASKS = ("pull-in-order", "keep-all-near")
SKILLS = ("push", "pull")
#: Whether each skill takes the cube far (push) or near (pull): what the environment checks a step by.
TAKES_FAR = {"push": True, "pull": False}
COLOUR_NAMES = tuple(COLOURS)
WIDTH, HEIGHT = 640, 480  # the head camera's image


class IcubLineEnv(WorldEnv[np.ndarray, np.ndarray, IcubLineWorld]):
    """``vslsp/ICubLine-v0``: the iCub pushing and pulling cubes across the line, one skill a step."""

    def __init__(
        self,
        task: str = "pull-in-order",
        render_mode: str | None = None,
        max_steps: int = 8,
        skills: str | None = None,
    ) -> None:
        if task not in TASKS:
            raise InputError(f"task must be one of {', '.join(TASKS)}, got {task!r}")
        super().__init__(render_mode, max_steps)
        self.task = task
        path = skills or default_library_path()
        self.library = SkillLibrary.load(path)
        self.library.require(SKILL_NAMES, path)
        self.became_near: list[str] = []  # the colours in the order they first became near
        self.observation_space = image_space(WIDTH, HEIGHT)
        self.action_space = gymnasium.spaces.MultiDiscrete([len(SKILLS), len(COLOUR_NAMES)])

    def _build(self, trial: int) -> IcubLineWorld:
        if self.task == "pull-in-order":
            spec = line_layout(reproduction_seed(trial), ORDERED_COLOURS, (True,) * len(ORDERED_COLOURS))
        else:
            spec = keep_all_near_scene(np.random.default_rng(trial), trial)
        self.became_near = []
        return IcubLineWorld.from_layout(spec, trial)

    def demonstrate(self) -> tuple[Domain, LearnedTask]:
        """What the robot of this episode's trial learns before its test scene (the experiment's
        ``pull-in-order``, :func:`~vslsp.experiments.icub_scripts.pull_in_order`, in worlds of
        its own): push's and pull's models from its own executions, then the task and its order
        (``sometime-before``) from the tutor pulling the orange, green and yellow cubes in turn."""
        if self.task != "pull-in-order":
            raise InputError(f"demonstrate() learns pull-in-order; this environment's task is {self.task!r}")
        if self.trial_seed is None:
            raise ResetNeeded("call reset() before demonstrate()")
        trial = IcubRun(self.trial_seed)
        explore(trial, np.random.default_rng(self.trial_seed), self.library)
        scene = line_layout(self.trial_seed, ORDERED_COLOURS, (True,) * len(ORDERED_COLOURS))
        with trial.world(scene) as world:
            steps = watch(world, trial, [(colour, "pull") for colour in ORDERED_COLOURS], "demonstration")
        assert trial.domain is not None
        return trial.domain, learn_task([steps], ordered=True)

    def _observe(self) -> np.ndarray:
        return self.live.observe("head", WIDTH, HEIGHT).rgb

    def _act(self, action: np.ndarray) -> dict[str, Any]:
        world = self.live
        skill, colour = SKILLS[int(action[0])], COLOUR_NAMES[int(action[1])]
        state = perceive(world)
        info: dict[str, Any] = {"skill": skill, "colour": colour}
        if colour not in state.objects:
            return {**info, "ok": False, "error": f"the robot sees no {colour} cube"}
        try:
            result, _ = execute_step(world, self.library, skill, colour, state, TAKES_FAR[skill])
        except TaskFailed as failure:
            return {**info, "ok": False, "error": str(failure)}
        for cube in world.spec.cubes:
            if not world.is_far(cube.name) and cube.colour not in self.became_near:
                self.became_near.append(cube.colour)
        return {**info, "ok": result.ok, "error": result.error}

    def _far(self) -> dict[str, bool]:
        world = self.live
        return {cube.colour: world.is_far(cube.name) for cube in world.spec.cubes}

    def _success(self) -> bool:
        if any(self._far().values()):
            return False
        return self.task != "pull-in-order" or self.became_near == list(ORDERED_COLOURS)

    def _failed(self) -> bool:
        return self.task == "pull-in-order" and self.became_near != list(ORDERED_COLOURS[: len(self.became_near)])

    def _render(self) -> np.ndarray:
        world = self.live
        return scene_camera().resized(*RENDER_SIZE).render(world.live_client, world.backdrop)[0]
