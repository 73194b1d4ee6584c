"""Line integral convolution: smooth along the field and not across it, seeded, tileable on
the torus (it commutes with turns of the torus, so no seam), cancellable, bounded."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from texeditor.errors import Cancelled, InputError
from texeditor.flow import contrast, line_integral_convolution, strokes_field
from texeditor.flow.lic import MAX_LENGTH, smooth_along


def correlation(picture, shift) -> float:
    """The autocorrelation of a picture at a (row, col) shift, on the torus."""
    a = picture - picture.mean()
    return float((a * np.roll(a, shift, axis=(0, 1))).mean() / a.var())


@pytest.mark.parametrize("theta, along, across", [
    (0.0, (0, 4), (4, 0)), (np.pi / 2, (4, 0), (0, 4)),
    (np.pi / 4, (3, 3), (3, -3)), (3 * np.pi / 4, (3, -3), (3, 3))])
def test_constant_field_smooth_along_and_not_across(theta, along, across):
    out = line_integral_convolution(np.full((96, 96), theta), 24, seed=3, wrap=True)
    assert correlation(out, along) > 0.75
    assert abs(correlation(out, across)) < 0.15


@settings(max_examples=10, deadline=None)
@given(st.floats(0, np.pi, exclude_max=True))
def test_any_direction_is_smoother_along_than_across(theta):
    out = line_integral_convolution(np.full((64, 64), theta), 20, seed=1, wrap=True)
    d = np.array([np.sin(theta), np.cos(theta)]) * 4
    along = tuple(np.round(d).astype(int))
    across = tuple(np.round([-d[1], d[0]]).astype(int))
    assert correlation(out, along) > correlation(out, across) + 0.4


def test_longer_streamlines_smooth_more():
    theta = np.full((64, 64), 0.3)
    spreads = [line_integral_convolution(theta, L, seed=2, wrap=True).std() for L in (2, 8, 32)]
    assert spreads[0] > spreads[1] > spreads[2]


def test_same_seed_same_picture_another_seed_another():
    theta, _ = strokes_field([[(5, 5), (30, 60), (10, 70)]], (40, 80))
    a = line_integral_convolution(theta, 12, seed=7)
    assert np.array_equal(a, line_integral_convolution(theta, 12, seed=7))
    assert not np.array_equal(a, line_integral_convolution(theta, 12, seed=8))


@settings(max_examples=8, deadline=None)
@given(st.integers(0, 39), st.integers(0, 47))
def test_on_the_torus_it_commutes_with_turns_so_it_tiles(dr, dc):
    theta, _ = strokes_field([[(3, 3), (20, 20), (30, 5)]], (40, 48), wrap=True)
    noise = np.random.default_rng(0).random((40, 48))
    out = smooth_along(noise, theta, 10, wrap=True)
    turned = smooth_along(np.roll(noise, (dr, dc), axis=(0, 1)),
                          np.roll(theta, (dr, dc), axis=(0, 1)), 10, wrap=True)
    assert np.allclose(turned, np.roll(out, (dr, dc), axis=(0, 1)), atol=1e-9)


def test_a_planar_picture_does_not_tile_but_is_the_torus_one_inside():
    theta = np.full((40, 48), 0.0)
    noise = np.random.default_rng(0).random((40, 48))
    planar = smooth_along(noise, theta, 10)
    torus = smooth_along(noise, theta, 10, wrap=True)
    assert np.allclose(planar[:, 6:-6], torus[:, 6:-6])       # streamlines never reach a border
    assert not np.allclose(planar[:, :4], torus[:, :4])


def test_a_constant_picture_stays_constant():
    theta, _ = strokes_field([[(3, 3), (20, 20), (30, 5)]], (40, 48))
    assert np.allclose(smooth_along(np.full((40, 48), 0.25), theta, 16), 0.25)


def test_progress_reaches_one_and_cancel_stops():
    seen = []
    line_integral_convolution(np.zeros((600, 600)), 2, seed=0, progress=seen.append)
    assert len(seen) > 1 and seen == sorted(seen) and seen[-1] == 1.0
    with pytest.raises(Cancelled):
        line_integral_convolution(np.zeros((600, 600)), 2, seed=0, cancel=lambda: True)


@pytest.mark.parametrize("length", [np.nan, np.inf, 0, 0.5, MAX_LENGTH + 1, 1e12, True, "20"])
def test_bad_lengths_are_refused(length):
    with pytest.raises(InputError):
        line_integral_convolution(np.zeros((8, 8)), length, seed=0)


@pytest.mark.parametrize("theta", [np.full((8, 8), np.nan), np.zeros((0, 8)), np.zeros(8)])
def test_bad_fields_are_refused(theta):
    with pytest.raises(InputError):
        line_integral_convolution(theta, 4, seed=0)


def test_contrast_gives_the_photos_greys_or_a_standard_spread():
    out = line_integral_convolution(np.full((32, 32), 1.0), 16, seed=4)
    photo = np.random.default_rng(5).integers(40, 200, (32, 32)).astype(np.uint8)
    matched = contrast(out, photo)
    assert np.allclose(np.sort(matched, axis=None), np.sort(photo / 255, axis=None))
    assert np.all(np.diff(matched.ravel()[np.argsort(out, axis=None)]) >= 0)   # ranks kept
    standard = contrast(out)
    assert standard.mean() == pytest.approx(0.5, abs=0.01) and standard.std() > 0.15
