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
from dataclasses import replace

import numpy as np

from vslsp.errors import InputError
from vslsp.outcomes import NoMatch
from vslsp.vsl3d.cloud import voxel_downsample, voxel_downsample_with
from vslsp.vsl3d.fpfh import compute_fpfh
from vslsp.vsl3d.kdtree import KDTree
from vslsp.vsl3d.normals import estimate_normals
from vslsp.vsl3d.parameters import DEFAULT_ALIGNMENT, Alignment
from vslsp.vsl3d.registration import (
    Registration,
    evaluate,
    icp,
    icp_batch,
    ransac_hypotheses,
    sac_ia_hypotheses,
    transform_error,
    transform_points,
)

FEATURE_VOXEL = DEFAULT_ALIGNMENT.feature_voxel  # the default rules' (vslsp.vsl3d.parameters.Alignment)
METHODS = ("prerejective_ransac", "sac_ia", "icp")
MIN_FITNESS = DEFAULT_ALIGNMENT.min_fitness


def describe(
    points: np.ndarray, viewpoint: np.ndarray, voxel: float = FEATURE_VOXEL
) -> tuple[np.ndarray, np.ndarray, KDTree]:
    """The cloud voxelised at ``voxel`` (M, 3), its FPFH descriptors (M, 33) and its tree; the
    ``viewpoint`` the normals face is one (3,) or each point's (N, 3) (a fused cloud's)."""
    if np.ndim(viewpoint) == 2:
        sparse, viewpoint = voxel_downsample_with(points, viewpoint, voxel)
    else:
        sparse = voxel_downsample(points, voxel)
    tree = KDTree(sparse)
    normals = estimate_normals(sparse, 2.5 * voxel, viewpoint, tree)
    return sparse, compute_fpfh(sparse, normals, 5.0 * voxel, tree), tree


