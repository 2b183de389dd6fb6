"""Depth back-projection, the pass-through filter, voxel-grid centroids and frames."""

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.sim.cloud_scene import SENSOR, CloudScene
from vslsp.vsl3d.cloud import DepthCamera, Frame, pass_through, voxel_downsample


def test_back_projection_inverts_projection():
    camera = DepthCamera.of(SENSOR)
    rng = np.random.default_rng(0)
    depth = rng.uniform(0.4, 1.2, (camera.height, camera.width)).astype(np.float32)
    depth[0, :5] = 0.0  # no return
    points, pixels = camera.back_project(depth)
    assert len(points) == depth.size - 5
    uv, z = camera.project(points)
    rows, cols = np.divmod(pixels, camera.width)
    np.testing.assert_allclose(uv, np.column_stack([cols + 0.5, rows + 0.5]), atol=1e-6)
    np.testing.assert_allclose(z, depth.ravel()[pixels], rtol=1e-6)


def test_rendered_table_lands_on_its_plane_and_objects_on_their_boxes():
    with CloudScene({"duck": (0.5, -0.1, 0.3)}, tray=False) as scene:
        image = scene.capture()
        lower, upper = scene.bounds("duck")
    camera = DepthCamera.of(image.camera)
    points, _ = camera.back_project(image.depth)
    table = points[points[:, 2] < 0.002]
    assert len(table) > 0.8 * len(points)
    assert np.abs(table[:, 2]).max() < 1e-3  # the table top is z = 0
    duck = points[points[:, 2] > 0.003]
    assert len(duck) > 1000
    assert np.all(duck >= lower - 0.002) and np.all(duck <= upper + 0.002)


def test_pass_through_keeps_the_frame():
    points = np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.5], [1.0, 1.0, 1.0], [0.5, 2.0, 0.5]])
    kept = pass_through(points, Frame((0.1, 0.1, 0.1), (1.0, 1.0, 1.0)))
    np.testing.assert_array_equal(kept, points[[1, 2]])


def test_voxel_grid_gives_one_centroid_per_occupied_voxel():
    rng = np.random.default_rng(1)
    cells = np.array([[0, 0, 0], [0, 0, 1], [3, 2, 1]])
    clouds = [cell * 0.01 + rng.uniform(0.0005, 0.0095, (n, 3)) for cell, n in zip(cells, (5, 1, 40))]
    points = np.vstack(clouds)
    centroids = voxel_downsample(points[rng.permutation(len(points))], 0.01)
    expected = np.array([cloud.mean(axis=0) for cloud in clouds])
    order = np.lexsort(centroids.T[::-1])
    np.testing.assert_allclose(centroids[order], expected[np.lexsort(expected.T[::-1])], atol=1e-12)


def test_voxel_grid_thins_a_dense_surface_to_the_leaf_spacing():
    rng = np.random.default_rng(2)
    plane = np.column_stack([rng.uniform(0, 0.1, 50_000), rng.uniform(0, 0.1, 50_000), np.zeros(50_000)])
    sparse = voxel_downsample(plane, 0.002)
    assert 2400 <= len(sparse) <= 2601  # a 50 x 50 grid of 2 mm cells (edge cells may stay empty)


def test_frames_and_bad_input():
    frame = Frame.around(np.array([[0.0, 0.0, 0.0], [0.1, 0.2, 0.3]]), 0.01)
    assert frame.lower == pytest.approx((-0.01, -0.01, -0.01)) and frame.upper == pytest.approx((0.11, 0.21, 0.31))
    assert Frame.from_dict(frame.to_dict()) == frame
    with pytest.raises(InputError, match="lower < upper"):
        Frame((0.0, 0.0, 0.0), (1.0, -1.0, 1.0))
    with pytest.raises(InputError, match=r"\(N, 3\)"):
        voxel_downsample(np.zeros((4, 2)), 0.01)
    with pytest.raises(InputError, match="leaf size"):
        voxel_downsample(np.zeros((4, 3)), 0.0)
    with pytest.raises(InputError, match="depth image"):
        DepthCamera.of(SENSOR).back_project(np.zeros((10, 10)))
