"""The RGB-D table of VSL-3D (paper, "VSL-3D"): a Franka Panda at a table of everyday objects
(and a box, or landmark boxes) seen by an RGB-D sensor, or with ``views=2`` by two (the
second across the table at a known pose: :data:`~vslsp.sim.cloud_scene.SENSOR_FAR`; the
observation then carries its capture in ``others``).

Its seeded layout is {name: (x, y, yaw)} (:func:`~vslsp.sim.cloud_scene.random_layout`); its
observation an :class:`~vslsp.sim.cloud_scene.RGBDImage`; the tutor moves an object to a (4, 4)
pose; the robot is the Panda, which carries out a grasp planned on the point cloud
(:meth:`RgbdTable.grasp_and_place`). With ``--tutor-slips`` the tutor's hand also nudges another
object during an operation (:meth:`RgbdTable.tutor_slip`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from vslsp.sim.cloud_scene import OBJECT_HEIGHT, CloudScene, RGBDImage, in_view, random_layout
from vslsp.sim.panda import FINGER_OPEN, Panda
from vslsp.sim.pick_place import PickPlaceResult, execute_between, wrist_branch
from vslsp.worlds.slips import Slip

__all__ = ["FINGER_OPEN", "SLIP_CLEARANCE", "RgbdTable", "random_layout"]

# A nudged object stays this far (m) from every other object, box and the tray, and from the
# places the caller keeps clear: the slip leaves it on the table, never onto, against or right
# beside another object (VSL-3D's getObject joins changes closer than 3 cm into one object).
SLIP_CLEARANCE = 0.035
# Where the drawn nudge does not fit, the same nudge turned (deg) and then half as far, in order.
SLIP_TRIES = tuple((scale, turn) for scale in (1.0, 0.5) for turn in (0.0, 90.0, 180.0, 270.0))


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

    def tutor_slip(self, slip: Slip, clear_of: Sequence[tuple[np.ndarray, np.ndarray]] = ()) -> Slip | None:
        """The tutor's hand slides object ``slip.name`` over the table by (``dx_m``, ``dy_m``) and
        turns it by ``dyaw_deg`` about the vertical through its middle, then lets it settle.
        Where the drawn nudge would bring it within :data:`SLIP_CLEARANCE` of another object, a
        box, the tray or a box (lower (3,), upper (3,)) of ``clear_of``, or out of the sensor's
        view, the same nudge turned by 90, 180 and 270 deg and then half as far is tried
        (:data:`SLIP_TRIES`). Returns the slip applied (its displacement as applied), or None
        when none fits (the object stays)."""
        name, start = slip.name, self.pose(slip.name)
        lower, upper = self.bounds(name)
        middle = (lower + upper) / 2.0
        turn = np.eye(4)
        c, s = math.cos(math.radians(slip.dyaw_deg)), math.sin(math.radians(slip.dyaw_deg))
        turn[:2, :2] = [[c, -s], [s, c]]
        turn[:2, 3] = middle[:2] - turn[:2, :2] @ middle[:2]  # about the vertical through the middle
        for scale, angle in SLIP_TRIES:
            ca, sa = math.cos(math.radians(angle)), math.sin(math.radians(angle))
            dx, dy = scale * (ca * slip.dx_m - sa * slip.dy_m), scale * (sa * slip.dx_m + ca * slip.dy_m)
            pose = turn @ start
            pose[:2, 3] += (dx, dy)
            self.tutor_move(name, pose)
            low, high = self.bounds(name)
            if (
                in_view(middle[0] + dx, middle[1] + dy, OBJECT_HEIGHT)
                and not self.near(name, SLIP_CLEARANCE)
                and not any(_overlap(low, high, *box, SLIP_CLEARANCE) for box in clear_of)
            ):
                self.settle()
                return replace(slip, dx_m=float(dx), dy_m=float(dy))
        self.tutor_move(name, start)
        return None


def _overlap(
    lower: np.ndarray, upper: np.ndarray, other_lower: np.ndarray, other_upper: np.ndarray, gap: float
) -> bool:
    """Whether two boxes' footprints on the table come within ``gap`` m of each other."""
    other_lower, other_upper = np.asarray(other_lower), np.asarray(other_upper)
    return bool(np.all(lower[:2] < other_upper[:2] + gap) and np.all(other_lower[:2] < upper[:2] + gap))