def tipping(transform: np.ndarray) -> float:
    """1 - cos of the angle by which ``transform`` (4, 4) tilts the vertical: 0 upright, 1 on
    its side, 2 upside down."""
    return 1.0 - float(transform[2, 2])


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
    source_seen_through: Callable[[np.ndarray], np.ndarray] | None = None,
    target_visible: Callable[[np.ndarray], np.ndarray] | None = None,
    min_fitness: float | None = None,
    refined: int | None = None,
    upright: float = 0.0,
    parameters: Alignment = DEFAULT_ALIGNMENT,
) -> Registration | NoMatch:
    """The rigid transform (in a :class:`Registration`) taking ``source`` (Ns, 3) onto the
    matching part of ``target`` (Nt, 3); the viewpoints orient the normals: one (3,) per cloud,
    or (a fused cloud of several sensors) each point's (Ns, 3) / (Nt, 3).

    ``parameters`` (:class:`~vslsp.vsl3d.parameters.Alignment`) hold its thresholds;
    ``min_fitness`` and ``refined``, when given, override theirs. The global method gives
    ``parameters.hypotheses`` poses, not one: a near-symmetric object or a
    box fits several ways, and the features alone may rank a flipped pose first. With ``turns``
    > 0 (``target`` is the object alone, as in getObject, or a window around it), ICP also
    starts from that many turns about the vertical with the source's centroid put on
    ``target_centre`` (default: the target's centroid). Every pose is scored by the observation:
    its fitness less three times the fraction of the source it puts where the target's sensor
    saw free space (``seen_through(points (N, 3)) -> mask (N,)``) and, when the source's capture
    is known (``source_seen_through``, getObject), three times the fraction of the target it
    puts back where the source's sensor saw free space; with ``upright`` > 0 (the object rests
    as it did), ``upright`` times (1 - cos) of the angle the pose tilts the vertical by is
    subtracted as well. The ``refined`` best distinct poses
    on the sparse clouds are refined on the full resolution and the best scoring one wins. With
    ``target_visible(points (N, 3)) -> mask (N,)`` (the target's capture could see them: in its
    image, not hidden) the fitness counts only against the source points the target's sensor
    could see at the pose, but at least ``parameters.visible_floor`` of them (two single views of a
    turned object, or of one half out of the image, share only part of its surface).
    :class:`NoMatch` (a typed outcome, as 2-D match finding's) when less than ``min_fitness``
    (half) of the source ends within 3 mm of the target, or when there is nothing to align."""
    min_fitness = parameters.min_fitness if min_fitness is None else min_fitness
    refined = parameters.refined if refined is None else refined
    if method not in METHODS:
        raise InputError(f"unknown match-finding method {method!r}; use one of {', '.join(METHODS)}")
    if len(source) < 10 or len(target) < 10:
        return NoMatch(
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
        find, name = (
            (ransac_hypotheses, "prerejective-ransac")
            if method == "prerejective_ransac"
            else (sac_ia_hypotheses, "sac-ia")
        )
        hypotheses = find(
            sparse_source,
            sparse_target,
            source_features,
            target_features,
            1.5 * voxel,
            keep=parameters.hypotheses,
            seed=seed,
            target_tree=sparse_tree,
        )
        if isinstance(hypotheses, NoMatch):
            if not turns:  # the turned starts below are the only other poses
                return hypotheses
        else:
            starts.extend((transform, name) for transform in hypotheses)
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

    def floating(transform: np.ndarray, points: np.ndarray, back: np.ndarray) -> float:
        """The penalty of a pose: the free space of the source ``points`` moved into the target's
        capture and of the target points ``back`` moved into the source's, and its tilt."""
        penalty = upright * tipping(transform) / parameters.floating_weight
        if seen_through is not None:
            penalty += float(seen_through(transform_points(transform, points)).mean())
        if source_seen_through is not None:
            penalty += float(source_seen_through(transform_points(np.linalg.inv(transform), back)).mean())
        return parameters.floating_weight * penalty

    scored = sorted(
        (
            (
                evaluate(sparse_source, sparse_tree, transform, 1.5 * voxel)[0]
                - floating(transform, sparse_source, sparse_target),
                index,
            )
            for index, (transform, _) in enumerate(starts)
        ),
        reverse=True,
    )
    centre = sparse_source.mean(axis=0)
    best_starts: list[tuple[np.ndarray, str]] = []
    for _, index in scored:
        transform = starts[index][0]
        if all(not _same_pose(transform, kept, centre, parameters) for kept, _ in best_starts):
            best_starts.append(starts[index])
        if len(best_starts) == refined:
            break
    tree = KDTree(target)
    normals = estimate_normals(target, parameters.fine_radius, target_viewpoint, tree).normals

    def score(registration: Registration) -> tuple[float, float]:
        return registration.fitness - floating(registration.transform, source, sparse_target), -registration.rmse

    poses = [
        r
        for initial, name in best_starts
        for r in _refine(source, sparse_source, target, tree, normals, initial, name, voxel, score, parameters)
    ]
    if target_visible is not None:
        poses = [_fitness_of_visible(r, source, tree, target_visible, parameters) for r in poses]
    best = max(poses, key=score, default=None)
    if best is None:
        return NoMatch(f"{best_starts[0][1]} put the observation where the world has no points")
    if best.fitness < min_fitness:
        return NoMatch(
            f"{best.method} fits only {best.fitness:.0%} of the observation within "
            f"{parameters.final_distance * 1000:.0f} mm (needs {min_fitness:.0%}); the object is not "
            "in this world or too little of it is visible"
        )
    return best


def _fitness_of_visible(
    registration: Registration,
    source: np.ndarray,
    tree: KDTree,
    visible: Callable[[np.ndarray], np.ndarray],
    parameters: Alignment,
) -> Registration:
    """``registration`` with its fitness counted against the source points the target's capture
    could see at its pose (at least ``parameters.visible_floor`` of the source)."""
    moved = transform_points(registration.transform, source)
    distance, _ = tree.query(moved, 1, parameters.final_distance)
    inliers = int(np.sum(distance[:, 0] <= parameters.final_distance))
    seen = max(float(np.sum(visible(moved))), parameters.visible_floor * len(source))
    return replace(registration, fitness=min(1.0, inliers / seen))


def _same_pose(first: np.ndarray, second: np.ndarray, at: np.ndarray, parameters: Alignment) -> bool:
    """Whether two poses (4, 4) agree within ``parameters.distinct_m`` at ``at`` (3,) and
    ``parameters.distinct_deg`` of rotation (refining both would find the same pose)."""
    offset, angle = transform_error(first, second, at)
    return offset < parameters.distinct_m and angle < parameters.distinct_deg


def _refine(
    source: np.ndarray,
    sparse_source: np.ndarray,
    target: np.ndarray,
    tree: KDTree,
    normals: np.ndarray,
    initial: np.ndarray,
    name: str,
    voxel: float,
    score: Callable[[Registration], tuple[float, float]],
    parameters: Alignment,
) -> list[Registration]:
    """ICP from ``initial`` onto the full-resolution target (its ``tree`` and ``normals`` (Nt,
    3)), first with the sparse source within 2 voxels, then with the full ``source`` within
    ``parameters.final_distance``: point-to-plane, and when that pose floats (``score``'s penalty) or
    fits less than ``parameters.min_fitness`` point-to-point as well (on a box seen mostly from above
    the top face dominates and point-to-plane slides along it, turning the walls away from their
    counterparts or off the box; point pairs hold the outline). Empty when no target point is
    near."""
    distance, _ = tree.query(transform_points(initial, sparse_source), 1, 4.0 * voxel)
    if np.sum(distance[:, 0] <= 4.0 * voxel) < 10:
        return []
    refined: list[Registration] = []
    for method in ("point_to_plane", "point_to_point"):
        if (
            refined
            and refined[0].fitness >= parameters.min_fitness
            and score(refined[0])[0] >= refined[0].fitness - parameters.floating_weight * parameters.refine_floating
        ):
            break  # the point-to-plane pose fits and does not float: nothing for point pairs to correct
        result = initial
        for points, max_distance, iterations in (
            (sparse_source, 2.0 * voxel, 40),
            (source, parameters.final_distance, 20),
        ):
            result = icp(
                points,
                target,
                result,
                max_distance=max_distance,
                iterations=iterations,
                method=method,
                target_normals=normals,
                target_tree=tree,
            ).transform
        fitness, rmse = evaluate(source, tree, result, parameters.final_distance)
        suffix = "+icp" if method == "point_to_plane" else "+icp-point-to-point"
        refined.append(Registration(result, fitness, rmse, f"{name}{suffix}"))
    return refined
