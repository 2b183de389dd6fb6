"""animal-puzzle (paper, "Animal Puzzle"): the frog's and the giraffe's halves assembled on the
'pond' and 'tree' labels, which the tutor moved before the reproduction; ground truth."""

import numpy as np
import pytest

from vslsp.worlds.panda_table import layouts as scenes

pytestmark = pytest.mark.slow


def test_animal_puzzle_assembles_each_animal_on_its_moved_label(reproduce, local):
    _, poses, demo_landmarks = reproduce("animal-puzzle", 0)
    for animal, label in scenes.LABEL_OF.items():
        assert np.hypot(*np.subtract(poses[label][:2], demo_landmarks[label][:2])) > 0.03  # the label moved
        for part, (x, y, yaw) in scenes.ON_LABEL.items():
            rx, ry, ryaw = local(poses, label, f"{animal}-{part}")
            assert (rx, ry) == pytest.approx((x, y), abs=0.015)
            assert abs(ryaw - yaw) < np.radians(12)
            assert poses[f"{animal}-{part}"][2] == pytest.approx(scenes.PLATE, abs=0.004)  # on the label
