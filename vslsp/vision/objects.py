"""Objects on the table: segmentation, symbols and poses (paper, Algorithm 1 line 7:
``getObject`` gives the symbol B_i, the pose P_i and the features φ_i of an object).

No prior knowledge of the objects is used: an object is a compact region whose colour differs
from the table's (the image's dominant colour) and that is not the black landmark. Regions
touching the image border are not wholly in view (the robot's body, the table's edge) and
are left out, as are regions too small (noise) or too large (not a tabletop object).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from vslsp.vision.colour import COLOUR_NAMES, GREY_CLASS, colour_classes, colour_name
from vslsp.vision.features import Features, object_features
from vslsp.vision.image import as_rgb, channel_max, channel_min, colour_distance, table_colour, to_working
from vslsp.vision.parameters import DEFAULT_OBJECT_FINDING, ObjectFinding

DARK_VALUE, DARK_CHROMA = 80, 40  # darker and greyer than this: the landmark, not an object
MIN_AREA, MAX_AREA = 0.0008, 0.15  # object area as a fraction of the image
_KERNEL = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3))


@dataclass(frozen=True, eq=False)
class DetectedObject:
    """An object seen in one image (pixel coordinates: x right, y down, pixel centres at +0.5).

    ``name``: colour symbol; ``centroid``: (x, y) px; ``box``: (x, y, w, h) px;
    ``orientation``: deg, angle of its minimum-area rectangle (modulo 90° for square shapes);
    ``area``: px²; ``features``: SIFT φ, or None when not asked for.
    """

    name: str
    centroid: tuple[float, float]
    box: tuple[int, int, int, int]
    orientation: float
    area: float
    features: Features | None = None

    def to_dict(self) -> dict:
        return {
            "name": self.name,
            "x": self.centroid[0],
            "y": self.centroid[1],
            "box": list(self.box),
            "orientation": self.orientation,
            "area": self.area,
        }


@dataclass(frozen=True, eq=False)
class Segmentation:
    """Objects of one image at the working scale: labels (h, w) int32, one label per object."""

    image: np.ndarray  # (h, w, 3) uint8, smoothed working image
    scale: int
    table: np.ndarray  # (3,) float32
    labels: np.ndarray  # (h, w) int32, 0 = not an object
    dark: np.ndarray  # (h, w) uint8 {0, 255}: dark grey pixels, candidates for the landmark
    object_labels: tuple[int, ...]
    stats: np.ndarray  # (n, 5) from cv2.connectedComponentsWithStats


def dark_mask(work: np.ndarray) -> np.ndarray:
    """Pixels (h, w) uint8 {0, 255} dark and grey: the black landmark line."""
    value = channel_max(work)
    return cv2.bitwise_and(
        cv2.compare(value, DARK_VALUE, cv2.CMP_LT),
        cv2.compare(cv2.subtract(value, channel_min(work)), DARK_CHROMA, cv2.CMP_LT),
    )


def object_mask(
    work: np.ndarray, table: np.ndarray, dark: np.ndarray, parameters: ObjectFinding = DEFAULT_OBJECT_FINDING
) -> np.ndarray:
    """Pixels (h, w) uint8 {0, 1} whose colour is an object's: not the table (by
    ``parameters.object_contrast``), not ``dark``."""
    contrast = cv2.compare(colour_distance(work, table), parameters.object_contrast, cv2.CMP_GT)
    mask = cv2.bitwise_and(contrast, cv2.bitwise_not(dark)) // 255
    return cv2.morphologyEx(mask, cv2.MORPH_OPEN, _KERNEL)


def segment(image: np.ndarray, parameters: ObjectFinding = DEFAULT_OBJECT_FINDING) -> Segmentation:
    """Segment the objects of an RGB image (H, W, 3) uint8 by the rules ``parameters``.

    A connected region of object pixels that holds several colours (objects of different
    colours touching in the image) is split by colour class, so that they stay two objects.
    """
    work, scale = to_working(as_rgb(image))
    table = table_colour(work)
    dark = dark_mask(work)
    objects = object_mask(work, table, dark, parameters)
    count, labels, stats, _ = cv2.connectedComponentsWithStats(objects, connectivity=8)
    h, w = labels.shape
    min_area, max_area = MIN_AREA * h * w, MAX_AREA * h * w
    all_stats = list(stats)
    kept: list[int] = []
    for label in range(1, count):
        if stats[label, 4] < min_area:
            continue
        parts = _split_by_colour(work, labels, label, all_stats, min_area, parameters.texture_share)
        reaches_in = _on_border(stats[label], w, h)
        for part_label, colour_class in parts:
            part = all_stats[part_label]
            # A grey or unnamed piece of a region reaching into the view is a part of the robot
            # (its white hand) or of the table's edge, not an object standing on the table.
            if reaches_in and colour_class > len(COLOUR_NAMES):
                continue
            if not _on_border(part, w, h) and min_area <= part[4] <= max_area:
                kept.append(part_label)
    return Segmentation(work, scale, table, labels, dark, tuple(kept), np.array(all_stats))


def _split_by_colour(
    work: np.ndarray,
    labels: np.ndarray,
    label: int,
    all_stats: list[np.ndarray],
    min_area: float,
    texture_share: float,
) -> list[tuple[int, int]]:
    """Split region ``label`` of ``labels`` (h, w) by colour class where it holds several
    colours, relabelling ``labels`` in place and appending the parts' stats to ``all_stats``.

    Returns (label, colour class) for each part; a region of one colour is its own part. A
    patch of no named colour smaller than ``texture_share`` of the region's named colour (a mark
    of a cube's texture, seen beside its colour) is no part: it would be a phantom object.
    """
    x, y, bw, bh, _ = all_stats[label]
    region = labels[y : y + bh, x : x + bw]
    inside = region == label
    classes = colour_classes(work[y : y + bh, x : x + bw])
    classes[~inside] = 0
    counts = np.bincount(classes.ravel(), minlength=GREY_CLASS + 1)
    major = np.nonzero(counts[1:] >= min_area)[0] + 1
    if len(major) <= 1:
        return [(label, int(major[0]) if len(major) else int(np.argmax(counts[1:])) + 1)]
    region[inside] = 0
    parts = []
    named = counts[1 : len(COLOUR_NAMES) + 1].max()
    for colour_class in major:
        if colour_class > len(COLOUR_NAMES) and counts[colour_class] < texture_share * named:
            continue  # a patch of no named colour (a texture's mark) on a named object: no object of its own
        # Opening drops the thin fringe where an object's colour blends into another.
        members = cv2.morphologyEx((classes == colour_class).view(np.uint8), cv2.MORPH_OPEN, _KERNEL)
        n, part_labels, part_stats, _ = cv2.connectedComponentsWithStats(members, connectivity=8)
        for part in range(1, n):
            region[part_labels == part] = len(all_stats)
            part_stats[part, :2] += (x, y)
            parts.append((len(all_stats), int(colour_class)))
            all_stats.append(part_stats[part])
    return parts


def _on_border(stat: np.ndarray, w: int, h: int) -> bool:
    """Whether a region's box (x, y, w, h, area) touches the edge of a w x h image."""
    x, y, bw, bh = stat[:4]
    return x <= 0 or y <= 0 or x + bw >= w or y + bh >= h


