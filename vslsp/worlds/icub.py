"""The iCub line world of VSL-SP (paper, VSL-SP "Implementation"): the iCub at a table with
coloured cubes and a landmark line; ``(far ?b)`` is the side of the line a cube is on.

Its seeded layout is a :class:`~vslsp.sim.SceneSpec` (:func:`line_layout`), its observation the
head camera's :class:`~vslsp.sim.Observation`; the tutor pushes or pulls a cube across the line
(:func:`tutor_operation`); the robot is the iCub (:class:`~vslsp.sim.icub.ICub`).
"""

from __future__ import annotations

import numpy as np

from vslsp.errors import InputError, TaskFailed
from vslsp.sim import SceneSpec
from vslsp.sim import World as SimWorld

TUTOR_BEYOND = 0.055  # the tutor puts a cube this far (m) on the other side of the line


class IcubLineWorld(SimWorld):
    """The iCub line world as a :class:`~vslsp.worlds.World` (``observe()``: the head camera's
    :class:`~vslsp.sim.Observation`; ``robot``: the iCub)."""

    @classmethod
    def from_layout(cls, layout: SceneSpec, seed: int = 0, gui: bool = False) -> IcubLineWorld:
        return cls(layout, gui=gui)

    def tutor_move(self, name: str, where: tuple[float, float]) -> None:
        """The tutor slides cube ``name`` by hand to ``where`` (x, y) m."""
        self.tutor.relocate(name, float(where[0]), float(where[1]))

    def truth(self, name: str) -> tuple[float, float, float]:
        """Cube ``name``'s pose on the table: x, y (m), yaw (rad)."""
        return self.cube_pose(name)


def line_layout(seed: int, colours: tuple[str, ...], far: tuple[bool, ...] | None = None) -> SceneSpec:
    """A random scene with these colours (the same seed, the same scene): the first of
    ``seed * 101 + k`` that places them."""
    for k in range(50):
        try:
            return SceneSpec.random(seed * 101 + k, colours=colours, far=far)
        except InputError:
            continue
    raise InputError(f"no scene found for {len(colours)} cubes with seed {seed}")


def tutor_operation(world: SimWorld, colour: str, action: str) -> None:
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
