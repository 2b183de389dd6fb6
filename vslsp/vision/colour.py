"""Colour names for object symbols (paper, VSL-SP "Implementation": objects are told apart
by colour, e.g. B_green, B_orange).

An object's colour is the saturation-weighted circular mean of its pixels' hue, named by the
hue band it falls in. Shading changes brightness, not hue, so the lit and the shaded faces of
a cube agree. Colours that are too pale, too dark, or between the bands (cyan, pink, brown,
grey...) get the honest generic symbol :data:`GENERIC` rather than a wrong name.
"""

from __future__ import annotations

import cv2
import numpy as np

GENERIC = "object"
COLOUR_NAMES = ("red", "orange", "yellow", "green", "blue", "purple")
# Hue bands in degrees [start, end): chosen between the hues of saturated paints/plastics.
_HUE_BANDS = (
    ("red", -20.0, 16.0),
    ("orange", 16.0, 42.0),
    ("yellow", 42.0, 70.0),
    ("green", 70.0, 165.0),
    ("blue", 195.0, 255.0),
    ("purple", 255.0, 320.0),
)
MIN_SATURATION = 0.45  # below: greyish (grey, white, beige, pink)
MIN_BRIGHTNESS = 0.40  # the brightest face darker than this: black, brown, dark shades


def colour_name(pixels: np.ndarray) -> str:
    """Name the colour of an object from its pixels (N, 3) uint8 RGB (N >= 1)."""
    pixels = np.asarray(pixels, dtype=np.uint8).reshape(-1, 1, 3)
    hsv = cv2.cvtColor(pixels, cv2.COLOR_RGB2HSV_FULL).reshape(-1, 3).astype(np.float32)
    hue = hsv[:, 0] * (2.0 * np.pi / 256.0)
    saturation = hsv[:, 1] / 255.0
    value = hsv[:, 2] / 255.0
    if np.median(saturation) < MIN_SATURATION or np.percentile(value, 90) < MIN_BRIGHTNESS:
        return GENERIC
    weight = saturation * value
    mean_hue = np.degrees(np.arctan2((weight * np.sin(hue)).sum(), (weight * np.cos(hue)).sum()))
    for name, start, end in _HUE_BANDS:
        for hue_deg in (mean_hue, mean_hue - 360.0, mean_hue + 360.0):
            if start <= hue_deg < end:
                return name
    return GENERIC


def _class_table() -> np.ndarray:
    """Hue (OpenCV's full range, 0..255) -> colour class: 1 + index in COLOUR_NAMES, or
    len(COLOUR_NAMES) + 1 for hues between the bands."""
    table = np.full(256, len(COLOUR_NAMES) + 1, np.uint8)
    degrees = np.arange(256) * 360.0 / 256.0
    for index, (_, start, end) in enumerate(_HUE_BANDS):
        for shift in (0.0, 360.0):
            table[(degrees >= start + shift) & (degrees < end + shift)] = index + 1
    return table


_CLASS_OF_HUE = _class_table()
GREY_CLASS = len(COLOUR_NAMES) + 2


def colour_classes(image: np.ndarray) -> np.ndarray:
    """Colour class (H, W) uint8 of every pixel of an RGB image (H, W, 3): the hue band
    (1..6, 7 between bands) or 8 for greyish pixels. Faces of one object share a class."""
    hsv = cv2.cvtColor(image, cv2.COLOR_RGB2HSV_FULL)
    classes = _CLASS_OF_HUE[hsv[:, :, 0]]
    classes[hsv[:, :, 1] < MIN_SATURATION * 255 * 0.75] = GREY_CLASS
    return classes
