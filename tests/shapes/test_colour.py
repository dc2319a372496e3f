"""Colour names from RGB: PITT's hue bins with grey, white and black left out."""

import numpy as np
import pytest

from shapes import colour_name, mean_colour
from shapes.synthetic import PALETTE


@pytest.mark.parametrize("name", sorted(PALETTE))
def test_palette_colours_get_their_names(name):
    rng = np.random.default_rng(0)
    pixels = np.clip(np.array(PALETTE[name]) + rng.normal(0, 0.03, (200, 3)), 0, 1)
    assert colour_name(pixels) == name


@pytest.mark.parametrize(
    "rgb", [(0.5, 0.5, 0.5), (1.0, 1.0, 1.0), (0.0, 0.0, 0.0), (0.05, 0.02, 0.02)]
)
def test_grey_white_black_and_very_dark_have_no_name(rgb):
    """PITT called these "red" (hue 0); they have no saturation or no brightness."""
    assert colour_name(np.array([rgb] * 10)) is None


def test_a_tie_has_no_name():
    assert colour_name(np.array([PALETTE["red"], PALETTE["blue"]])) is None


def test_mean_colour_is_the_channel_mean():
    assert mean_colour(np.array([[1.0, 0.0, 0.2], [0.0, 0.0, 0.4]])) == pytest.approx(
        (0.5, 0.0, 0.3)
    )
