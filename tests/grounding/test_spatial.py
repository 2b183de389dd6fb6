"""Spatial reasoning: (far b) relative to the line and the robot's side; push / pull / null."""

import pytest

from vslsp.errors import InputError
from vslsp.grounding.spatial import far_of, identify_action
from vslsp.vision.landmark import Line

HORIZONTAL = Line((0.0, 240.0), (640.0, 240.0))
VERTICAL = Line((320.0, 0.0), (320.0, 480.0))


@pytest.mark.parametrize(
    "line, robot_side, point, far",
    [
        (HORIZONTAL, "bottom", (100, 100), True),
        (HORIZONTAL, "bottom", (100, 400), False),
        (HORIZONTAL, "top", (100, 100), False),
        (HORIZONTAL, "top", (100, 400), True),
        (VERTICAL, "left", (500, 100), True),
        (VERTICAL, "left", (100, 100), False),
        (VERTICAL, "right", (100, 100), True),
        (Line((0.0, 400.0), (640.0, 100.0)), "bottom", (500, 120), True),
        (Line((640.0, 100.0), (0.0, 400.0)), "bottom", (500, 120), True),  # end order does not matter
    ],
)
def test_far_is_the_other_side_of_the_line_from_the_robot(line, robot_side, point, far):
    assert far_of(point, line, robot_side) is far


def test_a_line_running_towards_the_robot_leaves_far_undefined():
    with pytest.raises(InputError, match="runs towards the robot"):
        far_of((100, 100), VERTICAL, "bottom")


def test_an_unknown_robot_side_is_an_input_error():
    with pytest.raises(InputError, match="unknown robot side 'behind'"):
        far_of((100, 100), HORIZONTAL, "behind")


@pytest.mark.parametrize(
    "pre, post, action", [(False, True, "push"), (True, False, "pull"), (True, True, None), (False, False, None)]
)
def test_the_action_is_identified_from_the_change_of_far(pre, post, action):
    assert identify_action(pre, post) == action
