"""Change detection: the one object that moved, robust to noise and light; clear errors
for image pairs that cannot be grounded."""

import numpy as np
import pytest

from vslsp.errors import GroundingFailed, InputError
from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vision.change import CHANGE_THRESHOLD, changed_pixels, default_min_move, detect_change

STILL = Square("blue", (480, 400), angle=20)


def _pair(moved_from, moved_to, **post_kwargs):
    pre = tabletop_image([moved_from, STILL], noise=post_kwargs.get("noise", 0), seed=1)
    post = tabletop_image([moved_to, STILL], seed=2, **post_kwargs)
    return pre, post


def test_the_moved_object_is_found_at_both_places():
    change = detect_change(*_pair(Square("red", (150, 150)), Square("red", (260, 380), angle=15)))
    assert change.before.name == change.after.name == "red"
    assert np.hypot(change.before.centroid[0] - 150, change.before.centroid[1] - 150) < 1.5
    assert np.hypot(change.after.centroid[0] - 260, change.after.centroid[1] - 380) < 1.5


def test_a_short_move_with_overlap_still_gives_the_whole_object_at_both_places():
    change = detect_change(*_pair(Square("green", (200, 150)), Square("green", (225, 160))))
    assert np.hypot(change.before.centroid[0] - 200, change.before.centroid[1] - 150) < 1.5
    assert np.hypot(change.after.centroid[0] - 225, change.after.centroid[1] - 160) < 1.5


@pytest.mark.parametrize("noise, brightness", [(20, 1.0), (0, 0.85), (10, 1.12)])
def test_noise_and_a_global_brightness_change_are_not_motion(noise, brightness):
    change = detect_change(
        *_pair(Square("orange", (150, 150)), Square("orange", (300, 380)), noise=noise, brightness=brightness)
    )
    assert change.before.name == "orange"
    assert np.hypot(change.after.centroid[0] - 300, change.after.centroid[1] - 380) < 2.0


def test_nothing_moved_is_an_input_error():
    image = tabletop_image([STILL], noise=5)
    with pytest.raises(InputError, match="nothing moved"):
        detect_change(image, tabletop_image([STILL], noise=5, seed=9, brightness=0.9))


def test_several_moved_objects_are_named_with_where_they_went():
    pre = tabletop_image([Square("red", (150, 150)), Square("blue", (480, 400))])
    post = tabletop_image([Square("red", (150, 380)), Square("blue", (480, 130))])
    with pytest.raises(InputError, match=r"more than one object moved.*red left \(x=150, y=150\).*blue") as error:
        detect_change(pre, post)
    assert "blue arrived at (x=481, y=130)" in str(error.value)


def test_an_object_swapped_for_another_is_several_changes():
    pre = tabletop_image([Square("red", (150, 150)), STILL])
    post = tabletop_image([Square("green", (300, 380)), STILL])
    with pytest.raises(InputError, match="more than one object moved"):
        detect_change(pre, post)


def test_an_object_that_leaves_the_view_is_an_input_error():
    pre = tabletop_image([Square("red", (150, 150)), STILL])
    post = tabletop_image([Square("red", (620, 150)), STILL])
    with pytest.raises(InputError, match="red object at .* not wholly in view"):
        detect_change(pre, post)


def test_images_of_different_sizes_are_an_input_error():
    pre = tabletop_image([STILL])
    post = tabletop_image([STILL], size=(320, 240))
    with pytest.raises(InputError, match="differ in size.*640x480.*320x240"):
        detect_change(pre, post)


def test_an_object_moved_less_than_min_move_is_left_out_as_nudged():
    # blue is pulled across the table; red beside it is nudged 6 px by the hand
    pre = tabletop_image([Square("blue", (200, 150)), Square("red", (450, 200))])
    post = tabletop_image([Square("blue", (220, 400)), Square("red", (456, 200))])
    with pytest.raises(GroundingFailed, match="more than one object moved"):
        detect_change(pre, post)  # min_move 0: every change counts, as the paper's VSL
    change = detect_change(pre, post, min_move=default_min_move(pre.shape))
    assert change.before.name == "blue" and [name for name, _ in change.nudged] == ["red"]
    assert 5.0 < change.nudged[0][1] < 7.0
    assert default_min_move((480, 640, 3)) == 8.0 and default_min_move((960, 1280)) == 16.0


def test_min_move_never_leaves_out_every_moved_object():
    pre = tabletop_image([Square("blue", (200, 150)), Square("red", (450, 200))])
    post = tabletop_image([Square("blue", (206, 150)), Square("red", (456, 200))])
    with pytest.raises(GroundingFailed, match="more than one object moved"):
        detect_change(pre, post, min_move=8.0)


def test_a_pixel_changed_when_its_largest_channel_difference_exceeds_the_threshold():
    pre = np.full((40, 40, 3), 100, np.uint8)
    post = pre.copy()
    post[5:15, 5:15, 1] += CHANGE_THRESHOLD  # exactly the threshold: unchanged
    post[20:30, 20:30, 2] += CHANGE_THRESHOLD + 1
    changed = changed_pixels(pre, post)
    assert changed.dtype == np.uint8 and set(np.unique(changed)) == {0, 1}
    assert not changed[5:15, 5:15].any() and changed[20:30, 20:30].all()
    assert changed.sum() == 100
    assert changed_pixels(pre, post, threshold=CHANGE_THRESHOLD - 1)[5:15, 5:15].all()


def test_the_opening_removes_specks_and_the_closing_joins_gaps():
    pre = np.zeros((60, 60, 3), np.uint8)
    post = pre.copy()
    post[2, 2] = 255  # a speck
    post[20:40, 10:25] = post[20:40, 27:40] = 255  # one object seen in two parts, 2 px apart
    opened = changed_pixels(pre, post, opening=np.ones((3, 3), np.uint8))
    assert opened[2, 2] == 0 and opened[30, 15] == 1 and opened[30, 26] == 0
    closed = changed_pixels(pre, post, close=np.ones((9, 9), np.uint8))
    assert closed[30, 26] == 1
