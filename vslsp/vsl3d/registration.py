"""3D match finding and pose estimation (paper, section "VSL-3D": "The match finding and pose
estimation process ... utilizing three different algorithms consisting of Iterative Closest
Point (ICP), Pre-rejective RANSAC (Buch et al. 2013), and SAmple Consensus Initial Alignment
(SAC-IA) (Rusu et al. 2009)"; Table "VSL vs VSL-3D": a 3D-to-3D 4x4 transformation).

- Correspondences: each source point's most similar target points in FPFH space.
- Pre-rejective RANSAC: three sampled correspondences are rejected before any pose is computed
  unless the triangles they span in source and target have similar edges (each edge ratio
  ``min/max >= similarity``); the survivors' poses (Kabsch) are ranked by their inlier
  fraction on a fixed subset of the source points (a target point within ``max_distance``),
  and the best few are validated on the whole source.
- SAC-IA: three source points at least ``min_sample_distance`` apart, each paired with one of
  its ``k`` most similar target points at random; the pose with the smallest Huber-penalised
  nearest-neighbour error wins.
- ICP: point-to-point (Besl and McKay 1992, Kabsch per step) and point-to-plane (Chen and
  Medioni 1992, linearised in the rotation) over nearest neighbours closer than a distance.

All randomness comes from a seeded ``numpy.random.Generator``: the same seed, the same pose.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.errors import TaskFailed
from vslsp.outcomes import NoMatch
from vslsp.vsl3d.kdtree import KDTree


@dataclass(frozen=True, eq=False)
class Registration:
    """A rigid ``transform`` (4, 4) taking source points onto the target; ``fitness`` is the
    fraction of source points with a target point within the inlier distance, ``rmse`` their
    root-mean-square distance (m)."""

    transform: np.ndarray
    fitness: float
    rmse: float
    method: str

    def apply(self, points: np.ndarray) -> np.ndarray:
        """The points (N, 3) moved by the transform."""
        return transform_points(self.transform, points)


def transform_points(transform: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Apply a 4x4 rigid transform to points (N, 3)."""
    return np.asarray(points, dtype=float) @ transform[:3, :3].T + transform[:3, 3]


def transform_error(estimate: np.ndarray, truth: np.ndarray, at: np.ndarray) -> tuple[float, float]:
    """How far two 4x4 transforms disagree: the distance (m) between where they take the point
    ``at`` (3,) and the angle (deg) of the rotation between them."""
    relative = estimate[:3, :3] @ truth[:3, :3].T
    angle = np.degrees(np.arccos(np.clip((np.trace(relative) - 1.0) / 2.0, -1.0, 1.0)))
    gap = transform_points(estimate, np.asarray(at)[None]) - transform_points(truth, np.asarray(at)[None])
    return float(np.linalg.norm(gap)), float(angle)


