"""The scripted tutor: a person who moves objects, and who guides the robot's hand.

(a) For VSL demonstrations the tutor relocates a cube as a hand would (lift, carry, put
down); the robot sees only the scene before and after. (b) For kinesthetic teaching the tutor
guides the robot's hand along human-like paths: minimum-jerk segments through via-points
(Flash and Hogan 1985), varied timing and a little tremor; the hand's own trajectory is
recorded from the simulation at 240 Hz.
"""

from __future__ import annotations

import numpy as np

from vslsp.errors import InputError
from vslsp.sim.quiet import quiet
from vslsp.sim.scene import TABLE_Z

with quiet():
    import pybullet as pb


def minimum_jerk(via_points: np.ndarray, durations: np.ndarray, rate: float = 240.0) -> tuple[np.ndarray, np.ndarray]:
    """Minimum-jerk segments through via-points (K, 3), each taking ``durations[k]`` s.

    Returns t (T,) and positions (T, 3); velocity and acceleration are zero at every via-point.
    """
    via_points = np.asarray(via_points, dtype=float)
    times, positions = [np.zeros(1)], [via_points[:1]]
    start = 0.0
    for k, duration in enumerate(durations):
        n = max(2, int(round(duration * rate)))
        s = np.linspace(0.0, 1.0, n + 1)[1:]
        blend = 10 * s**3 - 15 * s**4 + 6 * s**5
        positions.append(via_points[k] + np.outer(blend, via_points[k + 1] - via_points[k]))
        times.append(start + s * duration)
        start += duration
    return np.concatenate(times), np.vstack(positions)


class Tutor:
    """The human of the demonstrations, scripted."""

    def __init__(self, world) -> None:
        self.world = world

    def relocate(self, name: str, x: float, y: float, yaw: float | None = None, lift: float = 0.08) -> None:
        """Pick the cube up, carry it along an arc and put it down at (x, y) (yaw kept if None)."""
        world = self.world
        if name not in world.cubes:
            raise InputError(f"no cube named {name!r}; the scene has {sorted(world.cubes)}")
        body = world.cubes[name]
        x0, y0, yaw0 = world.cube_pose(name)
        yaw = yaw0 if yaw is None else yaw
        size = world.spec.cube(name).size
        steps = 60
        for s in np.linspace(0.0, 1.0, steps):
            blend = 10 * s**3 - 15 * s**4 + 6 * s**5
            position = [
                x0 + blend * (x - x0),
                y0 + blend * (y - y0),
                TABLE_Z + size / 2 + 0.002 + lift * np.sin(np.pi * s),
            ]
            orientation = pb.getQuaternionFromEuler([0.0, 0.0, yaw0 + blend * (yaw - yaw0)])
            pb.resetBasePositionAndOrientation(body, position, orientation, physicsClientId=world.client)
            pb.resetBaseVelocity(body, [0, 0, 0], [0, 0, 0], physicsClientId=world.client)
            world.step()
        world.settle()

    def kinesthetic(
        self, via_points: np.ndarray, duration: float, seed: int = 0, tremor: float = 0.0005, yaw: float | None = None
    ):
        """Guide the hand through via-points (K, 3) in about ``duration`` s; record it.

        Timing is shared among segments by length, varied by ±15% per segment; a smooth
        tremor (standard deviation ``tremor`` m, ~8 Hz) is added between the via-points.
        Returns the recorded :class:`~vslsp.sim.robot.HandTrajectory` (240 Hz).
        """
        robot = self.world.robot
        if robot is None:
            raise InputError("kinesthetic teaching needs the robot: build the LineWorld with robot=True")
        rng = np.random.default_rng(seed)
        via_points = np.asarray(via_points, dtype=float)
        lengths = np.linalg.norm(np.diff(via_points, axis=0), axis=1) + 1e-3
        durations = duration * lengths / lengths.sum() * rng.uniform(0.85, 1.15, size=len(lengths))
        t, path = minimum_jerk(via_points, durations)
        path = path + _tremor(t, tremor, rng)
        # Bring the hand to the start first (not recorded), then follow the timed path.
        orientation = {} if yaw is None else {"yaw": yaw}
        robot.move_hand(path[:1], **orientation)
        return robot.move_hand(path[1:], record=True, timed=t[1:] - t[0], **orientation)


def _tremor(t: np.ndarray, amplitude: float, rng: np.random.Generator) -> np.ndarray:
    """Smooth physiological tremor (T, 3), zero at both ends of the movement."""
    if amplitude <= 0:
        return np.zeros((len(t), 3))
    phase = rng.uniform(0, 2 * np.pi, size=3)
    frequency = rng.uniform(6.0, 10.0, size=3)
    envelope = np.sin(np.pi * (t - t[0]) / max(t[-1] - t[0], 1e-9))[:, None]
    return amplitude * envelope * np.sin(2 * np.pi * frequency[None, :] * t[:, None] + phase[None, :])
