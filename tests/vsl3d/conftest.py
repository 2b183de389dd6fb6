"""Shared inputs of the VSL-3D tests: rendered clouds of real meshes from the RGB-D scene."""

import numpy as np
import pytest
from helpers.vsl3d import WORKSPACE

from vslsp.sim.cloud_scene import CloudScene
from vslsp.vsl3d.cloud import DepthCamera, voxel_downsample


@pytest.fixture(scope="session")
def duck_view() -> tuple[np.ndarray, np.ndarray]:
    """The duck as the sensor sees it (2 mm voxels, (N, 3)) and the sensor's position (3,)."""
    with CloudScene({"duck": (0.5, 0.0, 0.7)}, tray=False) as scene:
        image = scene.capture()
    camera = DepthCamera.of(image.camera)
    points, _ = camera.back_project(image.depth)
    return voxel_downsample(points[WORKSPACE.contains(points)], 0.002), camera.position
