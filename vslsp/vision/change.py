"""Change detection: which single object moved between a pre- and a post-action observation
(paper, "Methodology": "image-subtraction and thresholding applied on a couple of raw
observations"; Algorithm 1 line 7 ``getObject``; VSL-SP "Implementation": background
subtraction).

The post image is first corrected for a global change of brightness (per-channel gain that
maps its table colour onto the pre image's), both are smoothed against sensor noise, and their
difference is thresholded and cleaned with a morphological opening. An object of the pre image
whose region has largely changed has left; an object of the post image whose region has largely
changed has arrived; one that changed in one image only while an object of its colour stays in
place in the other was merely hidden or revealed by the moved one. Exactly one object must
leave and the same one arrive; anything else is an input error that says what was seen where.

A tolerance for the tutor's hand (``min_move``): **an object whose centroid moved less than
``min_move`` pixels between the images was nudged, not operated**; when more than one object
moved, the nudged ones are left out (and listed in :attr:`Change.nudged`). At 0 (the default)
every change counts.

When the tutor slips, any number of objects may move (:func:`detect_moves`, issue 30): each
region that left in the pre image is paired with the region of the same symbol (its colour) that
arrived in the post image, the nearest first; which of them the operation was about is the slip
rule's question (:func:`vslsp.vsl.slips.colour.ground_moves`).

:func:`changed_pixels` is the one image subtraction and thresholding of the package: this
module's change of one object, the 2-D slip detection (:mod:`vslsp.vsl.slips`), the pick-and-place
recorder's taken and put-down objects, the perceived turn and the reproduction's identification of
a moved object all threshold the difference of two observations at :data:`CHANGE_THRESHOLD`, each
with its own smoothing and morphology (the parameters).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from vslsp.errors import GroundingFailed, InputError
from vslsp.vision.image import as_rgb, channel_max
from vslsp.vision.objects import DetectedObject, Segmentation, describe, segment

#: Grey levels: a pixel changed between two observations of one scene when the largest of its
#: three channels' absolute differences exceeds this. Above the sensor's noise and the shading a
#: moved hand or object casts (a few to 20 levels), below the contrast of an object against the
#: table or the board (60 levels and more). Valid range 1-254.
CHANGE_THRESHOLD = 40
CHANGED_FRACTION = 0.1  # an object has moved when this much of its region changed
_KERNEL = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3))


@dataclass(frozen=True, eq=False)
class Change:
    """The object that moved: as seen ``before`` (pre image) and ``after`` (post image),
    with both images' segmentations (for the landmark and for features)."""

    before: DetectedObject
    after: DetectedObject
    pre: Segmentation
    post: Segmentation
    nudged: tuple[tuple[str, float], ...] = ()  # (symbol, px its centroid moved) of those left out


def default_min_move(shape: tuple[int, ...]) -> float:
    """The default ``min_move`` of ``vslsp ground`` for an image of ``shape`` (H, W, ...): 1 % of
    its diagonal (8 px at 640x480). An operation carries its object across the landmark line,
    tens of pixels at any resolution the camera resolves the objects at; a slip of the hand or a
    settling object moves a neighbour a few pixels."""
    return round(0.01 * float(np.hypot(shape[0], shape[1])), 1)


def changed_pixels(
    first: np.ndarray,
    second: np.ndarray,
    *,
    threshold: float = CHANGE_THRESHOLD,
    blur: int = 0,
    close: np.ndarray | None = None,
    opening: np.ndarray | None = None,
) -> np.ndarray:
    """Image subtraction and thresholding: the pixels (H, W) uint8 {0, 1} that changed between
    the observations ``first`` and ``second`` (H, W, 3) uint8 of one size: those whose largest
    channel difference exceeds ``threshold`` grey levels (default :data:`CHANGE_THRESHOLD`).

    ``blur``: the side (px, odd) of the Gaussian both observations are smoothed with first
    against sensor noise (0: none); ``close``: the structuring element a morphological closing
    joins changed pixels over gaps narrower than it with (None: none); ``opening``: the one a
    morphological opening then removes specks smaller than it with (None: none)."""
    if blur:
        first, second = cv2.GaussianBlur(first, (blur, blur), 0), cv2.GaussianBlur(second, (blur, blur), 0)
    changed = (channel_max(cv2.absdiff(first, second)) > threshold).astype(np.uint8)
    if close is not None:
        changed = cv2.morphologyEx(changed, cv2.MORPH_CLOSE, close)
    if opening is not None:
        changed = cv2.morphologyEx(changed, cv2.MORPH_OPEN, opening)
    return changed


