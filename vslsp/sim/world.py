"""The simulated tabletop world: the iCub at a table, coloured, textured cubes and a landmark line.

Paper section "Implementation" of VSL-SP: the iCub pushes and pulls cubes across a black
borderline drawn on the table, watching the scene through its eyes. pybullet runs headless
(DIRECT) unless ``gui=True``. Everything that makes a scene is in its
:class:`~vslsp.sim.scene.SceneSpec`, so the same spec (or seed) gives the same world and
byte-identical images.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from vslsp.errors import InputError
from vslsp.sim.camera import Backdrop, Camera
from vslsp.sim.client import PhysicsClient, mesh_visual, strip_mesh
from vslsp.sim.quiet import quiet
from vslsp.sim.robot import TIME_STEP
from vslsp.sim.scene import COLOURS, LINE_WIDTH, TABLE_Z, CubeSpec, SceneSpec
from vslsp.sim.textures import cube_atlas, cube_mesh, texture_file

with quiet():
    import pybullet as pb

TABLE_COLOUR = (0.80, 0.74, 0.62, 1.0)
TABLE_HALF = (0.40, 0.70, 0.02)  # half extents of the table top
TABLE_CENTRE = (0.46, -0.05)
CUBE_MASS = 0.08
CUBE_FRICTION = 0.6
CAMERA_NAMES = ("head", "overhead")
LANDMARK_SEGMENTS = 16  # pieces of the landmark line's mesh (see strip_mesh)


@dataclass(frozen=True)
class Observation:
    """What a camera saw: RGB (H, W, 3) uint8, depth (H, W) float32 m, and the camera."""

    rgb: np.ndarray
    depth: np.ndarray
    camera: Camera


def _table_backdrop(client: int, visual: int, centre: list[float]) -> Backdrop:
    """The table top as a solid backdrop, in the colour the renderer gives its visual."""
    look = pb.createMultiBody(0, -1, visual, centre, physicsClientId=client)
    small = Camera(
        "look",
        eye=(0.27, -0.07, TABLE_Z + 0.5),
        target=(0.27, -0.07, TABLE_Z),
        up=(1.0, 0.0, 0.0),
        width=8,
        height=6,
        fov=45.0,
    )
    colour = small.render(client)[0][small.height // 2, small.width // 2]
    pb.removeBody(look, physicsClientId=client)
    r, g, b = (int(v) for v in colour)
    return Backdrop(
        TABLE_Z,
        (TABLE_CENTRE[0] - TABLE_HALF[0], TABLE_CENTRE[0] + TABLE_HALF[0]),
        (TABLE_CENTRE[1] - TABLE_HALF[1], TABLE_CENTRE[1] + TABLE_HALF[1]),
        (r, g, b),
        solid=True,
    )


class LineWorld(PhysicsClient):
    """A pybullet world built from a :class:`SceneSpec`; close it (or use ``with``) when done."""

    def __init__(
        self,
        spec: SceneSpec | None = None,
        *,
        seed: int = 0,
        gui: bool = False,
        robot: bool = True,
        textured: bool = True,
    ) -> None:
        from vslsp.sim.robot import ICub  # robot imports the world's constants
        from vslsp.sim.tutor import Tutor

        self.spec = spec if spec is not None else SceneSpec.random(seed)
        self.textured = textured
        with quiet():
            self.client = pb.connect(pb.GUI if gui else pb.DIRECT)
        pb.resetSimulation(physicsClientId=self.client)
        pb.setGravity(0, 0, -9.81, physicsClientId=self.client)
        pb.setTimeStep(TIME_STEP, physicsClientId=self.client)
        pb.setPhysicsEngineParameter(deterministicOverlappingPairs=1, physicsClientId=self.client)
        if gui:
            pb.configureDebugVisualizer(pb.COV_ENABLE_GUI, 0, physicsClientId=self.client)
        self._seen: dict[tuple, tuple[tuple, Observation]] = {}
        # Called after every physics step when set (a video's camera: vslsp.sim.video).
        self.frame_hook: Callable[[LineWorld], None] | None = None
        self.table = self._make_table(gui)
        self.landmark_body = self._make_landmark()
        self.cubes: dict[str, int] = {}
        for cube in self.spec.cubes:
            self.cubes[cube.name] = self._make_cube(cube)
        self.robot = ICub(self, visuals=gui) if robot else None
        self.tutor = Tutor(self)
        self.settle()

    # -- building -----------------------------------------------------------------------
    def _make_table(self, gui: bool) -> int:
        """The table. Headless, its top is drawn as the cameras' solid :class:`Backdrop` (the
        colour the renderer gives it, read from a small render of the table alone) instead of
        being rasterised with every image: the same pixels but for ties at bodies' edges."""
        c, centre = self.client, [*TABLE_CENTRE, TABLE_Z - TABLE_HALF[2]]
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=TABLE_HALF, physicsClientId=c)
        visual = pb.createVisualShape(pb.GEOM_BOX, halfExtents=TABLE_HALF, rgbaColor=TABLE_COLOUR, physicsClientId=c)
        self.backdrop: Backdrop | None = None
        if gui or c is None:
            body = pb.createMultiBody(0, shape, visual, centre, physicsClientId=c)
        else:
            self.backdrop = _table_backdrop(c, visual, centre)
            # a body without a visual shape would be drawn from its collision box: give the
            # table a speck of a visual far above the cameras instead, which they never see
            speck = pb.createVisualShape(
                pb.GEOM_SPHERE,
                radius=1e-3,
                visualFramePosition=[0.0, 0.0, 50.0],
                rgbaColor=TABLE_COLOUR,
                physicsClientId=c,
            )
            body = pb.createMultiBody(0, shape, speck, centre, physicsClientId=c)
        pb.changeDynamics(body, -1, lateralFriction=CUBE_FRICTION, physicsClientId=c)
        return body

    def _make_landmark(self) -> int:
        landmark = self.spec.landmark
        half = (LINE_WIDTH / 2.0, 0.40, 0.0005)
        vertices, indices, uvs, normals = strip_mesh(half, LANDMARK_SEGMENTS)
        visual = pb.createVisualShape(
            pb.GEOM_MESH,
            vertices=vertices,
            indices=indices,
            uvs=uvs,
            normals=normals,
            rgbaColor=(0.02, 0.02, 0.02, 1.0),
            physicsClientId=self.client,
        )
        # Visual only: no collision shape, so it never disturbs the cubes.
        return pb.createMultiBody(
            0,
            -1,
            visual,
            [*landmark.point, TABLE_Z + half[2]],
            pb.getQuaternionFromEuler([0, 0, landmark.angle]),
            physicsClientId=self.client,
        )

    def _make_cube(self, cube: CubeSpec) -> int:
        c = self.live_client
        half = [cube.size / 2.0] * 3
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half, physicsClientId=c)
        if self.textured:  # the colour is the symbol; the texture gives match finding its keypoints
            visual = mesh_visual(c, cube_mesh(cube.size))
        else:
            visual = pb.createVisualShape(
                pb.GEOM_BOX, halfExtents=half, rgbaColor=(*COLOURS[cube.colour], 1.0), physicsClientId=c
            )
        body = pb.createMultiBody(
            CUBE_MASS,
            shape,
            visual,
            [cube.x, cube.y, TABLE_Z + cube.size / 2.0],
            pb.getQuaternionFromEuler([0, 0, cube.yaw]),
            physicsClientId=c,
        )
        pb.changeDynamics(body, -1, lateralFriction=CUBE_FRICTION, spinningFriction=0.001, physicsClientId=c)
        if self.textured:
            texture = pb.loadTexture(str(texture_file(cube_atlas(COLOURS[cube.colour], cube.name))), physicsClientId=c)
            pb.changeVisualShape(body, -1, textureUniqueId=texture, physicsClientId=c)
        return body

    # -- running ------------------------------------------------------------------------
    def step(self, n: int = 1) -> None:
        for _ in range(n):
            pb.stepSimulation(physicsClientId=self.client)
            if self.frame_hook is not None:
                self.frame_hook(self)

    def settle(self, max_steps: int = 480) -> None:
        """Step until every cube is at rest (or ``max_steps``)."""
        for step in range(max_steps):
            self.step()
            if step >= 10 and all(
                np.linalg.norm(pb.getBaseVelocity(body, physicsClientId=self.client)[0]) < 1e-3
                for body in self.cubes.values()
            ):
                break

    def close(self) -> None:
        if self.robot is not None:
            self.robot.close()
        super().close()

    # -- ground truth (for tests and the tutor; perception never reads it) ----------------
    def cube_pose(self, name: str) -> tuple[float, float, float]:
        """Ground-truth (x, y, yaw) of a cube."""
        if name not in self.cubes:
            raise InputError(f"no cube named {name!r}; the scene has {sorted(self.cubes)}")
        position, orientation = pb.getBasePositionAndOrientation(self.cubes[name], physicsClientId=self.client)
        yaw = pb.getEulerFromQuaternion(orientation)[2]
        return float(position[0]), float(position[1]), float(yaw)

    def cube_height(self, name: str) -> float:
        """Ground-truth height (m) of a cube's centre above the table top."""
        return pb.getBasePositionAndOrientation(self.cubes[name], physicsClientId=self.client)[0][2] - TABLE_Z

    def is_far(self, name: str) -> bool:
        """Ground truth of ``(far name)``: the cube's centre lies beyond the line."""
        return self.spec.landmark.signed_distance(np.asarray(self.cube_pose(name)[:2])) > 0.0

    def current_spec(self) -> SceneSpec:
        """The scene as it is now (cube poses from the simulation)."""
        spec = self.spec
        for cube in self.spec.cubes:
            x, y, yaw = self.cube_pose(cube.name)
            spec = spec.with_cube(CubeSpec(cube.name, cube.colour, x, y, yaw, cube.size))
        return spec

    # -- cameras --------------------------------------------------------------------------
    def camera(self, name: str, width: int = 640, height: int = 480) -> Camera:
        if name == "overhead":
            return Camera(
                "overhead",
                eye=(0.27, -0.07, TABLE_Z + 0.5),
                target=(0.27, -0.07, TABLE_Z),
                up=(1.0, 0.0, 0.0),
                width=width,
                height=height,
                fov=45.0,
            )
        if name == "head":
            if self.robot is not None:
                x, y, z = self.robot.eye_position()
                eye = (float(x), float(y), float(z))
            else:
                from vslsp.sim.robot import DEFAULT_EYE

                eye = DEFAULT_EYE
            return Camera(
                "head", eye=eye, target=(0.23, -0.07, TABLE_Z), up=(0.0, 0.0, 1.0), width=width, height=height, fov=60.0
            )
        raise InputError(f"unknown camera {name!r}; use one of {', '.join(CAMERA_NAMES)}")

    def observe(self, camera: str = "head", width: int = 640, height: int = 480) -> Observation:
        """Render what ``camera`` sees now (the arm is parked out of view first).

        A view of a world in which nothing moved since the camera last looked is that same
        view: the image is a function of the bodies' poses, so it is not rendered again."""
        if self.robot is not None:
            self.robot.park()
        view = self.camera(camera, width, height)
        state = self._poses()
        seen = self._seen.get((camera, width, height))
        if seen is None or seen[0] != state or seen[1].camera != view:
            rgb, depth = view.render(self.live_client, self.backdrop)
            seen = (state, Observation(rgb=rgb, depth=depth, camera=view))
            self._seen[(camera, width, height)] = seen
        return Observation(rgb=seen[1].rgb.copy(), depth=seen[1].depth.copy(), camera=view)

    def movable_poses(self) -> tuple:
        """The cubes' poses (for a video: :mod:`vslsp.sim.video`)."""
        return self._poses()[: len(self.cubes)]

    def arm_chain(self) -> np.ndarray | None:
        """The right arm's joints from the shoulder, then the hand (K, 3); None without a robot."""
        if self.robot is None:
            return None
        states = pb.getLinkStates(self.robot.body, self.robot.ik_indices[3:], physicsClientId=self.client)
        return np.array([state[4] for state in states] + [self.robot.hand_position()])

    def arm_body(self) -> int | None:
        return None if self.robot is None else self.robot.body

    def body_poses(self) -> tuple:
        """Every movable body's pose and the robot's joints: equal tuples, the same picture."""
        return self._poses()

    def _poses(self) -> tuple:
        """Every movable body's pose and the robot's joint positions, exactly as pybullet has them."""
        c = self.client
        poses = tuple(pb.getBasePositionAndOrientation(body, physicsClientId=c) for body in self.cubes.values())
        if self.robot is None:
            return poses
        joints = pb.getJointStates(self.robot.body, self.robot.ik_indices, physicsClientId=c)
        return poses + tuple(joint[0] for joint in joints)
