"""Grasping from the point cloud, and one pick-and-place of VSL-3D executed by the robot (paper,
section "Methodology", grasping: the grasp point and the approach come from the observation,
"the fingers stop closing when the measured torque is more than a pre-defined threshold";
section "VSL-3D": the object is moved by the demonstrated motion applied to the match).

- The grasp (:func:`plan_grasp`) comes from the matched pre-action observation's points in the
  new world, never from the simulator: the fingertips close :data:`GRASP_DEPTH` below the
  highest point (at least :data:`TIP_CLEARANCE` above the lowest), about the middle of the
  points' bounding box at that height, along the box's narrower side (principal axes in the
  table plane); an object wider than the gripper opens is "ungraspable".
- The place (:func:`place_for`): the grasp point moved by T_j M_j^-1 (the demonstrated motion
  T_j after undoing the match M_j), the hand turned by that motion's yaw; the held object comes
  down from just above the height the cloud shows until it touches what is below (the arm's
  guarded descent), so it lands on the table, in the box or on another object.
- :func:`pick_and_place` runs it on the Panda (:func:`vslsp.sim.pick_place.execute_between`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.errors import TaskFailed
from vslsp.sim.panda import FINGER_OPEN
from vslsp.sim.pick_place import PickPlaceResult, execute_between, wrist_branch

GRASP_DEPTH = 0.03  # m below the object's top where the fingertips close
TIP_CLEARANCE = 0.006  # m the fingertips stay above the object's lowest seen point
PLACE_CLEARANCE = 0.008  # m above the demonstrated height where the guarded descent starts
FINGER_ROOM = 0.008  # m each finger opens beyond the object's side
BAND = 0.015  # m of points above the fingertips that the grasp's box is measured on


@dataclass(frozen=True)
class Grasp:
    """Where the fingertips close: ``point`` (3,) m, the closing axis ``theta`` (rad from x) and
    the object's ``width`` (m) across it; ``top`` is the highest point of the object's cloud."""

    point: np.ndarray
    theta: float
    width: float
    top: float

    def to_dict(self) -> dict:
        return {"point": np.round(self.point, 4).tolist(), "theta_deg": round(float(np.degrees(self.theta)), 2),
                "width_m": round(self.width, 4), "top_m": round(self.top, 4)}


def plan_grasp(points: np.ndarray) -> Grasp:
    """The grasp of an object seen as ``points`` (N, 3) (the matched observation in the world).
    Raises :class:`TaskFailed` ("ungraspable") when both sides are wider than the gripper."""
    points = np.asarray(points, dtype=float)
    if len(points) < 10:
        raise TaskFailed(f"ungraspable: the object's cloud has only {len(points)} points")
    top = float(np.percentile(points[:, 2], 99.5))
    bottom = max(0.0, float(np.percentile(points[:, 2], 0.5)))
    tip = max(top - GRASP_DEPTH, bottom + TIP_CLEARANCE)
    band = points[points[:, 2] >= min(tip, top - 0.005) - BAND / 2][:, :2]
    centre = band.mean(axis=0)
    _, vectors = np.linalg.eigh(np.cov((band - centre).T))
    extents = []
    for axis in vectors.T:  # minor axis first
        along = (band - centre) @ axis
        extents.append((float(along.max() - along.min()), axis, float(along.max() + along.min()) / 2.0))
    widest = 2.0 * (FINGER_OPEN - FINGER_ROOM)
    for width, axis, middle in extents:
        if width <= widest:
            other = next(e for e in extents if e[1] is not axis)
            middle_point = centre + middle * axis + other[2] * other[1]
            return Grasp(np.array([*middle_point, tip]), float(np.arctan2(axis[1], axis[0])), width, top)
    raise TaskFailed(f"ungraspable: the object is {min(e[0] for e in extents) * 100:.1f} cm wide at its "
                     f"narrowest side, the gripper opens {widest * 100:.1f} cm")


def place_for(grasp: Grasp, motion: np.ndarray) -> tuple[np.ndarray, float]:
    """The fingertips' place point (3,) and closing-axis angle (rad) for the object grasped by
    ``grasp`` moved by ``motion`` (4, 4) = T_j M_j^-1."""
    point = motion[:3, :3] @ grasp.point + motion[:3, 3] + [0.0, 0.0, PLACE_CLEARANCE]
    return point, grasp.theta + float(np.arctan2(motion[1, 0], motion[0, 0]))


def pick_and_place(world, grasp: Grasp, motion: np.ndarray, movable: list[int]) -> PickPlaceResult:
    """Execute ``grasp`` and its place under ``motion`` (4, 4) with ``world``'s Panda; the
    fingers close on one of the ``movable`` bodies."""
    place, theta_place = place_for(grasp, motion)
    theta_pick, theta_place = wrist_branch(np.array([*grasp.point[:2], grasp.theta]),
                                           np.array([*place[:2], theta_place]))
    each = FINGER_OPEN  # a single view underestimates the width across it: open fully
    return execute_between(world, grasp.point, place, theta_pick, theta_place, each, movable)
