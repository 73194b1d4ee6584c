"""bench_tileable.py's seam figures read what they claim: about 1 for a field that truly repeats,
well above 1 for a crop whose opposite sides were never neighbours."""

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage as ndi

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"


@pytest.fixture(scope="module")
def bench():
    sys.path.insert(0, str(BENCH))          # bench_tileable imports quality from beside it
    try:
        spec = importlib.util.spec_from_file_location("bench_tileable", BENCH / "bench_tileable.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module
    finally:
        sys.path.remove(str(BENCH))


def blobs(seed, shape=(128, 128), sigma=4.0):
    """Levels 0..3 of smoothed noise on the torus (mode 'wrap'): a field that repeats."""
    noise = ndi.gaussian_filter(np.random.default_rng(seed).random(shape), sigma, mode="wrap")
    return np.digitize(noise, np.quantile(noise, [0.25, 0.5, 0.75])).astype(np.uint8)


def test_a_field_that_repeats_changes_across_its_seams_as_inside(bench):
    rows, cols = bench.seam_changes([blobs(s) for s in range(4)])
    assert 0.6 < rows < 1.5 and 0.6 < cols < 1.5


def test_a_crop_shows_its_seams(bench):
    crops = [blobs(s)[:80, :80] for s in range(4)]   # opposite sides 48 points apart
    rows, cols = bench.seam_changes(crops)
    assert rows > 2.5 and cols > 2.5


def test_torus_codes_read_windows_across_both_seams(bench):
    levels = blobs(0)
    codes = bench.torus_codes(levels, (3, 3), 4)
    rolled = bench.torus_codes(np.roll(levels, (5, 7), axis=(0, 1)), (3, 3), 4)
    assert codes.shape == levels.shape
    assert np.array_equal(np.roll(codes, (5, 7), axis=(0, 1)), rolled)


def stripes(seed, shape=(128, 128)):
    """Vertical stripes of levels 0..3, 2 points each (a period of 8), 5 % of the points
    another level: a field that repeats on any torus whose width is a multiple of 8."""
    rng = np.random.default_rng(seed)
    field = np.broadcast_to((np.arange(shape[1]) + seed) // 2 % 4, shape).copy()
    flip = rng.random(shape) < 0.05
    field[flip] = rng.integers(0, 4, flip.sum())
    return field.astype(np.uint8)


def test_the_seam_band_of_a_field_that_repeats_is_as_near_the_interior_as_a_band_inside(bench):
    """band_figures: stripes that repeat have their seam band as near their interior as the
    same band moved to the middle (0.13, 0.13); cropped to 84 points a side, their stripes
    break at the side seam and the band is far (0.39 against 0.17)."""
    repeats = [bench.torus_codes(stripes(s), (3, 3), 4) for s in range(4)]
    crops = [bench.torus_codes(stripes(s)[:84, :84], (3, 3), 4) for s in range(4)]
    fields = bench.band_figures(repeats, (128, 128))
    cropped = bench.band_figures(crops, (84, 84))
    assert abs(np.mean(fields["seam"]) - np.mean(fields["moved"])) < 0.03
    assert np.mean(cropped["seam"]) > np.mean(cropped["moved"]) + 0.15
    assert len(fields["spread"]) == len(fields["banded"]) == 4
    assert "worst" in bench.band_text(fields)
