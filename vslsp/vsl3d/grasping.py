"""Grasping from the point cloud (paper,
section "Methodology", grasping: the grasp point and the approach come from the observation,
"the fingers stop closing when the measured torque is more than a pre-defined threshold";
section "VSL-3D": the object is moved by the demonstrated motion applied to the match).

- The grasp (:func:`plan_grasp`) comes from the matched pre-action observation's points in the
  new world, never from the simulator: the fingertips close at half the object's seen height
  (else ``grasp_depth`` below the top, where it is narrower; the rules:
  :class:`~vslsp.vsl3d.parameters.Grasping`), about the middle
  of the bounding box of the points above them, along the box's narrower side (principal axes
  in the table plane); an object wider than the gripper opens is "ungraspable". One sensor sees
  the object's near side only: the box ends at the top's far rim, the width across the closing
  axis is short (the teddy's by a centimetre) and the grip's middle lies towards the sensor. With
  two sensors (``--views 2``) the matched observation is the fused cloud, which has the far side:
  the box, and so the closing width and the middle, is measured from both sides.
- The place (:func:`place_for`): the grasp point moved by T_j M_j^-1 (the demonstrated motion
  T_j after undoing the match M_j), the hand turned by that motion's yaw; the held object comes
  down from just above the height the cloud shows until it touches what is below (the arm's
  guarded descent), so it lands on the table, in the box or on another object.

The robot carries it out in its world (:meth:`vslsp.worlds.rgbd_table.RgbdTable.grasp_and_place`):
nothing here knows a robot but the gripper's opening, given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.errors import TaskFailed
from vslsp.vsl3d.parameters import DEFAULT_GRASPING, Grasping

# The default rules' figures, for the modules that read them by name (see Grasping).
GRASP_DEPTH = DEFAULT_GRASPING.grasp_depth
TIP_CLEARANCE = DEFAULT_GRASPING.tip_clearance
PLACE_CLEARANCE = DEFAULT_GRASPING.place_clearance
MIN_GRIP = DEFAULT_GRASPING.min_grip


@dataclass(frozen=True)
class Grasp:
    """Where the fingertips close: ``point`` (3,) m, the closing axis ``theta`` (rad from x) and
    the object's ``width`` (m) across it; ``top`` is the highest point of the object's cloud."""

    point: np.ndarray
    theta: float
    width: float
    top: float

    def to_dict(self) -> dict:
        return {
            "point": np.round(self.point, 4).tolist(),
            "theta_deg": round(float(np.degrees(self.theta)), 2),
            "width_m": round(self.width, 4),
            "top_m": round(self.top, 4),
        }


def plan_grasp(
    points: np.ndarray, finger_open: float, higher: float = 0.0, parameters: Grasping = DEFAULT_GRASPING
) -> Grasp:
    """The grasp of an object seen as ``points`` (N, 3) (the matched observation in the world) by
    a gripper whose fingers each open ``finger_open`` m from its middle, the fingertips ``higher``
    m above the first choice (a retry grips elsewhere), by the rules ``parameters``. Raises
    :class:`TaskFailed` ("ungraspable") when both sides are wider than the gripper."""
    points = np.asarray(points, dtype=float)
    if len(points) < 10:
        raise TaskFailed(f"ungraspable: the object's cloud has only {len(points)} points", cause="ungraspable")
    top = float(np.percentile(points[:, 2], 99.5))
    bottom = max(0.0, float(np.percentile(points[:, 2], 0.5)))
    widest = 2.0 * (finger_open - parameters.finger_room)
    narrowest = np.inf
    # The grip heights first (half the height: it holds a tall object without letting it pivot,
    # and a short round one at its widest; lower, the pads press down on its curve and wedge it
    # against the table); where it is too wide, the narrower part ``grasp_depth`` below the top.
    clearance, grip = parameters.tip_clearance, parameters.min_grip
    mid = [
        float(np.clip(bottom + f * (top - bottom) + higher, bottom + clearance, top - grip))
        for f in parameters.grip_heights
    ]
    for tip in dict.fromkeys([*mid, min(max(top - parameters.grasp_depth, bottom + clearance) + higher, top - grip)]):
        above = points[points[:, 2] >= tip - parameters.band / 2][:, :2]  # all that passes between the fingers
        if len(above) < 10:
            continue
        centre = above.mean(axis=0)
        _, vectors = np.linalg.eigh(np.cov((above - centre).T))
        extents = []
        for axis in vectors.T:  # minor axis first
            along = (above - centre) @ axis
            extents.append((float(along.max() - along.min()), axis, float(along.max() + along.min()) / 2.0))
        narrowest = min(narrowest, extents[0][0])
        for index, (width, axis, middle) in enumerate(extents):
            if width <= widest:
                _, other, other_middle = extents[1 - index]
                middle_point = centre + middle * axis + other_middle * other
                return Grasp(np.array([*middle_point, tip]), float(np.arctan2(axis[1], axis[0])), width, top)
    raise TaskFailed(
        f"ungraspable: the object is {narrowest * 100:.1f} cm wide at its narrowest side, "
        f"the gripper opens {widest * 100:.1f} cm",
        cause="ungraspable",
    )


def place_for(grasp: Grasp, motion: np.ndarray, parameters: Grasping = DEFAULT_GRASPING) -> tuple[np.ndarray, float]:
    """The fingertips' place point (3,) (``parameters.place_clearance`` above the demonstrated
    height) and closing-axis angle (rad) for the object grasped by ``grasp`` moved by
    ``motion`` (4, 4) = T_j M_j^-1."""
    point = motion[:3, :3] @ grasp.point + motion[:3, 3] + [0.0, 0.0, parameters.place_clearance]
    return point, grasp.theta + float(np.arctan2(motion[1, 0], motion[0, 0]))
