"""VSL-3D's reproduction (paper, Algorithm 1 part II; section "VSL-3D", "Table Cleaning") as a
policy of ``vslsp/RGBDTable-v0``: what the table-cleaning experiment's robot does
(:func:`~vslsp.experiments.cloud_reproduction.reproduce`), one pick-and-place per call.

For each demonstrated operation in order the policy turns the observation's depth into the world
cloud, finds the recorded pre-action observation in it (``findBestMatch``: M_j), leaving out what
earlier operations put down, plans the grasp from the matched points and puts the object down at
T_j M_j^-1 (:func:`~vslsp.vsl3d.grasping.place_for`). A grasp that failed or an object that
slipped is tried once more, gripping a little higher, from the next observation; any other
outcome moves on to the next operation, as the experiment does.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from vslsp.errors import VslspError
from vslsp.experiments.cloud_reproduction import RETRIED, RETRY_HIGHER, WORKSPACE, check_world
from vslsp.geometry.poses import wrap
from vslsp.outcomes import NoMatch
from vslsp.sim.camera import Camera
from vslsp.vsl3d.cloud import DepthCamera
from vslsp.vsl3d.grasping import place_for, plan_grasp
from vslsp.vsl3d.matching import find_best_match
from vslsp.vsl3d.registration import transform_points
from vslsp.vsl3d.vsl import MovedObject, WorldCloud
from vslsp.worlds.rgbd_table import FINGER_OPEN

RETRIED_DIAGNOSES = frozenset(str(diagnosis) for diagnosis in RETRIED)


class Vsl3dPolicy:
    """The demonstrated operations ``demonstrated`` (per operation the moved object, None where
    the demonstration found none) reproduced in the world the RGB-D sensor of calibration
    ``camera`` captures; ``method`` and ``seed``: the registration's (the experiment's: its
    method and the trial's seed). Call it with each observation and the last step's info."""

    def __init__(
        self,
        demonstrated: Sequence[MovedObject | None],
        camera: Camera,
        *,
        method: str = "prerejective_ransac",
        seed: int = 0,
    ) -> None:
        self.demonstrated = list(demonstrated)
        self.camera = DepthCamera.of(camera)
        self.method, self.seed = method, seed
        self.next = 0  # the operation to reproduce next
        self.retry = 0  # 1 on the operation's second and last attempt
        self.put_down: list[np.ndarray] = []  # (N, 3) each: where earlier operations put their objects
        self.errors: dict[int, str] = {}  # why an operation was given up (its index)
        self._placing: np.ndarray | None = None  # the matched points moved by the last action's motion

    @property
    def finished(self) -> bool:
        """Whether every operation was reproduced or given up."""
        return self.next >= len(self.demonstrated) and self._placing is None

    def __call__(
        self, observation: Mapping[str, np.ndarray], info: Mapping[str, Any] | None = None
    ) -> np.ndarray | None:
        """The next action, (pick x, y, θ, place x, y, θ), for ``observation`` (``depth``: (H, W)
        float m); ``info``: the step's before it (``ok``, ``diagnosis``). None when no operation is left."""
        if self._placing is not None:
            self._outcome(self._placing, info or {})
            self._placing = None
        world = WorldCloud.capture(np.asarray(observation["depth"], dtype=float), self.camera, WORKSPACE)
        while self.next < len(self.demonstrated):
            moved = self.demonstrated[self.next]
            if moved is None:
                self._give_up("demonstration: no object found")
                continue
            try:
                check_world(world)
                search = world.without(np.vstack(self.put_down)) if self.put_down else world
                found = find_best_match(search, moved.pre, method=self.method, seed=self.seed)
                if isinstance(found, NoMatch):
                    self._give_up(f"no match: {found.reason}")
                    continue
                grasp = plan_grasp(found.points, FINGER_OPEN, higher=RETRY_HIGHER * self.retry)
            except VslspError as error:
                self._give_up(str(error))
                continue
            motion = moved.transform @ np.linalg.inv(found.registration.transform)  # T_j M_j^-1
            place, theta_place = place_for(grasp, motion)
            self._placing = transform_points(motion, found.points)
            pick = grasp.point
            return np.array([pick[0], pick[1], wrap(grasp.theta), place[0], place[1], wrap(theta_place)], dtype=float)
        return None

    def _outcome(self, placing: np.ndarray, info: Mapping[str, Any]) -> None:
        """Judge the last action as the experiment does: held to the end, the object is where its
        operation wanted it; a failed grasp or a slip is retried once; anything else gives up."""
        if info.get("ok", True):
            self.put_down.append(placing)
            self.next, self.retry = self.next + 1, 0
        elif info.get("diagnosis") in RETRIED_DIAGNOSES and self.retry == 0:
            self.retry = 1
        else:
            self._give_up(str(info.get("diagnosis")))

    def _give_up(self, why: str) -> None:
        self.errors[self.next] = why
        self.next, self.retry = self.next + 1, 0
