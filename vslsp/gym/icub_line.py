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
  (:func:`~vslsp.loop.monitor.execute_step`); a colour it does not see does nothing;
- reward: 1.0 once the experiment's goal holds on the simulator's truth (``pull-in-order``:
  every cube near, each become near in the demonstrated order; ``keep-all-near``: no cube far),
  which terminates the episode; in ``pull-in-order`` a cube become near out of order ends it
  as failed.
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np

from vslsp.errors import InputError, TaskFailed
from vslsp.experiments.icub_scripts import ORDERED_COLOURS, keep_all_near_scene
from vslsp.experiments.seeds import reproduction_seed
from vslsp.gym.base import RENDER_SIZE, WorldEnv, image_space
from vslsp.loop.monitor import execute_step
from vslsp.loop.perception import perceive
from vslsp.sim import COLOURS
from vslsp.sim.video import scene_camera
from vslsp.skills.library import SKILL_NAMES, SkillLibrary, default_library_path
from vslsp.worlds.icub import IcubLineWorld, line_layout

TASKS = ("pull-in-order", "keep-all-near")
SKILLS = ("push", "pull")
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
            result, _ = execute_step(world, self.library, skill, colour, state)
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
