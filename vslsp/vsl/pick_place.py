"""VSL's demonstration of pick-and-place operations on a tabletop seen by an oblique camera
(paper, "Methodology", Algorithm 1 part I, and "Real-world Experiments": the pre-pick and
pre-place observations and their frames).

Observations are the camera's images seen from above (:class:`TableView`): an oblique camera
sees a box's top skewed differently wherever it lies, the top-down view does not, so a
similarity (what SIFT-RANSAC fits) maps an object or a place from one observation to another.

For each operation the tutor performs, the :class:`~vslsp.vsl.recorder.Recorder` with the
:class:`TableModel` keeps three observations:
pre-pick (the world before the tutor takes the object), pre-place (the world while the tutor
holds it, out of view) and post-place. Image subtraction of pre-pick and pre-place finds the
object (getObject): its silhouette, unprojected onto the planes of its top and of its bottom,
gives its footprint, centre (the pick point) and yaw, and likewise where it was put (the place
point); the two yaws give the turn the tutor gave it up to a quarter turn, and its SIFT
features φ matched from pre-pick to post-place tell which. The
heights of the object's top at the pick and at the place, and its own height, are the tutor's
(the paper's h, "provided by the tutor"). The pre-pick frame is the biggest object's size, the
pre-place frame :data:`PLACE_FRAME` times that. The reproduction is
:mod:`vslsp.vsl.reproduction`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.geometry.poses import wrap
from vslsp.vision.change import changed_pixels
from vslsp.vision.features import Features, extract_features
from vslsp.vision.matching import SCALE_RANGE
from vslsp.vision.parameters import DEFAULT_OBJECT_FINDING, ObjectFinding
from vslsp.vsl.recorder import Heights

PLACE_FRAME = 2.0  # the pre-place frame's side, in sizes of the biggest object (the paper: two to three)
_STEP = 25.0  # px: the offsets through which a transform's rotation on the table is measured


class TableCamera(Protocol):
    """The camera's calibration: image px <-> table metres at a height z (m) above the table top."""

    def pixel_to_table(self, u: float, v: float, z: float = 0.0) -> tuple[float, float]: ...

    def table_to_pixel(self, x: float, y: float, z: float = 0.0) -> tuple[float, float]: ...


class TableView:
    """The camera's observations resampled onto the table: a top-down view of ``x_range`` ×
    ``y_range`` (m) at ``px_per_m``, made with the homography of the plane at height ``z``
    (m). An oblique camera sees a box's top skewed differently wherever it lies; in this view
    the top of a box at any height is the same up to a constant scale, so a similarity (what
    SIFT-RANSAC fits) maps an object or a place from one observation to another. The robot is
    at the bottom (rows run against x), its left on the left (columns run against y). It is
    itself a :class:`TableCamera` for its own pixels (through the camera, at any height)."""

    def __init__(
        self,
        camera: TableCamera,
        x_range: tuple[float, float] = (0.22, 0.84),
        y_range: tuple[float, float] = (-0.42, 0.42),
        px_per_m: float = 1500.0,
        z: float = 0.02,
    ) -> None:
        self.camera, self.x_range, self.y_range, self.px_per_m = camera, x_range, y_range, px_per_m
        self.size = (int(round((y_range[1] - y_range[0]) * px_per_m)), int(round((x_range[1] - x_range[0]) * px_per_m)))
        corners = [(x, y) for x in x_range for y in y_range]
        image = np.array([camera.table_to_pixel(x, y, z) for x, y in corners], np.float32)
        view = np.array([self._to_view(x, y) for x, y in corners], np.float32)
        self.homography = cv2.getPerspectiveTransform(image, view)  # camera px -> view px, plane z
        self.inverse = np.linalg.inv(self.homography)

    def _to_view(self, x: float, y: float) -> tuple[float, float]:
        return (self.y_range[1] - y) * self.px_per_m, (self.x_range[1] - x) * self.px_per_m

    def rectify(self, image: np.ndarray) -> np.ndarray:
        """The camera's image (H, W, 3) as seen from above (h, w, 3)."""
        return cv2.warpPerspective(
            image, self.homography, self.size, flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE
        )

    def pixel_to_table(self, u: float, v: float, z: float = 0.0) -> tuple[float, float]:
        return self.camera.pixel_to_table(*apply(self.inverse, (u, v)), z)

    def table_to_pixel(self, x: float, y: float, z: float = 0.0) -> tuple[float, float]:
        return apply(self.homography, self.camera.table_to_pixel(x, y, z))


