"""The landmark: a black borderline on the table (paper, Algorithm 1 line 2 ``detectLandmarks``;
VSL-SP "Implementation": the robot detects the black line by thresholding).

The line is the longest straight band of dark, grey pixels. Its centre line is fitted with
RANSAC over those pixels and refined by a principal-axis fit of the inliers, so objects lying
on the line (which hide part of it but are not dark grey) and other dark specks do not bend
the fit. The line may be anywhere and at any angle in each image.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.errors import GroundingFailed, InputError

MIN_LENGTH = 0.25  # the visible line spans at least this fraction of the image diagonal
_HYPOTHESES = 64
_MAX_POINTS = 800


@dataclass(frozen=True)
class Line:
    """A line segment in the image: ends ``p1``, ``p2`` (x, y) px, p1 the left (or top) one."""

    p1: tuple[float, float]
    p2: tuple[float, float]

    @property
    def direction(self) -> np.ndarray:
        """Unit vector (2,) from p1 to p2."""
        d = np.subtract(self.p2, self.p1)
        return d / np.linalg.norm(d)

    @property
    def normal(self) -> np.ndarray:
        """Unit normal (2,): the direction rotated by +90° in image coordinates."""
        dx, dy = self.direction
        return np.array([-dy, dx])

    def signed_distance(self, point: tuple[float, float] | np.ndarray) -> float:
        """Distance (px) of a point from the line, positive on the side of :attr:`normal`."""
        return float(np.dot(np.asarray(point, float) - np.asarray(self.p1), self.normal))

    @property
    def angle(self) -> float:
        """Angle (deg) of the line from the image x axis, in [-90, 90)."""
        dx, dy = self.direction
        return float((np.degrees(np.arctan2(dy, dx)) + 90.0) % 180.0 - 90.0)

    def to_dict(self) -> dict:
        return {"p1": [round(self.p1[0], 2), round(self.p1[1], 2)], "p2": [round(self.p2[0], 2), round(self.p2[1], 2)]}

    @classmethod
    def from_dict(cls, data: dict) -> Line:
        (x1, y1), (x2, y2) = data["p1"], data["p2"]
        return cls((float(x1), float(y1)), (float(x2), float(y2)))


def fit_line(dark: np.ndarray, scale: int = 1, what: str = "image") -> Line:
    """The landmark line in a mask (h, w) of dark pixels; coordinates multiplied by ``scale``.

    Raises GroundingFailed (exit 1) when no straight dark band long enough is there.
    """
    h, w = dark.shape
    step = 2 if min(h, w) >= 200 else 1  # the line is several pixels thick: every other pixel will do
    ys, xs = np.nonzero(dark[::step, ::step])
    diagonal = float(np.hypot(h, w))
    tolerance = max(2.0, 0.02 * diagonal)
    if len(xs) * step < MIN_LENGTH * diagonal:
        raise _no_line(what)
    points = (np.column_stack([xs, ys]).astype(np.float32) + 0.5 / step) * step
    rng = np.random.default_rng(0)  # deterministic: same image, same line
    if len(points) > _MAX_POINTS:
        points = points[rng.choice(len(points), _MAX_POINTS, replace=False)]
    pairs = rng.integers(0, len(points), size=(_HYPOTHESES, 2))
    a, b = points[pairs[:, 0]], points[pairs[:, 1]]
    d = b - a
    length = np.linalg.norm(d, axis=1)
    good = length > 0.1 * diagonal  # far-apart pairs give well-conditioned directions
    if not good.any():
        raise _no_line(what)
    a, d = a[good], d[good] / length[good, None]
    normals = np.column_stack([-d[:, 1], d[:, 0]])
    distances = np.abs(points @ normals.T - (a * normals).sum(axis=1)).T  # (hypotheses, points)
    best = int(np.argmax((distances < tolerance).sum(axis=1)))
    inliers = points[distances[best] < tolerance]
    for _ in range(3):  # principal axis of the inlier band, re-centred on it
        centre = inliers.mean(axis=0)
        _, _, axes = np.linalg.svd(inliers - centre, full_matrices=False)
        direction = axes[0]
        normal = np.array([-direction[1], direction[0]])
        inliers = points[np.abs((points - centre) @ normal) < tolerance]
    along = (inliers - centre) @ direction
    if along.max() - along.min() < MIN_LENGTH * diagonal:
        raise _no_line(what)
    p1 = (centre + along.min() * direction) * scale
    p2 = (centre + along.max() * direction) * scale
    if (p1[0], p1[1]) > (p2[0], p2[1]):
        p1, p2 = p2, p1
    return Line((float(p1[0]), float(p1[1])), (float(p2[0]), float(p2[1])))


def find_landmark(image: np.ndarray) -> Line:
    """The black landmark line in an RGB image (H, W, 3) uint8 (ends in image pixels)."""
    from vslsp.vision.objects import segment

    seg = segment(image)
    return fit_line(seg.dark, seg.scale)


def _no_line(what: str) -> InputError:
    return GroundingFailed(
        f"no landmark line found in the {what}: put a black line (dark, thin and long, across "
        "at least a quarter of the view) on the table and keep it in view",
        cause=f"no landmark line found in the {what}",
    )
