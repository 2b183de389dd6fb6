"""Perception for VSL (paper, "Methodology" and VSL-SP "Implementation"): objects and their
colour symbols, the landmark line, change detection between a pre- and a post-action image,
SIFT features and match finding with adaptive frames.

Every function takes RGB images as numpy arrays (H, W, 3) uint8 and never reads the
simulator's ground truth.
"""

from vslsp.vision.change import Change, detect_change
from vslsp.vision.colour import COLOUR_NAMES, GENERIC, colour_name
from vslsp.vision.features import Features, extract_features
from vslsp.vision.image import read_image, write_image
from vslsp.vision.landmark import Line, find_landmark
from vslsp.vision.objects import DetectedObject, detect_objects

__all__ = [
    "COLOUR_NAMES",
    "GENERIC",
    "Change",
    "DetectedObject",
    "Features",
    "Line",
    "colour_name",
    "detect_change",
    "detect_objects",
    "extract_features",
    "find_landmark",
    "read_image",
    "write_image",
]