@dataclass(frozen=True, eq=False)
class RecordedOperation:
    """Operation i as VSL recorded it: the pre-pick, pre-place and post-place observations
    (H, W, 3) uint8; the pick point (u, v) px in pre-pick and the place point (u, v) px in
    post-place (the object's centre); the object's footprint (m, sides along and across its
    yaw), its yaw (rad, table frame) before and the turn the tutor gave it; its size in the
    image (px); the heights (m) of its top at the pick and at the place (the tutor's); the SIFT
    features of the object φ_i (pre-pick, inside its region)."""

    pre_pick: np.ndarray
    pre_place: np.ndarray
    post_place: np.ndarray
    pick_point: tuple[float, float]
    place_point: tuple[float, float]
    footprint: tuple[float, float]
    yaw: float
    turn: float
    object_size: float
    pick_z: float
    place_z: float
    features: Features
    # The side (px) of this operation's pre-place frame when it is not the demonstration's
    # (:attr:`PickPlaceDemonstration.place_frame`): the object it was put on, when the tutor's
    # slip had nudged that one (:func:`~vslsp.experiments.tabletop_slips.demonstrate_with_slips`).
    place_frame: float | None = None
    # The SIFT features of that object in the pre-place observation: the place is found by it,
    # as the pick finds the object (:func:`~vslsp.vsl.reproduction.find_place`).
    place_features: Features | None = None
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    def observation_features(self, which: str, point: tuple[float, float], side: float) -> Features:
        """SIFT features of the ``which`` ("pre_pick" or "pre_place") observation inside the
        square of ``side`` px about ``point`` (the largest frame it is matched with), once."""
        key = (which, point, side)
        if key not in self._cache:
            image = getattr(self, which)
            mask = np.zeros(image.shape[:2], np.uint8)
            half = side / 2.0 + 8.0  # SIFT needs a rim about a keypoint
            mask[
                max(0, int(point[1] - half)) : int(point[1] + half), max(0, int(point[0] - half)) : int(point[0] + half)
            ] = 1
            self._cache[key] = extract_features(image, mask)
        return self._cache[key]

    def to_dict(self) -> dict:
        return {
            "pick_point": [round(c, 2) for c in self.pick_point],
            "place_point": [round(c, 2) for c in self.place_point],
            "footprint_m": [round(c, 4) for c in self.footprint],
            "yaw": round(self.yaw, 4),
            "turn": round(self.turn, 4),
            "object_size_px": round(self.object_size, 1),
            "pick_z": round(self.pick_z, 4),
            "place_z": round(self.place_z, 4),
            "features": len(self.features),
        } | ({} if self.place_frame is None else {"place_frame_px": round(self.place_frame, 1)})


@dataclass(frozen=True, eq=False)
class PickPlaceDemonstration:
    """A recorded demonstration: the operations in order (Π: pick-and-place each)."""

    operations: tuple[RecordedOperation, ...]

    @property
    def pick_frame(self) -> float:
        """The pre-pick frame side (px): the biggest object's size in the image."""
        return max(op.object_size for op in self.operations)

    @property
    def place_frame(self) -> float:
        """The pre-place frame side (px): :data:`PLACE_FRAME` times the biggest object."""
        return PLACE_FRAME * self.pick_frame


