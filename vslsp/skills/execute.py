"""Executing a learned skill on an object in the simulator: DMP rollout -> IK -> the arm moves."""

from __future__ import annotations

import numpy as np

from vslsp.skills.library import Skill
from vslsp.skills.teach import hand_yaw
from vslsp.sim.robot import READY_POSITION, HandTrajectory


BEYOND = 0.05  # a push or pull aims to leave the object this far (m) past the line


def execute_skill(world, skill: Skill, object_xy: np.ndarray, normal: np.ndarray,
                  line_distance: float | None = None) -> HandTrajectory:
    """Run ``skill`` on the object seen at ``object_xy`` (table, m), the line's ``normal`` (2,).

    The reach starts from the ready pose the arm passes through when it leaves its parked
    posture; afterwards the arm parks again (out of the cameras' view) and the world settles.
    ``line_distance`` (m, the object's distance to the line) sizes the move so that the object
    ends about 5 cm past the line. Returns the hand's executed trajectory. Raises
    UnreachableError before moving if any waypoint is out of reach.
    """
    travel = None if line_distance is None else abs(line_distance) + BEYOND
    path = skill.hand_path(READY_POSITION, np.asarray(object_xy, dtype=float), np.asarray(normal, dtype=float),
                           travel)
    trajectory = world.robot.move_hand(path, yaw=hand_yaw(normal), record=True)
    world.robot.park()
    world.settle()
    return trajectory
