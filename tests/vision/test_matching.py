"""Match finding: SIFT + RANSAC pose of a recorded observation in a new world, and the
adaptive frame of the paper's house-and-roof simulation."""

import cv2
import numpy as np
import pytest

from vslsp.vision.matching import NoMatch, find_best_match, frame_sizes
from vslsp.worlds.house_roof.sprites import BODY_SIZE, houses_world


def test_frames_grow_from_the_object_to_the_whole_world():
    sizes = frame_sizes(40, (360, 480, 3))
    assert sizes[0] == 40 and sizes[-1] == 480
    assert all(b > a for a, b in zip(sizes, sizes[1:]))


@pytest.mark.parametrize("angle, shift", [(25.0, (40.0, -30.0)), (-60.0, (-25.0, 15.0)), (0.0, (70.0, 10.0))])
def test_a_known_rotation_and_translation_are_recovered(angle, shift):
    observation = houses_world([(200, 150)], [0], size=(480, 360))
    point = (230.0, 165.0)  # the house's centre
    # Turn the world by `angle` (counter-clockwise on screen) about the house and shift it.
    turn = cv2.getRotationMatrix2D(point, angle, 1.0)
    turn[:, 2] += shift
    world = cv2.warpAffine(observation, turn, (480, 360), borderMode=cv2.BORDER_REPLICATE)
    match = find_best_match(observation, world, point, object_size=BODY_SIZE)
    expected = turn @ np.array([*point, 1.0])
    assert np.hypot(match.x - expected[0], match.y - expected[1]) < 3.0
    # Image y points down: counter-clockwise on screen is a negative θ.
    assert abs(np.degrees(match.theta) + angle) < 2.0
    assert match.score > 0.8 and not match.ambiguous


# The house-and-roof simulation: in the demonstration the tutor has put roofs on the first two
# bodies, then places the third roof *below* the third body. In the new world two bodies
# already carry roofs; the right place is below the body without one.
DEMO = houses_world([(40, 100), (200, 100), (360, 100)], [0, 1], loose_roofs=[(60, 320)])
PLACE = (390.0, 175.0)  # where the third roof went, below the third body
WORLD = houses_world([(60, 170), (200, 60), (340, 190)], [0, 2], loose_roofs=[(380, 330)], seed=1)
RIGHT = (230.0, 135.0)  # below the body without a roof


def test_a_fixed_small_frame_sees_identical_bodies_and_picks_a_wrong_place():
    match = find_best_match(DEMO, WORLD, PLACE, object_size=40, frames=[60])
    assert match.ambiguous
    assert np.hypot(match.x - RIGHT[0], match.y - RIGHT[1]) > BODY_SIZE


def test_the_adaptive_frame_grows_until_the_roofs_tell_the_bodies_apart():
    match = find_best_match(DEMO, WORLD, PLACE, object_size=40)
    assert not match.ambiguous
    assert np.hypot(match.x - RIGHT[0], match.y - RIGHT[1]) < 3.0
    assert match.frame > 60  # it needed more context than the small frame
    assert abs(match.theta) < np.radians(2.0)


def test_the_paper_s_general_transform_can_be_fitted_and_decomposed():
    observation = houses_world([(120, 100), (300, 180)], [0, 1], size=(480, 360))
    turn = cv2.getRotationMatrix2D((240.0, 180.0), 15.0, 1.0)
    world = cv2.warpAffine(observation, turn, (480, 360), borderMode=cv2.BORDER_REPLICATE)
    match = find_best_match(observation, world, (150.0, 115.0), object_size=BODY_SIZE, model="homography")
    assert match.decomposition.compose() == pytest.approx(match.transform / match.transform[2, 2])
    assert abs(np.degrees(match.theta) + 15.0) < 2.0


def test_an_object_s_recorded_features_recognise_it_in_a_later_observation():
    from vslsp.vision.features import object_features

    observation = houses_world([(200, 150)], [0], size=(480, 360))
    phi = object_features(observation, (200, 120, BODY_SIZE, BODY_SIZE + 30))  # body and roof
    later = houses_world([(300, 200)], [0], size=(480, 360), seed=3)  # moved 100 px right, 50 down
    match = find_best_match(observation, later, (230.0, 165.0), object_size=BODY_SIZE, observation_features=phi)
    assert np.hypot(match.x - 330.0, match.y - 215.0) < 3.0 and abs(np.degrees(match.theta)) < 2.0


def test_an_object_that_is_not_in_the_world_is_a_no_match_result_not_an_exception():
    blank = np.full_like(WORLD, 128)
    match = find_best_match(DEMO, blank, PLACE, object_size=40)
    assert isinstance(match, NoMatch) and not match and "no SIFT match" in match.reason