class TableModel:
    """The observation model of a calibrated camera over a table (its images seen from above,
    :class:`TableView`): the :class:`~vslsp.vsl.recorder.Recorder` asks it for each operation
    (Algorithm 1 line 7), whose pre-place observation and heights it needs; the pick-and-place
    tasks have no landmark line (their landmarks are static bodies that the frames see)."""

    def __init__(self, camera: TableCamera) -> None:
        self.camera = camera

    def get_object(
        self, pre: np.ndarray, post: np.ndarray, pre_place: np.ndarray | None, heights: Heights | None
    ) -> RecordedOperation:
        """One operation from its pre-pick, post-place and pre-place observations (H, W, 3)
        uint8 and the tutor's ``heights``. Raises InputError when the pre-place observation or
        the heights are missing, when the object is not seen leaving or arriving, or when its
        features do not match from one to the other."""
        if pre_place is None or heights is None:
            raise InputError(
                "a pick-and-place operation needs its pre-place observation (the world while the "
                "tutor holds the object) and the tutor's heights; record them with each operation"
            )
        pick_z, place_z, height = heights.pick_z, heights.place_z, heights.height
        taken = changed_region(pre, pre_place, "taken from the pre-pick observation")
        put = changed_region(post, pre_place, "put down in the post-place observation")
        centre, footprint, yaw = footprint_on_table(taken, self.camera, pick_z, pick_z - height)
        placed, _, placed_yaw = footprint_on_table(put, self.camera, place_z, place_z - height)
        pick_point = self.camera.table_to_pixel(centre[0], centre[1], pick_z)
        place_point = self.camera.table_to_pixel(placed[0], placed[1], place_z)
        features = extract_features(pre, taken)
        turn = self._turn(
            features, extract_features(post, put), pick_point, place_point, (pick_z, place_z), placed_yaw - yaw
        )
        x, y, w, h = cv2.boundingRect(cv2.findNonZero(taken))
        return RecordedOperation(
            pre,
            pre_place,
            post,
            (float(pick_point[0]), float(pick_point[1])),
            (float(place_point[0]), float(place_point[1])),
            footprint,
            yaw,
            turn,
            float(max(w, h)),
            float(pick_z),
            float(place_z),
            features,
        )

    def _turn(
        self,
        before: Features,
        after: Features,
        pick_point: tuple[float, float],
        place_point: tuple[float, float],
        heights: tuple[float, float],
        boxes: float,
        parameters: ObjectFinding = DEFAULT_OBJECT_FINDING,
    ) -> float:
        """The turn (rad) the tutor gave the object: the boxes' yaws give it up to a quarter turn
        (``boxes``, their difference); the object's SIFT features matched from the pick to the
        place say which, from the first RANSAC placement that puts its centre where the object
        was seen put down (within ``parameters.agree``). Raises InputError when none does."""
        target = np.array(self.camera.pixel_to_table(*place_point, heights[1]))
        for transform, _ in object_candidates(before, after, 3, parameters):
            centre = np.array(self.camera.pixel_to_table(*apply(transform, pick_point), heights[1]))
            if np.hypot(*(centre - target)) <= parameters.agree:
                seen = table_rotation(self.camera, transform, pick_point, *heights)
                return wrap(boxes + np.pi / 2.0 * round((seen - boxes) / (np.pi / 2.0)))
        raise InputError(
            "the moved object's features do not match between pick and place; give it more "
            "texture, and let the tutor move one object at a time"
        )

    def demonstration(self, operations: tuple[RecordedOperation, ...]) -> PickPlaceDemonstration:
        return PickPlaceDemonstration(operations)


def changed_region(image: np.ndarray, reference: np.ndarray, what: str = "moved") -> np.ndarray:
    """The object that ``image`` shows and ``reference`` lacks (image subtraction and
    thresholding): a mask (H, W) uint8 {0, 255}, the convex hull of the largest changed blob
    and the blobs beside it. Raises InputError when nothing changed."""
    changed = changed_pixels(
        image, reference, blur=5, close=np.ones((9, 9), np.uint8), opening=np.ones((3, 3), np.uint8)
    )
    count, labels, stats, centroids = cv2.connectedComponentsWithStats(changed)
    if count < 2 or stats[1:, cv2.CC_STAT_AREA].max() < 100:
        raise InputError(f"no object was {what}: the observations do not differ; keep the object in view")
    largest = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
    reach = 0.75 * max(stats[largest, cv2.CC_STAT_WIDTH], stats[largest, cv2.CC_STAT_HEIGHT])
    keep = [
        k
        for k in range(1, count)
        if stats[k, cv2.CC_STAT_AREA] >= 0.05 * stats[largest, cv2.CC_STAT_AREA]
        and np.hypot(*(centroids[k] - centroids[largest])) <= reach
    ]
    points = np.vstack([cv2.findNonZero((labels == k).astype(np.uint8)) for k in keep])
    mask = np.zeros(changed.shape, np.uint8)
    cv2.fillConvexPoly(mask, cv2.convexHull(points), 255)
    return mask


def footprint_on_table(
    mask: np.ndarray, camera: TableCamera, top: float, bottom: float
) -> tuple[np.ndarray, tuple[float, float], float]:
    """The footprint of the box seen as ``mask`` (H, W): its silhouette unprojected onto the
    plane of its top (height ``top``, m) covers the top face and the visible sides seen from
    there; unprojected onto the plane of its bottom (``bottom``) it covers the bottom face and
    the top seen beyond it; the box's footprint is where the two overlap. Returns the centre (2,)
    m, the sides (m; along its yaw first) and the yaw (rad, in [-π/2, π/2))."""
    contour = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)[0]
    outline = max(contour, key=cv2.contourArea).reshape(-1, 2).astype(float)
    planes = [np.array([camera.pixel_to_table(u, v, z) for u, v in outline]) for z in (top, bottom)]
    origin = np.minimum(planes[0].min(axis=0), planes[1].min(axis=0))
    extent = np.maximum(planes[0].max(axis=0), planes[1].max(axis=0)) - origin
    grid = np.ceil(extent / _GRID).astype(int) + 2
    overlap = np.full((grid[1], grid[0]), 255, np.uint8)
    for plane in planes:
        region = np.zeros_like(overlap)
        cv2.fillPoly(region, [np.round((plane - origin) / _GRID).astype(np.int32)], 255)
        overlap &= region
    points = cv2.findNonZero(overlap)
    if points is None or len(points) < 10:
        raise InputError("the moved object's footprint on the table is empty; keep it in view")
    (cx, cy), (along, across), degrees = cv2.minAreaRect(points.astype(np.float32))
    yaw = wrap(np.radians(degrees) * 2.0) / 2.0  # a box's yaw is defined modulo π
    centre = origin + _GRID * np.array([cx, cy])
    return centre, (float(along * _GRID), float(across * _GRID)), float(yaw)


