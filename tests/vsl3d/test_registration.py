"""Kabsch, pre-rejective RANSAC, SAC-IA and ICP recover known rigid transforms of a rendered
object cloud, with sensor-like noise and outliers."""

import re

import numpy as np
import pytest

from vslsp.outcomes import NoMatch
from vslsp.vsl3d.alignment import align, describe
from vslsp.vsl3d.normals import estimate_normals
from vslsp.vsl3d.registration import (
    Registration,
    icp,
    prerejective_ransac,
    rigid_transform,
    sac_ia,
    transform_error,
    transform_points,
)


def _pose(yaw: float, tilt: float, shift) -> np.ndarray:
    cz, sz, cx, sx = np.cos(yaw), np.sin(yaw), np.cos(tilt), np.sin(tilt)
    pose = np.eye(4)
    pose[:3, :3] = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]]) @ np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    pose[:3, 3] = shift
    return pose


@pytest.fixture(scope="module")
def moved_duck(duck_view):
    """The rendered duck, and a copy moved by a known 6-DoF transform, with 1 mm noise and 10%
    outliers scattered around it."""
    points, sensor = duck_view
    truth = _pose(2.1, 0.35, [0.12, -0.25, 0.04])
    rng = np.random.default_rng(7)
    target = transform_points(truth, points) + rng.normal(0, 0.001, points.shape)
    lower, upper = target.min(axis=0) - 0.03, target.max(axis=0) + 0.03
    outliers = rng.uniform(lower, upper, (len(points) // 10, 3))
    return points, np.vstack([target, outliers]), truth, sensor, transform_points(truth, sensor[None])[0]


def test_kabsch_recovers_an_exact_transform():
    rng = np.random.default_rng(0)
    source = rng.normal(size=(30, 3))
    truth = _pose(-0.8, 1.1, [1.0, 2.0, -3.0])
    estimate = rigid_transform(source, transform_points(truth, source))
    np.testing.assert_allclose(estimate, truth, atol=1e-12)


@pytest.mark.parametrize("method", ["prerejective_ransac", "sac_ia"])
def test_global_registration_then_icp_recovers_the_transform(moved_duck, method):
    source, target, truth, sensor, moved_sensor = moved_duck
    result = align(source, target, sensor, moved_sensor, method=method, seed=1)
    assert isinstance(result, Registration), result
    translation, rotation = transform_error(result.transform, truth, source.mean(axis=0))
    assert translation < 0.002 and rotation < 1.0
    assert result.fitness > 0.8 and result.rmse < 0.002
    assert result.method == f"{method.replace('_', '-')}+icp"


def test_the_global_stage_alone_lands_within_icp_reach(moved_duck):
    source, target, truth, sensor, moved_sensor = moved_duck
    sparse_source, source_features, _ = describe(source, sensor)
    sparse_target, target_features, tree = describe(target, moved_sensor)
    coarse = prerejective_ransac(
        sparse_source, sparse_target, source_features, target_features, 0.0075, seed=3, target_tree=tree
    )
    translation, rotation = transform_error(coarse.transform, truth, source.mean(axis=0))
    assert translation < 0.01 and rotation < 8.0
    again = prerejective_ransac(
        sparse_source, sparse_target, source_features, target_features, 0.0075, seed=3, target_tree=tree
    )
    np.testing.assert_array_equal(again.transform, coarse.transform)  # seeded: deterministic
    sac = sac_ia(sparse_source, sparse_target, source_features, target_features, 0.0075, seed=3, target_tree=tree)
    assert transform_error(sac.transform, truth, source.mean(axis=0))[0] < 0.015


@pytest.mark.parametrize("method", ["point_to_point", "point_to_plane"])
def test_icp_converges_from_a_nearby_pose(duck_view, method):
    points, sensor = duck_view
    centre = points.mean(axis=0)
    truth = _pose(0.08, 0.05, [0.006, -0.004, 0.003])  # turned about the duck's centre, then shifted
    truth[:3, 3] += centre - truth[:3, :3] @ centre
    target = transform_points(truth, points)
    normals = estimate_normals(target, 0.006, transform_points(truth, sensor[None])[0]).normals
    result = icp(points, target, max_distance=0.015, method=method, target_normals=normals, iterations=80)
    translation, rotation = transform_error(result.transform, truth, points.mean(axis=0))
    assert translation < 5e-4 and rotation < 0.2
    assert result.fitness > 0.99


def test_registration_fails_clearly_on_an_unrelated_cloud(duck_view):
    points, sensor = duck_view
    u, v = np.meshgrid(np.linspace(0, 0.2, 80), np.linspace(0, 0.2, 80))
    plane = np.column_stack([u.ravel(), v.ravel(), 0.001 * np.sin(40 * u.ravel())])
    found = align(points, plane, sensor, sensor, seed=0)
    assert isinstance(found, NoMatch) and re.search("not in this world|edge test|fits only", found.reason), found
