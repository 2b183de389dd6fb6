"""Watching the tutor: pre- and post-action observations of a demonstration, grounded.

Paper, Algorithm 1 part I and VSL-SP "Implementation": the tutor moves one object at a time;
the robot only sees the scene before and after each operation. Each operation is grounded
(which object moved, ``far`` before and after, push / pull / null), and every object of both
observations is grounded too, which is the context the symbolic layer learns from.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vslsp.errors import TaskFailed
from vslsp.grounding.operation import Grounding, ground
from vslsp.loop.perception import PerceivedState, perceive
from vslsp.sim import World

TUTOR_BEYOND = 0.055  # the tutor puts a cube this far (m) on the other side of the line


@dataclass(frozen=True)
class ObservedStep:
    """One demonstrated operation as the robot saw it."""

    grounding: Grounding
    before: PerceivedState = field(repr=False)
    after: PerceivedState = field(repr=False)

    @property
    def obj(self) -> str:
        return self.grounding.name

    @property
    def action(self) -> str | None:
        return self.grounding.action

    def to_dict(self) -> dict:
        return {"grounding": self.grounding.to_dict(), "before": self.before.far(), "after": self.after.far()}


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


def watch_demonstration(world: World, operations: list[tuple[str, str]]) -> list[ObservedStep]:
    """The tutor performs ``operations`` [(colour, action), ...]; the robot watches and grounds."""
    steps = []
    state = perceive(world)
    for colour, action in operations:
        tutor_operation(world, colour, action)
        after = perceive(world)
        steps.append(ObservedStep(ground(state.image, after.image), state, after))
        state = after
    return steps
