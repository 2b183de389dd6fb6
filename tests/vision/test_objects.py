"""Object detection: every object wholly in view, with its colour symbol, centroid, box and
orientation; not the landmark, not the table, not what only touches the image border."""

import numpy as np
import pytest

from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vision.objects import detect_objects


def test_objects_are_found_left_to_right_with_colour_and_centroid():
    squares = [Square("green", (120, 150)), Square("orange", (330, 400), angle=30), Square("purple", (520, 180))]
    objects = detect_objects(tabletop_image(squares))
    assert [o.name for o in objects] == ["green", "orange", "purple"]
    for obj, square in zip(objects, squares):
        assert np.hypot(*np.subtract(obj.centroid, square.centre)) < 1.5
        assert 0.8 * 60**2 < obj.area < 1.2 * 60**2
        x, y, w, h = obj.box
        assert x <= square.centre[0] <= x + w and y <= square.centre[1] <= y + h


@pytest.mark.parametrize("angle", [-30.0, 0.0, 20.0])
def test_orientation_is_the_square_angle_modulo_90(angle):
    (obj,) = detect_objects(tabletop_image([Square("blue", (300, 150), 80, angle)]))
    assert abs((obj.orientation - angle + 45) % 90 - 45) < 3.0


def test_an_object_lying_on_the_line_is_one_object_and_the_line_is_none():
    image = tabletop_image([Square("yellow", (320, 280))], line=((0, 290), (640, 270)))
    (obj,) = detect_objects(image)
    assert obj.name == "yellow" and np.hypot(obj.centroid[0] - 320, obj.centroid[1] - 280) < 2.0


def test_the_robot_body_at_the_image_border_is_not_an_object():
    # The iCub's dark red covers reaching into the view from the bottom edge.
    image = tabletop_image([Square("blue", (300, 150)), Square((110, 25, 25), (320, 470), 140)])
    assert [o.name for o in detect_objects(image)] == ["blue"]


def test_noise_and_dim_light_do_not_create_or_lose_objects():
    squares = [Square("red", (150, 120)), Square("blue", (450, 400), angle=15)]
    objects = detect_objects(tabletop_image(squares, noise=20, brightness=0.85, seed=3))
    assert [o.name for o in objects] == ["red", "blue"]


def test_features_are_sift_descriptors_inside_the_object_box():
    (obj,) = detect_objects(tabletop_image([Square("purple", (300, 200), 80, 10)]))
    assert obj.features is not None and len(obj.features) > 0
    assert obj.features.descriptors.shape == (len(obj.features), 128)
    x, y, w, h = obj.box
    kx, ky = obj.features.keypoints[:, 0], obj.features.keypoints[:, 1]
    assert (kx > x - 10).all() and (kx < x + w + 10).all() and (ky > y - 10).all() and (ky < y + h + 10).all()
    assert detect_objects(tabletop_image([Square("purple", (300, 200))]), features=False)[0].features is None


def test_an_empty_table_has_no_objects():
    assert detect_objects(tabletop_image([], noise=10)) == []


def test_a_grey_hand_at_the_end_of_the_robot_s_arm_is_not_an_object():
    # In the head camera the parked arm reaches into the view: dark red covers and a white hand.
    arm = Square((110, 25, 25), (560, 450), 160, 30)
    hand = Square((235, 235, 235), (480, 385), 50, 30)
    objects = detect_objects(tabletop_image([Square("blue", (300, 150)), arm, hand]))
    assert [o.name for o in objects] == ["blue"]
