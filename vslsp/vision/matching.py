"""Match finding with adaptive frames (paper, Algorithm 1 lines 13-14 ``findBestMatch`` and
the house-and-roof simulation).

A recorded observation (an image of the demonstration world) is matched against a new world
image. The frame around the object starts at the object's size and grows up to the whole
world; at each size, SIFT features of the frame are matched to the world's (several nearest
neighbours each, so that every copy of a repeated object gets its matches), RANSAC extracts
one similarity transform per copy in turn, and each candidate is scored by the normalised
cross-correlation of the frame with the world under that transform. The first frame size at
which one candidate clearly beats the others gives the match: a larger frame adds context
(e.g. whether a house already has its roof) that tells visually identical objects apart.
The winning transform is refined on its inliers and decomposed as α T = T R_θ R_−φ S_v R_φ P.
"""

from __future__ import annotations

import enum
from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from vslsp.outcomes import NoMatch
from vslsp.vision.features import Features, extract_features
from vslsp.vision.image import as_rgb
from vslsp.vision.parameters import DEFAULT_FRAME_SEARCH, FrameSearch
from vslsp.vision.transform import Decomposition, decompose

# The default rules' figures, for the modules that read them by name (see FrameSearch).
MIN_SCORE = DEFAULT_FRAME_SEARCH.min_score
MARGIN = DEFAULT_FRAME_SEARCH.margin
SCALE_RANGE = DEFAULT_FRAME_SEARCH.scale_range


@dataclass(frozen=True, eq=False)
class Candidate:
    """One placement of the frame in the world: ``transform`` (3, 3) observation -> world,
    its RANSAC inlier matches (K, 2, 2) [observation xy, world xy], and its ``score`` (NCC)."""

    transform: np.ndarray
    inliers: np.ndarray
    score: float


@dataclass(frozen=True, eq=False)
class Match:
    """The best match of an observation in the world: the object's pose (x, y) px and θ (rad,
    rotation from the observation to the world, image coordinates), the ``score`` (NCC in
    [-1, 1]), the ``frame`` side (px) that made it unique, whether it stayed ``ambiguous`` up to
    the whole world, the ``transform`` (3, 3) and its :class:`Decomposition`."""

    x: float
    y: float
    theta: float
    score: float
    frame: int
    ambiguous: bool
    candidates: int
    transform: np.ndarray
    decomposition: Decomposition

    def to_dict(self) -> dict:
        return {
            "x": self.x,
            "y": self.y,
            "theta": self.theta,
            "score": self.score,
            "frame": self.frame,
            "ambiguous": self.ambiguous,
            "candidates": self.candidates,
        }

    def frame_corners(self, size: float, point: tuple[float, float]) -> np.ndarray:
        """The corners (4, 2) px in the world of the square frame of side ``size`` around the
        ``point`` recorded in the observation, mapped through the match's transform (overlays)."""
        half = size / 2.0
        x, y = point
        corners = np.array([[x - half, y - half], [x + half, y - half], [x + half, y + half], [x - half, y + half]])
        return cv2.perspectiveTransform(corners[None].astype(np.float32), self.transform)[0]


class FrameMode(enum.StrEnum):
    """How the pre-place frame is chosen: grown until one place stands out (the paper's
    adaptive frame) or a fixed small one (the baseline it is compared with)."""

    ADAPTIVE = "adaptive"
    FIXED = "fixed"


def frame_sizes(
    object_size: float, world_shape: tuple[int, ...], parameters: FrameSearch = DEFAULT_FRAME_SEARCH
) -> list[int]:
    """Adaptive frame sides (px): from the object's size (at least ``parameters.min_frame``),
    times ``parameters.frame_growth`` each step, to the whole world."""
    largest = int(max(world_shape[:2]))
    sizes, size = [], max(parameters.min_frame, float(object_size))
    while size < largest:
        sizes.append(int(round(size)))
        size *= parameters.frame_growth
    return sizes + [largest]


