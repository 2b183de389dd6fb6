"""``findBestMatch`` of VSL-3D (paper, Algorithm 1, lines 13-14; section "VSL-3D": "each
captured world observation after being voxelized is compared with the corresponding recorded
observations in the dictionaries and a metric is applied to find the best match").

The recorded observation is first aligned with the whole world (FPFH correspondences, a global
method, point-to-plane ICP). A match must fit (half of the observation within 3 mm of the
world) and must not float: a true pose puts almost no point where the sensor sees free space
(it saw a surface behind the point). When the global alignment fails those tests, or fits less
than ``confident_fitness`` once a tipped pose's penalty is taken off (a look-alike: the flat
box's top face on the other box; a box upside down), the match is searched window by window
("window search", the paper's other metric): the world is split into object-sized clusters
above the support surfaces, and the observation is aligned with each window from several turns
about the vertical; the best verified fit wins. The rules' figures are a
:class:`~vslsp.vsl3d.parameters.CloudMatching`.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from vslsp.errors import InputError
from vslsp.outcomes import NoMatch
from vslsp.vsl3d.alignment import METHODS, align, tipping
from vslsp.vsl3d.cloud import Frame
from vslsp.vsl3d.parameters import DEFAULT_CLOUD_MATCHING, CloudMatching
from vslsp.vsl3d.registration import Registration, transform_points
from vslsp.vsl3d.vsl import CloudObservation, WorldCloud, euclidean_clusters


@dataclass(frozen=True, eq=False)
class CloudMatch:
    """Where a recorded observation is in a new world: ``registration`` (observation -> world)
    and the observation's points moved there, ``points`` (N, 3), in their new ``frame``."""

    registration: Registration
    points: np.ndarray
    frame: Frame

    @property
    def position(self) -> np.ndarray:
        """Where the object's centroid is now (3,)."""
        return self.points.mean(axis=0)


def find_best_match(
    world: WorldCloud,
    observation: CloudObservation,
    *,
    method: str = "prerejective_ransac",
    seed: int = 0,
    parameters: CloudMatching = DEFAULT_CLOUD_MATCHING,
) -> CloudMatch | NoMatch:
    """Find ``observation`` in ``world`` and its pose there by the rules ``parameters``: the
    :class:`CloudMatch`, or :class:`NoMatch` (why) when no verified pose puts enough of the
    observation onto the world, as 2-D match finding (:func:`vslsp.vision.matching.find_best_match`)."""
    if len(observation.points) < 10:
        raise InputError(f"the observation has {len(observation.points)} points; record one of a visible object")
    if method not in METHODS:
        raise InputError(f"unknown match-finding method {method!r}; use one of {', '.join(METHODS)}")
    best: CloudMatch | None = None
    registration = align(
        observation.points,
        world.points,
        observation.viewpoint,
        world.viewpoint,
        method=method,
        seed=seed,
        seen_through=world.seen_through,
        upright=parameters.upright_weight,
    )
    found = _verified(world, observation, registration, parameters)
    if isinstance(found, NoMatch):
        global_failure = found.reason
    else:
        best = found
        if plausibility(best, parameters) >= parameters.confident_fitness:
            return best
        global_failure = f"the best global match fits only {best.registration.fitness:.0%}"
    # A window's match replaces a verified global one only when it fits clearly better (the
    # duckling's view fits the teddy's side about as well as the turned duckling itself).
    bar = -np.inf if best is None else plausibility(best, parameters) + parameters.clearly_better
    windows = 0
    for window, centre in object_windows(world.points, observation.points, parameters):
        windows += 1
        registration = align(
            observation.points,
            world.points[window],
            observation.viewpoint,
            world.viewpoint_of(window),
            method=method,
            seed=seed,
            turns=parameters.turns,
            target_centre=centre,
            seen_through=world.seen_through,
            upright=parameters.upright_weight,
        )
        match = _verified(world, observation, registration, parameters)
        if not isinstance(match, NoMatch) and plausibility(match, parameters) > bar:
            best, bar = match, plausibility(match, parameters)
    if best is None:
        return NoMatch(f"{global_failure}; nor in any of {windows} object-sized windows of the world")
    return best


def plausibility(match: CloudMatch, parameters: CloudMatching = DEFAULT_CLOUD_MATCHING) -> float:
    """The ``match``'s fitness less the tilt's penalty (``parameters.upright_weight``): how
    matches compare."""
    return match.registration.fitness - parameters.upright_weight * tipping(match.registration.transform)


def object_windows(
    points: np.ndarray, observation: np.ndarray, parameters: CloudMatching = DEFAULT_CLOUD_MATCHING
) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """The mask (N,) of the world's points around each object-sized cluster above the support
    surfaces, with the cluster's centroid (3,): clusters of at least a fifth of the observation's points
    and at most 2.5 times its extent (a box around objects is not a window)."""
    lifted = points[points[:, 2] > points[:, 2].min() + parameters.support_clearance]
    if len(lifted) == 0:
        return
    labels = euclidean_clusters(lifted, parameters.window_gap)
    extent = np.linalg.norm(observation.max(axis=0) - observation.min(axis=0))
    for label in range(labels.max() + 1):
        cluster = lifted[labels == label]
        if len(cluster) < 0.2 * len(observation):
            break  # labels run from the largest cluster down
        if np.linalg.norm(cluster.max(axis=0) - cluster.min(axis=0)) > 2.5 * extent:
            continue
        window = Frame.around(cluster, parameters.window_margin)
        yield window.contains(points), cluster.mean(axis=0)


def _verified(
    world: WorldCloud, observation: CloudObservation, registration: Registration | NoMatch, parameters: CloudMatching
) -> CloudMatch | NoMatch:
    """The match of ``registration``, unless it puts the observation where the sensor saw free space."""
    if isinstance(registration, NoMatch):
        return registration
    moved = transform_points(registration.transform, observation.points)
    floating = float(world.seen_through(moved).mean())
    if floating > parameters.max_seen_through:
        return NoMatch(
            f"the best match ({registration.method}, fitness {registration.fitness:.0%}) puts "
            f"{floating:.0%} of the observation where the sensor sees free space; the object "
            "is not in this world or too little of it is visible"
        )
    return CloudMatch(registration, moved, Frame.around(moved, parameters.frame_margin))
