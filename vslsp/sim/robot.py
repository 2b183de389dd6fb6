"""The simulated iCub in the world: joint control, the hand in Cartesian space, the eyes.

The robot stands at the table with a fixed base. The right arm (with the torso) follows
Cartesian waypoints: every waypoint is solved by damped-least-squares IK on a kinematics-only
copy (:mod:`vslsp.sim.icub`), then the joints are driven there by position control while the
physics runs, so the hand pushes what it meets. The left arm stays parked out to the side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.errors import UnreachableError
from vslsp.sim.icub import (
    BASE_Z,
    HEAD_POSE,
    IK_JOINTS,
    LEFT_ARM_PARK,
    RIGHT_ARM_PARK,
    KinematicICub,
    _load_robot,
    check_reached,
    palm_down_rotation,
)
from vslsp.sim.icub_model import simulated_urdf_path
from vslsp.sim.quiet import quiet

with quiet():
    import pybullet as pb

TIME_STEP = 1.0 / 240.0  # the world's physics step
DEFAULT_EYE = (0.06, 0.0, BASE_Z + 0.32)  # the eyes' position with the head pose below
HAND_YAW = np.radians(30.0)  # fingers yawed toward the body's midline, as a person pushes
MAX_SPEED = 0.15  # m/s of the hand along a path
JOINT_FORCE = 200.0
CUBE_CONTACT_LINKS = ("r_hand", "r_wrist_1")  # the links that touch the cubes
# The links a camera can see when the arm is parked (the head camera's lower right corner):
# of the iCub's links only these show in a rendered view (checked with the renderer's segmentation
# mask over the experiments' views); the rest are behind the cameras, below the table top or
# hidden by these, and leaving out their meshes makes a head-camera view about 25 ms cheaper.
VISIBLE_LINKS = ("chest", "r_upper_leg", "r_upper_arm", "r_forearm", "r_hand")
APPROACH_HEIGHT = 0.05  # the hand comes down onto a path from this far above its start
# Between parked and ready the arm is lifted out to the side, so it never sweeps the table.
ARM_ASIDE = {**RIGHT_ARM_PARK, "r_shoulder_roll": 1.3, "r_elbow": 0.6}
READY_POSITION = np.array([0.17, -0.12, BASE_Z + 0.05])  # hand above the workspace's near edge
# The arm swings between parked and ready (a joint-space move) only this high above the ready
# pose: from the ready pose itself, 1 cm above the cubes' tops, the swing swept the fingers
# through cubes on the robot's right.
SWING_HEIGHT = 0.06


@dataclass(frozen=True)
class HandTrajectory:
    """The hand's path over time: t (T,), position, velocity, acceleration (T, 3)."""

    t: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray

    @classmethod
    def from_positions(cls, t: np.ndarray, position: np.ndarray) -> HandTrajectory:
        velocity = np.gradient(position, t, axis=0)
        return cls(t=t, position=position, velocity=velocity, acceleration=np.gradient(velocity, t, axis=0))


