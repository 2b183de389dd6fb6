"""The RGB-D table of VSL-3D (paper, "VSL-3D"): a Franka Panda at a table of everyday objects
(and a box, or landmark boxes) seen by an RGB-D sensor, or with ``views=2`` by two (the
second across the table at a known pose: :data:`~vslsp.sim.cloud_scene.SENSOR_FAR`; the
observation then carries its capture in ``others``).

Its seeded layout is {name: (x, y, yaw)} (:func:`~vslsp.sim.cloud_scene.random_layout`); its
observation an :class:`~vslsp.sim.cloud_scene.RGBDImage`; the tutor moves an object to a (4, 4)
pose; the robot is the Panda, which carries out a grasp planned on the point cloud
(:meth:`RgbdTable.grasp_and_place`).
"""

from __future__ import annotations

import numpy as np

from vslsp.sim.cloud_scene import CloudScene, RGBDImage, random_layout
from vslsp.sim.panda import FINGER_OPEN, Panda
from vslsp.sim.pick_place import PickPlaceResult, execute_between, wrist_branch

__all__ = ["FINGER_OPEN", "RgbdTable", "random_layout"]


class RgbdTable(CloudScene):
    """The RGB-D table with its robot, as a :class:`~vslsp.worlds.World`."""

    @classmethod
    def from_layout(cls, layout: dict[str, tuple[float, float, float]], seed: int = 0) -> RgbdTable:
        return cls(layout, robot=True, seed=seed)

    def observe(self) -> RGBDImage:
        """The sensor's capture (colour, depth and its camera)."""
        return self.capture()

    @property
    def robot(self) -> Panda | None:
        return self.panda

    def truth(self, name: str) -> np.ndarray:
        """Object ``name``'s pose (4, 4)."""
        return self.pose(name)

    def grasp_and_place(
        self, pick: np.ndarray, theta_pick: float, place: np.ndarray, theta_place: float, movable: list[int]
    ) -> PickPlaceResult:
        """The Panda closes its fingers at ``pick`` (3,) m with the closing axis at ``theta_pick``
        (rad), and lets go at ``place`` (3,) with it at ``theta_place`` after a guarded descent;
        the fingers close on one of the ``movable`` bodies. The wrist turns the shorter way."""
        theta_pick, theta_place = wrist_branch(np.array([*pick[:2], theta_pick]), np.array([*place[:2], theta_place]))
        each = FINGER_OPEN  # a single view underestimates the width across it: open fully
        return execute_between(self, pick, place, theta_pick, theta_place, each, movable)
