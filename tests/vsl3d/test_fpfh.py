"""FPFH (Rusu 2009): pair features, invariance under rigid motion, and what they tell apart."""

import numpy as np

from vslsp.vsl3d.fpfh import BINS, compute_fpfh, pair_features
from vslsp.vsl3d.normals import estimate_normals


def _rotation(seed: int) -> np.ndarray:
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def test_pair_features_of_known_pairs():
    up = np.array([[0.0, 0.0, 1.0]])
    # Two points side by side on a plane: normals parallel, line perpendicular to them.
    flat = pair_features(np.zeros((1, 3)), up, np.array([[1.0, 0.0, 0.0]]), up)
    np.testing.assert_allclose(flat, [[0.0, 0.0, 0.0]], atol=1e-12)
    # The source normal leans towards the target by a: phi = sin a, theta = -a, alpha = 0.
    a = 0.3
    leaning = pair_features(np.zeros((1, 3)), np.array([[np.sin(a), 0.0, np.cos(a)]]), np.array([[1.0, 0.0, 0.0]]), up)
    np.testing.assert_allclose(leaning, [[0.0, np.sin(a), -a]], atol=1e-12)
    # The features do not depend on which point of the pair is the query.
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=(50, 3)), rng.normal(size=(50, 3))
    na, nb = (v / np.linalg.norm(v, axis=1, keepdims=True) for v in rng.normal(size=(2, 50, 3)))
    np.testing.assert_allclose(pair_features(a, na, b, nb), pair_features(b, nb, a, na), atol=1e-9)


def test_fpfh_is_invariant_under_a_rigid_transform(duck_view):
    points, sensor = duck_view
    rotation, shift = _rotation(1), np.array([0.3, -0.2, 0.1])
    moved, moved_sensor = points @ rotation.T + shift, rotation @ sensor + shift
    normals = estimate_normals(points, 0.006, sensor)
    features = compute_fpfh(points, normals, 0.012)
    moved_features = compute_fpfh(moved, estimate_normals(moved, 0.006, moved_sensor), 0.012)
    assert features.shape == (len(points), 3 * BINS)
    sums = features.reshape(-1, 3, BINS).sum(axis=2)
    described = sums[:, 0] > 0.0  # a stray pixel or two has no neighbour within the radius
    assert described.mean() > 0.99
    np.testing.assert_allclose(sums[described], 200.0)  # the point's SPFH and its neighbours', 100 each
    difference = np.abs(features - moved_features).sum(axis=1)
    assert np.median(difference) < 1e-6  # bins may flip only for features on a bin edge
    # A normal seen edge-on (at a grazing angle to the sensor) has no defined side: the last
    # rounding bit of the motion may flip it, and with it the FPFH of every point within two
    # radii (SPFH of the point, then FPFH of its neighbours). Elsewhere the descriptor holds.
    view = sensor - points
    grazing = np.abs(np.sum(normals.normals * view, axis=1)) < 0.05 * np.linalg.norm(view, axis=1)
    near_grazing = np.linalg.norm(points[:, None] - points[grazing][None], axis=2).min(axis=1, initial=np.inf)
    defined = near_grazing > 2 * 0.012
    assert defined.mean() > 0.5
    assert np.mean(difference[defined] < 1e-3) > 0.99


def test_fpfh_tells_a_plane_from_a_sphere_and_an_edge():
    u, v = np.meshgrid(np.arange(40) * 0.002, np.arange(40) * 0.002)
    plane = np.column_stack([u.ravel(), v.ravel(), np.zeros(u.size)])
    edge = np.vstack([plane, np.column_stack([u.ravel(), np.zeros(u.size), v.ravel()])])
    rng = np.random.default_rng(2)
    directions = rng.normal(size=(6000, 3))
    sphere = 0.03 * directions / np.linalg.norm(directions, axis=1, keepdims=True)
    viewpoint = np.array([0.5, 0.5, 1.0])

    def centre_feature(cloud, where):
        fpfh = compute_fpfh(cloud, estimate_normals(cloud, 0.006, viewpoint), 0.012)
        return fpfh[np.argmin(np.linalg.norm(cloud - where, axis=1))]

    flat = centre_feature(plane, [0.04, 0.04, 0.0])
    round_ = centre_feature(sphere, [0.0, 0.0, 0.03])
    crease = centre_feature(edge, [0.04, 0.0, 0.0])
    assert flat[BINS // 2] > 90 and flat[BINS + BINS // 2] > 90  # alpha, phi ~ 0 on a plane
    assert np.abs(flat - round_).sum() > 50 and np.abs(flat - crease).sum() > 50


def test_points_without_neighbours_get_zero_descriptors():
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    normals = estimate_normals(points, 0.1, np.array([0.0, 0.0, 5.0]))
    assert not compute_fpfh(points, normals, 0.1).any()
