"""The quality metrics of benchmarks/quality.py behave as distances (0 to itself, large for a
scrambled picture) and the quilting baseline is a seeded function of its photo."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from skimage import data

PATH = Path(__file__).resolve().parents[2] / "benchmarks" / "quality.py"
_spec = importlib.util.spec_from_file_location("bench_quality_metrics", PATH)
quality = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(quality)


@pytest.fixture(scope="module")
def photo():
    return data.gravel()[:128, :128]


@pytest.fixture(scope="module")
def shuffled(photo):
    return np.random.default_rng(0).permutation(photo.ravel()).reshape(photo.shape)


@pytest.mark.parametrize("metric", ["glcm_distance", "spectrum_distance", "tv3x3_distance"])
def test_a_picture_is_at_distance_zero_from_itself(photo, metric):
    assert getattr(quality, metric)(photo, photo) == pytest.approx(0, abs=1e-12)


@pytest.mark.parametrize("metric, far", [("glcm_distance", 0.25), ("spectrum_distance", 0.5),
                                         ("tv3x3_distance", 0.5)])
def test_shuffled_pixels_are_far(photo, shuffled, metric, far):
    """Same histogram, no structure: every metric but a per-pixel histogram sees it."""
    assert getattr(quality, metric)(shuffled, photo) > far


def test_spectrum_compares_sizes_on_the_same_scale():
    big = data.gravel()
    assert quality.spectrum_distance(big[:256, :256], big) < 0.15


def test_the_spectrum_by_band_says_where_the_power_differs(photo, shuffled):
    """Zero against itself; shuffled pixels (white noise) have too little power at long periods
    and too much at the shortest; a blurred copy loses more the shorter the period."""
    from scipy import ndimage
    assert quality.spectrum_by_band(photo, photo) == pytest.approx([0] * 4, abs=1e-12)
    low, *_, high = quality.spectrum_by_band(shuffled, photo)
    assert low < -0.3 and high > 0.3
    blurred = ndimage.gaussian_filter(photo.astype(float), 1.5).astype(np.uint8)
    low, mid, short, high = quality.spectrum_by_band(blurred, photo)
    assert abs(low) < 0.1 and high < short < mid < 0 and high < -1


def test_copied_share(photo, shuffled):
    assert quality.copied_share(photo, photo) == 1.0
    assert quality.copied_share(photo[10:80, 20:90], photo) == 1.0
    assert quality.copied_share(shuffled, photo) == 0.0
    noise = np.random.default_rng(1).integers(0, 256, photo.shape, dtype=np.uint8)
    assert quality.copied_share(noise, photo) == 0.0


def test_level_frequencies():
    levels = np.array([[0, 1], [1, 3]])
    assert quality.level_frequencies(levels, 4).tolist() == [0.25, 0.5, 0, 0.25]


@pytest.mark.parametrize("colour", [False, True])
def test_quilting_has_the_requested_shape_and_is_seeded(colour):
    photo = data.astronaut()[:96, :96] if colour else data.gravel()[:96, :96]
    out = quality.quilt(photo, (70, 110), patch=16, seed=3)
    assert out.shape == (70, 110) + photo.shape[2:] and out.dtype == np.uint8
    assert np.array_equal(out, quality.quilt(photo, (70, 110), patch=16, seed=3))
    assert not np.array_equal(out, quality.quilt(photo, (70, 110), patch=16, seed=4))
    assert quality.copied_share(out, photo) > 0.3         # patches of the photo, not noise
