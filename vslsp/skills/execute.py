"""Executing a learned skill on an object in a world (:class:`vslsp.worlds.World`, the iCub line
world's simulator): DMP rollout -> IK -> the arm moves, then the world settles."""

from __future__ import annotations

import numpy as np

from vslsp.errors import UnreachableError
from vslsp.sim import Observation
from vslsp.sim.robot import READY_POSITION, HandTrajectory
from vslsp.skills.library import Skill, from_object_frame, resample
from vslsp.skills.teach import hand_yaw
from vslsp.stages import in_stage
from vslsp.worlds import World

BEYOND = 0.06  # a push or pull aims to leave the object this far (m) past the line


@in_stage("execution")
def execute_skill(
    world: World[Observation],
    skill: Skill,
    object_xy: np.ndarray,
    normal: np.ndarray,
    line_distance: float | None = None,
) -> HandTrajectory:
    """Run ``skill`` on the object seen at ``object_xy`` (table, m), the line's ``normal`` (2,).

    The reach starts from the ready pose the arm passes through when it leaves its parked
    posture; afterwards the arm parks again (out of the cameras' view) and the world settles.
    ``line_distance`` (m, the object's distance to the line) sizes the move so that the object
    ends about 5 cm past the line. Returns the hand's executed trajectory. Raises
    UnreachableError before moving if any waypoint is out of reach.
    """
    travel = None if line_distance is None else abs(line_distance) + BEYOND
    object_xy, normal = np.asarray(object_xy, dtype=float), np.asarray(normal, dtype=float)
    robot = world.robot
    if robot is None:
        raise UnreachableError("this world was built without the robot (LineWorld(..., robot=False))")
    error: UnreachableError | None = None
    for start in reach_starts(skill, object_xy, normal):
        # The DMP generalises to any start: where the reach from the ready pose would bulge out
        # of the arm's reach, the hand first goes straight to a start nearer the object.
        lead = resample(np.array([READY_POSITION, start]))[:-1]
        path = np.vstack([lead, skill.hand_path(start, object_xy, normal, travel)])
        try:
            trajectory = robot.move_hand(path, yaw=hand_yaw(normal), record=True)
            break
        except UnreachableError as unreachable:  # raised before the arm moves
            error = error or unreachable
    else:
        raise error or UnreachableError("no start of the reach is within the arm's reach")
    assert trajectory is not None  # move_hand(record=True) returns the executed path
    robot.park()
    world.settle()
    return trajectory


def reach_starts(skill: Skill, object_xy: np.ndarray, normal: np.ndarray) -> list[np.ndarray]:
    """Where the reach may start (3,) each: the ready pose, then nearer and nearer the object."""
    above_goal = from_object_frame((skill.goal + [0.0, 0.0, 0.08])[None], object_xy, normal)[0]
    return [READY_POSITION + s * (above_goal - READY_POSITION) for s in (0.0, 0.4, 0.75)]
