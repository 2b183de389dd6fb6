"""Image input for perception: validation, reading files, the working scale, the table colour.

Paper, "Methodology": observations are plain RGB images of the world. Every perception
function takes ``uint8`` arrays of shape (H, W, 3) in RGB order; this module checks that once
and turns a wrong input into an :class:`~vslsp.errors.InputError` that says what to pass.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from vslsp.errors import InputError

# Perception runs on images whose longer side is at most this many pixels: enough for
# tabletop objects tens of pixels wide, and it keeps a grounding within milliseconds.
WORKING_SIZE = 320


def as_rgb(image: np.ndarray, what: str = "image") -> np.ndarray:
    """Check that ``image`` is an RGB picture: uint8 (H, W, 3), at least 32x32 pixels."""
    if not isinstance(image, np.ndarray):
        raise InputError(f"{what} must be a numpy array (H, W, 3) uint8 RGB, got {type(image).__name__}")
    if image.ndim != 3 or image.shape[2] != 3:
        raise InputError(f"{what} must have shape (H, W, 3) RGB, got shape {image.shape}")
    if image.dtype != np.uint8:
        raise InputError(f"{what} must be uint8 (0-255), got {image.dtype}; convert it with "
                         "(image * 255).astype(np.uint8) if it holds floats in 0..1")
    if min(image.shape[:2]) < 32:
        raise InputError(f"{what} is {image.shape[1]}x{image.shape[0]} pixels; use at least 32x32")
    return np.ascontiguousarray(image)


def read_image(path: str | Path) -> np.ndarray:
    """Read a PNG/JPEG file as RGB (H, W, 3) uint8; an unreadable file is an InputError."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"cannot read image {path}: no such file")
    image = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if image is None:
        raise InputError(f"cannot read image {path}: not an image file OpenCV can decode (use PNG or JPEG)")
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB)


def write_image(path: str | Path, image: np.ndarray) -> None:
    """Write an RGB (H, W, 3) uint8 image (PNG by the file's extension)."""
    if not cv2.imwrite(str(path), cv2.cvtColor(image, cv2.COLOR_RGB2BGR)):
        raise InputError(f"cannot write image {path}: check the folder exists and the extension (.png)")


def working_scale(shape: tuple[int, ...]) -> int:
    """The integer factor by which an image of ``shape`` is reduced for perception."""
    return max(1, int(np.ceil(max(shape[:2]) / WORKING_SIZE)))


def to_working(image: np.ndarray) -> tuple[np.ndarray, int]:
    """The image (H/s, W/s, 3) at the working scale, smoothed against sensor noise, and s."""
    scale = working_scale(image.shape)
    if scale > 1:
        image = cv2.resize(image, (image.shape[1] // scale, image.shape[0] // scale),
                           interpolation=cv2.INTER_AREA)
    return cv2.GaussianBlur(image, (5, 5), 0), scale


def table_colour(image: np.ndarray) -> np.ndarray:
    """The dominant colour (3,) float32 of an RGB image: the table the objects stand on.

    The mode of a coarse colour histogram over a subsample, refined by the median of the
    pixels in that bin: robust to objects, the line and sensor noise.
    """
    sample = image[::8, ::8].reshape(-1, 3)
    bins = (sample >> 4).astype(np.int32)
    code = (bins[:, 0] << 8) | (bins[:, 1] << 4) | bins[:, 2]
    mode = np.bincount(code, minlength=4096).argmax()
    centre = np.median(sample[code == mode], axis=0)
    near = np.abs(sample - centre).max(axis=1) < 40
    return np.median(sample[near], axis=0).astype(np.float32)


def channel_max(image: np.ndarray) -> np.ndarray:
    """Per-pixel maximum (H, W) over the channels of (H, W, 3) (OpenCV: much faster than numpy)."""
    a, b, c = cv2.split(image)
    return cv2.max(cv2.max(a, b), c)


def channel_min(image: np.ndarray) -> np.ndarray:
    """Per-pixel minimum (H, W) over the channels of (H, W, 3)."""
    a, b, c = cv2.split(image)
    return cv2.min(cv2.min(a, b), c)


def colour_distance(image: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """Largest per-channel difference (H, W) uint8 between an image (H, W, 3) and one colour (3,)."""
    a, b, c = (cv2.absdiff(channel, float(value)) for channel, value in zip(cv2.split(image), colour))
    return cv2.max(cv2.max(a, b), c)
