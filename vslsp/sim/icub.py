"""The iCub's right arm driven in Cartesian space.

Inverse kinematics is damped least squares (Wampler 1986; Buss 2004) on the torso and the
right arm (10 joints): ``dq = Jᵀ (J Jᵀ + λ² I)⁻¹ e`` with ``e`` the position and orientation
error of the hand frame ``r_hand_dh_frame``. pybullet's own IK cannot lock joints, and the
Jacobian must be evaluated at a configuration we choose, so IK runs on a kinematics-only copy
of the robot in a second pybullet client: the simulated robot is never reset by a solve.

The hand frame's axes: x runs along the fingers, z out of the palm.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vslsp.errors import UnreachableError
from vslsp.sim.icub_model import reduced_urdf_path
from vslsp.sim.quiet import quiet

with quiet():
    import pybullet as pb

BASE_Z = 0.63
TORSO_JOINTS = ("torso_pitch", "torso_roll", "torso_yaw")
RIGHT_ARM_JOINTS = (
    "r_shoulder_pitch",
    "r_shoulder_roll",
    "r_shoulder_yaw",
    "r_elbow",
    "r_wrist_prosup",
    "r_wrist_pitch",
    "r_wrist_yaw",
)
IK_JOINTS = TORSO_JOINTS + RIGHT_ARM_JOINTS
HAND_FRAME = "r_hand_dh_frame"
# Left arm hanging beside the body, out of the table's way.
LEFT_ARM_PARK = {"l_shoulder_pitch": 0.17, "l_shoulder_roll": 0.12, "l_elbow": 0.27}
# Right arm out of the cameras' view, hanging beside the body (the covers are dark red, so
# the arm must not be in view when the robot observes).
RIGHT_ARM_PARK = {
    "torso_pitch": 0.0,
    "torso_roll": 0.0,
    "torso_yaw": 0.0,
    "r_shoulder_pitch": 0.17,
    "r_shoulder_roll": 0.12,
    "r_shoulder_yaw": 0.0,
    "r_elbow": 0.27,
    "r_wrist_prosup": 0.0,
    "r_wrist_pitch": 0.0,
    "r_wrist_yaw": 0.0,
}
# Looking down at the table in front.
HEAD_POSE = {"neck_pitch": -0.6, "neck_roll": 0.0, "neck_yaw": 0.0}


def palm_down_rotation(yaw: float, pitch: float = 0.0) -> np.ndarray:
    """Hand orientation (3, 3): palm toward the table, fingers at ``yaw`` (rad) about z and
    tilted down by ``pitch`` (rad), so that the wrist and forearm rise away from the table."""
    fingers = np.array([np.cos(yaw) * np.cos(pitch), np.sin(yaw) * np.cos(pitch), -np.sin(pitch)])
    side = np.array([np.sin(yaw), -np.cos(yaw), 0.0])
    palm = np.cross(fingers, side)
    return np.column_stack([fingers, side, palm])


def rotation_error(current: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Axis-angle vector (3,) rotating ``current`` onto ``target`` (both (3, 3), world frame)."""
    relative = target @ current.T
    angle = np.arccos(np.clip((np.trace(relative) - 1.0) / 2.0, -1.0, 1.0))
    axis = np.array(
        [
            relative[2, 1] - relative[1, 2],
            relative[0, 2] - relative[2, 0],
            relative[1, 0] - relative[0, 1],
        ]
    )
    norm = np.linalg.norm(axis)
    if norm < 1e-9:
        if angle < 1e-6:
            return np.zeros(3)
        # 180 degrees: take the axis from the symmetric part.
        values, vectors = np.linalg.eigh(relative + np.eye(3))
        return vectors[:, np.argmax(values)] * angle
    return axis / norm * angle


# A solve stops when its error fell by less than STALL_GAIN over the last STALL_WINDOW steps:
# such solves ended at 200 iterations about as far (a fraction of a millimetre) as they were.
STALL_WINDOW, STALL_GAIN = 20, 0.01


@dataclass(frozen=True)
class IKResult:
    """A joint solution of the IK joints, and how far the hand is from the target."""

    q: np.ndarray  # (10,) torso + right arm
    position_error: float  # m
    orientation_error: float  # rad