def find_best_match(
    observation: np.ndarray,
    world: np.ndarray,
    point: tuple[float, float],
    object_size: float,
    frames: Sequence[int] | None = None,
    observation_features: Features | None = None,
    world_features: Features | None = None,
    model: str = "similarity",
    parameters: FrameSearch = DEFAULT_FRAME_SEARCH,
) -> Match | NoMatch:
    """Where the object at ``point`` (x, y px) of ``observation`` (h, w, 3) is in ``world``
    (H, W, 3), both RGB uint8.

    ``object_size`` (px) is where the adaptive frame starts; ``frames`` fixes the frame sides
    to try instead (e.g. ``[40]`` for a fixed small frame). Precomputed SIFT features of either
    image may be passed. ``model``: the transform fitted to the winning inliers, "similarity"
    (rigid motion on the table seen by the same camera: the default, stable with few
    inliers) or "homography" (the paper's general T_sift, when at least 8 inliers).
    ``parameters``: the search's rules (:class:`~vslsp.vision.parameters.FrameSearch`).
    Returns :class:`NoMatch` when no frame finds any match (ValueError: an unknown ``model``).
    """
    if model not in ("similarity", "homography"):
        raise ValueError(f"unknown model {model!r}; use 'similarity' or 'homography'")
    observation, world = as_rgb(observation, "observation"), as_rgb(world, "world image")
    obs_features = observation_features if observation_features is not None else extract_features(observation)
    world_feats = world_features if world_features is not None else extract_features(world)
    sizes = list(frames) if frames is not None else frame_sizes(object_size, world.shape, parameters)
    grey_obs = cv2.cvtColor(observation, cv2.COLOR_RGB2GRAY).astype(np.float32)
    grey_world = cv2.cvtColor(world, cv2.COLOR_RGB2GRAY).astype(np.float32)
    matcher = cv2.BFMatcher(cv2.NORM_L2)
    best: tuple[Candidate, int, int, bool] | None = None
    for size in sizes:
        box = _frame_box(point, size, observation.shape)
        candidates = _candidates(obs_features, world_feats, box, matcher, grey_obs, grey_world, parameters)
        if not candidates:
            continue
        unique = len(candidates) == 1 or candidates[0].score - candidates[1].score >= parameters.margin
        if best is None or unique:
            best = (candidates[0], size, len(candidates), unique)
        if unique and candidates[0].score >= parameters.min_score:
            break
    if best is None:
        return NoMatch("no SIFT match of the observation's frame in the world at any frame size")
    candidate, size, count, unique = best
    transform = _refine(candidate, model)
    x, y = cv2.perspectiveTransform(np.array([[point]], np.float32), transform)[0, 0]
    decomposition = decompose(transform)
    return Match(
        float(x), float(y), decomposition.theta, candidate.score, int(size), not unique, count, transform, decomposition
    )


def _frame_box(point: tuple[float, float], size: int, shape: tuple[int, ...]) -> tuple[int, int, int, int]:
    """The frame (x0, y0, x1, y1) of side ``size`` centred on ``point``, clipped to the image."""
    half = size / 2.0
    x0, y0 = int(max(0, round(point[0] - half))), int(max(0, round(point[1] - half)))
    x1, y1 = int(min(shape[1], round(point[0] + half))), int(min(shape[0], round(point[1] + half)))
    return x0, y0, x1, y1