def change_mask(pre: Segmentation, post: Segmentation) -> np.ndarray:
    """Changed pixels (h, w) uint8 {0, 1} between two segmented images of the same size (their
    smoothed images, the post one's brightness corrected to the pre one's table colour)."""
    gain = pre.table / np.maximum(post.table, 1.0)
    corrected = cv2.merge([cv2.multiply(channel, float(g)) for channel, g in zip(cv2.split(post.image), gain)])
    return changed_pixels(pre.image, corrected, opening=_KERNEL)


def moved_labels(seg: Segmentation, changed: np.ndarray) -> list[int]:
    """Labels of the objects of ``seg`` whose region has largely changed."""
    moved = []
    for label in seg.object_labels:
        x, y, w, h, area = seg.stats[label]
        region = seg.labels[y : y + h, x : x + w] == label
        if np.count_nonzero(changed[y : y + h, x : x + w][region]) > CHANGED_FRACTION * area:
            moved.append(label)
    return moved


def detect_change(pre: np.ndarray, post: np.ndarray, min_move: float = 0.0) -> Change:
    """The one object moved between RGB images ``pre`` and ``post`` (H, W, 3) uint8; with
    ``min_move`` > 0, objects that moved less than that many pixels are left out when more than
    one moved (the module's rule).

    Raises InputError when the images differ in size; GroundingFailed (a failed task, exit 1)
    when nothing moved, when several objects moved (naming them and where), or when the object
    left the view.
    """
    left, arrived, seg_pre, seg_post = moved_regions(pre, post, "the tutor moved one object")
    nudged: list[tuple[str, float]] = []
    if min_move > 0 and len(left) + len(arrived) > 2:
        left, arrived, nudged = without_nudged(left, arrived, min_move)
    if len(left) == 1 and len(arrived) == 1 and left[0].name == arrived[0].name:
        return Change(left[0], arrived[0], seg_pre, seg_post, tuple(nudged))
    if len(left) == 1 and not arrived:
        raise GroundingFailed(
            f"the {left[0].name} object at {_at(left[0])} in the pre-action image is not wholly in "
            "view in the post-action image; keep the moved object inside the camera's view"
        )
    if len(arrived) == 1 and not left:
        raise GroundingFailed(
            f"the {arrived[0].name} object at {_at(arrived[0])} in the post-action image was not "
            "wholly in view before; keep the moved object inside the camera's view"
        )
    seen = [f"{o.name} left {_at(o)}" for o in left] + [f"{o.name} arrived at {_at(o)}" for o in arrived]
    raise GroundingFailed(
        f"more than one object moved ({'; '.join(seen)}); give one image pair per moved "
        "object (one operation of the demonstration at a time)"
    )


def detect_moves(pre: np.ndarray, post: np.ndarray) -> list[Change]:
    """Every object moved between RGB images ``pre`` and ``post`` (H, W, 3) uint8, left to
    right by its pre-action place; one :class:`Change` each.

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


def without_nudged(
    left: list[DetectedObject], arrived: list[DetectedObject], min_move: float
) -> tuple[list[DetectedObject], list[DetectedObject], list[tuple[str, float]]]:
    """``left`` and ``arrived`` without the objects that left and arrived (one of a colour each)
    less than ``min_move`` px apart, and those (symbol, px moved); nothing is left out when
    every moved object was nudged (then the message names them all)."""
    nudged: list[tuple[str, float]] = []
    for name in {o.name for o in left}:
        went = [o for o in left if o.name == name]
        came = [o for o in arrived if o.name == name]
        if len(went) == 1 and len(came) == 1:
            moved = float(np.hypot(*np.subtract(came[0].centroid, went[0].centroid)))
            if moved < min_move:
                nudged.append((name, round(moved, 1)))
    names = {name for name, _ in nudged}
    kept_left = [o for o in left if o.name not in names]
    kept_arrived = [o for o in arrived if o.name not in names]
    if not kept_left and not kept_arrived:
        return left, arrived, []
    return kept_left, kept_arrived, sorted(nudged)


def moved_regions(
    pre: np.ndarray, post: np.ndarray, operation: str
) -> tuple[list[DetectedObject], list[DetectedObject], Segmentation, Segmentation]:
    """The objects that left in ``pre`` and arrived in ``post`` (RGB images of one size) and both
    segmentations. Raises InputError when the images differ in size, GroundingFailed when nothing
    moved (the message asks for images just before and just after ``operation``)."""
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
    # An object that only changed in one image and is still in place in the other was hidden
    # or revealed by the moved one (seen in perspective), not moved itself.
    left = [o for o in left if any(a.name == o.name for a in arrived) or not in_place(o, seg_post)]
    arrived = [o for o in arrived if any(a.name == o.name for a in left) or not in_place(o, seg_pre)]
    if not left and not arrived:
        raise GroundingFailed(
            "nothing moved between the pre- and the post-action image; give the images taken "
            f"just before and just after {operation}"
        )
    return left, arrived, seg_pre, seg_post


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
