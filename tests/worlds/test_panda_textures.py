"""The procedural textures of the real-world tasks: deterministic, and busy enough for SIFT at
the size the camera sees them (a 5 cm tile about a hundred pixels wide), each its own."""

import cv2
import numpy as np
import pytest

from vslsp.vision.features import extract_features
from vslsp.worlds.panda_table import textures

CAMERA_SCALE = 1500.0 / textures.PX_PER_M  # the top-down view's px per m over the textures'

ALL = {
    **{f"letter {c}": lambda c=c: textures.letter_tile(c, (0.04, 0.055)) for c in "ABCD"},
    **{
        f"{a} {p}": lambda a=a, p=p: textures.puzzle_piece(a, p, (0.055, 0.04))
        for a in ("frog", "giraffe")
        for p in (0, 1)
    },
    **{s: lambda s=s: textures.picture(s, (0.055, 0.045)) for s in textures.PICTURES},
    **{f"domino {k}": lambda k=k: textures.domino_piece(k, (0.07, 0.035)) for k in range(1, 6)},
    **{f"disk {k}": lambda k=k: textures.hanoi_disk(k, (0.045 + 0.015 * k, 0.045)) for k in (1, 2, 3)},
    "base": lambda: textures.hanoi_base((0.12, 0.12)),
    "baseline": lambda: textures.baseline((0.025, 0.34), "long"),
    "pond": lambda: textures.label("pond", (0.15, 0.09)),
    "tree": lambda: textures.label("tree", (0.15, 0.09)),
    "bin animals": lambda: textures.bin_plate("animals", (0.2, 0.13)),
    "bin machines": lambda: textures.bin_plate("machines", (0.2, 0.13)),
}


def seen(texture: np.ndarray) -> np.ndarray:
    return cv2.resize(texture, None, fx=CAMERA_SCALE, fy=CAMERA_SCALE, interpolation=cv2.INTER_AREA)


@pytest.mark.parametrize("name", sorted(ALL))
def test_every_texture_is_deterministic_and_gives_sift_plenty_of_keypoints(name):
    texture = ALL[name]()
    assert texture.dtype == np.uint8 and texture.ndim == 3 and texture.shape[2] == 3
    assert np.array_equal(texture, ALL[name]())  # same call, same pixels
    side_cm = min(texture.shape[:2]) / textures.PX_PER_M * 100
    assert len(extract_features(seen(texture))) >= 6 * side_cm  # e.g. >= 24 on a 4 cm wide piece


def test_a_texture_is_told_from_the_others_of_its_task():
    """Ratio-tested SIFT matches of letter A find A again, far more than in B, C or D."""
    a = extract_features(seen(textures.letter_tile("A", (0.04, 0.055))))
    matcher = cv2.BFMatcher(cv2.NORM_L2)

    def matches(other: np.ndarray) -> int:
        features = extract_features(cv2.rotate(seen(other), cv2.ROTATE_90_CLOCKWISE))
        pairs = matcher.knnMatch(a.descriptors, features.descriptors, k=2)
        return sum(1 for m in pairs if len(m) == 2 and m[0].distance < 0.75 * m[1].distance)

    itself = matches(textures.letter_tile("A", (0.04, 0.055)))
    others = [matches(textures.letter_tile(c, (0.04, 0.055))) for c in "BCD"]
    assert itself >= 15 and max(others) <= itself / 4


def test_domino_pieces_laid_end_to_end_complete_a_picture():
    first, second = textures.domino_piece(1), textures.domino_piece(2)
    half = first.shape[1] // 2
    joined = np.hstack([first[:, half:], second[:, :half]])  # picture 1: right half of piece 1, left of 2
    picture = textures._domino_picture(1, (0.08, 0.04))
    inside = (slice(10, -10), slice(10, half - 10))
    assert np.abs(joined[inside].astype(int) - picture[inside].astype(int)).mean() < 1.0


def test_unknown_subjects_are_refused():
    with pytest.raises(ValueError, match="frog, giraffe"):
        textures.puzzle_piece("cow", 0)
    with pytest.raises(ValueError, match="subjects"):
        textures.picture("plane")
