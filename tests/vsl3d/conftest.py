"""Shared inputs of the VSL-3D tests: rendered clouds of real meshes from the RGB-D scene."""

import numpy as np
import pytest

from vslsp.sim.cloud_scene import CloudScene
from vslsp.vsl3d.cloud import DepthCamera, Frame, voxel_downsample

WORKSPACE = Frame((0.25, -0.40, 0.006), (0.90, 0.40, 0.40))  # above the table top, around the tray


@pytest.fixture(scope="session")
def duck_view() -> tuple[np.ndarray, np.ndarray]:
    """The duck as the sensor sees it (2 mm voxels, (N, 3)) and the sensor's position (3,)."""
    with CloudScene({"duck": (0.5, 0.0, 0.7)}, tray=False) as scene:
        image = scene.capture()
    camera = DepthCamera.of(image.camera)
    points, _ = camera.back_project(image.depth)
    return voxel_downsample(points[WORKSPACE.contains(points)], 0.002), camera.position
