"""2-D midpoint displacement (companion 003): every grid point computed exactly once (the
erratum), tileable, the variogram slope about 2H, seeded."""

import numpy as np
import pytest

from texeditor.errors import InputError
from texeditor.fractal.midpoint import midpoint_displacement, torus_side


@pytest.mark.parametrize("side", [2, 4, 32, 256])
def test_each_grid_point_is_written_exactly_once(side):
    _, writes = midpoint_displacement((side, side), 0.5, seed=1, count=True)
    assert writes.shape == (side, side) and (writes == 1).all()


def test_a_non_power_of_two_size_is_drawn_on_the_next_torus():
    field, writes = midpoint_displacement((100, 37), 0.5, seed=1, count=True)
    assert field.shape == (100, 37) and writes.shape == (128, 128) and (writes == 1).all()
    assert torus_side((100, 37)) == 128 and torus_side((1, 1)) == 2


def test_the_field_is_the_torus_and_tiles():
    """A power-of-two field's opposite edges are neighbours on the torus: the step across the
    seam is no larger than any step inside."""
    g = midpoint_displacement((256, 256), 0.8, seed=2)
    inside = np.abs(np.diff(g, axis=1)).mean()
    seam = np.abs(g[:, 0] - g[:, -1]).mean()
    assert seam < 1.5 * inside
    cropped_seam = np.abs(g[:, 0] - g[:, 127]).mean()
    assert cropped_seam > 3 * inside              # the check can fail: a half is no tile


def variogram_slope(g, lags=(1, 2, 4, 8, 16)):
    v = [np.mean((np.roll(g, -d, axis=1) - g) ** 2) for d in lags]
    return np.polyfit(np.log(lags), np.log(v), 1)[0]


@pytest.mark.parametrize("h", [0.3, 0.5, 0.8])
def test_the_variogram_grows_as_d_to_the_2h(h):
    slopes = [variogram_slope(midpoint_displacement((512, 512), h, seed=s)) for s in range(3)]
    assert abs(np.mean(slopes) - 2 * h) < 0.25


def test_seeded_and_bit_identical():
    a = midpoint_displacement((64, 48), 0.4, seed=7)
    assert np.array_equal(a, midpoint_displacement((64, 48), 0.4, seed=7))
    assert not np.array_equal(a, midpoint_displacement((64, 48), 0.4, seed=8))


@pytest.mark.parametrize("shape, h", [((0, 4), 0.5), ((5000, 4), 0.5), ((4, 4), float("nan")),
                                      ((4, 4), -0.1), ((4, 4), 1.5), ((4, 4), "rough"),
                                      ((2.5, 4), 0.5), (None, 0.5)])
def test_bad_requests_are_input_errors(shape, h):
    with pytest.raises(InputError):
        midpoint_displacement(shape, h)
