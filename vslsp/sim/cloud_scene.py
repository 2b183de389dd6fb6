"""The table-cleaning world of VSL-3D (paper, section "VSL-3D", "Table Cleaning": "the world
includes an empty box and a set of objects which are randomly placed in the workspace"),
watched by an RGB-D sensor in the role of the paper's Asus Xtion Pro Live.

Objects are meshes from ``pybullet_data`` (a duck, a teddy bear, a mug, random blocks and blobs, a small cube)
on a table whose top is the plane z = 0; a tray (the box) stands in it as a static landmark.
The tutor puts an object at a given 6-DoF pose (it holds the object there: no physics step
runs, so a tilted object stays tilted); :meth:`CloudScene.resting_pose` gives the pose at
which an object with a given yaw and tilt touches the table. With ``robot=True`` the world is
physical: gravity acts, objects settle after the tutor lets go (:meth:`CloudScene.settle`), and
the Franka Panda of the tabletop world (:class:`vslsp.sim.panda.Panda`, base at the origin on
the table's near edge, parked out of the sensor's view) picks and places them. Ground-truth poses are for tests
and benchmarks only: VSL-3D sees nothing but the depth image.

Frame: x away from the sensor over the table, y to the left, z up, metres.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from vslsp.errors import InputError
from vslsp.sim.camera import Camera
from vslsp.sim.client import PhysicsClient
from vslsp.sim.panda import PARK, Panda
from vslsp.sim.pick_place import TIME_STEP
from vslsp.sim.quiet import quiet

with quiet():
    import pybullet as pb
    import pybullet_data

TABLE_HALF = (0.45, 0.50, 0.02)
TABLE_CENTRE = (0.50, 0.0)
TABLE_COLOUR = (0.80, 0.74, 0.62, 1.0)
WORKSPACE_X = (0.36, 0.72)  # where objects may lie: well inside the sensor's view
WORKSPACE_Y = (-0.24, 0.24)
# The sensor sees each object whole: its footprint's half-width and height, and the pixels kept
# clear of the image's border (a stacked object stands on a box: the stacking asks for more).
VIEW_RADIUS, OBJECT_HEIGHT, VIEW_MARGIN = 0.07, 0.09, 8.0
LAYOUT_ATTEMPTS = 20
TRAY_POSITION = (0.56, 0.16)
TRAY_SCALE = 0.4  # pybullet's traybox is 60 cm wide; this makes a 24 cm box
# The stacking experiment's landmark boxes (x, y, z extents, m): shaped unlike each other so that
# the cloud tells them apart; a box looks the same turned by its symmetry (a half or quarter turn).
BOXES = {"box1": (0.14, 0.09, 0.04), "box2": (0.09, 0.09, 0.08)}
BOX_COLOUR = (0.25, 0.45, 0.75, 1.0)
BOX_MASS = 0.5
CLEARANCE = 0.14  # m between the centres of two objects (and an object and the tray's rim)
PLACE_CLEARANCE = 0.11  # m from a place kept clear to an object's centre: two half-widths and a margin
FRICTION = 1.0  # lateral friction of the table, the objects and the tray (pybullet multiplies two)
# Torsional friction of the objects (Bullet multiplies it with the finger pads' 0.1): an object
# held by its upper part does not pivot about the closing axis as a pendulum (the table has none).
SPINNING_FRICTION = 1.0
REST_STEPS = 24  # steps (0.1 s) an object must stay still to count as settled


@dataclass(frozen=True)
class ObjectModel:
    """A mesh from pybullet_data: its URDF, scale and the roll/pitch (rad) that sets it upright."""

    urdf: str
    scale: float = 1.0
    upright: tuple[float, float] = (0.0, 0.0)


OBJECTS: dict[str, ObjectModel] = {
    "duck": ObjectModel("duck_vhacd.urdf", 1.0, (np.pi / 2, 0.0)),
    "duckling": ObjectModel("duck_vhacd.urdf", 0.7, (np.pi / 2, 0.0)),  # a smaller duck
    "teddy": ObjectModel("teddy_vhacd.urdf", 1.0, (np.pi / 2, 0.0)),
    "blob": ObjectModel("random_urdfs/013/013.urdf", 1.0),
    "shell": ObjectModel("random_urdfs/000/000.urdf", 1.0),
    "mug": ObjectModel("objects/mug.urdf", 1.0),
    "ell": ObjectModel("random_urdfs/005/005.urdf", 1.0),  # an L-shaped block
    "cube": ObjectModel("cube_small.urdf", 1.0),
}
# Objects whose pose any single view pins down (no rotational symmetry): the ducks and the
# teddy. The L-shaped block looks the same turned over, the mug's turn shows only in its handle,
# the blob is nearly symmetric under a half turn, the shell about its long axis, the cube under
# quarter turns: their position is found, their rotation only up to that symmetry when the
# telling part is out of view.
ASYMMETRIC = ("duck", "duckling", "teddy")

# The RGB-D sensor: 640 x 480, 45 degrees vertical field of view (an Xtion's), 0.63 m from the
# middle of the workspace, looking down at about 53 degrees.
SENSOR = Camera(
    "rgbd", eye=(0.15, 0.0, 0.50), target=(0.53, 0.0, 0.0), up=(0.0, 0.0, 1.0), width=640, height=480, fov=45.0
)
# The second RGB-D sensor (``views=2``): the same intrinsics, across the table from the first,
# 0.63 m from the middle of the workspace looking down at the same angle, so that it sees the
# objects' far sides (+x), which the first one never does. Its pose is known (calibrated): its
# cloud is put into the world frame by it and fused with the first's.
SENSOR_FAR = Camera(
    "rgbd-far", eye=(0.91, 0.0, 0.50), target=(0.53, 0.0, 0.0), up=(0.0, 0.0, 1.0), width=640, height=480, fov=45.0
)
SENSORS = (SENSOR, SENSOR_FAR)  # the sensors of ``views=1`` and ``views=2``, in that order


def axial_noise(depth: np.ndarray) -> np.ndarray:
    """Standard deviation (m) of a structured-light sensor's depth at ``depth`` (m) (Nguyen,
    Izadi and Lovell 2012: 1.2 mm + 1.9 mm (z - 0.4)^2)."""
    return 0.0012 + 0.0019 * (depth - 0.4) ** 2


@dataclass(frozen=True, eq=False)
class RGBDImage:
    """One capture: RGB (H, W, 3) uint8, depth (H, W) float32 m along the optical axis (0 where
    nothing is seen), and the camera; ``others``: the other sensors' captures taken at the same
    moment (``views=2``: the far sensor's), none with one sensor."""

    rgb: np.ndarray
    depth: np.ndarray
    camera: Camera
    others: tuple[RGBDImage, ...] = ()


def pose_matrix(position: np.ndarray, orientation: np.ndarray) -> np.ndarray:
    """4x4 pose from a position (3,) and a quaternion (x, y, z, w)."""
    pose = np.eye(4)
    pose[:3, :3] = np.asarray(pb.getMatrixFromQuaternion(list(orientation))).reshape(3, 3)
    pose[:3, 3] = position
    return pose


def euler_pose(x: float, y: float, z: float, roll: float = 0.0, pitch: float = 0.0, yaw: float = 0.0) -> np.ndarray:
    """4x4 pose from a position and roll, pitch, yaw (rad; extrinsic x, y, z as in pybullet)."""
    return pose_matrix(np.array([x, y, z]), pb.getQuaternionFromEuler([roll, pitch, yaw]))


class CloudScene(PhysicsClient):
    """A pybullet world (DIRECT) with the table, the tray and ``objects``: name -> (x, y, yaw).

    Each name must be one of :data:`OBJECTS` (a name may carry a suffix after ``#`` for a
    second copy, e.g. ``"duck#2"``). Close it (or use ``with``) when done."""

    def __init__(
        self,
        objects: dict[str, tuple[float, float, float]],
        *,
        tray: bool = True,
        camera: Camera = SENSOR,
        noise: bool = False,
        seed: int = 0,
        robot: bool = False,
        boxes: dict[str, tuple[float, float, float]] | None = None,
        views: int = 1,
    ) -> None:
        if views not in (1, 2):
            raise InputError(f"views must be 1 or 2 (RGB-D sensors), got {views!r}")
        for name in objects:
            if name.split("#")[0] not in OBJECTS:
                raise InputError(f"unknown object {name!r}; use one of {', '.join(OBJECTS)}")
        self.camera = camera
        # With two views the far sensor too, at its known pose (the same intrinsics as ``camera``).
        self.others = tuple(SENSORS[1:views])
        self.noise = noise
        self._rng = np.random.default_rng(seed)
        with quiet():
            self.client = pb.connect(pb.DIRECT)
        c = self.client
        pb.resetSimulation(physicsClientId=c)
        pb.setAdditionalSearchPath(pybullet_data.getDataPath(), physicsClientId=c)
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=TABLE_HALF, physicsClientId=c)
        visual = pb.createVisualShape(pb.GEOM_BOX, halfExtents=TABLE_HALF, rgbaColor=TABLE_COLOUR, physicsClientId=c)
        self.table = pb.createMultiBody(0, shape, visual, [*TABLE_CENTRE, -TABLE_HALF[2]], physicsClientId=c)
        self.panda: Panda | None = None
        # A video's camera and captions (vslsp.sim.video), when one films the scene.
        self.frame_hook: Callable[[CloudScene], None] | None = None
        self.narrator: Callable[[CloudScene, tuple[str, ...], float], None] | None = None
        self.backdrop = None
        if robot:
            pb.setGravity(0, 0, -9.81, physicsClientId=c)
            pb.setTimeStep(TIME_STEP, physicsClientId=c)
            pb.setPhysicsEngineParameter(deterministicOverlappingPairs=1, physicsClientId=c)
            pb.changeDynamics(self.table, -1, lateralFriction=FRICTION, physicsClientId=c)
            self.panda = Panda(c)
        self.tray = None
        if tray:
            with quiet():
                self.tray = pb.loadURDF(
                    os.path.join("tray", "traybox.urdf"),
                    [*TRAY_POSITION, 0.0],
                    useFixedBase=True,
                    globalScaling=TRAY_SCALE,
                    physicsClientId=c,
                )
            self._rest_on_table(self.tray)
        self.bodies: dict[str, int] = {}
        for name, (x, y, yaw) in objects.items():
            model = OBJECTS[name.split("#")[0]]
            with quiet():
                self.bodies[name] = pb.loadURDF(model.urdf, [x, y, 0.2], globalScaling=model.scale, physicsClientId=c)
            if robot:
                pb.changeDynamics(
                    self.bodies[name],
                    -1,
                    lateralFriction=FRICTION,
                    spinningFriction=SPINNING_FRICTION,
                    physicsClientId=c,
                )
            self.tutor_move(name, self.resting_pose(name, x, y, yaw))
        self.boxes: dict[str, int] = {}
        for name, (x, y, yaw) in (boxes or {}).items():
            self.add_box(name, x, y, yaw)
        if robot:
            self.settle()

    # -- the tutor -------------------------------------------------------------------------
    def tutor_move(self, name: str, pose: np.ndarray) -> None:
        """The tutor puts object ``name`` at ``pose`` (4, 4), the pose of its base frame."""
        body = self._body(name)
        pose = np.asarray(pose, dtype=float)
        if pose.shape != (4, 4) or not np.allclose(pose[:3, :3] @ pose[:3, :3].T, np.eye(3), atol=1e-6):
            raise InputError("a pose is a 4x4 rigid transform (orthonormal rotation)")
        quaternion = _quaternion(pose[:3, :3])
        pb.resetBasePositionAndOrientation(body, pose[:3, 3].tolist(), quaternion, physicsClientId=self.client)
        pb.resetBaseVelocity(body, [0, 0, 0], [0, 0, 0], physicsClientId=self.client)

    # -- physics (robot=True) --------------------------------------------------------------
    def add_box(self, name: str, x: float, y: float, yaw: float) -> None:
        """The landmark box ``name`` of :data:`BOXES` (a movable body: the tutor repositions it)
        resting on the table at (x, y) turned by ``yaw`` (rad)."""
        if name not in BOXES or name in self.bodies:
            raise InputError(f"unknown or repeated box {name!r}; use each of {', '.join(BOXES)} at most once")
        c = self.client
        half = [v / 2.0 for v in BOXES[name]]
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half, physicsClientId=c)
        visual = pb.createVisualShape(pb.GEOM_BOX, halfExtents=half, rgbaColor=BOX_COLOUR, physicsClientId=c)
        body = pb.createMultiBody(
            BOX_MASS,
            shape,
            visual,
            [x, y, half[2] + 0.0005],
            pb.getQuaternionFromEuler([0.0, 0.0, yaw]),
            physicsClientId=c,
        )
        pb.changeDynamics(body, -1, lateralFriction=FRICTION, spinningFriction=SPINNING_FRICTION, physicsClientId=c)
        self.bodies[name] = body
        self.boxes[name] = body

    def step(self, n: int = 1) -> None:
        """Advance the physics by ``n`` steps of :data:`TIME_STEP`."""
        for _ in range(n):
            pb.stepSimulation(physicsClientId=self.client)
            if self.frame_hook is not None:
                self.frame_hook(self)

    # -- what a video shows (vslsp.sim.video) -----------------------------------------------
    def say(self, *lines: str, hold: float = 0.0) -> None:
        """The caption of a video filming this scene (nothing otherwise), and ``hold`` seconds
        of the scene as it is now under it."""
        if self.narrator is not None:
            self.narrator(self, lines, hold)

    def movable_poses(self) -> tuple:
        """The objects' and boxes' poses, as pybullet has them."""
        return tuple(
            pb.getBasePositionAndOrientation(body, physicsClientId=self.client) for body in self.bodies.values()
        )

    def arm_chain(self) -> np.ndarray | None:
        """The Panda's joints from its base, then the fingertips (K, 3); None without it."""
        if self.panda is None:
            return None
        states = pb.getLinkStates(self.panda.body, list(range(7)), physicsClientId=self.client)
        return np.array([[0.0, 0.0, 0.0]] + [state[4] for state in states] + [self.panda.hand()[0]])

    def arm_body(self) -> int | None:
        return None if self.panda is None else self.panda.body

    def settle(self, max_steps: int = 960) -> None:
        """Step until every object has been at rest for :data:`REST_STEPS` steps (below 1 mm/s
        and 0.01 rad/s: a rocking teddy creeps otherwise) or ``max_steps``; a no-op in a static
        world."""
        if self.panda is None:
            return
        quiet_steps = 0
        for _ in range(max_steps):
            self.step()
            velocities = [pb.getBaseVelocity(b, physicsClientId=self.client) for b in self.bodies.values()]
            still = all(np.linalg.norm(v) < 1e-3 and np.linalg.norm(w) < 1e-2 for v, w in velocities)
            quiet_steps = quiet_steps + 1 if still else 0
            if quiet_steps >= REST_STEPS:
                break

    def park(self) -> None:
        """Park the arm out of the sensor's view (a no-op without a robot)."""
        if self.panda is not None:
            self.panda.reset(PARK)

    def resting_pose(
        self, name: str, x: float, y: float, yaw: float, roll: float = 0.0, pitch: float = 0.0, support: float = 0.0
    ) -> np.ndarray:
        """The pose (4, 4) at which ``name``, upright then tilted by ``roll``/``pitch`` and turned
        by ``yaw`` (rad), has the middle of its box over (x, y) and touches the plane z = ``support``."""
        body = self._body(name)
        current = self.pose(name)
        model = OBJECTS.get(name.split("#")[0])
        upright = model.upright if model is not None else (0.0, 0.0)  # a landmark box stands as built
        rotation = _rotation(0.0, 0.0, yaw) @ _rotation(roll, pitch, 0.0) @ _rotation(*upright, 0.0)
        probe = np.eye(4)
        probe[:3, :3] = rotation
        self.tutor_move(name, probe)
        lower, upper = (np.asarray(v) for v in pb.getAABB(body, physicsClientId=self.client))
        middle = (lower + upper) / 2.0
        probe[:3, 3] = [x - middle[0], y - middle[1], support - lower[2] + 0.0005]
        self.tutor_move(name, current)
        return probe

    # -- sensing ---------------------------------------------------------------------------
    def capture(self) -> RGBDImage:
        """What the RGB-D sensor sees now (with ``views=2`` the far sensor's capture too, in
        ``others``); with ``noise`` the depth carries the sensor's axial noise (seeded)."""
        first = self._capture(self.camera)
        if not self.others:
            return first
        return RGBDImage(first.rgb, first.depth, first.camera, tuple(self._capture(c) for c in self.others))

    def picture(self) -> np.ndarray:
        """The first sensor's RGB (H, W, 3) now (a report's picture: no other sensor renders)."""
        return self._capture(self.camera).rgb

    def _capture(self, camera: Camera) -> RGBDImage:
        """One sensor's capture."""
        rgb, depth = camera.render(self.live_client)
        depth = depth.astype(np.float64)
        depth[depth > 2.9] = 0.0  # beyond the far plane: no return
        if self.noise:
            seen = depth > 0.0
            depth[seen] += self._rng.normal(0.0, 1.0, seen.sum()) * axial_noise(depth[seen])
        return RGBDImage(rgb, depth.astype(np.float32), camera)

    # -- ground truth ----------------------------------------------------------------------
    def pose(self, name: str) -> np.ndarray:
        """Ground-truth pose (4, 4) of object ``name``'s base frame."""
        position, orientation = pb.getBasePositionAndOrientation(self._body(name), physicsClientId=self.client)
        return pose_matrix(np.asarray(position), orientation)

    def bounds(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Ground-truth axis-aligned bounding box (lower (3,), upper (3,)) of object ``name``."""
        lower, upper = pb.getAABB(self._body(name), physicsClientId=self.client)
        return np.asarray(lower), np.asarray(upper)

    def object_at(self, point: np.ndarray) -> str | None:
        """The object whose bounding box holds ``point`` (3,) (the nearest box centre if several
        do), or None: what a gripper closing there would take."""
        holding = []
        for name in self.bodies:
            lower, upper = self.bounds(name)
            if np.all(point >= lower - 0.005) and np.all(point <= upper + 0.005):
                holding.append((float(np.linalg.norm(point - (lower + upper) / 2.0)), name))
        return min(holding)[1] if holding else None

    def surface_height(self, x: float, y: float) -> float:
        """Height (m) of the first surface below (x, y) seen from above: the table, the tray's
        floor or an object (a depth probe straight down)."""
        start, end = [x, y, 1.0], [x, y, -0.1]
        _, _, fraction, _, _ = pb.rayTest(start, end, physicsClientId=self.client)[0]
        return float(start[2] - fraction * (start[2] - end[2]))

    def near(self, name: str, distance: float) -> list[str]:
        """The other objects, boxes and the tray (``"tray"``) within ``distance`` m of object
        ``name`` (closest points of their collision shapes)."""
        body, c = self._body(name), self.client
        others = {**self.bodies, **({"tray": self.tray} if self.tray is not None else {})}
        return [
            other
            for other, handle in others.items()
            if handle != body and pb.getClosestPoints(body, handle, distance, physicsClientId=c)
        ]

    def _body(self, name: str) -> int:
        if name not in self.bodies:
            raise InputError(f"no object named {name!r}; the scene has {sorted(self.bodies)}")
        return self.bodies[name]

    def _rest_on_table(self, body: int) -> None:
        lower, _ = pb.getAABB(body, physicsClientId=self.client)
        position, orientation = pb.getBasePositionAndOrientation(body, physicsClientId=self.client)
        pb.resetBasePositionAndOrientation(
            body, [position[0], position[1], position[2] - lower[2]], orientation, physicsClientId=self.client
        )


def in_view(x: float, y: float, height: float, radius: float = VIEW_RADIUS) -> bool:
    """Whether the upright square prism of half-width ``radius`` and ``height`` (m) standing at
    (``x``, ``y``) on the table lies in the sensor's image, :data:`VIEW_MARGIN` pixels inside
    its border (what stands there is seen whole, whichever way it is turned)."""
    corners = np.array(
        [[x + dx, y + dy, z] for dx in (-radius, radius) for dy in (-radius, radius) for z in (0, height)]
    )
    uv = SENSOR.project(corners)
    return bool(
        np.all(uv >= VIEW_MARGIN)
        and np.all(uv[:, 0] <= SENSOR.width - VIEW_MARGIN)
        and np.all(uv[:, 1] <= SENSOR.height - VIEW_MARGIN)
    )


def random_layout(
    names: list[str],
    seed: int,
    tray: bool = True,
    keep_clear: dict[str, tuple[tuple[float, float], ...]] | None = None,
    heights: dict[str, float] | None = None,
    radii: dict[str, float] | None = None,
) -> dict[str, tuple[float, float, float]]:
    """Seeded random (x, y, yaw) per name in the workspace, centres at least :data:`CLEARANCE`
    apart, or the sum of the two items' footprint radii in ``radii`` where that is more (a box
    turned by any angle must not touch what stands beside it, default :data:`CLEARANCE` / 2),
    and clear of the tray, each seen whole by the sensor up to its
    height in ``heights`` (default :data:`OBJECT_HEIGHT`; :func:`in_view`: a landmark that
    carries a stacked object is taller than an object); the objects named in ``keep_clear`` also
    at least :data:`PLACE_CLEARANCE` from its places (x, y) (where a task puts another object
    down while they stay). When the objects drawn first leave a later one no room, the layout is
    drawn again from a seed derived from ``seed`` (deterministic)."""
    for attempt in range(LAYOUT_ATTEMPTS):
        layout = _draw_layout(names, seed + 100_000 * attempt, tray, keep_clear or {}, heights or {}, radii or {})
        if layout is not None:
            return layout
    raise InputError(
        f"cannot lay out {', '.join(names)} {CLEARANCE} m apart, in the sensor's view and clear of "
        f"the places kept clear (seed {seed}); use fewer objects"
    )


def _draw_layout(
    names: list[str],
    seed: int,
    tray: bool,
    keep_clear: dict[str, tuple[tuple[float, float], ...]],
    heights: dict[str, float],
    radii: dict[str, float],
) -> dict[str, tuple[float, float, float]] | None:
    """One draw of :func:`random_layout` (None: a later object found no room)."""
    rng = np.random.default_rng(seed)
    taken: list[tuple[float, float]] = [TRAY_POSITION] if tray else []
    footprint = [CLEARANCE / 2.0 + 0.08] if tray else []  # the tray is 24 cm wide
    layout = {}
    for name in names:
        radius = radii.get(name, CLEARANCE / 2.0)
        for _ in range(1000):
            x, y = rng.uniform(*WORKSPACE_X), rng.uniform(*WORKSPACE_Y)
            if (
                in_view(x, y, heights.get(name, OBJECT_HEIGHT))
                and all(
                    np.hypot(x - tx, y - ty) >= max(CLEARANCE, r + radius)
                    for (tx, ty), r in zip(taken, footprint, strict=True)
                )
                and all(np.hypot(x - px, y - py) >= PLACE_CLEARANCE for px, py in keep_clear.get(name, ()))
            ):
                break
        else:
            return None
        taken.append((x, y))
        footprint.append(radius)
        layout[name] = (float(x), float(y), float(rng.uniform(-np.pi, np.pi)))
    return layout


def _rotation(roll: float, pitch: float, yaw: float) -> np.ndarray:
    return np.asarray(pb.getMatrixFromQuaternion(pb.getQuaternionFromEuler([roll, pitch, yaw]))).reshape(3, 3)


def _quaternion(rotation: np.ndarray) -> list[float]:
    """Quaternion (x, y, z, w) of a rotation matrix (3, 3) (Shepperd's method)."""
    m = rotation
    trace = np.trace(m)
    if trace > 0.0:
        s = 2.0 * np.sqrt(trace + 1.0)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = [0.0, 0.0, 0.0, (m[k, j] - m[j, k]) / s]
        q[i] = 0.25 * s
        q[j] = (m[j, i] + m[i, j]) / s
        q[k] = (m[k, i] + m[i, k]) / s
    return [float(v) for v in q]
