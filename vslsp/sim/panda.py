"""The Franka Panda of the tabletop world: IK with the gripper pointing down, position control of
the joints, and a parallel gripper that closes until a contact-force threshold.

It stands in for the paper's Barrett WAM with its Barrett hand (section "Real-world
Experiments"): "the fingers stop closing when the measured torque is more than a pre-defined
threshold value" (section "Methodology", grasping). Here the measured quantity is the normal
force of the contacts between each finger and what it closes on.

The hand's pose is the point between the fingertips' lower ends (x, y, z) and the angle θ of
its closing axis in the table plane; θ and θ + π close the same way, so a caller chooses the
branch that keeps joint 7 within its limits (:meth:`Panda.wrist_angle`).
"""

from __future__ import annotations

import numpy as np
import pybullet_data

from vslsp.sim.quiet import quiet

with quiet():
    import pybullet as pb

ARM_JOINTS = tuple(range(7))
FINGER_JOINTS = (9, 10)
GRASP_LINK = 11  # panda_grasptarget: between the finger pads, 10.5 cm below the hand's flange
# The fingertips' lower ends lie this far below panda_grasptarget (the finger joints are 5.84 cm
# below the flange, the finger mesh 5.385 cm long, panda_grasptarget 10.5 cm below the flange).
TIP_BELOW_GRASP = 0.0584 + 0.05385 - 0.105
FINGER_OPEN = 0.04  # m per finger: the gripper opens 8 cm
LOWER = np.array([-2.9671, -1.8326, -2.9671, -3.1416, -2.9671, -0.0873, -2.9671])
UPPER = np.array([2.9671, 1.8326, 2.9671, 0.0, 2.9671, 3.8223, 2.9671])
ARM_FORCES = np.array([87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0]) * 3.0  # stiff, items are light
READY = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785])  # a pose for the IK's null space
# At rest the hand points down 30 cm above (0.25, 0) closing along x (θ = 0); parked, the same
# pose is turned to the robot's right, out of the camera's view.
REST = np.array([0.205, -1.043, -0.191, -2.917, -0.172, 1.877, -0.625])
PARK = np.array([-np.pi / 2.0, *REST[1:]])
FINGER_FRICTION = 1.0
FINGER_SPINNING_FRICTION = 0.1  # torsional: keeps a held tile from pivoting about the closing axis
FINGER_FORCE = 20.0  # N the gripper's motor pushes with while closing and holding
FINGER_SPEED = 0.1  # m/s
PAD_STIFFNESS, PAD_DAMPING = 1e7, 100.0  # N/m, N s/m
CONTACT_THRESHOLD = 3.0  # N of normal force on each finger that ends the closing
IK_POSITION_TOLERANCE = 0.005  # m
IK_ANGLE_TOLERANCE = np.radians(3.0)


def down_orientation(theta: float) -> tuple[float, float, float, float]:
    """The hand's quaternion pointing down with its closing axis at angle ``theta`` (rad) from x.

    The fingers move along the hand's y axis, which points along (sin ψ, −cos ψ) for a hand
    yawed by ψ about the vertical, so ψ = θ + π/2 closes along (cos θ, sin θ)."""
    return pb.getQuaternionFromEuler([np.pi, 0.0, theta + np.pi / 2.0])


