"""The RGB-D table of VSL-3D (paper, section "VSL-3D", "Table Cleaning") as a Gymnasium
environment, ``vslsp/RGBDTable-v0``.

An episode is the robot's reproduction of one trial of the table-cleaning experiment
(:mod:`vslsp.experiments.table_cleaning`): ``reset(seed=s)`` lets the tutor put the duck and the
teddy into the box and the duckling in front of it in trial ``s``'s scene (unrecorded: the goal
poses the judge checks) and builds the reshuffled scene the experiment's robot starts from.

- observation: the RGB-D sensor's capture as a Dict: ``rgb`` (480, 640, 3) uint8 and ``depth``
  (480, 640) float32 m along the optical axis (0 where nothing is seen); the sensor's calibration
  is :attr:`RgbdTableEnv.camera` (a point cloud: :meth:`vslsp.vsl3d.cloud.WorldCloud.capture`);
- action: one pick-and-place, (pick x, y, θ, place x, y, θ) in table metres and radians, θ the
  fingers' closing axis; the fingertips close below the top that a depth probe finds at the
  pick, and let go as high above the place's surface after a guarded descent
  (:meth:`~vslsp.worlds.rgbd_table.RgbdTable.grasp_and_place`);
- reward: 1.0 once every operated object lies within the experiment's tolerances
  (:data:`~vslsp.experiments.table_cleaning.TOLERANCE_M`,
  :data:`~vslsp.experiments.table_cleaning.TOLERANCE_DEG` about the vertical) of its
  demonstrated pose, which terminates the episode.

:meth:`RgbdTableEnv.demonstrate` records the tutor's demonstration of the episode's trial as the
experiment does (the moved objects VSL-3D's policy, :class:`vslsp.gym.vsl3d_policy.Vsl3dPolicy`,
reproduces).
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np
from gymnasium.error import ResetNeeded

from vslsp.experiments.cloud_reproduction import WORKSPACE
from vslsp.experiments.table_cleaning import (
    OPERATIONS,
    TOLERANCE_DEG,
    TOLERANCE_M,
    demonstrate,
    demonstration_layout,
    pose_error,
    reshuffle,
    tutor_operation,
)
from vslsp.gym.base import WorldEnv, image_space, pick_place_space
from vslsp.sim.camera import Camera
from vslsp.sim.cloud_scene import SENSOR
from vslsp.vsl3d.vsl import MovedObject
from vslsp.worlds.rgbd_table import RgbdTable

GRIP_DEPTH = 0.03  # m: the fingertips close this far below the top seen at the pick
LOWEST_GRIP = 0.01  # m above the table: the fingertips never close lower
RELEASE = 0.01  # m: the held object's bottom starts its guarded descent this far above the place's surface
MAX_DEPTH = 3.0  # m: the sensor sees nothing beyond its far plane


class RgbdTableEnv(WorldEnv[dict[str, Any], np.ndarray, RgbdTable]):
    """``vslsp/RGBDTable-v0``: the Panda cleaning the table, one pick-and-place a step."""

    def __init__(self, render_mode: str | None = None, max_steps: int = 6) -> None:
        super().__init__(render_mode, max_steps)
        self.goals: dict[str, np.ndarray] = {}  # each operated object's demonstrated pose (4, 4)
        self.observation_space = gymnasium.spaces.Dict(
            {
                "rgb": image_space(SENSOR.width, SENSOR.height),
                "depth": gymnasium.spaces.Box(0.0, MAX_DEPTH, (SENSOR.height, SENSOR.width), dtype=np.float32),
            }
        )
        low, high = WORKSPACE.lower, WORKSPACE.upper
        self.action_space = pick_place_space((low[0], high[0]), (low[1], high[1]))

    @property
    def camera(self) -> Camera:
        """The RGB-D sensor's calibration."""
        return self.live.camera

    def _build(self, trial: int) -> RgbdTable:
        rng = np.random.default_rng(trial)
        layout = demonstration_layout(trial)
        with RgbdTable(layout, robot=True) as shown:
            for index, (name, _, _) in enumerate(OPERATIONS):
                shown.park()
                tutor_operation(shown, layout, rng, index)
                self.goals[name] = shown.truth(name)
        return RgbdTable(reshuffle(layout, trial, rng), robot=True)

    def demonstrate(self, method: str = "prerejective_ransac") -> list[MovedObject | None]:
        """The tutor's demonstration of this episode's trial, recorded (the experiment's
        :func:`~vslsp.experiments.table_cleaning.demonstrate`, in a scene of its own): per
        operation of :data:`~vslsp.experiments.table_cleaning.OPERATIONS` the moved object
        getObject found by registration ``method`` (None where it found none); the tutor puts
        the objects where the episode's goal poses are."""
        trial = self.trial_seed
        if trial is None:
            raise ResetNeeded("call reset() before demonstrate()")
        layout = demonstration_layout(trial)
        with RgbdTable(layout, robot=True) as shown:
            demonstrated, _, _ = demonstrate(shown, layout, np.random.default_rng(trial), method, trial)
        return [moved for moved, _ in demonstrated]

    def _observe(self) -> dict[str, Any]:
        scene = self.live
        scene.park()
        capture = scene.observe()
        return {"rgb": capture.rgb, "depth": capture.depth}

    def _act(self, action: np.ndarray) -> dict[str, Any]:
        scene = self.live
        pick, place = np.asarray(action, dtype=float).reshape(2, 3)
        scene.park()
        top = scene.surface_height(pick[0], pick[1])
        grip = max(top - GRIP_DEPTH, LOWEST_GRIP)
        below = scene.surface_height(place[0], place[1])
        pick_point = np.array([pick[0], pick[1], grip])
        place_point = np.array([place[0], place[1], below + grip + RELEASE])
        result = scene.grasp_and_place(pick_point, pick[2], place_point, place[2], list(scene.bodies.values()))
        return {
            "ok": result.ok,
            "diagnosis": None if result.diagnosis is None else str(result.diagnosis),
            "held": result.held,
        }

    def _success(self) -> bool:
        scene = self.live
        for name, goal in self.goals.items():
            lower, upper = scene.bounds(name)
            offset_mm, turn_deg, _ = pose_error(goal, scene.truth(name), (lower + upper) / 2.0)
            if not (offset_mm < TOLERANCE_M * 1000 and turn_deg < TOLERANCE_DEG):
                return False
        return True

    def _render(self) -> np.ndarray:
        return self.live.picture()
