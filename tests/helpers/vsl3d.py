"""The VSL-3D tests' shared scene and checks: the tutor's layout of real meshes, the workspace
above the table, a world captured from the RGB-D scene, a tutor's demonstration and the
tolerances of a recovered motion."""

from __future__ import annotations

import numpy as np

from vslsp.sim.cloud_scene import CloudScene
from vslsp.vsl3d.cloud import DepthCamera, Frame
from vslsp.vsl3d.vsl import WorldCloud

WORKSPACE = Frame((0.25, -0.40, 0.006), (0.90, 0.40, 0.40))  # above the table top, around the tray
LAYOUT = {"duck": (0.42, -0.17, 0.4), "teddy": (0.62, -0.16, -0.5), "mug": (0.40, 0.03, 2.4), "blob": (0.66, 0.0, 1.0)}
TOLERANCE_M, TOLERANCE_DEG = 0.005, 3.0


def world(scene: CloudScene) -> WorldCloud:
    image = scene.capture()
    return WorldCloud.capture(image.depth, DepthCamera.of(image.camera), WORKSPACE)


def _centre(scene: CloudScene, name: str) -> np.ndarray:
    lower, upper = scene.bounds(name)
    return (lower + upper) / 2.0


def demonstrate(
    scene: CloudScene,
    name: str,
    x: float,
    y: float,
    yaw: float,
    roll: float = 0.0,
    pitch: float = 0.0,
    into_tray: bool = False,
):
    """The tutor moves ``name``; returns the pre and post worlds, the true motion (4, 4) and the
    object's centre before the move."""
    pre = world(scene)
    before, centre = scene.pose(name), _centre(scene, name)
    support = scene.surface_height(x, y) if into_tray else 0.0
    scene.tutor_move(name, scene.resting_pose(name, x, y, yaw, roll, pitch, support))
    return pre, world(scene), scene.pose(name) @ np.linalg.inv(before), centre


def assert_within_bounds(points: np.ndarray, scene: CloudScene, name: str) -> None:
    lower, upper = scene.bounds(name)
    inside = np.all((points >= lower - 0.003) & (points <= upper + 0.003), axis=1)
    assert inside.mean() > 0.98