class ICub:
    """The iCub of a :class:`~vslsp.sim.world.LineWorld`."""

    def __init__(self, world, visuals: bool = True) -> None:
        """The robot at ``world``'s table; ``visuals`` False leaves out the meshes no camera
        sees (headless worlds: all but the right arm's, which shows at the head camera's lower
        right corner when parked; the rest of the body is behind the cameras)."""
        self.world = world
        self.client = world.client
        # Only the torso and the right arm move: every other joint is frozen at its posture in
        # the simulated model, and only the hand touches the cubes (see below), so the other
        # links carry no collision shape.
        self.body = _load_robot(
            self.client,
            path=simulated_urdf_path(
                IK_JOINTS,
                tuple(sorted({**LEFT_ARM_PARK, **HEAD_POSE}.items())),
                CUBE_CONTACT_LINKS,
                None if visuals else VISIBLE_LINKS,
            ),
        )
        self.kinematics = KinematicICub()
        self.joint_index = dict(self.kinematics.joint_index)
        self.ik_indices = [self.joint_index[name] for name in IK_JOINTS]
        # The model's shoulder sits low over the table, so with the palm down the forearm and
        # upper arm lie just above the table top (the wrist cannot pitch enough to lift them).
        # A person or an iCub at a lower table would pass over the other cubes: only the hand
        # touches them, so that pushing one cube does not drag its neighbours with the forearm.
        # The table is static and the hand stays above it: no robot-table contacts.
        for link in range(-1, pb.getNumJoints(self.body, physicsClientId=self.client)):
            pb.setCollisionFilterPair(self.body, world.table, link, -1, 0, physicsClientId=self.client)
        for name, value in RIGHT_ARM_PARK.items():
            pb.resetJointState(self.body, self.joint_index[name], value, physicsClientId=self.client)
        self.kinematics.set_joints({**LEFT_ARM_PARK, **HEAD_POSE})
        self._hold_all()
        self.parked = True
        # The eyes sit 6.5 cm in front of and 9 cm above the neck's yaw axis (head upright).
        self.kinematics.set_joints({name: 0.0 for name in HEAD_POSE})
        state = pb.getLinkState(
            self.kinematics.body,
            self.kinematics.link_index["head"],
            computeForwardKinematics=True,
            physicsClientId=self.kinematics.client,
        )
        upright = np.array(pb.getMatrixFromQuaternion(state[5])).reshape(3, 3)
        self._eye_offset = upright.T @ np.array([0.065, 0.0, 0.09])
        self.kinematics.set_joints(HEAD_POSE)

    def close(self) -> None:
        self.kinematics.close()

    # -- state ------------------------------------------------------------------------------
    def ik_joint_positions(self) -> np.ndarray:
        states = pb.getJointStates(self.body, self.ik_indices, physicsClientId=self.client)
        return np.array([state[0] for state in states])

    def hand_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Position (3,) and rotation (3, 3) of the right hand frame in the world."""
        state = pb.getLinkState(
            self.body, self.kinematics.hand_link, computeForwardKinematics=True, physicsClientId=self.client
        )
        return np.array(state[4]), np.array(pb.getMatrixFromQuaternion(state[5])).reshape(3, 3)

    def hand_position(self) -> np.ndarray:
        return self.hand_pose()[0]

    def eye_position(self) -> np.ndarray:
        """Between the eyes: a fixed point of the head link (the model has no camera frame)."""
        state = pb.getLinkState(
            self.body, self.kinematics.link_index["head"], computeForwardKinematics=True, physicsClientId=self.client
        )
        rotation = np.array(pb.getMatrixFromQuaternion(state[5])).reshape(3, 3)
        return np.array(state[4]) + rotation @ self._eye_offset

    # -- control ----------------------------------------------------------------------------
    def _hold_all(self) -> None:
        """Position-hold every moving joint at its current value."""
        indices = sorted(self.ik_indices)
        targets = [pb.getJointState(self.body, i, physicsClientId=self.client)[0] for i in indices]
        pb.setJointMotorControlArray(
            self.body,
            indices,
            pb.POSITION_CONTROL,
            targetPositions=targets,
            forces=[JOINT_FORCE] * len(indices),
            physicsClientId=self.client,
        )

    def _command(self, q: np.ndarray) -> None:
        """Position targets ``q`` (10,) for the IK joints."""
        pb.setJointMotorControlArray(
            self.body,
            self.ik_indices,
            pb.POSITION_CONTROL,
            targetPositions=list(q),
            forces=[JOINT_FORCE] * len(q),
            positionGains=[0.2] * len(q),
            physicsClientId=self.client,
        )

    def _drive(self, q: np.ndarray, steps: int) -> None:
        self._command(q)
        self.world.step(steps)

    def _settle_joints(self, q: np.ndarray, tolerance: float = 2e-3, max_steps: int = 240) -> None:
        for _ in range(max_steps // 4):
            if np.max(np.abs(self.ik_joint_positions() - q)) < tolerance:
                return
            self._drive(q, 4)

    def solve_path(
        self, path: np.ndarray, yaw: float = HAND_YAW, tolerance: float = 0.01, pitch: float = 0.0
    ) -> np.ndarray:
        """Joint solutions (N, 10) for Cartesian hand waypoints (N, 3), palm down.

        Raises :class:`UnreachableError` (before anything moves) if a waypoint is out of reach.
        """
        path = np.atleast_2d(np.asarray(path, dtype=float))
        rotation = palm_down_rotation(yaw, pitch)
        q = self.ik_joint_positions() if not self.parked else _reach_seed()
        solutions = []
        for point in path:
            result = self.kinematics.solve(point, rotation, q)
            if result.position_error > tolerance:  # try again from a neutral reaching posture
                retry = self.kinematics.solve(point, rotation, _reach_seed())
                result = retry if retry.position_error < result.position_error else result
            check_reached(result, point, tolerance)
            q = result.q
            solutions.append(q)
        return np.array(solutions)

    def move_hand(
        self,
        path: np.ndarray,
        *,
        yaw: float = HAND_YAW,
        pitch: float = 0.0,
        speed: float = MAX_SPEED,
        record: bool = False,
        timed: np.ndarray | None = None,
    ) -> HandTrajectory | None:
        """Move the hand through Cartesian waypoints (N, 3) at a bounded speed (m/s).

        The palm faces the table, fingers at ``yaw`` and tilted down by ``pitch`` (rad).
        ``timed`` (N,) gives the time (s) at which each waypoint is commanded instead. Coming
        from the parked posture, the hand first goes to 8 cm above the first waypoint, then
        down. With ``record`` the hand's trajectory is sampled at every physics step (240 Hz)
        and returned.
        """
        path = np.atleast_2d(np.asarray(path, dtype=float))
        solutions = self.solve_path(path, yaw, pitch=pitch)  # raises before anything moves
        if self.parked:
            self._unpark(path[0], yaw, speed, pitch)
        if timed is not None:
            ticks = np.round(np.asarray(timed, dtype=float) / TIME_STEP).astype(int)
            steps = np.maximum(np.diff(np.concatenate([[0], ticks])), 1)
        else:
            steps = self._steps_for(path, self.hand_position(), speed)
        samples: list[np.ndarray] | None = [] if record else None
        self._follow(solutions, steps, samples)
        if samples is not None:
            positions = np.array(samples)
            t = np.arange(len(positions)) * TIME_STEP
            return HandTrajectory.from_positions(t, positions)
        return None

    @staticmethod
    def _steps_for(path: np.ndarray, start: np.ndarray, speed: float) -> np.ndarray:
        """Physics steps (N,) to spend on each waypoint so the hand moves at ``speed``."""
        lengths = np.linalg.norm(np.diff(np.vstack([start, path]), axis=0), axis=1)
        return np.maximum(1, np.ceil(lengths / speed / TIME_STEP)).astype(int)

    def _follow(self, solutions: np.ndarray, steps: np.ndarray, samples: list[np.ndarray] | None) -> None:
        for q, n in zip(solutions, steps):
            self._command(q)
            for _ in range(int(n)):
                self.world.step()
                if samples is not None:
                    samples.append(self.hand_position())
        self._settle_joints(solutions[-1])

    def _cartesian(self, points: np.ndarray, yaw: float, speed: float, pitch: float = 0.0) -> None:
        """Straight lines through ``points`` (K, 3) in 5 mm steps."""
        start = self.hand_position()
        steps: list[np.ndarray] = []
        for point in points:
            n = max(1, int(np.ceil(np.linalg.norm(point - start) / 0.005)))
            steps.extend(start + (point - start) * s for s in np.linspace(0, 1, n + 1)[1:])
            start = point
        waypoints = np.array(steps)
        solutions = self.solve_path(waypoints, yaw, pitch=pitch)
        self._follow(solutions, self._steps_for(waypoints, self.hand_position(), speed), None)

    def _joint_move(self, q: np.ndarray, joint_speed: float = 1.2) -> None:
        """Interpolate the IK joints to ``q`` at a bounded joint speed (rad/s)."""
        start = self.ik_joint_positions()
        n = max(1, int(np.ceil(np.max(np.abs(q - start)) / joint_speed / TIME_STEP)))
        for s in np.linspace(0.0, 1.0, n + 1)[1:]:
            self._drive(start + s * (q - start), 1)
        self._settle_joints(q)

    def _unpark(self, first: np.ndarray, yaw: float, speed: float, pitch: float = 0.0) -> None:
        """From the parked posture: up to above the ready pose, over the first waypoint, down onto it."""
        swing = self.solve_path((READY_POSITION + [0.0, 0.0, SWING_HEIGHT])[None, :], yaw, pitch=pitch)[0]
        self._joint_move(_ik_vector(ARM_ASIDE))
        self._joint_move(swing)
        self.parked = False
        above = first + np.array([0.0, 0.0, APPROACH_HEIGHT])
        self._cartesian(np.array([above, first]), yaw, speed, pitch)

    def park(self) -> None:
        """Take the arm out of the cameras' view: up, back above the ready pose, then down beside the body."""
        if self.parked:
            return
        hand = self.hand_position()
        # Straight up to above the ready height first, so the forearm clears the cubes it passes.
        lifted = np.array([hand[0], hand[1], max(hand[2] + APPROACH_HEIGHT, READY_POSITION[2] + 0.04)])
        try:
            self._cartesian(np.array([lifted, READY_POSITION + [0.0, 0.0, SWING_HEIGHT]]), HAND_YAW, MAX_SPEED)
        except UnreachableError:
            pass
        self._joint_move(_ik_vector(ARM_ASIDE))
        self._joint_move(_ik_vector(RIGHT_ARM_PARK))
        self.parked = True


def _ik_vector(posture: dict[str, float]) -> np.ndarray:
    return np.array([posture[name] for name in IK_JOINTS])


def _reach_seed() -> np.ndarray:
    """A neutral reaching posture (torso + right arm) to start IK from."""
    return np.array([0.3, 0.0, 0.0, -0.8, 0.4, 0.3, 1.2, 0.0, 0.0, 0.0])