def _load_robot(client: int, kinematic: bool = False, path: Path | None = None) -> int:
    """Load the reduced iCub (or the URDF at ``path``) facing the table."""
    with quiet():
        return pb.loadURDF(
            str(path if path is not None else reduced_urdf_path(kinematic)),
            [0.0, 0.0, BASE_Z],
            pb.getQuaternionFromEuler([0.0, 0.0, np.pi]),  # the model faces -x: turn it to the table
            useFixedBase=True,
            flags=pb.URDF_USE_INERTIA_FROM_FILE,
            physicsClientId=client,
        )


class KinematicICub:
    """A kinematics-only iCub in its own pybullet client: forward kinematics, Jacobian, IK."""

    def __init__(self) -> None:
        with quiet():
            self.client = pb.connect(pb.DIRECT)
        self.body = _load_robot(self.client, kinematic=True)
        self.joint_index: dict[str, int] = {}
        self.movable: list[int] = []
        link_index: dict[str, int] = {}
        self.lower: dict[int, float] = {}
        self.upper: dict[int, float] = {}
        for i in range(pb.getNumJoints(self.body, physicsClientId=self.client)):
            info = pb.getJointInfo(self.body, i, physicsClientId=self.client)
            link_index[info[12].decode()] = i
            if info[2] != pb.JOINT_FIXED:
                self.joint_index[info[1].decode()] = i
                self.movable.append(i)
                self.lower[i], self.upper[i] = info[8], info[9]
        self.link_index = link_index
        self.hand_link = link_index[HAND_FRAME]
        self.ik_indices = [self.joint_index[name] for name in IK_JOINTS]
        self.ik_columns = [self.movable.index(i) for i in self.ik_indices]
        self.ik_lower = np.array([self.lower[i] for i in self.ik_indices])
        self.ik_upper = np.array([self.upper[i] for i in self.ik_indices])
        self._q = np.zeros(len(self.ik_indices))
        # Every movable joint's position, kept here so the Jacobian needs no state queries.
        self._positions = {i: pb.getJointState(self.body, i, physicsClientId=self.client)[0] for i in self.movable}
        self.set_ik_joints(self._q, force=True)
        self._jacobian_frame = np.eye(3)
        self._jacobian_frame = self._calibrate_jacobian_frame()

    def close(self) -> None:
        if self.client is not None:
            pb.disconnect(self.client)
            self.client = None

    def set_joints(self, values: dict[str, float]) -> None:
        for name, value in values.items():
            pb.resetJointState(self.body, self.joint_index[name], value, physicsClientId=self.client)
            self._positions[self.joint_index[name]] = float(value)

    def set_ik_joints(self, q: np.ndarray, force: bool = False) -> None:
        changed = [
            (index, float(value)) for index, value, old in zip(self.ik_indices, q, self._q) if force or value != old
        ]
        if changed:
            indices, values = zip(*changed)
            pb.resetJointStatesMultiDof(self.body, list(indices), [[v] for v in values], physicsClientId=self.client)
            self._positions.update(changed)
        self._q = np.array(q, dtype=float)

    def hand_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """Position (3,) and rotation (3, 3) of the hand frame at the current configuration."""
        state = pb.getLinkState(self.body, self.hand_link, computeForwardKinematics=True, physicsClientId=self.client)
        rotation = np.array(pb.getMatrixFromQuaternion(state[5])).reshape(3, 3)
        return np.array(state[4]), rotation

    def jacobian(self) -> np.ndarray:
        """(6, 10) world-frame Jacobian of the hand frame w.r.t. the IK joints."""
        positions = [self._positions[i] for i in self.movable]
        zeros = [0.0] * len(positions)
        linear, angular = pb.calculateJacobian(
            self.body,
            self.hand_link,
            [0.0, 0.0, 0.0],
            positions,
            zeros,
            zeros,
            physicsClientId=self.client,
        )
        frame = self._jacobian_frame
        full = np.vstack([frame @ np.array(linear), frame @ np.array(angular)])
        return full[:, self.ik_columns]

    def _calibrate_jacobian_frame(self) -> np.ndarray:
        """The rotation from the frame ``calculateJacobian`` answers in to the world frame.

        pybullet expresses the Jacobian in a base frame that depends on the base's inertial
        frame and on how the robot was placed; rather than rely on that convention, compare
        it once with finite differences of the forward kinematics.
        """
        q = np.clip(np.linspace(0.1, 0.4, len(self.ik_indices)), self.ik_lower, self.ik_upper)
        self.set_ik_joints(q)
        raw = self.jacobian()[:3]
        origin = self.hand_pose()[0]
        numeric = np.zeros_like(raw)
        for column in range(len(q)):
            moved = q.copy()
            moved[column] += 1e-4
            self.set_ik_joints(moved)
            numeric[:, column] = (self.hand_pose()[0] - origin) / 1e-4
        self.set_ik_joints(np.zeros_like(q))
        u, _, vt = np.linalg.svd(numeric @ raw.T)  # orthogonal Procrustes
        return u @ vt

    def solve(
        self,
        position: np.ndarray,
        rotation: np.ndarray | None,
        q0: np.ndarray,
        *,
        iterations: int = 200,
        damping: float = 0.02,
        position_tolerance: float = 1e-4,
        orientation_tolerance: float = 1e-3,
        orientation_weight: float = 0.3,
    ) -> IKResult:
        """Damped-least-squares IK for the hand frame; ``rotation`` None solves position only."""
        q = np.clip(np.asarray(q0, dtype=float), self.ik_lower, self.ik_upper)
        position = np.asarray(position, dtype=float)
        position_error = orientation_error = np.inf
        history: list[float] = []  # the error, in tolerances, at every iteration
        for _ in range(iterations):
            self.set_ik_joints(q)
            current_position, current_rotation = self.hand_pose()
            error_position = position - current_position
            position_error = float(np.linalg.norm(error_position))
            if rotation is None:
                error, orientation_error = error_position, 0.0
            else:
                error_rotation = rotation_error(current_rotation, rotation)
                orientation_error = float(np.linalg.norm(error_rotation))
                error = np.concatenate([error_position, orientation_weight * error_rotation])
            if position_error < position_tolerance and orientation_error < orientation_tolerance:
                break  # before the Jacobian: most warm-started solves end at their second look
            history.append(position_error / position_tolerance + orientation_error / orientation_tolerance)
            if len(history) > STALL_WINDOW and history[-1] > (1.0 - STALL_GAIN) * history[-1 - STALL_WINDOW]:
                break  # stalled (a joint at its limit, a target at the edge of reach): more steps gain nothing
            jacobian = self.jacobian()
            if rotation is None:
                jacobian = jacobian[:3]
            else:
                jacobian = np.vstack([jacobian[:3], orientation_weight * jacobian[3:]])
            q = np.clip(q + self._step(jacobian, error, q, damping), self.ik_lower, self.ik_upper)
        return IKResult(q=q, position_error=position_error, orientation_error=orientation_error)

    def _step(self, jacobian: np.ndarray, error: np.ndarray, q: np.ndarray, damping: float) -> np.ndarray:
        """One damped-least-squares step (10,) for the task-space ``error`` (3,) or (6,) with the
        joints at a limit that the step would push beyond held still (their columns of the
        Jacobian (3|6, 10) left out, the step solved again): clipping such a step instead moves
        the hand only part of the way and the solve converges linearly, about 0.7 per step, where
        it otherwise takes two or three steps."""
        free = np.ones(len(q), dtype=bool)
        damped = damping**2 * np.eye(len(error))
        while True:
            active = jacobian * free
            step = active.T @ np.linalg.solve(active @ active.T + damped, error)
            largest = np.max(np.abs(step))
            if largest > 0.2:  # keep each step inside the region where J is a good model
                step *= 0.2 / largest
            beyond = (q + step < self.ik_lower) & (q <= self.ik_lower + 1e-9)
            beyond |= (q + step > self.ik_upper) & (q >= self.ik_upper - 1e-9)
            blocked = free & beyond
            if not blocked.any():
                return step
            free &= ~blocked


def check_reached(result: IKResult, target: np.ndarray, tolerance: float = 0.01) -> None:
    """Raise :class:`UnreachableError` when an IK solution misses its target by > ``tolerance``."""
    if result.position_error > tolerance:
        x, y, z = np.round(np.asarray(target, dtype=float), 3)
        raise UnreachableError(
            f"the hand cannot reach ({x}, {y}, {z}) m: the best solution is "
            f"{result.position_error * 1000:.0f} mm away; keep targets on the table in front of "
            "the robot (x about 0.05-0.32 m, y about -0.25-0.10 m for the right hand)"
        )
