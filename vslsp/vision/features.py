"""SIFT features φ of an object (paper, "Methodology": Algorithm 1 line 7 extracts φ_i with
SIFT, Lowe 2004, so that the object is recognised in later observations).
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from dataclasses import dataclass

import cv2
import numpy as np

from vslsp.stages import in_stage

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
        return cls(
            np.asarray(arrays[f"{prefix}_keypoints"], np.float32),
            np.asarray(arrays[f"{prefix}_descriptors"], np.float32),
        )


@in_stage("perception")
def extract_features(image: np.ndarray, mask: np.ndarray | None = None) -> Features:
    """SIFT features of an RGB image (H, W, 3) uint8, optionally only where ``mask`` (H, W) is set.

    Keypoint coordinates are in the pixels of ``image``. With a mask only the mask's bounding
    box and a rim of :data:`MASK_RIM` px about it are processed: OpenCV builds the whole scale
    space under a mask, so a small object in a 1280x960 view would otherwise cost a full
    extraction (about 0.3 s instead of 10-20 ms; the keypoints inside the mask are the same but
    for a few of the largest scales, which the rim cuts).
    """
    offset = (0, 0)
    if mask is not None:
        mask = (np.asarray(mask) > 0).astype(np.uint8) * 255
        rows, cols = np.nonzero(mask.any(axis=1))[0], np.nonzero(mask.any(axis=0))[0]
        if not len(rows):
            return Features.empty()
        y0, y1 = max(0, rows[0] - MASK_RIM), min(mask.shape[0], rows[-1] + 1 + MASK_RIM)
        x0, x1 = max(0, cols[0] - MASK_RIM), min(mask.shape[1], cols[-1] + 1 + MASK_RIM)
        image, mask, offset = image[y0:y1, x0:x1], np.ascontiguousarray(mask[y0:y1, x0:x1]), (x0, y0)
    grey = cv2.cvtColor(np.ascontiguousarray(image), cv2.COLOR_RGB2GRAY)
    keypoints, descriptors = sift().detectAndCompute(grey, mask)
    if descriptors is None or not keypoints:
        return Features.empty()
    points = np.array([(k.pt[0] + offset[0], k.pt[1] + offset[1], k.size, k.angle) for k in keypoints], np.float32)
    return Features(points, descriptors.astype(np.float32))


MASK_RIM = 32  # px of image about a mask's bounding box that SIFT sees (its blurs and descriptors reach out)


class FeatureMemo:
    """:func:`extract_features` of whole images, remembered by the image's content (its bytes'
    SHA-1 and shape) for the last ``size`` images: a reproduction that looks again at a world
    nothing changed in, or matches the same recorded observation twice, extracts SIFT once
    (about 60 ms a 640x480 view). The features handed out are read-only."""

    def __init__(self, size: int = 8) -> None:
        self.size = size
        self._seen: OrderedDict[tuple[bytes, tuple[int, ...]], Features] = OrderedDict()

    def __call__(self, image: np.ndarray) -> Features:
        image = np.ascontiguousarray(image)
        key = (hashlib.sha1(image.tobytes()).digest(), image.shape)
        found = self._seen.get(key)
        if found is None:
            found = extract_features(image)
            found.keypoints.flags.writeable = found.descriptors.flags.writeable = False
            self._seen[key] = found
            while len(self._seen) > self.size:
                self._seen.popitem(last=False)
        self._seen.move_to_end(key)
        return found


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
