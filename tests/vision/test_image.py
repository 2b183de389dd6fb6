"""Image input: what perception accepts, and the errors for what it does not."""

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.vision.image import as_rgb, read_image, table_colour, write_image
from vslsp.vision.synthetic import TABLE_RGB, Square, tabletop_image


@pytest.mark.parametrize("bad, message", [
    (np.zeros((48, 64, 3), np.float32), "uint8"),
    (np.zeros((48, 64), np.uint8), "shape"),
    (np.zeros((48, 64, 4), np.uint8), "shape"),
    (np.zeros((20, 64, 3), np.uint8), "at least 32x32"),
    ([[0, 0, 0]], "numpy array"),
])
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


def test_png_round_trip_keeps_rgb_order(tmp_path):
    image = tabletop_image([Square("red", (100, 100))])
    write_image(tmp_path / "scene.png", image)
    assert np.array_equal(read_image(tmp_path / "scene.png"), image)


def test_table_colour_is_the_dominant_colour_despite_objects_and_noise():
    image = tabletop_image([Square("blue", (200, 200), 120), Square("red", (420, 160), 120)], noise=15)
    assert np.abs(table_colour(image) - np.array(TABLE_RGB)).max() < 8
