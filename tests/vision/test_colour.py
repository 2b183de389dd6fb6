"""Colour symbols: the six named colours under shading, and the generic symbol otherwise."""

import numpy as np
import pytest

from vslsp.grounding.synthetic import PAINTS
from vslsp.sim import COLOURS
from vslsp.vision.colour import COLOUR_NAMES, GENERIC, colour_name


@pytest.mark.parametrize("name", COLOUR_NAMES)
@pytest.mark.parametrize("shade", [1.0, 0.8, 0.65])
def test_paints_are_named_in_light_and_shade(name, shade):
    pixels = np.array([PAINTS[name]], np.float32) * shade
    assert colour_name(pixels.astype(np.uint8)) == name


@pytest.mark.parametrize("name", sorted(COLOURS))
def test_simulator_colours_are_named(name):
    rgb = (np.array(COLOURS[name]) * 255).astype(np.uint8)[None]
    assert colour_name(rgb) == name


@pytest.mark.parametrize(
    "rgb", [(128, 128, 128), (250, 250, 250), (20, 200, 200), (250, 160, 185), (100, 60, 20), (15, 15, 15)]
)
def test_colours_outside_the_six_get_the_generic_symbol(rgb):
    assert colour_name(np.array([rgb], np.uint8)) == GENERIC


def test_a_two_faced_cube_is_named_by_its_hue_not_by_its_darker_face():
    lit = np.tile(np.array([[240, 215, 30]], np.uint8), (60, 1))
    shaded = np.tile(np.array([[130, 115, 15]], np.uint8), (40, 1))
    assert colour_name(np.vstack([lit, shaded])) == "yellow"
