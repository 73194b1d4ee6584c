"""Texture attributes (thesis §1.5, issue 10): each formula on hand-made matrices whose answer is
known, then ranges on random matrices and the "more like this" distance."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from tests.support import PROPERTY
from texeditor.bank import attributes as A
from texeditor.markov.dpj import grey_ramp
from texeditor.errors import FormatError, InputError

BW = grey_ramp(2)                                   # black, white
RR, CC = np.indices((96, 96))


def stripes(width: int, axis: int, shape=(96, 96)) -> np.ndarray:
    """Stripes `width` points wide: axis 1 = vertical stripes (they change across columns)."""
    index = np.indices(shape)[axis]
    return ((index // width) % 2).astype(np.uint8)


def blocks(size: int, seed: int = 0, shape=(128, 128)) -> np.ndarray:
    """Random black or white squares of size×size points."""
    rng = np.random.default_rng(seed)
    cells = rng.integers(0, 2, (shape[0] // size + 1, shape[1] // size + 1), dtype=np.uint8)
    return np.repeat(np.repeat(cells, size, 0), size, 1)[:shape[0], :shape[1]]


def noise(seed: int = 0, shape=(128, 128), levels: int = 2) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, levels, shape, dtype=np.uint8)


# -- contrast ----------------------------------------------------------------------------------

def test_contrast_is_the_spread_of_greys_through_the_palette():
    half = stripes(4, 1)
    assert A.contrast(half, BW) == pytest.approx(1.0)
    assert A.contrast(np.zeros((8, 8), np.uint8), BW) == 0.0
    # the same levels through a narrower grey scale: the contrast drops, the structure is equal
    narrow = [(100, 100, 100), (156, 156, 156)]
    assert A.contrast(half, narrow) == pytest.approx(56 / 255)
    # colours count by their luma: pure green is brighter than pure blue
    assert A.contrast(half, [(0, 0, 0), (0, 255, 0)]) > A.contrast(half, [(0, 0, 0), (0, 0, 255)])


# -- granularity and density -------------------------------------------------------------------

def test_granularity_is_the_mean_region_size():
    assert A.granularity(np.zeros((6, 10), np.uint8)) == 60.0
    checker = ((RR[:8, :8] + CC[:8, :8]) % 2).astype(np.uint8)
    assert A.granularity(checker) == 1.0              # 4-connected: every point its own region
    assert A.granularity(((RR // 4 + CC // 4) % 2)[:16, :16].astype(np.uint8)) == 16.0
    assert A.granularity(blocks(2)) < A.granularity(blocks(8))


def test_density_is_the_share_of_non_background_points():
    levels = np.zeros((10, 10), np.uint8)
    levels[:3] = 2
    levels[3, :5] = 1
    assert A.density(levels) == pytest.approx(0.35)


# -- directivity -------------------------------------------------------------------------------

@pytest.mark.parametrize("levels, angle", [
    (stripes(3, 1), 90.0),                            # vertical stripes
    (stripes(3, 0), 0.0),                             # horizontal stripes
    ((((RR - CC) // 3) % 2).astype(np.uint8), 135.0),  # going down to the right
    ((((RR + CC) // 3) % 2).astype(np.uint8), 45.0),   # going up to the right
])
def test_directivity_finds_the_direction_of_stripes(levels, angle):
    strength, orientation = A.directivity(A.greys(BW)[levels])
    assert strength > 0.95
    assert min(abs(orientation - angle), 180 - abs(orientation - angle)) < 1.0


def test_an_isotropic_texture_has_no_direction_and_a_quarter_turn_turns_it():
    assert A.directivity(A.greys(BW)[noise()])[0] < 0.1
    assert A.directivity(A.greys(BW)[blocks(6)])[0] < 0.1
    elongated = np.repeat(blocks(4, seed=3, shape=(64, 256)), 4, axis=0)[:128, :128]
    strength, angle = A.directivity(A.greys(BW)[elongated])
    turned = A.directivity(A.greys(BW)[np.rot90(elongated).copy()])
    assert strength > 0.3 and turned[0] == pytest.approx(strength)
    assert (turned[1] - angle) % 180 == pytest.approx(90, abs=1e-6)


# -- regularity and coarseness -----------------------------------------------------------------

def test_a_repeated_motif_is_regular_with_its_period():
    motif = np.zeros((12, 12), np.uint8)
    motif[2:5, 3:9] = 1
    motif[7:10, 1:4] = 1
    tiled = np.tile(motif, (10, 10))
    acf = A.autocorrelation(A.greys(BW)[tiled])
    assert acf[acf.shape[0] // 2, acf.shape[1] // 2] == pytest.approx(1.0)
    regularity, period = A.regularity(acf)
    assert regularity == pytest.approx(1.0, abs=1e-9) and period == pytest.approx(12.0)
    assert A.regularity(A.autocorrelation(A.greys(BW)[stripes(3, 1)])) == \
        pytest.approx((1.0, 6.0))


def test_random_placements_are_not_regular():
    for levels in (noise(1), blocks(4, seed=2)):
        regularity, period = A.regularity(A.autocorrelation(A.greys(BW)[levels]))
        assert regularity < 0.3 and period == 0.0


def test_coarseness_grows_with_the_size_of_the_elements():
    values = [A.coarseness(A.autocorrelation(A.greys(BW)[x]))
              for x in (noise(), blocks(2), blocks(4), blocks(8))]
    assert values == sorted(values) and values[0] < 1.0 < values[-1]
    # a square of side s is correlated at 1/2 about s/3 to s/2 away
    assert 8 / 3 < values[-1] < 8 / 2 + 0.5


def test_flat_textures_have_no_autocorrelation():
    flat = np.full((20, 20), 1, np.uint8)
    assert A.autocorrelation(A.greys(BW)[flat]) is None
    a = A.compute(flat, BW)
    assert (a.contrast, a.regularity, a.period, a.coarseness, a.directivity) == (0, 0, 0, 0, 0)
    assert a.granularity == 400 and a.density == 1.0


# -- the whole set ------------------------------------------------------------------------------

def test_compute_reads_a_central_crop_of_large_textures():
    big = noise(5, shape=(700, 600), levels=3)
    crop = big[94:94 + A.MAX_SIDE, 44:44 + A.MAX_SIDE]
    assert A.compute(big, grey_ramp(3)) == A.compute(crop, grey_ramp(3))


def test_compute_refuses_an_empty_matrix():
    with pytest.raises(InputError):
        A.compute(np.zeros((0, 5), np.uint8), BW)


@PROPERTY
@given(arrays(np.uint8, st.tuples(st.integers(1, 40), st.integers(1, 40)),
              elements=st.integers(0, 3)))
def test_every_attribute_stays_in_its_range(levels):
    a = A.compute(levels, grey_ramp(4))
    assert 0 <= a.contrast <= 1 and 0 <= a.density <= 1 and 0 <= a.directivity <= 1
    assert 0 <= a.regularity <= 1 and 0 <= a.orientation < 180
    assert a.granularity >= 1 and a.period >= 0 and a.coarseness >= 0
    assert all(math.isfinite(v) for v in a.to_dict().values())


def test_stored_attributes_are_validated():
    a = A.compute(stripes(2, 1), BW)
    assert A.Attributes.from_dict(a.to_dict()) == a
    for bad in ({**a.to_dict(), "contrast": float("nan")}, {**a.to_dict(), "extra": 1},
                {k: v for k, v in a.to_dict().items() if k != "density"},
                {**a.to_dict(), "density": "high"}, [1, 2]):
        with pytest.raises(FormatError):
            A.Attributes.from_dict(bad)


def test_nearest_weighs_each_attribute_by_its_spread():
    base = A.Attributes(0.5, 10, 0.5, 0.0, 0.0, 0.1, 0, 2)
    near = A.Attributes(0.52, 11, 0.5, 0.0, 0.0, 0.1, 0, 2)
    far = A.Attributes(0.5, 10, 0.5, 0.9, 90.0, 0.1, 0, 2)      # the same, but oriented
    other = A.Attributes(0.9, 400, 0.95, 0.1, 10.0, 0.9, 8, 20)
    rows = np.array([A.feature_vector(x) for x in (other, far, near)])
    assert list(A.nearest(A.feature_vector(base), rows)) == [2, 1, 0]
    # 1° and 179° are nearly the same orientation
    one, late = (A.feature_vector(A.Attributes(0.5, 10, 0.5, 0.9, d, 0.1, 0, 2)) for d in (1, 179))
    assert np.linalg.norm(one - late) < 0.07