def _candidates(
    obs: Features, world: Features, box, matcher, grey_obs, grey_world, parameters: FrameSearch
) -> list[Candidate]:
    """Candidate placements of the frame ``box`` in the world, best first."""
    x0, y0, x1, y1 = box
    inside = (
        (obs.keypoints[:, 0] >= x0)
        & (obs.keypoints[:, 0] < x1)
        & (obs.keypoints[:, 1] >= y0)
        & (obs.keypoints[:, 1] < y1)
    )
    if inside.sum() < 2 or len(world) < 2:
        return []
    query = obs.keypoints[inside, :2]
    knn = matcher.knnMatch(obs.descriptors[inside], world.descriptors, k=min(parameters.neighbours, len(world)))
    pairs = np.array(
        [
            (query[m.queryIdx], world.keypoints[m.trainIdx, :2])
            for row in knn
            for m in row
            if m.distance <= parameters.alternative * row[0].distance
        ],
        np.float32,
    )  # (M, 2, 2)
    candidates: list[Candidate] = []
    cv2.setRNGSeed(0)  # deterministic RANSAC
    while len(pairs) >= 3 and len(candidates) < parameters.max_candidates:
        model, mask = cv2.estimateAffinePartial2D(
            _c(pairs[:, 0]), _c(pairs[:, 1]), method=cv2.RANSAC, ransacReprojThreshold=parameters.reprojection
        )
        if model is None or mask is None or mask.sum() < 3:
            break
        mask = mask.ravel().astype(bool)
        transform = np.vstack([model, [0.0, 0.0, 1.0]])
        scale = float(np.sqrt(abs(np.linalg.det(model[:, :2]))))
        if parameters.scale_range[0] <= scale <= parameters.scale_range[1]:
            score = _correlation(grey_obs, grey_world, box, transform)
            candidates.append(Candidate(transform, pairs[mask], score))
        pairs = pairs[~mask]
    candidates.sort(key=lambda c: -c.score)
    return _distinct(candidates, box)


def _distinct(candidates: list[Candidate], box) -> list[Candidate]:
    """Drop candidates that put the frame where a better one already did."""
    centre = np.array([[(box[0] + box[2]) / 2.0, (box[1] + box[3]) / 2.0, 1.0]])
    kept: list[Candidate] = []
    places: list[np.ndarray] = []
    radius = max(4.0, min(box[2] - box[0], box[3] - box[1]) / 4.0)
    for candidate in candidates:
        place = (candidate.transform @ centre.T).ravel()[:2]
        if all(np.linalg.norm(place - other) > radius for other in places):
            kept.append(candidate)
            places.append(place)
    return kept


def _correlation(grey_obs: np.ndarray, grey_world: np.ndarray, box, transform: np.ndarray) -> float:
    """NCC between the frame ``box`` of the observation and the world seen through ``transform``."""
    x0, y0, x1, y1 = box
    shift = np.array([[1.0, 0.0, x0], [0.0, 1.0, y0], [0.0, 0.0, 1.0]])
    to_world = (transform @ shift)[:2]  # frame pixel -> world pixel
    size = (x1 - x0, y1 - y0)
    seen = cv2.warpAffine(
        grey_world,
        to_world,
        size,
        flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
        borderMode=cv2.BORDER_CONSTANT,
        borderValue=-1.0,
    )
    frame = grey_obs[y0:y1, x0:x1]
    valid = seen >= 0.0
    if valid.sum() < 0.5 * valid.size:
        return -1.0
    a, b = frame[valid] - frame[valid].mean(), seen[valid] - seen[valid].mean()
    denominator = float(np.sqrt((a * a).sum() * (b * b).sum()))
    return float((a * b).sum() / denominator) if denominator > 1e-6 else 0.0


def _refine(candidate: Candidate, model: str) -> np.ndarray:
    """The transform (3, 3) re-estimated on the candidate's inliers: a similarity, or a
    homography when asked and there are enough inliers."""
    inliers = candidate.inliers
    if model == "homography" and len(inliers) >= 8:
        homography, _ = cv2.findHomography(_c(inliers[:, 0]), _c(inliers[:, 1]), 0)
        if homography is not None and abs(homography[2, 2]) > 1e-9:
            return homography / homography[2, 2]
    if len(inliers) >= 3:
        model, _ = cv2.estimateAffinePartial2D(_c(inliers[:, 0]), _c(inliers[:, 1]), method=cv2.LMEDS)
        if model is not None:
            return np.vstack([model, [0.0, 0.0, 1.0]])
    return candidate.transform


def _c(points: np.ndarray) -> np.ndarray:
    """Points (N, 2) as the contiguous float32 array OpenCV's estimators expect."""
    return np.ascontiguousarray(points, dtype=np.float32).reshape(-1, 1, 2)
