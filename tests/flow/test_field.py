"""Orientation fields: a photo's structure tensor gives the direction of its stripes, not of
their gradient; resampling averages directions (doubled angles), never raw angles; a drawn
field follows its strokes, and one straight stroke gives a constant field."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from texeditor.errors import InputError
from texeditor.flow import orientation_field, strokes_field


def stripes(angle: float, shape=(96, 96), period=7.0) -> np.ndarray:
    """Grey stripes running along (sin angle, cos angle) in (row, col): they vary only across."""
    r, c = np.mgrid[:shape[0], :shape[1]].astype(float)
    return 0.5 + 0.4 * np.sin(2 * np.pi * (r * np.cos(angle) - c * np.sin(angle)) / period)


def angle_error(theta, angle) -> np.ndarray:
    """|θ − angle| modulo π, in degrees."""
    return np.abs(np.rad2deg(np.angle(np.exp(2j * (theta - angle))) / 2))


@pytest.mark.parametrize("degrees", [0, 17, 45, 90, 118, 135, 179])
def test_stripes_give_their_own_direction_within_two_degrees(degrees):
    theta, coherence = orientation_field(stripes(np.deg2rad(degrees)))
    inner = (slice(20, -20), slice(20, -20))
    assert angle_error(theta[inner], np.deg2rad(degrees)).max() < 2
    assert coherence[inner].min() > 0.95
    assert theta.min() >= 0 and theta.max() < np.pi


@settings(max_examples=25, deadline=None)
@given(st.floats(0, np.pi, exclude_max=True), st.floats(4, 12))
def test_any_stripes_any_period_within_two_degrees(angle, period):
    theta, _ = orientation_field(stripes(angle, (64, 64), period), sigma=4)
    assert angle_error(theta[16:-16, 16:-16], angle).max() < 2


def test_horizontal_stripes_run_along_rows_not_down_columns():
    rows = np.zeros((40, 40))
    rows[::4] = 1.0                       # lines along each 4th row: θ = 0, the gradient's is π/2
    theta, _ = orientation_field(rows)
    assert angle_error(theta[10:-10, 10:-10], 0.0).max() < 1


def test_a_colour_photo_has_its_greys_field():
    grey = stripes(0.6)
    colour = np.repeat(grey[..., None], 3, axis=2)
    assert np.allclose(orientation_field(colour)[0], orientation_field(grey)[0], atol=1e-9)


def test_resampling_averages_doubled_angles_never_raw_angles():
    # stripes at +4° left, −4° (= 176°) right: raw angles would average to 90° at the join
    left, right = stripes(np.deg2rad(4), (64, 32)), stripes(np.deg2rad(-4), (64, 32))
    theta, coherence = orientation_field(np.concatenate([left, right], axis=1), (150, 170))
    assert theta.shape == coherence.shape == (150, 170)
    assert angle_error(theta[30:-30], 0.0).max() < 6


def test_the_field_resampled_keeps_the_direction():
    theta, _ = orientation_field(stripes(np.deg2rad(60)), (200, 50))
    assert angle_error(theta[50:-50, 12:-12], np.deg2rad(60)).max() < 2


def test_one_straight_stroke_gives_a_constant_field_along_it():
    theta, coherence = strokes_field([[(10, 10), (50, 90)]], (64, 80))
    assert np.ptp(theta) < 1e-12 and np.allclose(coherence, 1)
    assert theta[0, 0] == pytest.approx(np.arctan2(40, 80), abs=1e-12)
    # a polyline of collinear points, drawn either way, is the same field
    again, _ = strokes_field([[(50, 90), (30, 50), (10, 10)]], (64, 80))
    assert np.allclose(again, theta, atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(st.lists(st.integers(-20, 120), min_size=4, max_size=4), st.booleans())
def test_any_single_segment_gives_its_direction_everywhere(coords, wrap):
    r0, c0, r1, c1 = coords
    if (r0, c0) == (r1, c1):
        return
    theta, _ = strokes_field([[(r0, c0), (r1, c1)]], (48, 40), wrap=wrap)
    assert angle_error(theta, np.arctan2(r1 - r0, c1 - c0)).max() < 1e-9


def test_near_each_stroke_the_field_follows_it_and_turns_between():
    theta, coherence = strokes_field([[(10, 5), (10, 95)], [(60, 90), (90, 90)]], (100, 100))
    assert angle_error(theta[10, 10:60], 0.0).max() < 3            # along the horizontal one
    assert angle_error(theta[65:90, 90], np.pi / 2).max() < 3      # along the vertical one
    assert coherence[10, 30] > 0.9 and coherence[45, 60] < coherence[10, 30]
    # smooth: no jumps, but at the defect where the two directions cancel (no coherence)
    steps = angle_error(theta[1:], theta[:-1])
    assert steps[coherence[1:] > 0.2].max() < 10 and (steps > 10).mean() < 0.01


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 47), st.integers(0, 39))
def test_a_drawn_field_on_the_torus_moves_with_its_strokes(dr, dc):
    stroke = [(5, 3), (20, 30), (12, 38)]
    theta, _ = strokes_field([stroke], (48, 40), wrap=True)
    moved, _ = strokes_field([[(r + dr, c + dc) for r, c in stroke]], (48, 40), wrap=True)
    assert angle_error(moved, np.roll(theta, (dr, dc), axis=(0, 1))).max() < 1e-6


def test_a_large_output_is_drawn_on_a_coarse_grid_then_resampled():
    theta, _ = strokes_field([[(0, 0), (1000, 1000)], [(1000, 0), (0, 1000)]], (1000, 1000))
    assert theta.shape == (1000, 1000)
    assert angle_error(theta[100, 100], np.pi / 4) < 3
    assert angle_error(theta[100, 900], 3 * np.pi / 4) < 3


@pytest.mark.parametrize("strokes", [[], [[(3, 3)]], [[(3, 3), (3, 3)]], [[(1, np.nan), (5, 5)]],
                                     [[(1, 2, 3), (4, 5, 6)]], "10,10 20,20", np.zeros((2, 2, 2))])
def test_strokes_without_a_direction_are_refused(strokes):
    with pytest.raises(InputError):
        strokes_field(strokes, (20, 20))


@pytest.mark.parametrize("photo, kwargs", [
    (np.full((20, 20), np.nan), {}), (np.zeros((1, 20)), {}), (np.zeros(20), {}),
    (np.zeros((20, 20)), {"sigma": np.nan}), (np.zeros((20, 20)), {"sigma": 1e6}),
    (np.zeros((20, 20)), {"shape": (0, 5)}), (np.zeros((20, 20)), {"shape": "big"})])
def test_bad_photos_and_settings_are_refused(photo, kwargs):
    with pytest.raises(InputError):
        orientation_field(photo, **kwargs)


def test_a_flat_photo_has_no_coherence():
    theta, coherence = orientation_field(np.full((20, 20), 0.5))
    assert np.all(coherence == 0) and np.isfinite(theta).all()
