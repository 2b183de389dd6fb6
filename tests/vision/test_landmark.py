"""The landmark line: found anywhere at any angle, unbent by objects lying on it."""

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vision.landmark import find_landmark


def _distance_to(line, point):
    return abs(line.signed_distance(point))


@pytest.mark.parametrize(
    "a, b", [((0, 300), (640, 260)), ((0, 100), (640, 420)), ((200, 0), (330, 480)), ((0, 240), (640, 240))]
)
def test_the_line_is_found_where_it_was_drawn(a, b):
    line = find_landmark(tabletop_image([], line=(a, b), noise=5))
    for t in np.linspace(0.1, 0.9, 5):
        point = np.add(a, t * np.subtract(b, a))
        assert _distance_to(line, point) < 1.5
    truth = np.degrees(np.arctan2(b[1] - a[1], b[0] - a[0]))
    assert abs((line.angle - truth + 90) % 180 - 90) < 1.0


def test_objects_on_the_line_do_not_bend_the_fit():
    squares = [
        Square(colour, (x, 300 - 40 * x / 640), 70, 25) for colour, x in (("red", 120), ("blue", 330), ("green", 520))
    ]
    line = find_landmark(tabletop_image(squares, line=((0, 300), (640, 260)), noise=10))
    for x in (0, 320, 640):
        assert _distance_to(line, (x, 300 - 40 * x / 640)) < 1.5


def test_the_segment_ends_span_the_visible_line():
    line = find_landmark(tabletop_image([], line=((0, 300), (640, 260))))
    assert line.p1[0] < 5 and line.p2[0] > 635


def test_no_line_is_an_input_error_that_says_what_to_do():
    with pytest.raises(InputError, match="no landmark line found.*black line"):
        find_landmark(tabletop_image([Square("red", (200, 200))], line=None))


def test_a_dark_blob_is_not_a_line():
    image = tabletop_image([Square((10, 10, 10), (300, 200), 90)], line=None)
    with pytest.raises(InputError, match="no landmark line"):
        find_landmark(image)
