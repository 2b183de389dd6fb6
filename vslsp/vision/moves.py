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

from vslsp.errors import GroundingFailed
from vslsp.vision.change import Change, moved_regions
from vslsp.vision.objects import DetectedObject


def detect_moves(pre: np.ndarray, post: np.ndarray) -> list[Change]:
    """Every object moved between RGB images ``pre`` and ``post`` (H, W, 3) uint8, left to
    right by its pre-action place; one :class:`~vslsp.vision.change.Change` each.

    Raises InputError when the images differ in size; GroundingFailed when nothing moved or a
    moved object is seen in one image only (it left the view, or came into it).
    """
    left, arrived, seg_pre, seg_post = moved_regions(pre, post, "the tutor's operation")
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


def _at(obj: DetectedObject) -> str:
    return f"(x={obj.centroid[0]:.0f}, y={obj.centroid[1]:.0f}) px"
