"""Every object that moved between a pre- and a post-action observation (issue 30: the tutor
slips and disturbs another object while operating one).

The same image subtraction and thresholding as :func:`vslsp.vision.change.detect_change` (gain
correction, smoothing, the threshold, the opening, an object moved when a tenth of its region
changed; one hidden or revealed by a moved object, still in place in the other image, did not
move), but any number of objects may move: each region that left in the pre image is paired with
the region of the same symbol (its colour) that arrived in the post image, the nearest first.
Which of them the operation was about is the grounding's question
(:func:`vslsp.grounding.moves.ground_moves`).
"""

from __future__ import annotations

import numpy as np

from vslsp.errors import GroundingFailed, InputError
from vslsp.vision.change import Change, change_mask, moved_labels
from vslsp.vision.image import as_rgb
from vslsp.vision.objects import DetectedObject, Segmentation, describe, segment


def detect_moves(pre: np.ndarray, post: np.ndarray) -> list[Change]:
    """Every object moved between RGB images ``pre`` and ``post`` (H, W, 3) uint8, left to
    right by its pre-action place; one :class:`~vslsp.vision.change.Change` each.

    Raises InputError when the images differ in size; GroundingFailed when nothing moved or a
    moved object is seen in one image only (it left the view, or came into it).
    """
    pre, post = as_rgb(pre, "pre-action image"), as_rgb(post, "post-action image")
    if pre.shape != post.shape:
        raise InputError(
            f"the images differ in size: pre-action {pre.shape[1]}x{pre.shape[0]}, post-action "
            f"{post.shape[1]}x{post.shape[0]}; take both with the same camera and resolution"
        )
    seg_pre, seg_post = segment(pre), segment(post)
    changed = change_mask(seg_pre, seg_post)
    left = [describe(seg_pre, label) for label in moved_labels(seg_pre, changed)]
    arrived = [describe(seg_post, label) for label in moved_labels(seg_post, changed)]
    # As detect_change: changed in one image only and in place in the other is hidden or revealed.
    left = [o for o in left if any(a.name == o.name for a in arrived) or not in_place(o, seg_post)]
    arrived = [o for o in arrived if any(a.name == o.name for a in left) or not in_place(o, seg_pre)]
    if not left and not arrived:
        raise GroundingFailed(
            "nothing moved between the pre- and the post-action image; give the images taken "
            "just before and just after the tutor's operation"
        )
    changes = []
    waiting = list(arrived)
    for before in sorted(left, key=lambda o: o.centroid):
        same = [a for a in waiting if a.name == before.name]
        if not same:
            raise GroundingFailed(
                f"the {before.name} object at {_at(before)} in the pre-action image is not wholly in "
                "view in the post-action image; keep every object inside the camera's view"
            )
        after = min(same, key=lambda a: float(np.hypot(*np.subtract(a.centroid, before.centroid))))
        waiting.remove(after)
        changes.append(Change(before, after, seg_pre, seg_post))
    if waiting:
        raise GroundingFailed(
            f"the {waiting[0].name} object at {_at(waiting[0])} in the post-action image was not "
            "wholly in view before; keep every object inside the camera's view"
        )
    return changes


def in_place(obj: DetectedObject, other: Segmentation) -> bool:
    """Whether ``other`` has an object of the same colour overlapping ``obj``'s box."""
    x, y, w, h = obj.box
    for label in other.object_labels:
        ox, oy, ow, oh = (int(v) * other.scale for v in other.stats[label][:4])
        overlaps = ox < x + w and x < ox + ow and oy < y + h and y < oy + oh
        if overlaps and describe(other, label).name == obj.name:
            return True
    return False


def _at(obj: DetectedObject) -> str:
    return f"(x={obj.centroid[0]:.0f}, y={obj.centroid[1]:.0f}) px"