class Panda:
    """The arm on ``client`` with its base at the origin (the table's near edge), x forward."""

    def __init__(self, client: int) -> None:
        self.client = client
        with quiet():
            self.body = pb.loadURDF(
                f"{pybullet_data.getDataPath()}/franka_panda/panda.urdf",
                [0, 0, 0],
                useFixedBase=True,
                physicsClientId=client,
            )
        for joint in FINGER_JOINTS:
            # The URDF's soft pads (stiffness 3e4, damping 1e3) with friction anchors jammed the
            # fingers on a tile after a long turn, and their damping held items to an opening
            # finger: stiffer, less damped pads without anchors let go.
            pb.changeDynamics(
                self.body,
                joint,
                lateralFriction=FINGER_FRICTION,
                spinningFriction=FINGER_SPINNING_FRICTION,
                frictionAnchor=0,
                contactStiffness=PAD_STIFFNESS,
                contactDamping=PAD_DAMPING,
                physicsClientId=client,
            )
        # The fingers are geared together as in the real gripper (the URDF's mimic joint, which
        # pybullet ignores): the first finger's motor drives both, and a held item stays centred.
        gear = pb.createConstraint(
            self.body,
            FINGER_JOINTS[0],
            self.body,
            FINGER_JOINTS[1],
            pb.JOINT_GEAR,
            [1, 0, 0],
            [0, 0, 0],
            [0, 0, 0],
            physicsClientId=client,
        )
        pb.changeConstraint(gear, gearRatio=-1, erp=0.1, maxForce=100, physicsClientId=client)
        pb.setJointMotorControl2(self.body, FINGER_JOINTS[1], pb.VELOCITY_CONTROL, force=0.0, physicsClientId=client)
        self.reset(PARK)
        self.fingers_to(FINGER_OPEN)

    # -- joints ---------------------------------------------------------------------------
    def joints(self) -> np.ndarray:
        """The arm's joint angles (7,)."""
        states = pb.getJointStates(self.body, ARM_JOINTS, physicsClientId=self.client)
        return np.array([s[0] for s in states])

    def finger_opening(self) -> float:
        """Distance (m) between the finger pads."""
        states = pb.getJointStates(self.body, FINGER_JOINTS, physicsClientId=self.client)
        return float(states[0][0] + states[1][0])

    def reset(self, q: np.ndarray) -> None:
        """Put the arm at ``q`` (7,) at rest, with its motors holding it there."""
        for joint, angle in zip(ARM_JOINTS, q):
            pb.resetJointState(self.body, joint, float(angle), 0.0, physicsClientId=self.client)
        self.drive(q)

    def drive(self, q: np.ndarray) -> None:
        """Command the arm's joints to ``q`` (7,) by position control."""
        pb.setJointMotorControlArray(
            self.body,
            ARM_JOINTS,
            pb.POSITION_CONTROL,
            targetPositions=list(q),
            forces=list(ARM_FORCES),
            physicsClientId=self.client,
        )

    def fingers_to(self, each: float, force: float = FINGER_FORCE) -> None:
        """Command both fingers to ``each`` m from the middle, pushing with at most ``force`` N."""
        pb.setJointMotorControl2(
            self.body,
            FINGER_JOINTS[0],
            pb.POSITION_CONTROL,
            targetPosition=each,
            force=force,
            maxVelocity=FINGER_SPEED,
            physicsClientId=self.client,
        )

    # -- the hand -------------------------------------------------------------------------
    def hand(self) -> tuple[np.ndarray, float]:
        """The fingertips' point (3,) and the closing-axis angle θ (rad) as they are now."""
        state = pb.getLinkState(self.body, GRASP_LINK, computeForwardKinematics=True, physicsClientId=self.client)
        position = np.array(state[4]) - [0.0, 0.0, TIP_BELOW_GRASP]
        yaw = pb.getEulerFromQuaternion(state[5])[2]
        return position, float(np.arctan2(np.sin(yaw - np.pi / 2.0), np.cos(yaw - np.pi / 2.0)))

    @staticmethod
    def wrist_angle(x: float, y: float, theta: float) -> float:
        """Joint 7's angle (rad) when the hand over (x, y) closes along θ: the arm turns by
        atan2(y, x) at joint 1 and joint 7 turns the hand the other way round."""
        return float(np.pi / 4.0 + np.arctan2(y, x) - (theta + np.pi / 2.0))

    def inverse_kinematics(self, position: np.ndarray, theta: float, refine: bool = False) -> np.ndarray:
        """Joint angles (7,) that put the fingertips at ``position`` (3,) closing along ``theta``,
        from the arm's current joints, with the null space pulled towards :data:`READY` (joint 1
        towards the target, joint 7 towards the wrist angle). That pull makes pybullet's
        solution miss by a few mm; ``refine`` sets the arm there and solves again with the null
        space pulled towards the solution itself (the arm is left at the result)."""
        x, y = float(position[0]), float(position[1])
        rest = READY.copy()
        rest[0] = np.arctan2(y, x)
        rest[6] = np.clip(self.wrist_angle(x, y, theta), LOWER[6], UPPER[6])
        target = (np.asarray(position, float) + [0.0, 0.0, TIP_BELOW_GRASP]).tolist()
        q = self._null_space_ik(target, down_orientation(theta), rest)
        if refine:
            self._set(q)
            q = self._null_space_ik(target, down_orientation(theta), q)
        return q

    def _null_space_ik(self, target: list[float], orientation: tuple, rest: np.ndarray) -> np.ndarray:
        solution = pb.calculateInverseKinematics(
            self.body,
            GRASP_LINK,
            target,
            orientation,
            lowerLimits=[*LOWER, 0.0, 0.0],
            upperLimits=[*UPPER, FINGER_OPEN, FINGER_OPEN],
            jointRanges=[*(UPPER - LOWER), FINGER_OPEN, FINGER_OPEN],
            restPoses=[*rest, 0.0, 0.0],
            maxNumIterations=100,
            residualThreshold=1e-5,
            physicsClientId=self.client,
        )
        return np.clip(np.array(solution[:7]), LOWER, UPPER)

    def plan(self, points: np.ndarray, thetas: np.ndarray, start: np.ndarray) -> tuple[np.ndarray, float, float]:
        """Joint angles (N, 7) along hand poses ``points`` (N, 3), ``thetas`` (N,), each solved
        from the previous one beginning at joints ``start`` (7,), and the largest position (m)
        and angle (rad) errors of the solutions' hands. The arm is left as it was."""
        saved = self.joints()
        self._set(start)
        path, worst_position, worst_angle = [], 0.0, 0.0
        for point, theta in zip(points, thetas):
            q = self.inverse_kinematics(point, float(theta), refine=True)
            self._set(q)
            reached, reached_theta = self.hand()
            turn = np.angle(np.exp(2j * (reached_theta - theta))) / 2.0
            worst_position = max(worst_position, float(np.linalg.norm(reached - point)))
            worst_angle = max(worst_angle, float(abs(turn)))
            path.append(q)
        self._set(saved)
        return np.array(path), worst_position, worst_angle

    def _set(self, q: np.ndarray) -> None:
        for joint, angle in zip(ARM_JOINTS, q):
            pb.resetJointState(self.body, joint, float(angle), physicsClientId=self.client)

    # -- touch ----------------------------------------------------------------------------
    def finger_forces(self, body: int) -> tuple[float, float]:
        """Normal force (N) of the contacts between each finger and ``body``."""
        return tuple(  # type: ignore[return-value]
            float(sum(c[9] for c in pb.getContactPoints(self.body, body, finger, -1, physicsClientId=self.client)))
            for finger in FINGER_JOINTS
        )

    def between_fingers(self, bodies: list[int]) -> int | None:
        """The one of ``bodies`` both fingers touch (the largest squeeze), or None."""
        best, best_force = None, 0.0
        for body in bodies:
            left, right = self.finger_forces(body)
            if left > 0.0 and right > 0.0 and min(left, right) > best_force:
                best, best_force = body, min(left, right)
        return best
