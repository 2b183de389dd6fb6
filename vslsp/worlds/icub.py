"""The iCub line world of VSL-SP (paper, VSL-SP "Implementation"): the iCub at a table with
coloured cubes and a landmark line; ``(far ?b)`` is the side of the line a cube is on.

Its seeded layout is a :class:`~vslsp.sim.SceneSpec` (:func:`line_layout`), its observation the
head camera's :class:`~vslsp.sim.Observation`; the tutor pushes or pulls a cube across the line
(:func:`tutor_operation`); the robot is the iCub (:class:`~vslsp.sim.icub.ICub`).
"""

from __future__ import annotations

import numpy as np

from vslsp.errors import InputError, TaskFailed
from vslsp.sim import LineWorld, SceneSpec
from vslsp.sim.scene import LayoutImpossible, seen_whole
from vslsp.sim.scene import check_layout as check_layout  # re-exported: a task checks its layouts
from vslsp.worlds.slips import Slip

TUTOR_BEYOND = 0.055  # the tutor puts a cube this far (m) on the other side of the line
# A nudged cube keeps this far (m) along the line from every other cube: two cube half-diagonals,
# so that no cube touches another, where it stands or where the tutor carries it across the line.
SLIP_CLEARANCE = 0.072


class IcubLineWorld(LineWorld):
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
    ``seed * 101 + k`` that places them. Sides ``far`` that no seed can lay out raise
    :class:`~vslsp.sim.scene.LayoutImpossible` at once (a task checks its layouts before the first
    trial with :func:`check_layout`)."""
    reason = ""
    for k in range(50):
        try:
            return SceneSpec.random(seed * 101 + k, colours=colours, far=far)
        except LayoutImpossible:
            raise  # no seed can give it: said at once
        except InputError as error:
            reason = str(error)
    raise InputError(f"no scene found for {len(colours)} cubes with seed {seed}: {reason}")


def tutor_operation(world: LineWorld, colour: str, action: str) -> None:
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


def tutor_slip(world: LineWorld, slip: Slip) -> Slip | None:
    """The tutor's slip while operating another cube: cube ``slip.name`` slides by (``dx_m``,
    ``dy_m``) and turns by ``dyaw_deg``. Returns the slip as applied, or None (no slip).

    The rule that keeps a slip a slip: every cube moves only across the line in a demonstration
    (the tutor carries each straight across it), so a nudged cube must keep
    :data:`SLIP_CLEARANCE` along the line from every other cube, and be seen whole by the head
    camera where it lands and where the tutor would carry it across the line (the scene
    generator's bounds). A nudge that breaks this goes the other way along the line, else the
    other way across it, else both; when all four are blocked the tutor's hand misses (None).
    The robot never acts in a demonstration's world, so its sweep bands do not apply.
    """
    landmark = world.spec.landmark
    x, y, yaw = world.cube_pose(slip.name)
    shift = np.array([slip.dx_m, slip.dy_m])
    along, across = float(shift @ landmark.direction), float(shift @ landmark.normal)
    others = [np.array(world.cube_pose(c.name)[:2]) for c in world.spec.cubes if c.name != slip.name]
    for sa, sc in ((1, 1), (-1, 1), (1, -1), (-1, -1)):
        moved = np.array([x, y]) + sa * along * landmark.direction + sc * across * landmark.normal
        side = landmark.signed_distance(moved)
        carried = moved - (side + np.sign(side or 1.0) * TUTOR_BEYOND) * landmark.normal
        clear = all(abs(float((moved - o) @ landmark.direction)) >= SLIP_CLEARANCE for o in others)
        if clear and seen_whole(*moved) and seen_whole(*carried):
            dx, dy = (float(v) for v in moved - np.array([x, y]))
            world.tutor.relocate(slip.name, float(moved[0]), float(moved[1]), yaw + np.radians(slip.dyaw_deg), lift=0.0)
            return Slip(slip.operation, slip.name, dx, dy, slip.dyaw_deg)
    return None