def describe(seg: Segmentation, label: int, image: np.ndarray | None = None) -> DetectedObject:
    """The :class:`DetectedObject` of one label; SIFT features too when ``image`` is given."""
    s = seg.scale
    x, y, bw, bh, area = (int(v) for v in seg.stats[label])
    ys, xs = np.nonzero(seg.labels[y : y + bh, x : x + bw] == label)
    ys, xs = ys + y, xs + x
    box = (x * s, y * s, bw * s, bh * s)
    features = object_features(image, box) if image is not None else None
    return DetectedObject(
        name=colour_name(seg.image[ys, xs]),
        centroid=(float((xs.mean() + 0.5) * s), float((ys.mean() + 0.5) * s)),
        box=box,
        orientation=_orientation(xs, ys),
        area=float(area * s * s),
        features=features,
    )


def _orientation(xs: np.ndarray, ys: np.ndarray) -> float:
    """Angle (deg) of the minimum-area rectangle around the pixels: in [-45, 45) for squarish
    shapes, else the long side's angle in [-90, 90)."""
    (_, _), (width, height), angle = cv2.minAreaRect(np.column_stack([xs, ys]).astype(np.float32))
    if max(width, height) < 1.2 * min(width, height):
        return float((angle + 45.0) % 90.0 - 45.0)
    if width < height:
        angle += 90.0
    return float((angle + 90.0) % 180.0 - 90.0)


def detect_objects(
    image: np.ndarray, features: bool = True, parameters: ObjectFinding = DEFAULT_OBJECT_FINDING
) -> list[DetectedObject]:
    """All objects wholly in view in an RGB image (H, W, 3) uint8, left to right (segmented by
    the rules ``parameters``).

    With ``features`` each object carries its SIFT features φ (costs a few ms per object).
    """
    seg = segment(image, parameters)
    objects = [describe(seg, label, image if features else None) for label in seg.object_labels]
    return sorted(objects, key=lambda o: o.centroid)