def rigid_transform(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The least-squares rigid transform (4, 4) taking ``source`` (N, 3) onto ``target`` (N, 3)
    (Kabsch: SVD of the cross-covariance, reflections excluded)."""
    return _kabsch(source[None], target[None])[0]


def _kabsch(source: np.ndarray, target: np.ndarray, weights: np.ndarray | None = None) -> np.ndarray:
    """Batched (weighted) Kabsch: sources and targets (B, N, 3), weights (B, N) (default all
    1) to transforms (B, 4, 4)."""
    weights = np.ones(source.shape[:2]) if weights is None else weights
    total = np.maximum(weights.sum(axis=1), 1e-12)[:, None, None]
    source_mean = np.einsum("bn,bni->bi", weights, source)[:, None] / total
    target_mean = np.einsum("bn,bni->bi", weights, target)[:, None] / total
    covariance = np.einsum("bn,bni,bnj->bij", weights, source - source_mean, target - target_mean)
    u, _, vt = np.linalg.svd(covariance)
    sign = np.sign(np.linalg.det(np.einsum("bij,bjk->bik", vt.transpose(0, 2, 1), u.transpose(0, 2, 1))))
    sign[sign == 0] = 1.0
    fix = np.ones((len(source), 3))
    fix[:, 2] = sign
    rotation = np.einsum("bji,bj,bkj->bik", vt, fix, u)
    transform = np.tile(np.eye(4), (len(source), 1, 1))
    transform[:, :3, :3] = rotation
    transform[:, :3, 3] = target_mean[:, 0] - np.einsum("bij,bj->bi", rotation, source_mean[:, 0])
    return transform


def evaluate(
    source: np.ndarray, target_tree: KDTree, transform: np.ndarray, max_distance: float
) -> tuple[float, float]:
    """(fitness, inlier RMSE) of ``transform`` moving ``source`` (N, 3) onto the tree's cloud."""
    distance, _ = target_tree.query(transform_points(transform, source), 1, max_distance)
    inlier = distance[:, 0] <= max_distance
    rmse = float(np.sqrt(np.mean(distance[inlier, 0] ** 2))) if inlier.any() else float("inf")
    return float(inlier.mean()), rmse


def feature_neighbours(source_features: np.ndarray, target_features: np.ndarray, k: int = 1) -> np.ndarray:
    """Indices (Ns, k) of each source descriptor's ``k`` nearest target descriptors (Euclidean
    in feature space), nearest first."""
    k = min(k, len(target_features))
    target_sq = np.einsum("ij,ij->i", target_features, target_features)
    result = np.empty((len(source_features), k), dtype=np.int64)
    step = max(1, 4_000_000 // max(len(target_features), 1))
    for begin in range(0, len(source_features), step):
        chunk = source_features[begin : begin + step]
        d2 = target_sq[None, :] - 2.0 * chunk @ target_features.T
        nearest = np.argpartition(d2, k - 1, axis=1)[:, :k] if k < d2.shape[1] else np.argsort(d2, axis=1)
        order = np.argsort(np.take_along_axis(d2, nearest, axis=1), axis=1)
        result[begin : begin + len(chunk)] = np.take_along_axis(nearest, order, axis=1)
    return result


def _move(transforms: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Points (N, 3) moved by each of the transforms (B, 4, 4): (B, N, 3)."""
    return np.einsum("bij,nj->bni", transforms[:, :3, :3], points) + transforms[:, None, :3, 3]


def _sample_triples(
    rng: np.random.Generator, n_source: int, candidates: np.ndarray, count: int
) -> tuple[np.ndarray, np.ndarray]:
    """``count`` triples of distinct source indices (count, 3) and, for each, one of its
    candidate target indices at random (count, 3)."""
    source = rng.integers(0, n_source, (count, 3))
    distinct = (source[:, 0] != source[:, 1]) & (source[:, 1] != source[:, 2]) & (source[:, 0] != source[:, 2])
    source = source[distinct]
    pick = rng.integers(0, candidates.shape[1], source.shape)
    return source, candidates[source, pick]


def _edges(points: np.ndarray) -> np.ndarray:
    """The three edge lengths (B, 3) of triangles (B, 3, 3)."""
    return np.linalg.norm(points - points[:, [1, 2, 0]], axis=2)


def prerejective_ransac(
    source: np.ndarray,
    target: np.ndarray,
    source_features: np.ndarray,
    target_features: np.ndarray,
    max_distance: float,
    *,
    iterations: int = 20000,
    similarity: float = 0.9,
    correspondences: int = 3,
    validate: int = 20,
    screening_points: int = 100,
    min_fitness: float = 0.25,
    seed: int = 0,
    target_tree: KDTree | None = None,
) -> Registration:
    """Pre-rejective RANSAC (Buch et al. 2013) from ``source`` (Ns, 3) to ``target`` (Nt, 3)
    with their FPFH descriptors. Raises :class:`TaskFailed` when no pose puts at least
    ``min_fitness`` of the source within ``max_distance`` of the target."""
    tree = target_tree if target_tree is not None else KDTree(target)
    transforms = ransac_hypotheses(
        source,
        target,
        source_features,
        target_features,
        max_distance,
        iterations=iterations,
        similarity=similarity,
        correspondences=correspondences,
        keep=validate,
        screening_points=screening_points,
        seed=seed,
        target_tree=tree,
    )
    if isinstance(transforms, NoMatch):
        raise TaskFailed(transforms.reason)
    return _best_by_fitness(source, tree, transforms, max_distance, min_fitness, "prerejective-ransac")


def ransac_hypotheses(
    source: np.ndarray,
    target: np.ndarray,
    source_features: np.ndarray,
    target_features: np.ndarray,
    max_distance: float,
    *,
    iterations: int = 20000,
    similarity: float = 0.9,
    correspondences: int = 3,
    keep: int = 20,
    screening_points: int = 100,
    seed: int = 0,
    target_tree: KDTree | None = None,
) -> np.ndarray | NoMatch:
    """Pre-rejective RANSAC's ``keep`` best hypotheses (K, 4, 4), best first by their inlier
    count on a fixed subset of ``screening_points`` source points (Buch's inlier fraction).
    :class:`NoMatch` when no sampled triangle passes the edge test."""
    rng = np.random.default_rng(seed)
    tree = target_tree if target_tree is not None else KDTree(target)
    candidates = feature_neighbours(source_features, target_features, correspondences)
    picked_source, picked_target = _sample_triples(rng, len(source), candidates, iterations)
    source_edges, target_edges = _edges(source[picked_source]), _edges(target[picked_target])
    ratio = np.minimum(source_edges, target_edges) / np.maximum(np.maximum(source_edges, target_edges), 1e-12)
    alike = np.all(ratio >= similarity, axis=1) & np.all(source_edges >= 2.0 * max_distance, axis=1)
    if not alike.any():
        return NoMatch(
            "pre-rejective RANSAC: no sampled correspondences passed the edge test; "
            "the observation and the world share no similar geometry"
        )
    transforms = _kabsch(source[picked_source[alike]], target[picked_target[alike]])
    subset = source[rng.choice(len(source), min(screening_points, len(source)), replace=False)]
    inliers = np.concatenate(
        [
            np.sum(
                tree.query(_move(transforms[begin : begin + 512], subset).reshape(-1, 3), 1, max_distance)[0].reshape(
                    -1, len(subset)
                )
                <= max_distance,
                axis=1,
            )
            for begin in range(0, len(transforms), 512)
        ]
    )
    return transforms[np.argsort(-inliers, kind="stable")[:keep]]


def sac_ia(
    source: np.ndarray,
    target: np.ndarray,
    source_features: np.ndarray,
    target_features: np.ndarray,
    max_distance: float,
    *,
    min_sample_distance: float = 0.02,
    iterations: int = 1000,
    correspondences: int = 3,
    evaluation_points: int = 200,
    min_fitness: float = 0.25,
    seed: int = 0,
    target_tree: KDTree | None = None,
) -> Registration:
    """SAC-IA (Rusu et al. 2009) from ``source`` (Ns, 3) to ``target`` (Nt, 3) with their FPFH
    descriptors: the hypothesis with the smallest Huber-penalised error over a fixed random
    subset of ``evaluation_points`` source points wins."""
    tree = target_tree if target_tree is not None else KDTree(target)
    transforms = sac_ia_hypotheses(
        source,
        target,
        source_features,
        target_features,
        max_distance,
        min_sample_distance=min_sample_distance,
        iterations=iterations,
        correspondences=correspondences,
        evaluation_points=evaluation_points,
        keep=1,
        seed=seed,
        target_tree=tree,
    )
    if isinstance(transforms, NoMatch):
        raise TaskFailed(transforms.reason)
    return _best_by_fitness(source, tree, transforms, max_distance, min_fitness, "sac-ia")


def sac_ia_hypotheses(
    source: np.ndarray,
    target: np.ndarray,
    source_features: np.ndarray,
    target_features: np.ndarray,
    max_distance: float,
    *,
    min_sample_distance: float = 0.02,
    iterations: int = 1000,
    correspondences: int = 3,
    evaluation_points: int = 200,
    keep: int = 20,
    seed: int = 0,
    target_tree: KDTree | None = None,
) -> np.ndarray | NoMatch:
    """SAC-IA's ``keep`` best hypotheses (K, 4, 4), smallest Huber-penalised error first;
    :class:`NoMatch` when no three source points lie ``min_sample_distance`` apart."""
    rng = np.random.default_rng(seed)
    tree = target_tree if target_tree is not None else KDTree(target)
    candidates = feature_neighbours(source_features, target_features, correspondences)
    picked_source, picked_target = _sample_triples(rng, len(source), candidates, iterations * 4)
    spread = np.all(_edges(source[picked_source]) >= min_sample_distance, axis=1)
    picked_source, picked_target = picked_source[spread][:iterations], picked_target[spread][:iterations]
    if len(picked_source) == 0:
        return NoMatch(
            f"SAC-IA: no three source points lie {min_sample_distance} m apart; "
            "lower min_sample_distance or use a larger observation"
        )
    transforms = _kabsch(source[picked_source], target[picked_target])
    subset = source[rng.choice(len(source), min(evaluation_points, len(source)), replace=False)]
    distance, _ = tree.query(_move(transforms, subset).reshape(-1, 3), 1)
    distance = distance.reshape(len(transforms), len(subset))
    huber = np.where(distance <= max_distance, 0.5 * distance**2, max_distance * (distance - 0.5 * max_distance))
    return transforms[np.argsort(huber.sum(axis=1), kind="stable")[:keep]]


def _best_by_fitness(
    source: np.ndarray, tree: KDTree, transforms: np.ndarray, max_distance: float, min_fitness: float, method: str
) -> Registration:
    scored = [(*evaluate(source, tree, transform, max_distance), index) for index, transform in enumerate(transforms)]
    fitness, rmse, index = max(scored, key=lambda item: (item[0], -item[1]))
    if fitness < min_fitness:
        raise TaskFailed(
            f"{method}: the best pose fits only {fitness:.0%} of the observation within "
            f"{max_distance * 1000:.0f} mm (needs {min_fitness:.0%}); the object is not in this world "
            "or too little of it is visible"
        )
    return Registration(transforms[index], fitness, rmse, method)


def icp(
    source: np.ndarray,
    target: np.ndarray,
    initial: np.ndarray | None = None,
    *,
    max_distance: float = 0.01,
    iterations: int = 50,
    method: str = "point_to_plane",
    target_normals: np.ndarray | None = None,
    tolerance: float = 1e-6,
    target_tree: KDTree | None = None,
) -> Registration:
    """Refine ``initial`` (4, 4; identity if None) by ICP from ``source`` (Ns, 3) to ``target``
    (Nt, 3): ``method`` "point_to_point" or "point_to_plane" (needs ``target_normals`` (Nt, 3)).
    Pairs farther apart than ``max_distance`` are ignored."""
    if method not in ("point_to_point", "point_to_plane"):
        raise ValueError(f"ICP method must be point_to_point or point_to_plane, got {method!r}")
    if method == "point_to_plane" and target_normals is None:
        raise ValueError("point-to-plane ICP needs the target's normals")
    tree = target_tree if target_tree is not None else KDTree(target)
    transform = np.eye(4) if initial is None else np.array(initial, dtype=float)
    previous = np.inf
    for _ in range(iterations):
        moved = transform_points(transform, source)
        distance, index = tree.query(moved, 1, max_distance)
        inlier = distance[:, 0] <= max_distance
        if inlier.sum() < 6:
            break
        error = float(np.sqrt(np.mean(distance[inlier, 0] ** 2)))
        matched = target[index[inlier, 0]]
        if method == "point_to_point":
            step = rigid_transform(moved[inlier], matched)
        else:
            assert target_normals is not None  # checked above
            step = _point_to_plane_step(moved[inlier], matched, target_normals[index[inlier, 0]])
        transform = step @ transform
        if abs(previous - error) < tolerance:
            break
        previous = error
    fitness, rmse = evaluate(source, tree, transform, max_distance)
    return Registration(transform, fitness, rmse, f"icp-{method.replace('_', '-')}")


def icp_batch(
    source: np.ndarray,
    target: np.ndarray,
    starts: np.ndarray,
    *,
    max_distance: float,
    iterations: int = 30,
    target_tree: KDTree | None = None,
) -> np.ndarray:
    """Point-to-point ICP from each of ``starts`` (B, 4, 4) at once (one tree query per
    iteration for all of them): the refined transforms (B, 4, 4)."""
    tree = target_tree if target_tree is not None else KDTree(target)
    transforms = np.array(starts, dtype=float)
    for _ in range(iterations):
        moved = _move(transforms, source)
        distance, index = tree.query(moved.reshape(-1, 3), 1, max_distance)
        inlier = (distance[:, 0] <= max_distance).reshape(len(transforms), len(source))
        matched = target[np.where(index[:, 0] >= 0, index[:, 0], 0)].reshape(moved.shape)
        steps = _kabsch(moved, matched, inlier.astype(float))
        steps[inlier.sum(axis=1) < 6] = np.eye(4)
        transforms = np.einsum("bij,bjk->bik", steps, transforms)
        if np.allclose(steps, np.eye(4), atol=1e-7):
            break
    return transforms


def _point_to_plane_step(source: np.ndarray, target: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """One linearised point-to-plane step: minimise Σ ((R s + t - q) · n)^2 with R ≈ I + [r]x,
    about the source's centroid (so that turning does not swing far points about the origin)."""
    centre = source.mean(axis=0)
    source, target = source - centre, target - centre
    a = np.hstack([np.cross(source, normals), normals])
    b = np.einsum("ij,ij->i", target - source, normals)
    # The 6x6 normal equations, lightly damped: a direction the planes do not constrain (sliding
    # along a plane) gets no step, as least squares' minimum-norm solution would give it.
    normal = a.T @ a
    x = np.linalg.solve(normal + 1e-9 * max(float(np.trace(normal)), 1e-12) * np.eye(6), a.T @ b)
    angle = np.linalg.norm(x[:3])
    rotation = np.eye(3)
    if angle > 0.0:
        axis = x[:3] / angle
        k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
        rotation = np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * k @ k
    step = np.eye(4)
    step[:3, :3] = rotation
    step[:3, 3] = x[3:] + centre - rotation @ centre
    return step
