"""PCA normals face the viewpoint and measure curvature."""

import numpy as np

from vslsp.vsl3d.normals import estimate_normals


def _grid(n: int = 60, spacing: float = 0.002) -> np.ndarray:
    u, v = np.meshgrid(np.arange(n) * spacing, np.arange(n) * spacing)
    return np.column_stack([u.ravel(), v.ravel(), np.zeros(u.size)])


def test_a_plane_has_the_plane_normal_towards_the_viewpoint_and_no_curvature():
    plane = _grid()
    up = estimate_normals(plane, 0.006, viewpoint=np.array([0.05, 0.05, 1.0]))
    np.testing.assert_allclose(up.normals, np.tile([0.0, 0.0, 1.0], (len(plane), 1)), atol=1e-9)
    assert np.all(up.curvature < 1e-12)
    down = estimate_normals(plane, 0.006, viewpoint=np.array([0.05, 0.05, -1.0]))
    np.testing.assert_allclose(down.normals[:, 2], -1.0)


def test_a_tilted_plane_seen_from_above():
    rotation = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(0.5), -np.sin(0.5)], [0.0, np.sin(0.5), np.cos(0.5)]])
    plane = _grid() @ rotation.T
    normals = estimate_normals(plane, 0.006, viewpoint=np.array([0.0, 0.0, 2.0])).normals
    np.testing.assert_allclose(normals, np.tile(rotation[:, 2], (len(plane), 1)), atol=1e-9)


def test_a_sphere_has_radial_normals_and_curvature_growing_with_the_radius_ratio():
    rng = np.random.default_rng(0)
    directions = rng.normal(size=(8000, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    sphere = 0.05 * directions
    inside = estimate_normals(sphere, 0.01, viewpoint=np.zeros(3))  # seen from the centre
    assert np.all(np.einsum("ij,ij->i", inside.normals, -directions) > 0.99)
    small = estimate_normals(sphere, 0.01, viewpoint=np.zeros(3), max_neighbours=1000).curvature
    large = estimate_normals(sphere, 0.02, viewpoint=np.zeros(3), max_neighbours=1000).curvature
    assert 0.0 < np.median(small) < np.median(large) < 1.0 / 3.0


def test_rendered_duck_normals_face_the_sensor(duck_view):
    points, sensor = duck_view
    result = estimate_normals(points, 0.006, sensor)
    assert result.valid.mean() > 0.99
    towards = np.einsum("ij,ij->i", result.normals, sensor - points)
    assert np.all(towards[result.valid] >= 0.0)


def test_isolated_points_get_no_normal():
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    result = estimate_normals(points, 0.1, viewpoint=np.array([0.0, 0.0, 1.0]))
    assert not result.valid.any() and np.all(result.normals == 0.0)
