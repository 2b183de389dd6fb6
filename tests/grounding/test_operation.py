"""Grounding one operation (push / pull / null) and every object of one observation."""

import json

import numpy as np
import pytest

import vslsp
from vslsp.errors import InputError
from vslsp.grounding.operation import Grounding, ground, ground_scene
from vslsp.grounding.synthetic import Square, tabletop_image

LINE = ((0, 300), (640, 260))  # far is above it in the image (the robot is at the bottom)
STILL = Square("blue", (500, 420), angle=20)


def _images(before: Square, after: Square, line=LINE):
    return (
        tabletop_image([before, STILL], line=line, noise=4, seed=1),
        tabletop_image([after, STILL], line=line, noise=4, seed=2),
    )


@pytest.mark.parametrize(
    "before, after, far, action",
    [
        ((200, 400), (210, 150), (False, True), "push"),
        ((200, 150), (230, 400), (True, False), "pull"),
        ((200, 150), (400, 120), (True, True), None),
        ((120, 420), (320, 400), (False, False), None),
    ],
)
def test_push_pull_and_null_are_grounded(before, after, far, action):
    grounding = ground(*_images(Square("green", before), Square("green", after, angle=12)))
    assert grounding.name == "green"
    assert (grounding.far_pre, grounding.far_post) == far
    assert grounding.action == action
    assert np.hypot(*np.subtract(grounding.pre, before)) < 1.5
    assert np.hypot(*np.subtract(grounding.post, after)) < 1.5


def test_the_robot_side_turns_far_around():
    pre, post = _images(Square("red", (200, 400)), Square("red", (210, 150)))
    assert ground(pre, post, robot_side="top").action == "pull"


def test_to_dict_is_the_json_contract_of_vslsp_ground():
    grounding = vslsp.ground(*_images(Square("yellow", (200, 400)), Square("yellow", (210, 150))))
    data = json.loads(json.dumps(grounding.to_dict()))
    assert set(data) == {"object", "landmark", "far", "action"}
    assert set(data["object"]) == {"name", "pre", "post"} and data["object"]["name"] == "yellow"
    assert set(data["object"]["pre"]) == set(data["object"]["post"]) == {"x", "y"}
    assert set(data["landmark"]) == {"p1", "p2"} and len(data["landmark"]["p1"]) == 2
    assert data["far"] == {"pre": False, "post": True} and data["action"] == "push"
    assert Grounding.from_dict(data).to_dict() == data


def test_a_pair_without_a_landmark_is_an_input_error():
    pre, post = _images(Square("red", (200, 400)), Square("red", (210, 150)), line=None)
    with pytest.raises(InputError, match="no landmark line found in the pre-action image"):
        ground(pre, post)


def test_every_object_of_one_observation_is_grounded():
    image = tabletop_image(
        [Square("red", (100, 150)), Square("orange", (300, 420)), Square("red", (520, 120))], line=LINE, noise=8
    )
    scene = ground_scene(image)
    assert [o.name for o in scene.objects] == ["red", "orange", "red"]
    assert scene.far == (True, False, True)
    assert scene.far_by_name() == {"red": True, "orange": False, "red_2": True}
    assert scene.to_dict()["objects"][1] == {
        "name": "orange",
        "x": pytest.approx(300, abs=1.5),
        "y": pytest.approx(420, abs=1.5),
        "far": False,
    }


def test_a_line_moved_between_the_images_is_found_in_each():
    # The object stays above where the line was, but the line moved above it: far -> not far.
    pre = tabletop_image([Square("red", (200, 230)), STILL], line=LINE, noise=4, seed=1)
    post = tabletop_image([Square("red", (210, 200)), STILL], line=((0, 150), (640, 130)), noise=4, seed=2)
    grounding = ground(pre, post)
    assert (grounding.far_pre, grounding.far_post, grounding.action) == (True, False, "pull")
    assert abs(grounding.post_landmark.signed_distance((320, 140))) < 1.5


@pytest.mark.parametrize("robot_side, action", [("left", "push"), ("right", "pull")])
def test_a_robot_beside_the_image_sees_far_across_a_vertical_line(robot_side, action):
    line = ((330, 0), (300, 480))
    pre, post = _images(Square("green", (150, 200)), Square("green", (470, 180)), line=line)
    grounding = ground(pre, post, robot_side=robot_side)
    assert grounding.action == action and grounding.robot_side == robot_side


def test_a_scene_without_a_landmark_or_with_one_towards_the_robot_is_an_input_error():
    with pytest.raises(InputError, match="no landmark line found in the image"):
        ground_scene(tabletop_image([STILL], line=None))
    with pytest.raises(InputError, match="runs towards the robot"):
        ground_scene(tabletop_image([STILL], line=((320, 0), (330, 480))))
