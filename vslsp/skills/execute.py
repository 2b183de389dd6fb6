"""Executing a learned skill on an object in the simulator: DMP rollout -> IK -> the arm moves."""

from __future__ import annotations

import numpy as np

from vslsp.skills.library import Skill
from vslsp.skills.teach import hand_yaw
from vslsp.sim.robot import READY_POSITION, HandTrajectory


def execute_skill(world, skill: Skill, object_xy: np.ndarray, normal: np.ndarray) -> HandTrajectory:
    """Run ``skill`` on the object seen at ``object_xy`` (table, m), the line's ``normal`` (2,).

    The reach starts from the ready pose the arm passes through when it leaves its parked
    posture; afterwards the arm parks again (out of the cameras' view) and the world settles.
    Returns the hand's executed trajectory. Raises UnreachableError before moving if any
    waypoint is out of reach.
    """
    path = skill.hand_path(READY_POSITION, np.asarray(object_xy, dtype=float), np.asarray(normal, dtype=float))
    trajectory = world.robot.move_hand(path, yaw=hand_yaw(normal), record=True)
    world.robot.park()
    world.settle()
    return trajectory
