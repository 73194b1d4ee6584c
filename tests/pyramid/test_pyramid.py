"""The steerable pyramid (exact, oriented, any size) and Heeger–Bergen synthesis (sub-band
histograms reached, deterministic, cancellable), against answers computed from the definitions."""

import math

import numpy as np
import pytest
from scipy.stats import ks_2samp
from skimage import data, exposure

import texeditor
from texeditor.errors import Cancelled, InputError
from texeditor.pyramid import (SteerablePyramid, heeger_bergen, match_quantiles,
                               pyramid_levels, quantiles, steerable_pyramid)

SHAPES = [(64, 64), (37, 50), (33, 17), (16, 16), (100, 23), (96, 128)]


# -- the pyramid -------------------------------------------------------------------------------

@pytest.mark.parametrize("shape", SHAPES)
def test_reconstruct_undoes_decompose_on_every_size(shape):
    x = np.random.default_rng(sum(shape)).standard_normal(shape)
    pyramid = SteerablePyramid(shape, pyramid_levels(shape))
    assert np.abs(pyramid.reconstruct(pyramid.decompose(x)) - x).max() < 1e-10


def test_reconstruction_is_exact_down_to_grids_of_a_few_pixels():
    """Odd and even sides halved (rounded up) down to 2 px: the crop of the low-pass spectrum
    loses nothing whatever the parity."""
    x = np.random.default_rng(1).standard_normal((45, 38))
    pyramid = SteerablePyramid(x.shape, 5)
    assert pyramid.shapes == [(45, 38), (23, 19), (12, 10), (6, 5), (3, 3), (2, 2)]
    assert [b.shape for b in pyramid.decompose(x)] == pyramid.band_shapes()
    assert np.abs(pyramid.reconstruct(pyramid.decompose(x)) - x).max() < 1e-10


def test_float32_pyramid_is_float32_and_exact_to_its_precision():
    x = np.random.default_rng(2).standard_normal((64, 48))
    pyramid = steerable_pyramid((64, 48), 3, dtype=np.float32)
    bands = pyramid.decompose(x)
    assert {b.dtype for b in bands} == {np.dtype(np.float32)}
    assert np.abs(pyramid.reconstruct(bands) - x).max() < 1e-5


def test_a_plane_wave_lands_in_the_bands_its_orientation_and_radius_say():
    """cos(ω·col), ω = 3π/4 (level 0's octave): the filters' definitions give the high-pass
    H0(ω)·cos, the horizontal band −α·L0(ω)·sin (the (−i)³ factor), nothing in the vertical band
    (cos(θ − π/2) = 0), the diagonals α·cos³(π/4)·L0(ω) each, and nothing at coarser levels."""
    n = 64
    omega = 2 * np.pi * 24 / n                             # 3π/4
    col = np.arange(n)[None, :] * np.ones((n, 1))
    bands = SteerablePyramid((n, n), 3).decompose(np.cos(omega * col))
    u = math.log2(np.pi / omega)                          # where ω sits in [π/2, π]
    h0, l0 = math.cos(math.pi / 2 * u), math.sin(math.pi / 2 * u)
    alpha = 8 * 6 / math.sqrt(4 * 720)                    # 2^3·3!/sqrt(4·6!)
    assert np.allclose(bands[0], h0 * np.cos(omega * col), atol=1e-12)
    assert np.allclose(bands[1], -alpha * l0 * np.sin(omega * col), atol=1e-12)
    assert np.allclose(bands[3], 0, atol=1e-12)
    diagonal = -alpha * l0 * math.cos(math.pi / 4) ** 3 * np.sin(omega * col)
    assert np.allclose(bands[2], diagonal, atol=1e-12)      # θ = π/4
    assert np.allclose(bands[4], -diagonal, atol=1e-12)     # θ = 3π/4: cos(−3π/4)³ < 0
    assert all(np.abs(b).max() < 1e-12 for b in bands[5:])


def test_levels_fit_the_smaller_picture_and_tiny_pictures_are_refused():
    assert pyramid_levels((512, 512)) == 6                # low-pass residual 8x8
    assert pyramid_levels((512, 512), (40, 300)) == 2
    with pytest.raises(InputError, match="too small"):
        pyramid_levels((15, 200))


# -- histogram matching --------------------------------------------------------------------------

def test_matching_gives_scikit_images_match_histograms():
    rng = np.random.default_rng(3)
    source, reference = rng.standard_normal((30, 40)), rng.gamma(2.0, size=(17, 23))
    ours = match_quantiles(source, quantiles(np.sort(reference, axis=None), source.size))
    assert np.array_equal(ours, exposure.match_histograms(source, reference))


