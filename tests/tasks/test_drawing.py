"""The report pictures' labels (vslsp.tasks.drawing.label): a text wider than its panel goes on
as many lines as it needs, each on its dark band; a short one stays on one line."""

from __future__ import annotations

import numpy as np

from vslsp.tasks.drawing import label


def banded_rows(image: np.ndarray) -> np.ndarray:
    """The rows a label darkened (a white panel: any pixel below 200 in them)."""
    return np.nonzero((image < 200).any(axis=(1, 2)))[0]


def test_a_long_caption_wraps_inside_the_panel_and_a_short_one_does_not():
    panel = np.full((200, 240, 3), 255, np.uint8)
    short = label(panel, "op 1: post")
    long = label(panel, "op 2: post-place; operated roof-1; disturbed roof-2, body-3; slip: roof-2")
    assert banded_rows(short).max() < 40  # one line
    assert banded_rows(long).max() > 70  # three or more lines, not cut off at the right edge
    # every word was drawn: the darkened area grows with the text, within the panel's width
    assert (long < 200).any(axis=2).sum() > 3 * (short < 200).any(axis=2).sum()
    assert np.array_equal(panel, np.full((200, 240, 3), 255, np.uint8))  # the panel is not changed
