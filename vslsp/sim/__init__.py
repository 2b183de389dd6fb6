"""The simulated world (pybullet): the iCub at a table with coloured cubes and a landmark line.

Only this package talks to pybullet. Entry points: :class:`LineWorld` built from a
:class:`SceneSpec` (or a seed), its cameras (:meth:`LineWorld.observe`), its robot
(``world.robot.move_hand``) and its tutor (``world.tutor.relocate``, ``world.tutor.kinesthetic``).
"""

from vslsp.sim.camera import Camera
from vslsp.sim.scene import COLOURS, CUBE_SIZE, TABLE_Z, CubeSpec, LandmarkSpec, SceneSpec
from vslsp.sim.tabletop import Item, PickPlaceResult, Placement, TabletopWorld
from vslsp.sim.world import CAMERA_NAMES, LineWorld, Observation

__all__ = [
    "CAMERA_NAMES",
    "COLOURS",
    "CUBE_SIZE",
    "TABLE_Z",
    "Camera",
    "CubeSpec",
    "LandmarkSpec",
    "Observation",
    "SceneSpec",
    "LineWorld",
    "Item",
    "PickPlaceResult",
    "Placement",
    "TabletopWorld",
]
