"""The post observation the tutor meant (issue 30: the tutor's slips): the objects that moved in
one demonstrated operation (:func:`vslsp.vsl.slips.detect.find_moved`) and the post observation with
the disturbed objects restored, so that VSL records the operation as if only the operated object
had moved (see :mod:`vslsp.vsl.slips` for the rules)."""

from __future__ import annotations

import cv2
import numpy as np

from vslsp.vsl.slips.detect import MIN_REGION, MovedObject, Moves, changes_between, find_moved, keypoint_area


def separate(pre: np.ndarray, post: np.ndarray, pre_place: np.ndarray | None = None) -> tuple[Moves, np.ndarray]:
    """The objects that moved between ``pre`` and ``post`` (H, W, 3) uint8 (the operated one
    lacking in ``pre_place``, when given) and the post observation the tutor meant (H, W, 3):
    the disturbed objects' changed pixels restored from the world before the slip. That is the
    pre-place observation when given (the operated object already taken from its place, so a
    disturbed object it lay on is restored without it), else the pre one. A changed pixel
    (between that observation and ``post``) is a disturbed object's when its changed region
    holds a disturbed object's identified keypoints (where it was or where it is) and, of all
    the moved objects' keypoints (the operated object's where it arrived, with the pre-place
    observation), the nearest is a disturbed object's."""
    moves = find_moved(pre, post, pre_place)
    if not moves.disturbed:
        return moves, post
    source = pre if pre_place is None else pre_place
    changed = cv2.dilate(changes_between(source, post), np.ones((5, 5), np.uint8))
    _, regions = cv2.connectedComponents(changed)
    seeds = {}
    operated: list[np.ndarray] = []
    if moves.operated is not None:  # with the pre-place observation it changed where it arrived only
        operated = [moves.operated.keypoints_after]
        if pre_place is None:
            operated.append(moves.operated.keypoints_before)
    disturbed = [points for obj in moves.disturbed for points in (obj.keypoints_before, obj.keypoints_after)]
    for key, points in (("operated", operated), ("disturbed", disturbed)):
        xy = np.round(np.vstack(points).reshape(-1, 2) if points else np.zeros((0, 2))).astype(int)
        inside = (xy[:, 0] >= 0) & (xy[:, 1] >= 0) & (xy[:, 0] < changed.shape[1]) & (xy[:, 1] < changed.shape[0])
        seeds[key] = xy[inside]
    # Only the changed regions the disturbed objects' keypoints lie in; in one shared with the
    # operated object, the pixels nearer to a disturbed object's keypoint.
    touched = np.isin(regions, regions[seeds["disturbed"][:, 1], seeds["disturbed"][:, 0]]) & (regions > 0)
    restore = touched
    if len(seeds["operated"]):
        distance = {}
        for key, xy in seeds.items():
            image = np.full(changed.shape, 255, np.uint8)
            image[xy[:, 1], xy[:, 0]] = 0
            distance[key] = cv2.distanceTransform(image, cv2.DIST_L2, 5)
        restore = touched & (distance["disturbed"] < distance["operated"])
    meant = post.copy()
    meant[restore] = source[restore]
    if moves.operated is None and pre_place is not None and not _put_down(pre_place, meant):
        # The operated object not identified (its look alike in part to others', as dominoes'
        # are) and its arrival in a changed region with a disturbed object's, restoring the
        # regions whole erased the arrival: only the disturbed objects' own pixels are restored
        # (the hulls of their keypoints before and after, and a rim).
        own = keypoint_area(
            changed.shape, [p for obj in moves.disturbed for p in (obj.keypoints_before, obj.keypoints_after)]
        )
        restore = touched & (own > 0)
        meant = post.copy()
        meant[restore] = source[restore]
    return moves, meant


def _put_down(pre_place: np.ndarray, post: np.ndarray) -> bool:
    """Whether ``post`` shows something put down that ``pre_place`` lacks (a changed region of
    at least :data:`MIN_REGION` px)."""
    count, _, stats, _ = cv2.connectedComponentsWithStats(changes_between(pre_place, post))
    return any(stats[k, cv2.CC_STAT_AREA] >= MIN_REGION for k in range(1, count))


def only_arrival(pre_place: np.ndarray, post: np.ndarray, operated: MovedObject) -> np.ndarray:
    """``post`` (H, W, 3) with every pixel outside the ``operated`` object's own (the hull of its
    keypoints where it arrived, and a rim) taken from ``pre_place``: the post observation in
    which only the operated object's arrival changed (see
    :func:`vslsp.vsl.slips.record.record_meant` for when)."""
    own = keypoint_area(post.shape, [operated.keypoints_after]) > 0
    meant = pre_place.copy()
    meant[own] = post[own]
    return meant
