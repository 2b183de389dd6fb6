"""alphabet-ordering (paper, "Alphabet Ordering"): the letters A-D sorted along a static
right-angle baseline, from a new scatter; checked on the ground truth."""

import pytest

from vslsp.worlds.panda_table import layouts as scenes

pytestmark = pytest.mark.slow


def test_alphabet_ordering_puts_the_letters_in_order_along_the_static_baseline(reproduce):
    _, poses, _ = reproduce("alphabet-ordering", 0)
    for letter, (x, y, _) in scenes.LETTER_GOALS.items():  # absolute positioning
        assert poses[letter][:2] == pytest.approx((x, y), abs=0.015)
    assert poses["A"][1] > poses["B"][1] > poses["C"][1] > poses["D"][1]  # and in order
