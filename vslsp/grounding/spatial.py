"""Spatial reasoning: the ``far`` predicate and action identification (paper, Algorithm 1
lines 8-9 ``getConstraint``/``getAction``; VSL-SP "Implementation": "a simple (boolean)
spatial reasoning [...] utilizes the detected pose of the object and the detected borderline
and then decides that the object is far or near"; Table "ActionGrounding": push turns
¬(far ?b) into (far ?b), pull the reverse).
"""

from __future__ import annotations

import numpy as np

from vslsp.errors import InputError
from vslsp.vision.landmark import Line

# Where the robot is, seen from the image: the direction (x, y) from the image towards it.
ROBOT_SIDES: dict[str, tuple[float, float]] = {
    "bottom": (0.0, 1.0),
    "top": (0.0, -1.0),
    "left": (-1.0, 0.0),
    "right": (1.0, 0.0),
}
_MIN_CROSSING = np.sin(np.radians(15.0))  # the line must cross the robot's direction by 15° at least


def check_robot_side(robot_side: str) -> str:
    if robot_side not in ROBOT_SIDES:
        raise InputError(f"unknown robot side {robot_side!r}; use one of {', '.join(ROBOT_SIDES)}")
    return robot_side


def towards_robot(line: Line, robot_side: str = "bottom") -> float:
    """The cosine between the line's normal and the direction towards the robot (beyond the
    image's ``robot_side`` edge); an InputError when the line runs towards the robot."""
    cosine = float(np.dot(line.normal, ROBOT_SIDES[check_robot_side(robot_side)]))
    if abs(cosine) < _MIN_CROSSING:
        raise InputError(
            f"the landmark line (at {line.angle:.0f} deg in the image) runs towards the robot "
            f"(robot side {robot_side!r}), so near and far are undefined; check --robot-side"
        )
    return cosine


def far_of(point: tuple[float, float], line: Line, robot_side: str = "bottom") -> bool:
    """(far b) for an object at ``point`` (x, y) px: it lies on the other side of ``line``
    from the robot, which is beyond the image's ``robot_side`` edge."""
    return line.signed_distance(point) * towards_robot(line, robot_side) < 0.0


def identify_action(far_pre: bool, far_post: bool) -> str | None:
    """The action from the change of (far b): ¬far → far is push, far → ¬far pull, else None."""
    if far_pre == far_post:
        return None
    return "push" if far_post else "pull"
