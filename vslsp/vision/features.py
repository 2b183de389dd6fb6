"""SIFT features φ of an object (paper, "Methodology": Algorithm 1 line 7 extracts φ_i with
SIFT, Lowe 2004, so that the object is recognised in later observations).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

_SIFT = None


def sift() -> cv2.SIFT:
    """One shared SIFT detector (creating it costs more than running it on a small frame)."""
    global _SIFT
    if _SIFT is None:
        _SIFT = cv2.SIFT_create()
    return _SIFT


@dataclass(frozen=True, eq=False)
class Features:
    """SIFT keypoints (N, 4): x, y, size, angle (px, px, px, deg) and descriptors (N, 128) float32."""

    keypoints: np.ndarray
    descriptors: np.ndarray

    def __len__(self) -> int:
        return len(self.keypoints)

    @classmethod
    def empty(cls) -> Features:
        return cls(np.zeros((0, 4), np.float32), np.zeros((0, 128), np.float32))

    def to_arrays(self, prefix: str) -> dict[str, np.ndarray]:
        """Arrays for ``np.savez`` under ``prefix`` (no pickle)."""
        return {f"{prefix}_keypoints": self.keypoints, f"{prefix}_descriptors": self.descriptors}

    @classmethod
    def from_arrays(cls, arrays, prefix: str) -> Features:
        return cls(np.asarray(arrays[f"{prefix}_keypoints"], np.float32),
                   np.asarray(arrays[f"{prefix}_descriptors"], np.float32))


def extract_features(image: np.ndarray, mask: np.ndarray | None = None) -> Features:
    """SIFT features of an RGB image (H, W, 3) uint8, optionally only where ``mask`` (H, W) is set.

    Keypoint coordinates are in the pixels of ``image``.
    """
    grey = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY)
    if mask is not None:
        mask = (np.asarray(mask) > 0).astype(np.uint8) * 255
    keypoints, descriptors = sift().detectAndCompute(grey, mask)
    if descriptors is None or not keypoints:
        return Features.empty()
    points = np.array([(k.pt[0], k.pt[1], k.size, k.angle) for k in keypoints], np.float32)
    return Features(points, descriptors.astype(np.float32))


def object_features(image: np.ndarray, box: tuple[int, int, int, int], margin: int = 8) -> Features:
    """SIFT features of the object inside ``box`` (x, y, w, h px) of an RGB image (H, W, 3).

    Only a frame a little larger than the box is processed; keypoints are in image pixels.
    """
    x, y, w, h = box
    x0, y0 = max(0, x - margin), max(0, y - margin)
    x1, y1 = min(image.shape[1], x + w + margin), min(image.shape[0], y + h + margin)
    features = extract_features(image[y0:y1, x0:x1])
    if len(features):
        features.keypoints[:, :2] += (x0, y0)
    return features
