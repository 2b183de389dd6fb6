"""Every object that moved in one demonstrated operation, and which one the operation was about
(issue 30: the tutor's slips; the paper's own limit, "if the tutor accidentally moves one object
while operating another, the algorithm may fail").

The changed points of an operation (:func:`~vslsp.vsl3d.vsl.changed_points`, both ways: what
left the pre-action cloud and what arrived in the post-action cloud) are identified with the
objects they belong to by segmenting the *union* of the two clouds (Euclidean clustering,
:data:`SEGMENT_GAP`): an object's place before and its place after are one segment of the union
exactly when they overlap or touch. So each union segment that carries at least
:data:`~vslsp.vsl3d.vsl.MIN_CLUSTER_POINTS` changed points is one moved object, or one end of a
move:

- a segment with points that left and points that arrived is an object that moved *within its
  own place* (a nudge of a few centimetres leaves its old and new places overlapping, and its
  changes are the crescents at its rim);
- a segment with only points that left is a place an object left; one with only points that
  arrived, a place an object came to.

The rule for the operated object: the tutor's operation carries an object from its place to
another (into the box, onto a landmark, in front of the box: places apart), so the operated
object is the one that left its place empty (a departure-only segment of which at least
:data:`EMPTIED` of the points left) and arrived at an empty place (an arrival-only segment of
which at least :data:`EMPTIED` of the points are new) or, where it joined what stood there (the
box, a landmark), where the most new points are; every other moved object was disturbed: it moved within
its own place, or a slide of a centimetre changed one side of it only (its rim left, nothing
new beyond the threshold; its place keeps most of its points). Any other combination (two
objects carried off, nothing carried off, an object that left the view) is not one operation
plus disturbances and is refused as before.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from vslsp.errors import TaskFailed
from vslsp.stages import in_stage
from vslsp.vsl3d.vsl import (
    CHANGE_THRESHOLD,
    CLUSTER_DISTANCE,
    DISTURBED,
    MIN_CLUSTER_POINTS,
    OPERATED,
    Move,
    MovedObject,
    WorldCloud,
    changed_points,
    euclidean_clusters,
    get_object,
    moved_object,
)

__all__ = ["MIN_SIDE_POINTS", "SEGMENT_GAP", "detect_moves", "get_operated_object"]

# Points of the union of the pre- and post-action clouds closer than this are one object (or one
# object before and after a nudge): wider than the 2 mm voxels' gaps on a surface seen at a slant,
# narrower than the 3.5 cm the tutor's nudge keeps between objects.
SEGMENT_GAP = 0.008
# A side (left or arrived) of a segment counts with at least this many changed points (1.6 cm^2
# of 2 mm voxels); fewer are the rim of an object that settled a little differently.
MIN_SIDE_POINTS = 40
# An object carried away leaves its place empty: at least this share of the points its segment had
# before left (a nudged object's segment keeps most of its points: only its rim changed); one
# carried to an empty place fills it: at least this share of its segment's points are new.
EMPTIED = 0.5
SEVERAL = "several objects moved"


@in_stage("perception")
def get_operated_object(
    pre: WorldCloud,
    post: WorldCloud,
    *,
    detect: bool = True,
    threshold: float = CHANGE_THRESHOLD,
    min_points: int = MIN_CLUSTER_POINTS,
    method: str = "prerejective_ransac",
    seed: int = 0,
) -> MovedObject:
    """``getObject`` with the slip detection (``detect``): the object the operation was about,
    with every object that moved in its ``moves`` (the operated one first). Where one object left
    one place and arrived at another, this is :func:`~vslsp.vsl3d.vsl.get_object` (its result,
    the same records); where more changed, :func:`detect_moves` tells the operated object from
    those disturbed, and the observations and the motion are the operated object's alone.
    Without ``detect`` (the paper's VSL) it is :func:`~vslsp.vsl3d.vsl.get_object`: the whole
    difference is the object, and several moved objects are refused."""
    try:
        moved = get_object(pre, post, threshold=threshold, min_points=min_points, method=method, seed=seed)
    except TaskFailed as error:
        if not detect or error.cause != SEVERAL:
            raise
    else:
        operated = Move(moved.pre.points, moved.post.points, moved.pre.points, moved.post.points, OPERATED)
        return replace(moved, moves=(operated,))
    left, arrived = changed_points(post, pre, threshold), changed_points(pre, post, threshold)
    moves = detect_moves(pre, post, left, arrived, min_points)
    moved = moved_object(pre, post, moves[0].left, moves[0].arrived, method=method, seed=seed)
    return replace(moved, moves=moves)


def detect_moves(
    pre: WorldCloud,
    post: WorldCloud,
    left: np.ndarray,
    arrived: np.ndarray,
    min_points: int = MIN_CLUSTER_POINTS,
) -> tuple[Move, ...]:
    """Every object that moved between ``pre`` and ``post``, the operated one first, then those
    disturbed (farthest first), from the masks of ``pre``'s points that ``left`` (N,) and
    ``post``'s that ``arrived`` (M,) (the module's rule). Raises :class:`TaskFailed` when the
    changes are not one operation and disturbances (the message says what moved where)."""
    points = np.vstack([pre.points, post.points])
    is_post = np.r_[np.zeros(len(pre.points), dtype=bool), np.ones(len(post.points), dtype=bool)]
    changed = np.r_[left, arrived]
    labels = objects(points, changed)
    departures, arrivals, in_place = [], [], []
    for label in np.unique(labels[changed]):
        segment = labels == label
        gone, came = segment & changed & ~is_post, segment & changed & is_post
        if gone.sum() + came.sum() < min_points:
            continue
        move = Move(points[gone], points[came], points[segment & ~is_post], points[segment & is_post], DISTURBED)
        if gone.sum() >= MIN_SIDE_POINTS and came.sum() >= MIN_SIDE_POINTS:
            in_place.append(move)
        elif gone.sum() >= MIN_SIDE_POINTS:
            departures.append(move)
        elif came.sum() >= MIN_SIDE_POINTS:
            arrivals.append(move)
    # A nudge may change one side only (a centimetre's slide: its rim left, nothing new beyond the
    # threshold): the place an object was carried from is the one it left empty (most of its
    # points gone); the place it was carried to, the one it filled (most of its points new) or,
    # where it joined what stood there (the box, a landmark), the one with the most new points.
    departures.sort(key=lambda m: -len(m.left) / len(m.before))
    arrivals.sort(key=lambda m: -len(m.arrived))
    carried = [m for m in departures if len(m.left) >= EMPTIED * len(m.before)]
    filled = [m for m in arrivals if len(m.arrived) >= EMPTIED * len(m.after)]
    if len(carried) != 1 or not arrivals or len(filled) > 1:
        where = "; ".join(
            [f"left {_centre(m.left)}" for m in departures]
            + [f"arrived {_centre(m.arrived)}" for m in arrivals]
            + [f"moved in its place {_centre(m.after)}" for m in in_place]
        )
        raise TaskFailed(
            f"{SEVERAL} ({where}) and no one of them was carried from its place to another while "
            "the rest were only nudged in theirs; VSL-3D learns one object carried per operation",
            cause=SEVERAL,
        )
    arrival = (filled or arrivals)[0]
    operated = Move(carried[0].left, arrival.arrived, carried[0].left, arrival.arrived, OPERATED)
    others = [*in_place, *departures[1:], *(m for m in arrivals if m is not arrival)]
    return (operated, *sorted(others, key=lambda m: -m.shift))


def objects(points: np.ndarray, changed: np.ndarray) -> np.ndarray:
    """Labels (N,) of ``points`` (the union of both clouds) by object: segments of the union
    (:data:`SEGMENT_GAP`), joined where one region of ``changed`` points (Euclidean clusters at
    :data:`~vslsp.vsl3d.vsl.CLUSTER_DISTANCE`, as getObject's) spans several (a duck's head seen
    apart from its body: a self-occlusion gap)."""
    segments = euclidean_clusters(points, SEGMENT_GAP)
    regions = euclidean_clusters(points[changed], CLUSTER_DISTANCE)
    count = int(segments.max()) + 1 if len(segments) else 0
    nodes = count + (int(regions.max()) + 1 if len(regions) else 0)
    edges = coo_matrix((np.ones(len(regions)), (segments[changed], count + regions)), shape=(nodes, nodes))
    _, component = connected_components(edges, directed=False)
    return component[segments]


def _centre(points: np.ndarray) -> str:
    x, y, z = points.mean(axis=0)
    return f"at ({x:.3f}, {y:.3f}, {z:.3f}) m"