_GRID = 0.0005  # m per cell of the footprint's raster


def object_candidates(
    features: Features, seen: Features, count: int = 2, parameters: ObjectFinding = DEFAULT_OBJECT_FINDING
) -> list[tuple[np.ndarray, int]]:
    """Up to ``count`` placements of an object's ``features`` among the ``seen`` ones: ratio-
    tested SIFT matches, each seen keypoint kept for its closest match only, RANSAC
    similarities one after the other on the matches left over; each a transform (3, 3) px and
    its number of inliers (at least ``parameters.min_inliers``; the rules:
    :class:`~vslsp.vision.parameters.ObjectFinding`). A similarity that shrinks or grows
    the object beyond :data:`~vslsp.vision.matching.SCALE_RANGE` is no placement (the view is from above, and heights
    change an object's size by a few per cent): one that maps many features onto one spot
    would otherwise outvote the object seen turned."""
    if len(features) < 2 or len(seen) < 2:
        return []
    pairs = cv2.BFMatcher(cv2.NORM_L2).knnMatch(features.descriptors, seen.descriptors, k=2)
    closest: dict[int, cv2.DMatch] = {}
    for m in pairs:
        if len(m) == 2 and m[0].distance < parameters.ratio * m[1].distance:
            if m[0].trainIdx not in closest or m[0].distance < closest[m[0].trainIdx].distance:
                closest[m[0].trainIdx] = m[0]
    good = sorted(closest.values(), key=lambda m: m.queryIdx)
    source = features.keypoints[[m.queryIdx for m in good], :2].reshape(-1, 1, 2)
    target = seen.keypoints[[m.trainIdx for m in good], :2].reshape(-1, 1, 2)
    cv2.setRNGSeed(0)  # deterministic RANSAC
    found: list[tuple[np.ndarray, int]] = []
    while len(source) >= parameters.min_inliers and len(found) < count:
        model, inliers = cv2.estimateAffinePartial2D(
            source, target, method=cv2.RANSAC, ransacReprojThreshold=parameters.reprojection
        )
        if model is None or inliers is None or inliers.sum() < parameters.min_inliers:
            break
        inliers = inliers.ravel().astype(bool)
        if SCALE_RANGE[0] <= np.hypot(model[0, 0], model[1, 0]) <= SCALE_RANGE[1]:
            found.append((np.vstack([model, [0.0, 0.0, 1.0]]), int(inliers.sum())))
        source, target = source[~inliers], target[~inliers]
    return found


def apply(transform: np.ndarray, point: tuple[float, float]) -> tuple[float, float]:
    """``transform`` (3, 3) applied to a pixel ``point`` (u, v)."""
    u, v = cv2.perspectiveTransform(np.array([[point]], np.float64), transform)[0, 0]
    return float(u), float(v)


def table_rotation(
    camera: TableCamera, transform: np.ndarray, point: tuple[float, float], z_from: float, z_to: float
) -> float:
    """The rotation (rad, counter-clockwise on the table) that the image ``transform`` (3, 3)
    applies about ``point`` (px, on a surface at height ``z_from``, mapped onto one at
    ``z_to``): the turn of two short offsets seen on the table, averaged."""
    origin = np.array(camera.pixel_to_table(*point, z_from))
    target = np.array(camera.pixel_to_table(*apply(transform, point), z_to))
    turns = []
    for offset in ((_STEP, 0.0), (0.0, _STEP)):
        moved = (point[0] + offset[0], point[1] + offset[1])
        before = np.array(camera.pixel_to_table(*moved, z_from)) - origin
        after = np.array(camera.pixel_to_table(*apply(transform, moved), z_to)) - target
        turns.append(np.arctan2(after[1], after[0]) - np.arctan2(before[1], before[0]))
    return float(np.arctan2(np.mean(np.sin(turns)), np.mean(np.cos(turns))))
