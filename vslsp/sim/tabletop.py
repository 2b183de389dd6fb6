"""The tabletop world of the original VSL (paper, section "Real-world Experiments"): a table, a
camera above the workspace looking down obliquely at 1280×960, textured items and landmarks,
and a Franka Panda with a parallel gripper standing in for the WAM with its Barrett hand.

A pick-and-place follows the paper's cycle rest → pick → place → rest
(:func:`vslsp.geometry.trajectory.pick_and_place`: cubic paths in x and y, the height profile
(traj3), cubic time scaling, trapezoidal rotation θ_pick → θ_place). The arm is driven along it
by position control of IK solutions; the fingers close until the contact force reaches a
threshold (the paper's torque threshold), and at the place the hand comes down until the held
item touches what is below (a guarded move, so items stack). Heights come from a downward
depth probe (ray casts), as a depth sensor would give them.

Frame: the Panda's base at the origin on the table's near edge, x away from the robot, y to
its left, z up from the table top. In the camera image the robot is at the bottom.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.sim.camera import Backdrop, Camera
from vslsp.sim.client import PhysicsClient, mesh_visual
from vslsp.sim.panda import PARK, Panda
from vslsp.sim.pick_place import TIME_STEP, PickPlaceResult, execute_pick_and_place
from vslsp.sim.quiet import quiet

with quiet():
    import pybullet as pb

TABLE_HALF = (0.56, 0.62, 0.02)
TABLE_CENTRE = (0.44, 0.0)  # the table spans x -0.12 .. 1.0 around the robot's base
TABLE_COLOUR = (0.86, 0.84, 0.80, 1.0)
WORKSPACE_X = (0.30, 0.70)  # where items may lie: the camera sees it and the arm reaches it
WORKSPACE_Y = (-0.30, 0.30)
ITEM_FRICTION = 1.0
CAMERA_TILT = np.radians(25.0)  # the optical axis' angle from the vertical
CAMERA_TARGET = (0.50, 0.0, 0.0)
CAMERA_DISTANCE = 1.25
CAMERA_FOV = 27.0  # vertical, degrees


@dataclass(frozen=True, eq=False)
class Item:
    """A box of ``size`` (x, y, z) m with ``texture`` (H, W, 3) uint8 RGB on its top face
    (columns along +x, rows along −y); ``movable=False`` makes a static landmark (mass 0);
    ``friction`` is its lateral friction coefficient (pybullet multiplies the two in contact)."""

    name: str
    size: tuple[float, float, float]
    texture: np.ndarray
    movable: bool = True
    mass: float = 0.05
    friction: float = ITEM_FRICTION

    def __post_init__(self) -> None:
        if len(self.size) != 3 or not all(np.isfinite(s) and 0.002 <= s <= 0.5 for s in self.size):
            raise InputError(
                f"item {self.name!r}: size must be three extents between 2 mm and 0.5 m, got {self.size!r}"
            )
        texture = np.asarray(self.texture)
        if texture.ndim != 3 or texture.shape[2] != 3 or texture.dtype != np.uint8 or min(texture.shape[:2]) < 2:
            raise InputError(
                f"item {self.name!r}: texture must be an (H, W, 3) uint8 RGB image, got {texture.dtype} {texture.shape}"
            )
        if self.movable and not (np.isfinite(self.mass) and self.mass > 0.0):
            raise InputError(f"item {self.name!r}: a movable item needs a mass > 0 kg, got {self.mass!r}")
        if not (np.isfinite(self.friction) and self.friction > 0.0):
            raise InputError(f"item {self.name!r}: friction must be > 0, got {self.friction!r}")


@dataclass(frozen=True)
class Placement:
    """Where an item lies: (x, y) m and ``yaw`` rad in the table frame, on the table or ``on``
    top of another item."""

    x: float
    y: float
    yaw: float = 0.0
    on: str | None = None


def tabletop_camera() -> Camera:
    """The camera behind the robot, above the workspace, tilted :data:`CAMERA_TILT` from the
    vertical towards +x, so the robot is at the bottom of its 1280×960 image."""
    tx, ty, tz = CAMERA_TARGET
    eye = (tx - CAMERA_DISTANCE * np.sin(CAMERA_TILT), ty, tz + CAMERA_DISTANCE * np.cos(CAMERA_TILT))
    return Camera(
        "tabletop",
        eye=(float(eye[0]), float(eye[1]), float(eye[2])),
        target=CAMERA_TARGET,
        up=(0.0, 0.0, 1.0),
        width=TabletopWorld.WIDTH,
        height=TabletopWorld.HEIGHT,
        fov=CAMERA_FOV,
    )


def box_mesh(size: tuple[float, float, float], top_rows: float) -> tuple[list, list, list, list]:
    """Vertices, triangle indices, texture coordinates and normals of a box whose top face maps
    the upper ``top_rows`` fraction of a texture atlas and whose sides sample the plain strip
    below it."""
    hx, hy, hz = (s / 2.0 for s in size)
    side_uv = [0.5, 1.0 - (1.0 + top_rows) / 2.0]
    faces = [  # corners counter-clockwise seen from outside, and the face's normal
        ([(-hx, hy, hz), (-hx, -hy, hz), (hx, -hy, hz), (hx, hy, hz)], (0, 0, 1)),
        ([(-hx, hy, -hz), (hx, hy, -hz), (hx, -hy, -hz), (-hx, -hy, -hz)], (0, 0, -1)),
        ([(hx, -hy, -hz), (hx, hy, -hz), (hx, hy, hz), (hx, -hy, hz)], (1, 0, 0)),
        ([(-hx, hy, -hz), (-hx, -hy, -hz), (-hx, -hy, hz), (-hx, hy, hz)], (-1, 0, 0)),
        ([(hx, hy, -hz), (-hx, hy, -hz), (-hx, hy, hz), (hx, hy, hz)], (0, 1, 0)),
        ([(-hx, -hy, -hz), (hx, -hy, -hz), (hx, -hy, hz), (-hx, -hy, hz)], (0, -1, 0)),
    ]
    vertices, indices, uvs, normals = [], [], [], []
    for k, (corners, normal) in enumerate(faces):
        vertices += [list(c) for c in corners]
        normals += [list(normal)] * 4
        if k == 0:  # image column along +x, image row along -y; v runs up the atlas
            uvs += [[(c[0] + hx) / (2 * hx), 1.0 - top_rows * (hy - c[1]) / (2 * hy)] for c in corners]
        else:
            uvs += [side_uv] * 4
        indices += [4 * k, 4 * k + 1, 4 * k + 2, 4 * k, 4 * k + 2, 4 * k + 3]
    return vertices, indices, uvs, normals


class TabletopWorld(PhysicsClient):
    """The world of ``layout`` (items in order: an item ``on`` another follows it). pybullet
    runs headless unless ``gui``; the world has no randomness of its own, so the same layout
    gives byte-identical observations and the same outcomes (``seed`` is kept for reports)."""

    WIDTH, HEIGHT = 1280, 960

    def __init__(self, layout: list[tuple[Item, Placement]], seed: int = 0, gui: bool = False) -> None:
        self.seed = seed
        self.camera = tabletop_camera()
        with quiet():
            self.client = pb.connect(pb.GUI if gui else pb.DIRECT)
        c = self.client
        pb.resetSimulation(physicsClientId=c)
        pb.setGravity(0, 0, -9.81, physicsClientId=c)
        pb.setTimeStep(TIME_STEP, physicsClientId=c)
        pb.setPhysicsEngineParameter(deterministicOverlappingPairs=1, physicsClientId=c)
        self.table = self._make_table(gui)
        self.panda = Panda(c)
        # Called after every physics step when set (a video's camera: vslsp.sim.video).
        self.frame_hook: Callable[[TabletopWorld], None] | None = None
        self.narrator: Callable[[TabletopWorld, tuple[str, ...], float], None] | None = None
        self.bodies: dict[str, int] = {}
        self.specs: dict[str, Item] = {}
        try:
            for item, placement in layout:
                if item.name in self.bodies:
                    raise InputError(f"two items are named {item.name!r}; give every item its own name")
                self._add(item, placement)
        except BaseException:
            self.close()
            raise
        self.settle()

    # -- building -------------------------------------------------------------------------
    def _make_table(self, gui: bool) -> int:
        """The table. Headless, its top is drawn as the camera's :class:`Backdrop` (the colour
        the renderer gives it, read from a small render of the table alone) instead of being
        rasterised with every image: a view renders in about half the time, the same pixels."""
        c, centre = self.live_client, [*TABLE_CENTRE, -TABLE_HALF[2]]
        visual = pb.createVisualShape(pb.GEOM_BOX, halfExtents=TABLE_HALF, rgbaColor=TABLE_COLOUR, physicsClientId=c)
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=TABLE_HALF, physicsClientId=c)
        if gui:
            self.backdrop = None
            body = pb.createMultiBody(0, shape, visual, centre, physicsClientId=c)
        else:
            look = pb.createMultiBody(0, -1, visual, centre, physicsClientId=c)
            small = self.camera.resized(8, 6)
            colour = small.render(c)[0][small.height // 2, small.width // 2]
            pb.removeBody(look, physicsClientId=c)
            self.backdrop = Backdrop(
                0.0,
                (TABLE_CENTRE[0] - TABLE_HALF[0], TABLE_CENTRE[0] + TABLE_HALF[0]),
                (TABLE_CENTRE[1] - TABLE_HALF[1], TABLE_CENTRE[1] + TABLE_HALF[1]),
                (int(colour[0]), int(colour[1]), int(colour[2])),
            )
            # a body without a visual shape would be drawn from its collision box: give the
            # table a speck of a visual far above the camera instead, which it never sees
            speck = pb.createVisualShape(
                pb.GEOM_SPHERE,
                radius=1e-3,
                visualFramePosition=[0.0, 0.0, 50.0],
                rgbaColor=TABLE_COLOUR,
                physicsClientId=c,
            )
            body = pb.createMultiBody(0, shape, speck, centre, physicsClientId=c)
        pb.changeDynamics(body, -1, lateralFriction=ITEM_FRICTION, physicsClientId=c)
        return body

    def _add(self, item: Item, placement: Placement) -> None:
        c = self.live_client
        half = [s / 2.0 for s in item.size]
        texture = np.asarray(item.texture)
        strip = max(4, texture.shape[0] // 8)  # plain rows for the sides: the texture's mean colour
        atlas = np.concatenate(
            [texture, np.broadcast_to(texture.reshape(-1, 3).mean(0).astype(np.uint8), (strip, texture.shape[1], 3))]
        )
        visual = mesh_visual(c, box_mesh(item.size, texture.shape[0] / atlas.shape[0]))
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half, physicsClientId=c)
        body = pb.createMultiBody(item.mass if item.movable else 0.0, shape, visual, [0, 0, 0], physicsClientId=c)
        handle, path = tempfile.mkstemp(suffix=".png")
        os.close(handle)
        try:
            encoded = cv2.imencode(".png", cv2.cvtColor(np.ascontiguousarray(atlas), cv2.COLOR_RGB2BGR))[1]
            Path(path).write_bytes(encoded.tobytes())  # a full disk: an OSError saying so
            texture_id = pb.loadTexture(path, physicsClientId=c)
        finally:
            os.remove(path)
        pb.changeVisualShape(body, -1, textureUniqueId=texture_id, physicsClientId=c)
        pb.changeDynamics(body, -1, lateralFriction=item.friction, spinningFriction=0.001, physicsClientId=c)
        self.bodies[item.name] = body
        self.specs[item.name] = item
        self._put(item.name, placement)

    def add_plain_box(
        self, size: tuple[float, float, float], colour: tuple[float, float, float], x: float, y: float, yaw: float
    ) -> int:
        """A movable box of ``size`` (m) and one plain ``colour`` (RGB 0-1) on the table at (x, y),
        turned ``yaw`` rad, that is no item of the world (a distractor: the items, the judge and
        the tutor never see it); its body."""
        c = self.live_client
        half = [s / 2.0 for s in size]
        visual = pb.createVisualShape(pb.GEOM_BOX, halfExtents=half, rgbaColor=[*colour, 1.0], physicsClientId=c)
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half, physicsClientId=c)
        orientation = pb.getQuaternionFromEuler([0, 0, yaw])
        body = pb.createMultiBody(0.05, shape, visual, [x, y, half[2]], orientation, physicsClientId=c)
        pb.changeDynamics(body, -1, lateralFriction=ITEM_FRICTION, physicsClientId=c)
        return int(body)

    def _put(self, name: str, placement: Placement) -> None:
        if not all(np.isfinite([placement.x, placement.y, placement.yaw])):
            raise InputError(f"the placement of {name!r} must have finite x, y and yaw, got {placement!r}")
        base = 0.0
        if placement.on is not None:
            if placement.on not in self.bodies or placement.on == name:
                raise InputError(
                    f"{name!r} cannot go on {placement.on!r}: name an item listed before it "
                    f"(the world has {sorted(self.bodies)})"
                )
            base = self.pose(placement.on)[2] + self.specs[placement.on].size[2]
        centre = [placement.x, placement.y, base + self.specs[name].size[2] / 2.0]
        pb.resetBasePositionAndOrientation(
            self.bodies[name], centre, pb.getQuaternionFromEuler([0, 0, placement.yaw]), physicsClientId=self.client
        )
        pb.resetBaseVelocity(self.bodies[name], [0, 0, 0], [0, 0, 0], physicsClientId=self.client)

    # -- running ------------------------------------------------------------------------
    def step(self, n: int = 1) -> None:
        for _ in range(n):
            pb.stepSimulation(physicsClientId=self.client)
            if self.frame_hook is not None:
                self.frame_hook(self)

    # -- what a video shows (vslsp.sim.video) -----------------------------------------------
    def say(self, *lines: str, hold: float = 0.0) -> None:
        """The caption of a video filming this world (nothing otherwise), and ``hold`` seconds
        of the world as it is now under it."""
        if self.narrator is not None:
            self.narrator(self, lines, hold)

    def movable_poses(self) -> tuple:
        """The movable items' poses, as pybullet has them."""
        return tuple(
            pb.getBasePositionAndOrientation(self.bodies[name], physicsClientId=self.client)
            for name, item in self.specs.items()
            if item.movable
        )

    def arm_chain(self) -> np.ndarray:
        """The Panda's joints from its base, then the fingertips (K, 3)."""
        states = pb.getLinkStates(self.panda.body, list(range(7)), physicsClientId=self.client)
        return np.array([[0.0, 0.0, 0.0]] + [state[4] for state in states] + [self.panda.hand()[0]])

    def arm_body(self) -> int:
        return self.panda.body

    def settle(self, max_steps: int = 480) -> None:
        """Step until every movable item is at rest (or ``max_steps``)."""
        movable = [self.bodies[n] for n, item in self.specs.items() if item.movable]
        for k in range(max_steps):
            self.step()
            if k >= 5 and all(
                np.linalg.norm(pb.getBaseVelocity(b, physicsClientId=self.client)[0]) < 1e-3 for b in movable
            ):
                break

    # -- what the camera sees -------------------------------------------------------------
    def observe(self) -> np.ndarray:
        """The camera's RGB image (960, 1280, 3) uint8, with the arm parked out of view."""
        self.panda.reset(PARK)
        return self.camera.render(self.live_client, self.backdrop)[0]

    def pixel_to_table(self, u: float, v: float, z: float = 0.0) -> tuple[float, float]:
        """The point (x, y) at height ``z`` above the table seen at pixel (u, v)."""
        return self.camera.pixel_to_table(u, v, z)

    def table_to_pixel(self, x: float, y: float, z: float = 0.0) -> tuple[float, float]:
        return self.camera.table_to_pixel(x, y, z)

    # -- ground truth (reports, tests and the tutor; perception never reads it) -----------
    def items(self) -> tuple[str, ...]:
        return tuple(self.bodies)

    def pose(self, name: str) -> tuple[float, float, float, float]:
        """x, y, the height of the item's bottom above the table, and its yaw (rad)."""
        if name not in self.bodies:
            raise InputError(f"no item named {name!r}; the world has {sorted(self.bodies)}")
        position, orientation = pb.getBasePositionAndOrientation(self.bodies[name], physicsClientId=self.client)
        bottom = position[2] - self.specs[name].size[2] / 2.0
        return float(position[0]), float(position[1]), float(bottom), float(pb.getEulerFromQuaternion(orientation)[2])

    def tutor_place(self, name: str, placement: Placement) -> None:
        """The tutor's hand puts ``name`` at ``placement``; the world settles."""
        if name not in self.bodies:
            raise InputError(f"no item named {name!r}; the world has {sorted(self.bodies)}")
        self._put(name, placement)
        self.settle()

    # -- the robot ------------------------------------------------------------------------
    def pick_and_place(
        self, pick: tuple[float, float, float], place: tuple[float, float, float], grasp_width: float | None = None
    ) -> PickPlaceResult:
        """Pick what lies at ``pick`` = (x, y, θ) and put it down at ``place`` = (x, y, θ), θ
        the gripper's closing-axis angle (rad); the item turns by θ_place − θ_pick. The
        fingers open to ``grasp_width`` + 2 cm (m; default fully open)."""
        return execute_pick_and_place(self, pick, place, grasp_width)

    def probe(self, x: float, y: float, ignore: int | None = None) -> tuple[float, int]:
        """The height of the first surface below (x, y) seen from above and its body (height 0
        and body -1 off the table): a depth sensor's reading that looks through ``ignore``."""
        start = 0.6
        while True:
            hit = pb.rayTest([x, y, start], [x, y, -0.01], physicsClientId=self.client)[0]
            if hit[0] < 0:
                return 0.0, -1
            if hit[0] != ignore:
                return float(hit[3][2]), int(hit[0])
            start = hit[3][2] - 1e-4
