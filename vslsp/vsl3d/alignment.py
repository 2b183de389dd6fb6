"""Coarse-to-fine alignment of an observation onto a cloud: the 3D match finding of VSL-3D
(paper, section "VSL-3D", "Point Cloud Processing", and the "Match finding" row of Table "VSL
vs VSL-3D": voxelizing, normal/curvature estimation, 3D features, ICP/RANSAC/SAC-IA).

Both clouds are voxelised at ``voxel`` (5 mm: features need neighbourhoods of some tens of
points), given normals (radius 2.5 voxels) and FPFH descriptors (radius 5 voxels); a global
method finds the pose (pre-rejective RANSAC, SAC-IA, or for "icp" none: the centroids are
put on each other), and point-to-plane ICP refines it on the full-resolution points.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from vslsp.errors import InputError, TaskFailed
from vslsp.vsl3d.cloud import Frame, voxel_downsample
from vslsp.vsl3d.fpfh import compute_fpfh
from vslsp.vsl3d.kdtree import KDTree
from vslsp.vsl3d.normals import estimate_normals
from vslsp.vsl3d.registration import (
    Registration,
    evaluate,
    icp,
    icp_batch,
    prerejective_ransac,
    sac_ia,
    transform_points,
)

FEATURE_VOXEL = 0.005
METHODS = ("prerejective_ransac", "sac_ia", "icp")
FINE_RADIUS = 0.006  # normals of the full-resolution target, for point-to-plane ICP
FINAL_DISTANCE = 0.003  # inlier distance of the last ICP round and of the reported fitness
MIN_FITNESS = 0.5
MAX_SEEN_THROUGH = 0.1  # a true pose floats in front of the sensor's surfaces only at its rim
# A point in free space is evidence against a pose (the sensor saw through it); a point without a
# counterpart may just be a side the other view does not show. The former weighs three times.
FLOATING_WEIGHT = 3.0


def describe(
    points: np.ndarray, viewpoint: np.ndarray, voxel: float = FEATURE_VOXEL
) -> tuple[np.ndarray, np.ndarray, KDTree]:
    """The cloud voxelised at ``voxel`` (M, 3), its FPFH descriptors (M, 33) and its tree."""
    sparse = voxel_downsample(points, voxel)
    tree = KDTree(sparse)
    normals = estimate_normals(sparse, 2.5 * voxel, viewpoint, tree)
    return sparse, compute_fpfh(sparse, normals, 5.0 * voxel, tree), tree


def _turned_starts(source: np.ndarray, target_centre: np.ndarray, turns: int) -> list[np.ndarray]:
    """``turns`` poses (4, 4) that turn ``source`` about the vertical through its centroid by
    multiples of 360/turns degrees and put its centroid on ``target_centre`` (3,): the starts of
    a multi-start ICP for objects resting on a table (mostly turned about z)."""
    source_centre = source.mean(axis=0)
    starts = []
    for angle in np.arange(turns) * 2.0 * np.pi / turns:
        pose = np.eye(4)
        pose[:2, :2] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
        pose[:3, 3] = target_centre - pose[:3, :3] @ source_centre
        starts.append(pose)
    return starts


def align(
    source: np.ndarray,
    target: np.ndarray,
    source_viewpoint: np.ndarray,
    target_viewpoint: np.ndarray,
    *,
    method: str = "prerejective_ransac",
    voxel: float = FEATURE_VOXEL,
    seed: int = 0,
    turns: int = 0,
    target_centre: np.ndarray | None = None,
    seen_through: Callable[[np.ndarray], np.ndarray] | None = None,
    min_fitness: float = MIN_FITNESS,
) -> Registration:
    """The rigid transform (in a :class:`Registration`) taking ``source`` (Ns, 3) onto the
    matching part of ``target`` (Nt, 3); the viewpoints (3,) orient the normals.

    With ``turns`` > 0 (``target`` is the object alone, as in getObject, or a window around it),
    ICP also starts from that many turns about the vertical with the source's centroid put on
    ``target_centre`` (default: the target's centroid): a fallback when the features of a
    view-changed object correspond poorly. ``seen_through(points (N, 3)) -> mask (N,)`` marks
    points where the target's sensor saw free space; a pose's score is its fitness less three
    times the fraction of the source it puts there. The three best starts on the sparse clouds
    are refined on the full resolution and the best scoring pose wins. Raises
    :class:`TaskFailed` when less than ``min_fitness`` (half) of the source ends within 3 mm of
    the target."""
    if method not in METHODS:
        raise InputError(f"unknown match-finding method {method!r}; use one of {', '.join(METHODS)}")
    if len(source) < 10 or len(target) < 10:
        raise TaskFailed(
            f"too few points to align ({len(source)} onto {len(target)}); "
            "is the object inside the workspace and in view?"
        )
    sparse_source, sparse_target = voxel_downsample(source, voxel), voxel_downsample(target, voxel)
    sparse_tree = KDTree(sparse_target)
    starts: list[tuple[np.ndarray, str]] = []
    if method == "icp":
        starts.append((_turned_starts(source, target.mean(axis=0), 1)[0], "centroids"))
    else:
        sparse_source, source_features, _ = describe(source, source_viewpoint, voxel)
        sparse_target, target_features, sparse_tree = describe(target, target_viewpoint, voxel)
        find = prerejective_ransac if method == "prerejective_ransac" else sac_ia
        try:
            coarse = find(
                sparse_source,
                sparse_target,
                source_features,
                target_features,
                1.5 * voxel,
                seed=seed,
                target_tree=sparse_tree,
            )
            starts.append((coarse.transform, coarse.method))
        except TaskFailed:
            if not turns:
                raise
    if turns:
        centre = target.mean(axis=0) if target_centre is None else np.asarray(target_centre, dtype=float)
        turned = icp_batch(
            sparse_source,
            sparse_target,
            np.stack(_turned_starts(source, centre, turns)),
            max_distance=3.0 * voxel,
            target_tree=sparse_tree,
        )
        starts.extend((transform, "multi-start-icp") for transform in turned)

    def floating(transform: np.ndarray, points: np.ndarray) -> float:
        if seen_through is None:
            return 0.0
        return FLOATING_WEIGHT * float(seen_through(transform_points(transform, points)).mean())

    def sparse_score(start: tuple[np.ndarray, str]) -> float:
        return evaluate(sparse_source, sparse_tree, start[0], 1.5 * voxel)[0] - floating(start[0], sparse_source)

    best_starts = sorted(starts, key=sparse_score, reverse=True)[:3]
    refined = [
        r
        for r in (_refine(source, target, target_viewpoint, initial, name, voxel) for initial, name in best_starts)
        if r is not None
    ]
    best = max(refined, key=lambda r: (r.fitness - floating(r.transform, source), -r.rmse), default=None)
    if best is None:
        raise TaskFailed(f"{best_starts[0][1]} put the observation where the world has no points")
    if best.fitness < min_fitness:
        raise TaskFailed(
            f"{best.method} fits only {best.fitness:.0%} of the observation within "
            f"{FINAL_DISTANCE * 1000:.0f} mm (needs {min_fitness:.0%}); the object is not "
            "in this world or too little of it is visible"
        )
    return best


def _refine(
    source: np.ndarray, target: np.ndarray, target_viewpoint: np.ndarray, initial: np.ndarray, name: str, voxel: float
) -> Registration | None:
    """Point-to-plane ICP from ``initial`` on the full-resolution target near it (None when no
    target point is near)."""
    near = Frame.around(transform_points(initial, source), 4.0 * voxel).contains(target)
    if near.sum() < 10:
        return None
    fine = target[near]
    tree = KDTree(fine)
    normals = estimate_normals(fine, FINE_RADIUS, target_viewpoint, tree).normals
    result = icp(source, fine, initial, max_distance=2.0 * voxel, target_normals=normals, target_tree=tree)
    result = icp(source, fine, result.transform, max_distance=FINAL_DISTANCE, target_normals=normals, target_tree=tree)
    fitness, rmse = evaluate(source, tree, result.transform, FINAL_DISTANCE)
    return Registration(result.transform, fitness, rmse, f"{name}+icp")