def test_matching_to_a_picture_of_the_same_size_copies_its_values_in_rank_order():
    """φ = c_f⁻¹ ∘ c_g: the smallest value becomes the reference's smallest, and so on."""
    source = np.array([[0.3, -2.0, 7.0], [1.0, 0.0, 5.0]])
    reference = np.array([10.0, 40.0, 20.0, 60.0, 50.0, 30.0])
    out = match_quantiles(source, quantiles(np.sort(reference), 6))
    assert out.tolist() == [[30.0, 10.0, 60.0], [40.0, 20.0, 50.0]]


# -- Heeger–Bergen -------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def brick():
    return data.brick()[:128, :128]


def band_ks(texture, photo):
    """Kolmogorov–Smirnov distance between each sub-band of ``texture`` and of ``photo``."""
    levels = pyramid_levels(photo.shape, texture.shape)
    ours = steerable_pyramid(texture.shape, levels).decompose(texture.astype(float))
    theirs = steerable_pyramid(photo.shape, levels).decompose(photo.astype(float))
    return np.array([ks_2samp(a.ravel(), b.ravel()).statistic for a, b in zip(ours, theirs)])


def test_iterations_bring_the_sub_band_histograms_to_the_photos(brick):
    """Seed noise with the photo's grey histogram has sub-bands far from the photo's (KS up to
    0.44); after 5 iterations the full-size sub-bands (15360 values) are within KS 0.07, the
    coarse ones (a few hundred values, so a noisier KS) within 0.15, and the mean is less than
    0.4 of the noise's."""
    shape = (96, 160)                                     # another size than the photo's
    noise = band_ks(heeger_bergen(brick, shape, seed=4, iterations=0), brick)
    texture = band_ks(heeger_bergen(brick, shape, seed=4, iterations=5), brick)
    assert noise.max() > 0.3
    assert texture[:5].max() < 0.07 and texture.max() < 0.15
    assert texture.mean() < 0.4 * noise.mean()


def test_a_texture_of_the_photos_size_has_exactly_its_grey_histogram(brick):
    texture = heeger_bergen(brick, brick.shape, seed=0, iterations=2)
    assert texture.dtype == np.uint8 and texture.shape == brick.shape
    assert np.array_equal(np.sort(texture, axis=None), np.sort(brick, axis=None))


def test_same_seed_same_texture_other_seed_another(brick):
    a = heeger_bergen(brick, (48, 80), seed=7, iterations=2)
    assert np.array_equal(a, heeger_bergen(brick, (48, 80), seed=7, iterations=2))
    assert not np.array_equal(a, heeger_bergen(brick, (48, 80), seed=8, iterations=2))


def test_colour_keeps_the_photos_colour_correlations():
    """Principal channels synthesised apart: the RGB covariance (strongly correlated in the
    photo) comes back; channels synthesised independently would lose the off-diagonal."""
    photo = data.coffee()[250:378, 420:548]
    texture = heeger_bergen(photo, (128, 160), seed=1, iterations=3)
    assert texture.shape == (128, 160, 3) and texture.dtype == np.uint8
    cov = [np.cov(p.reshape(-1, 3).astype(float), rowvar=False) for p in (photo, texture)]
    assert np.linalg.norm(cov[1] - cov[0]) < 0.15 * np.linalg.norm(cov[0])
    mean = [p.reshape(-1, 3).mean(axis=0) for p in (photo, texture)]
    assert np.abs(mean[1] - mean[0]).max() < 3


def test_float_photo_gives_a_float_texture_in_its_range(brick):
    photo = brick / 255.0
    texture = heeger_bergen(photo, (64, 64), seed=0, iterations=1)
    assert texture.dtype == np.float64
    assert photo.min() <= texture.min() and texture.max() <= photo.max()


def test_progress_after_each_iteration_and_cancel_before_the_next(brick):
    seen = []
    heeger_bergen(brick, (32, 32), seed=0, iterations=4, progress=seen.append)
    assert seen == [0.25, 0.5, 0.75, 1.0]
    asked, seen = [], []

    def cancel():
        asked.append(True)
        return len(asked) == 3
    with pytest.raises(Cancelled):
        heeger_bergen(brick, (32, 32), seed=0, iterations=4, progress=seen.append, cancel=cancel)
    assert seen == [0.25, 0.5]


@pytest.mark.parametrize("kwargs, message", [
    ({"image": np.zeros((8, 64), np.uint8)}, "too small"),
    ({"image": np.zeros((32, 32, 2), np.uint8)}, "shape"),
    ({"image": np.full((32, 32), np.nan)}, "NaN"),
    ({"shape": (10, 64)}, "too small"),
    ({"shape": "big"}, "height, width"),
    ({"seed": -1}, "seed"),
    ({"iterations": 101}, "iterations"),
])
def test_bad_requests_are_input_errors(kwargs, message):
    call = {"image": np.zeros((32, 32), np.uint8), "shape": (32, 32), "seed": 0} | kwargs
    with pytest.raises(InputError, match=message):
        heeger_bergen(call.pop("image"), call.pop("shape"), **call)


def test_exported_from_the_engine():
    assert texeditor.heeger_bergen is heeger_bergen
