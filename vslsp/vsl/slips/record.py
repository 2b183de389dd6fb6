"""Recording an operation the tutor slipped in (issue 30: the tutor's slips), the rules the
2-D recorder follows beyond :func:`~vslsp.vsl.slips.restore.separate`'s meant post observation:
when the restored observation still does not record (:func:`record_meant`), and what was put on
an object a slip had nudged (:func:`on_nudged`)."""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.vision.features import extract_features
from vslsp.vsl.recorder import Heights, Recorder
from vslsp.vsl.slips.detect import Moves, keypoint_area
from vslsp.vsl.slips.restore import only_arrival


def record_meant(recorder: Recorder, observations: tuple, heights: Heights, moves: Moves | None):
    """The operation recorded from its pre-pick, meant post-place and pre-place
    ``observations``. The rule: a slip's nudge can push a neighbour a little (a domino turned
    against the next one, a shift too small to be a move of its own), a change that the restore
    leaves beside the operated item's arrival and that widens its changed region. When the
    arrival then does not match the operated item's features, every change outside the operated
    item's own pixels (its keypoints' hull where it arrived, and a rim) is taken for the slip's
    and restored from the pre-place observation (:func:`~vslsp.vsl.slips.restore.only_arrival`;
    the case is pinned in tests/vsl/test_stacked_slips.py). Raises InputError when the operation still
    cannot be recorded."""
    pre_pick, post, pre_place = observations
    try:
        return recorder.record(pre_pick, post, pre_place, heights)
    except InputError:
        if moves is None or moves.operated is None or not moves.disturbed:
            raise
        return recorder.record(pre_pick, only_arrival(pre_place, post, moves.operated), pre_place, heights)


def on_nudged(recorder: Recorder, operation, moves: Moves, nudged: list[np.ndarray]) -> list[np.ndarray]:
    """Mind what was put on an item the tutor's slip had nudged. The rule: an item put on a
    nudged one lies where it lies on it, so its place is found by the item below (that item's
    features in the pre-place observation, matched as the pick matches its object; the frame
    reported that item's size), not by the wider frame whose surroundings the slip no longer
    agrees with (the Tower of Hanoi's disk put on a disk nudged off its base's centre, which the
    new world has centred). ``nudged``: the keypoints (N, 2) px of the items
    disturbed so far, where the slips left them; an item stays nudged until the tutor takes it
    (a third of its keypoints where the operated item was seen); the operation's own disturbed
    items join. Sets the last recorded operation's frame; returns the items nudged now."""
    below = [points for points in nudged if _inside(operation.place_point, points)]
    if below:
        side = max(float(np.ptp(points, axis=0).max()) for points in below)
        features = extract_features(operation.pre_place, keypoint_area(operation.pre_place.shape, below))
        recorder.operations[-1] = replace(operation, place_frame=side, place_features=features)
    taken = moves.operated.keypoints_before if moves.operated is not None else np.zeros((0, 2))
    kept = [points for points in nudged if not _same_item(points, taken)]
    return kept + [obj.keypoints_after for obj in moves.disturbed]


def _inside(point: tuple[float, float], points: np.ndarray) -> bool:
    """Whether ``point`` (px) lies in the convex hull of ``points`` (N, 2) px."""
    hull = cv2.convexHull(np.asarray(points, np.float32))
    return cv2.pointPolygonTest(hull, (float(point[0]), float(point[1])), False) >= 0


def _same_item(points: np.ndarray, taken: np.ndarray, near: float = 3.0) -> bool:
    """Whether a third of ``points`` (N, 2) px lie within ``near`` px of ``taken`` (M, 2): the
    nudged item is the one the tutor took."""
    if not len(points) or not len(taken):
        return False
    gaps = np.min(np.hypot(*(points[:, None, :] - taken[None, :, :]).transpose(2, 0, 1)), axis=1)
    return bool(np.mean(gaps <= near) >= 1.0 / 3.0)
