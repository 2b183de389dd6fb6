"""The Panda table of VSL's real-world tasks (paper, "Real-world Experiments", Table 1) as a
Gymnasium environment, ``vslsp/PandaTable-v0``.

An episode is the robot's reproduction of one trial of a tabletop experiment
(``alphabet-ordering`` by default, or ``animal-puzzle``, ``tower-of-hanoi``): ``reset(seed=s)``
lets the tutor demonstrate in trial ``s``'s demonstration world (unrecorded: the relations the
judge checks) and builds the reproduction world of the experiment's
:func:`~vslsp.experiments.seeds.reproduction_seed`.

- observation: the oblique camera's RGB image, (960, 1280, 3) uint8, the arm parked out of view;
- action: one pick-and-place, (pick x, y, θ, place x, y, θ) in table metres and radians, θ the
  fingers' closing axis (:meth:`~vslsp.sim.tabletop.TabletopWorld.pick_and_place`; the item
  turns by θ_place − θ_pick);
- reward: 1.0 once every demonstrated relation holds (the experiment's goal,
  :func:`~vslsp.experiments.tabletop_protocol.relations_hold`), which terminates the episode.

:meth:`PandaTableEnv.demonstrate` records the tutor's demonstration of the episode's trial as
the experiment does (Algorithm 1 part I), for a policy that learns from it
(:class:`~vslsp.gym.policies.VslPolicy`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from vslsp.errors import InputError
from vslsp.experiments.seeds import reproduction_seed
from vslsp.experiments.tabletop import TabletopExperiment
from vslsp.experiments.tabletop_protocol import Relations, TabletopDemonstration, relations_hold, tutor_relations
from vslsp.gym.base import RENDER_SIZE, WorldEnv, image_space, pick_place_space
from vslsp.sim.camera import Camera
from vslsp.sim.tabletop import WORKSPACE_X, WORKSPACE_Y, TabletopWorld
from vslsp.sim.video import tabletop_scene_camera
from vslsp.tasks.registry import get_task
from vslsp.worlds.panda_table import PandaTable

# The experiments whose reproduction is the plain protocol: the robot does every operation in
# the demonstrated order (Tower of Hanoi without the user's intervention of its odd seeds).
TASKS = ("alphabet-ordering", "animal-puzzle", "tower-of-hanoi")
REACH = 0.12  # m: actions may pick and place this far beyond the workspace's edges (the goal areas lie there)


class PandaTableEnv(WorldEnv[np.ndarray, np.ndarray, PandaTable]):
    """``vslsp/PandaTable-v0``: the Panda reproducing a tabletop task, one pick-and-place a step."""

    def __init__(self, task: str = "alphabet-ordering", render_mode: str | None = None, max_steps: int | None = None):
        if task not in TASKS:
            raise InputError(f"task must be one of {', '.join(TASKS)}, got {task!r}")
        experiment = get_task(task)
        assert isinstance(experiment, TabletopExperiment)  # the TASKS are tabletop experiments
        self.task = experiment
        self.relations: Relations | None = None
        self._operations = 0
        super().__init__(render_mode, max_steps or 12)
        self.observation_space = image_space(TabletopWorld.WIDTH, TabletopWorld.HEIGHT)
        x = (WORKSPACE_X[0] - REACH, WORKSPACE_X[1] + REACH)
        y = (WORKSPACE_Y[0] - REACH, WORKSPACE_Y[1] + REACH)
        self.action_space = pick_place_space(x, y)

    @property
    def camera(self) -> Camera:
        """The observing camera's calibration (image px <-> table metres at a height)."""
        return self.live.camera

    def _build(self, trial: int) -> PandaTable:
        rng = np.random.default_rng(trial)
        with PandaTable.from_layout(self.task.layout(rng, "demonstration"), trial) as shown:
            self.relations = tutor_relations(shown, self.task.moves(rng))
        self._operations = len(self.relations.items)
        rng = np.random.default_rng(reproduction_seed(trial))
        return PandaTable.from_layout(self.task.layout(rng, "reproduction"), trial)

    def demonstrate(self) -> TabletopDemonstration:
        """The tutor's demonstration of this episode's trial, recorded (the experiment's
        :meth:`~vslsp.experiments.tabletop.TabletopExperiment.demonstrate`, in a world of its own)."""
        if self.trial_seed is None:
            self.live  # noqa: B018 (raises ResetNeeded)
        assert self.trial_seed is not None
        rng = np.random.default_rng(self.trial_seed)
        with PandaTable.from_layout(self.task.layout(rng, "demonstration"), self.trial_seed) as shown:
            return self.task.demonstrate(shown, rng)

    def _observe(self) -> np.ndarray:
        return self.live.observe()

    def _act(self, action: np.ndarray) -> dict[str, Any]:
        pick, place = np.asarray(action, dtype=float).reshape(2, 3)
        result = self.live.pick_and_place((pick[0], pick[1], pick[2]), (place[0], place[1], place[2]))
        return {
            "ok": result.ok,
            "diagnosis": None if result.diagnosis is None else str(result.diagnosis),
            "held": result.held,
        }

    def _success(self) -> bool:
        assert self.relations is not None  # measured at reset
        return relations_hold(self.live, self.relations, range(self._operations), self.task.anchor_map)

    def _render(self) -> np.ndarray:
        world = self.live
        return tabletop_scene_camera().resized(*RENDER_SIZE).render(world.live_client, world.backdrop)[0]
