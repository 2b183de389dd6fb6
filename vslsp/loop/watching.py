"""The tutor's operations in the iCub world: one cube moved by hand across the landmark line.

Paper, Algorithm 1 part I and VSL-SP "Implementation": the tutor moves one object at a time;
the robot only sees the scene before and after each operation (grounded by
:func:`vslsp.grounding.operation.ground`, which is what the symbolic layer learns from).
"""

from __future__ import annotations

import numpy as np

from vslsp.errors import TaskFailed
from vslsp.sim import World

TUTOR_BEYOND = 0.055  # the tutor puts a cube this far (m) on the other side of the line


def tutor_operation(world: World, colour: str, action: str) -> None:
    """The tutor pushes (``push``) or pulls (``pull``) the cube of ``colour`` by hand, straight across
    the line to 5.5 cm beyond it."""
    cube = next((c for c in world.spec.cubes if c.colour == colour), None)
    if cube is None:
        raise TaskFailed(f"the tutor cannot find a {colour} cube in the scene")
    x, y, _ = world.cube_pose(cube.name)
    landmark = world.spec.landmark
    side = float(np.dot(np.array([x, y]) - landmark.point, landmark.normal))  # signed distance to the line
    direction = 1.0 if action == "push" else -1.0
    target = np.array([x, y]) + (direction * TUTOR_BEYOND - side) * landmark.normal
    world.tutor.relocate(cube.name, float(target[0]), float(target[1]))
