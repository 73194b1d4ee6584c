"""Tileable synthesis: the Markov process drawn on the torus, so a texture repeats without a seam
(each row closed across the side seam, each column across the bottom one, with the DPJ's own
law; nothing blended)."""

import numpy as np
import pytest
import skimage as ski
from numpy.lib.stride_tricks import sliding_window_view

from texeditor import DPJ, estimate_dpj, quantize, synthesize
from texeditor.markov.dpj import encode
from texeditor.markov.multiscale import estimate_scales, synthesize_scales
from texeditor.photo import acquire_model
from texeditor.photo.tone import context_codes


def off_the_dpj(levels, dpj, torus=True) -> float:
    """Share of the windows (read on the torus: across both seams and the corner too) that the
    DPJ does not have."""
    u, v = dpj.window
    a = np.pad(levels, ((0, v - 1), (0, u - 1)), mode="wrap") if torus else levels
    codes = encode(np.ascontiguousarray(sliding_window_view(a, (v, u)).reshape(-1, v, u)),
                   dpj.levels)
    return float(np.mean(~np.isin(codes, dpj.codes)))


def photo_dpj(name, window, levels=4):
    q = quantize(getattr(ski.data, name)(), levels, "lloyd")
    return estimate_dpj(q.levels, window, levels, wrap=True)


def random_dpj(seed, g=3):
    """A hand-made 2×2 DPJ over every configuration: a torus always closes."""
    rng = np.random.default_rng(seed)
    configs = np.array(np.meshgrid(*[range(g)] * 4, indexing="ij")).reshape(4, -1).T
    q = rng.random(len(configs)) ** 3 + 1e-3
    return DPJ(configs.reshape(-1, 2, 2).astype(np.uint8), q / q.sum(), g)


@pytest.mark.parametrize("name", ["brick", "grass", "gravel"])
@pytest.mark.parametrize("shape", [(64, 96), (37, 53)])
def test_two_by_two_photo_dpjs_tile_without_a_window_they_lack(name, shape):
    dpj = photo_dpj(name, (2, 2))
    for seed in range(3):
        levels = synthesize(dpj, shape, seed=seed, tileable=True).levels
        assert levels.shape == shape
        assert off_the_dpj(levels, dpj) == 0.0


def test_a_hand_made_dpj_tiles_and_the_same_seed_gives_the_same_texture():
    dpj = random_dpj(1)
    a = synthesize(dpj, (30, 41), seed=5, tileable=True).levels
    assert off_the_dpj(a, dpj) == 0.0
    assert np.array_equal(a, synthesize(dpj, (30, 41), seed=5, tileable=True).levels)
    assert not np.array_equal(a, synthesize(dpj, (30, 41), seed=5).levels)


@pytest.mark.parametrize("name", ["brick", "grass", "gravel"])
def test_three_by_three_photo_dpjs_leave_far_fewer_windows_across_the_seams(name):
    """A plain draw leaves 0.1–0.3 % of its torus windows outside the DPJ (all along its
    seams); a tileable one far fewer (rows or columns whose end found no way back)."""
    dpj = photo_dpj(name, (3, 3))
    plain = off_the_dpj(synthesize(dpj, (256, 256), seed=2).levels, dpj)
    tiled = off_the_dpj(synthesize(dpj, (256, 256), seed=2, tileable=True).levels, dpj)
    assert tiled < plain / 2


def seam_jump(picture, axis):
    """Mean grey jump across the seam over the mean jump between neighbours inside."""
    g = picture.astype(float) if picture.ndim == 2 else picture.mean(axis=2)
    inside = np.abs(np.diff(g, axis=axis)).mean()
    across = np.abs(np.take(g, 0, axis=axis) - np.take(g, -1, axis=axis)).mean()
    return across / inside


def test_photo_models_draw_tiling_scales_and_tone():
    photo = ski.data.brick()
    model = acquire_model(photo)
    jumps = {False: [], True: []}
    for seed in range(3):
        for tileable in (False, True):
            image = model.synthesize((120, 160), seed=seed, tileable=tileable).image
            jumps[tileable].append([seam_jump(image, 0), seam_jump(image, 1)])
    plain, tiled = np.mean(jumps[False], axis=0), np.mean(jumps[True], axis=0)
    assert np.all(tiled < plain) and tiled[0] < plain[0] / 2    # across the rows, the columns
    ms, _ = estimate_scales(photo, scales=3)
    levels = synthesize_scales(ms, (50, 70), seed=1, tileable=True).levels
    assert np.array_equal(levels, synthesize_scales(ms, (50, 70), seed=1, tileable=True).levels)


def test_tone_contexts_read_across_the_seams_when_the_levels_tile():
    levels = np.random.default_rng(0).integers(0, 3, (5, 7)).astype(np.uint8)
    nine, five, own = context_codes(levels, 3, wrap=True)
    padded = np.pad(levels, 1, mode="wrap")
    i, j = 0, 6                                        # a corner: its context wraps both ways
    block = padded[i:i + 3, j:j + 3].ravel()
    assert nine[i * 7 + j] == int("".join(map(str, block)), 3)
    cross = [padded[i, j + 1], padded[i + 1, j], padded[i + 1, j + 1], padded[i + 1, j + 2],
             padded[i + 2, j + 1]]
    assert five[i * 7 + j] == int("".join(map(str, cross)), 3)
    assert own[i * 7 + j] == levels[i, j]
