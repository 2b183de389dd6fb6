"""The k-d tree answers exactly what a brute-force search answers."""

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.vsl3d.kdtree import KDTree, brute_force_knn


@pytest.mark.parametrize("n", [1, 7, 33, 1000, 6000])
@pytest.mark.parametrize("leaf_size", [1, 16])
def test_knn_matches_brute_force(n, leaf_size):
    rng = np.random.default_rng(n)
    points = rng.uniform(-1, 1, (n, 3)) * [0.3, 0.2, 0.05]  # flat, like a tabletop cloud
    queries = rng.uniform(-1.2, 1.2, (700, 3)) * [0.3, 0.2, 0.05]
    tree = KDTree(points, leaf_size)
    for k in sorted({1, min(n, 5), min(n, 30)}):
        distance, index = tree.query(queries, k)
        reference, _ = brute_force_knn(points, queries, k)
        np.testing.assert_allclose(distance, reference, atol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(points[index] - queries[:, None], axis=2), distance, atol=1e-12)


def test_radius_search_matches_brute_force_with_duplicates():
    rng = np.random.default_rng(3)
    points = rng.uniform(0, 0.1, (3000, 3))
    points = np.vstack([points, points[:200]])  # exact duplicates
    tree = KDTree(points)
    found = tree.query_radius(points[::7], 0.01)
    expected = np.linalg.norm(points[::7, None] - points[None], axis=2) <= 0.01
    np.testing.assert_array_equal(found.counts(len(points[::7])), expected.sum(axis=1))
    assert np.all(np.diff(found.query) >= 0)
    same_query = np.diff(found.query) == 0
    assert np.all(np.diff(found.distance)[same_query] >= 0)  # nearest first
    assert np.all(expected[found.query, found.index])


def test_radius_search_keeps_the_nearest_when_capped():
    rng = np.random.default_rng(4)
    points = rng.uniform(0, 0.05, (2000, 3))
    tree = KDTree(points)
    capped = tree.query_radius(points[:50], 0.02, max_neighbours=8)
    distance, index = tree.query(points[:50], 8)
    assert np.all(capped.counts(50) == 8)
    np.testing.assert_allclose(capped.distance.reshape(50, 8), distance)


def test_a_point_of_the_tree_finds_itself_first():
    points = np.random.default_rng(5).uniform(0, 1, (500, 3))
    distance, index = KDTree(points).query(points, 2)
    np.testing.assert_array_equal(index[:, 0], np.arange(500))
    assert np.all(distance[:, 0] == 0.0) and np.all(distance[:, 1] > 0.0)


def test_bad_input():
    with pytest.raises(InputError, match="non-empty"):
        KDTree(np.zeros((0, 3)))
    tree = KDTree(np.zeros((5, 3)))
    with pytest.raises(InputError, match="between 1 and the 5 points"):
        tree.query(np.zeros((1, 3)), 6)
    with pytest.raises(InputError, match="radius"):
        tree.query_radius(np.zeros((1, 3)), -1.0)


def test_bounded_knn_reports_only_neighbours_within_the_distance():
    rng = np.random.default_rng(6)
    points = rng.uniform(0, 0.2, (4000, 3))
    queries = rng.uniform(-0.05, 0.25, (800, 3))
    tree = KDTree(points)
    distance, index = tree.query(queries, 3, max_distance=0.01)
    reference, reference_index = brute_force_knn(points, queries, 3)
    near = reference <= 0.01
    np.testing.assert_allclose(distance[near], reference[near])
    np.testing.assert_array_equal(index[near], reference_index[near])
    assert np.all(np.isinf(distance[~near])) and np.all(index[~near] == -1)


def test_large_batches_are_answered_in_chunks_like_small_ones():
    rng = np.random.default_rng(8)
    points = rng.uniform(0, 0.1, (1500, 3))
    queries = rng.uniform(0, 0.1, (9000, 3))  # more than one chunk of queries
    tree = KDTree(points)
    distance, index = tree.query(queries, 4)
    reference, _ = brute_force_knn(points, queries, 4)
    np.testing.assert_allclose(distance, reference)
    found = tree.query_radius(queries, 0.008)
    expected = (np.linalg.norm(queries[:, None] - points[None], axis=2) <= 0.008).sum(axis=1)
    np.testing.assert_array_equal(found.counts(len(queries)), expected)
    assert np.all(np.diff(found.query) >= 0)
