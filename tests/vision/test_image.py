"""Image input: what perception accepts, and the errors for what it does not."""

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.grounding.synthetic import TABLE_RGB, Square, tabletop_image
from vslsp.vision.image import (
    as_rgb,
    flatten_table,
    header_size,
    read_image,
    table_colour,
    table_grain,
    write_image,
)


@pytest.mark.parametrize(
    "bad, message",
    [
        (np.zeros((48, 64, 3), np.float32), "uint8"),
        (np.zeros((48, 64), np.uint8), "shape"),
        (np.zeros((48, 64, 4), np.uint8), "shape"),
        (np.zeros((20, 64, 3), np.uint8), "at least 32 and at most 8192 pixels a side"),
        (np.zeros((40, 9000, 3), np.uint8), "is 9000x40 pixels"),
        (np.zeros((40, 400, 3), np.uint8), "at most 8:1 between the sides"),
        ([[0, 0, 0]], "numpy array"),
    ],
)
def test_wrong_images_are_input_errors(bad, message):
    with pytest.raises(InputError, match=message):
        as_rgb(bad)


def test_unreadable_files_are_input_errors(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_image(tmp_path / "missing.png")
    text = tmp_path / "notes.png"
    text.write_text("not an image")
    with pytest.raises(InputError, match="not an image"):
        read_image(text)


def test_oversized_files_are_refused_from_their_header(tmp_path):
    import cv2

    cv2.imwrite(str(tmp_path / "wide.png"), np.zeros((40, 20000, 3), np.uint8))
    cv2.imwrite(str(tmp_path / "tall.jpg"), np.zeros((9000, 1200, 3), np.uint8))
    assert header_size(tmp_path / "wide.png") == (20000, 40)
    assert header_size(tmp_path / "tall.jpg") == (1200, 9000)
    for name in ("wide.png", "tall.jpg"):
        with pytest.raises(InputError, match="megapixels"):
            read_image(tmp_path / name)


@pytest.mark.parametrize(
    "name, message", [("x.txt", "ending in .png"), ("noext", "ending in .png"), ("missing/o.png", "does not exist")]
)
def test_unwritable_image_names_are_input_errors(tmp_path, name, message):
    with pytest.raises(InputError, match=message):
        write_image(tmp_path / name, np.zeros((40, 40, 3), np.uint8))


def test_png_round_trip_keeps_rgb_order(tmp_path):
    image = tabletop_image([Square("red", (100, 100))])
    write_image(tmp_path / "scene.png", image)
    assert np.array_equal(read_image(tmp_path / "scene.png"), image)


def test_table_colour_is_the_dominant_colour_despite_objects_and_noise():
    image = tabletop_image([Square("blue", (200, 200), 120), Square("red", (420, 160), 120)], noise=15)
    assert np.abs(table_colour(image) - np.array(TABLE_RGB)).max() < 8


def test_flatten_table_paints_the_grain_and_keeps_the_objects_whole():
    rng = np.random.default_rng(0)
    image = tabletop_image([Square("blue", (200, 200), 120), Square("red", (420, 160), 120)], line=None)
    grain = rng.normal(0, 14, image.shape[:2])[..., None]  # a grey grain over the table
    image = np.clip(image + np.where(_off_squares(image.shape), grain, 0), 0, 255).astype(np.uint8)
    image[300:306, 100:106] = 255  # a fleck of the table's grain, far narrower than an object
    image[190:210, 190:210] = TABLE_RGB  # an object showing the table's colour within its outline
    image = np.clip(image + rng.normal(0, 6, image.shape), 0, 255).astype(np.uint8)
    flat = flatten_table(image)
    colour = np.rint(table_colour(image))
    assert np.all(flat[300:306, 100:106] == colour) and np.all(flat[20:40, 20:40] == colour)
    assert np.array_equal(flat[150:250, 150:250], image[150:250, 150:250])
    assert np.array_equal(flat[120:200, 380:460], image[120:200, 380:460])


def test_a_plain_table_is_left_as_it_is():
    image = np.full((480, 640, 3), TABLE_RGB, np.float64)
    image[140:260, 140:260] = (40, 60, 200)
    image = np.clip(image + np.random.default_rng(1).normal(0, 2, image.shape), 0, 255).astype(np.uint8)
    assert table_grain(image) == 0 and flatten_table(image) is image


def _off_squares(shape):
    """(H, W, 1): True off the two squares of the grain test."""
    off = np.ones(shape[:2] + (1,), bool)
    off[140:260, 140:260] = off[100:220, 360:480] = False
    return off
