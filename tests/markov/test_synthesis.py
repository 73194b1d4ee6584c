"""The 2-D Markov sampler: its law on real photos, exact hand-made DPJs, determinism, dead ends."""

import itertools
import threading

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import chisquare
from skimage import data

from texeditor import DPJ, estimate_dpj, quantize, synthesize
from texeditor.markov import synthesis
from texeditor.errors import Cancelled, InputError
from texeditor.markov.estimation import window_codes

PHOTOS = ["brick", "grass", "gravel"]


def photo_levels(name, levels, method="band"):
    return quantize(getattr(data, name)(), levels, method=method).levels


def zero_share(levels, dpj):
    """Share of the output's windows that have zero probability under the DPJ."""
    codes = window_codes(levels, dpj.window, dpj.levels)
    return float(np.mean(~np.isin(codes, dpj.codes)))


def total_variation(a: DPJ, b: DPJ) -> float:
    codes = np.union1d(a.codes, b.codes)
    pa, pb = np.zeros(len(codes)), np.zeros(len(codes))
    pa[np.searchsorted(codes, a.codes)] = a.probs
    pb[np.searchsorted(codes, b.codes)] = b.probs
    return 0.5 * float(np.abs(pa - pb).sum())


@pytest.mark.parametrize("name", PHOTOS)
@pytest.mark.parametrize("levels", [2, 4, 8])
def test_2x2_output_has_no_forbidden_window_and_no_repair(name, levels):
    dpj = estimate_dpj(photo_levels(name, levels), (2, 2), levels)
    result = synthesize(dpj, (512, 512), seed=levels)
    assert result.repairs == 0
    assert zero_share(result.levels, dpj) == 0.0


@pytest.mark.parametrize("name", PHOTOS)
def test_3x3_g4_torus_output_has_at_most_0_05_percent_forbidden_windows(name):
    dpj = estimate_dpj(photo_levels(name, 4), (3, 3), 4, wrap=True)
    result = synthesize(dpj, (512, 512), seed=11)
    assert zero_share(result.levels, dpj) <= 0.0005


@pytest.mark.parametrize("name", PHOTOS)
@pytest.mark.parametrize("window,levels,wrap", [((2, 2), 8, False), ((3, 3), 4, True)])
def test_output_window_law_is_as_close_to_the_dpj_as_the_photo_halves(name, window, levels, wrap):
    lv = photo_levels(name, levels)
    dpj = estimate_dpj(lv, window, levels, wrap=wrap)
    out = synthesize(dpj, (512, 512), seed=5).levels
    halves = max(total_variation(estimate_dpj(a, window, levels), estimate_dpj(b, window, levels))
                 for a, b in [(lv[:256], lv[256:]), (lv[:, :256], lv[:, 256:])])
    # "of the same order": within twice the larger distance between the photo's two halves
    assert total_variation(estimate_dpj(out, window, levels), dpj) <= 2 * halves


def test_one_row_follows_the_exact_conditional_law_given_the_rows_above():
    """Forward filtering / backward sampling draws a row from P(b | a) exactly (digest §6):
    compare with the law enumerated by brute force for a random 3x2 DPJ on 5 columns."""
    g, u, v, w = 2, 3, 2, 5
    configs = np.array(list(itertools.product(range(g), repeat=u * v)), np.uint8).reshape(-1, v, u)
    q = np.random.default_rng(1).random(len(configs)) ** 3
    dpj = DPJ(configs, q / q.sum(), g)
    above = np.array([0, 1, 1, 0, 1], np.uint8)

    def mu(cols):  # the marginal of the first u-1 columns
        return dpj.marginal(cols=slice(0, u - 1)).prob(cols)

    exact = {}
    for b in itertools.product(range(g), repeat=w):
        full = np.vstack([above, b]).astype(np.uint8)
        p = dpj.prob(full[:, :u])
        for n in range(1, w - u + 1):
            p *= dpj.prob(full[:, n:n + u]) / mu(full[:, n:n + u - 1])
        exact[b] = p
    z = sum(exact.values())
    tables, state = synthesis._tables(dpj), np.array([2024], np.uint64)
    out, counts, draws = np.zeros((2, w), np.uint8), {}, 20000
    for _ in range(draws):
        out[0] = above
        synthesis._sample_rows(out, 1, 2, tables, state, 0, np.int64(synthesis.NO_BUDGET),
                               np.int64(0), np.int64(0), np.int64(1), np.int64(synthesis.NO_BUDGET),
                               np.int64(synthesis.NO_BUDGET), synthesis.NO_PULL)
        counts[tuple(out[1])] = counts.get(tuple(out[1]), 0) + 1
    keys = [b for b in exact if exact[b] > 0]
    assert set(counts) <= set(keys)
    observed = [counts.get(b, 0) for b in keys]
    expected = [draws * exact[b] / z for b in keys]
    assert chisquare(observed, expected).pvalue > 1e-3


def test_a_redrawn_segment_follows_its_exact_law_given_everything_around_it():
    """Dead ends are repaired by redrawing a segment of the rows above: that segment must be
    drawn from its conditional law given the points left and right of it and the rows above."""
    g, u, v, w, c0, c1 = 2, 2, 2, 7, 2, 5
    configs = np.array(list(itertools.product(range(g), repeat=u * v)), np.uint8).reshape(-1, v, u)
    q = np.random.default_rng(3).random(len(configs)) ** 2
    dpj = DPJ(configs, q / q.sum(), g)
    mu = dpj.marginal(cols=slice(0, u - 1))
    above = np.array([1, 0, 0, 1, 1, 0, 1], np.uint8)
    row = np.array([0, 1, 9, 9, 9, 1, 0], np.uint8)  # 9: the points to redraw

    exact = {}
    for seg in itertools.product(range(g), repeat=c1 - c0):
        full = np.vstack([above, np.concatenate([row[:c0], seg, row[c1:]])]).astype(np.uint8)
        p = 1.0
        for n in range(max(1, c0 - u + 1), c1):  # the chain factors that involve the segment
            p *= dpj.prob(full[:, n:n + u]) / mu.prob(full[:, n:n + u - 1])
        exact[seg] = p
    z = sum(exact.values())
    tables, state = synthesis._tables(dpj), np.array([77], np.uint64)
    work = synthesis._new_work(g, u, w, 1)
    out, counts, draws = np.zeros((2, w), np.uint8), {}, 20000
    for _ in range(draws):
        out[0], out[1] = above, row
        assert synthesis._redraw_segment(out, 1, c0, c1, np.int64(0), tables, work, state,
                                         False, np.int64(0), np.int64(0)) < 0
        assert np.array_equal(out[1, :c0], row[:c0]) and np.array_equal(out[1, c1:], row[c1:])
        key = tuple(out[1, c0:c1])
        counts[key] = counts.get(key, 0) + 1
    keys = [k for k in exact if exact[k] > 0]
    observed = [counts.get(k, 0) for k in keys]
    assert chisquare(observed, [draws * exact[k] / z for k in keys]).pvalue > 1e-3


def test_checkerboard_dpj_gives_a_perfect_checkerboard():
    configs = np.array([[[0, 1], [1, 0]], [[1, 0], [0, 1]]], np.uint8)
    out = synthesize(DPJ(configs, [0.5, 0.5], 2), (37, 53), seed=3).levels
    rows, cols = np.indices(out.shape)
    board = (rows + cols) % 2
    assert np.array_equal(out, board) or np.array_equal(out, 1 - board)


def test_horizontal_stripes_dpj_gives_constant_rows_that_alternate():
    configs = np.array([[[0, 0], [2, 2]], [[2, 2], [0, 0]]], np.uint8)
    out = synthesize(DPJ(configs, [0.5, 0.5], 3), (40, 30), seed=1).levels
    assert np.all(out == out[:, :1])  # every row is constant
    assert set(np.unique(out[:, 0])) == {0, 2}
    assert np.all(out[1:, 0] != out[:-1, 0])  # and the rows alternate


def test_vertical_stripes_of_period_three():
    # a 3x2 window over the columns 0 1 2 0 1 2 ...: each column is constant
    configs = np.array([[[0, 1, 2]] * 2, [[1, 2, 0]] * 2, [[2, 0, 1]] * 2], np.uint8)
    out = synthesize(DPJ(configs, [1 / 3] * 3, 3), (20, 31), seed=4).levels
    assert np.all(out == out[:1, :])
    assert np.all((out[0, 1:].astype(int) - out[0, :-1]) % 3 == 1)


def test_single_level_window_samples_the_point_law():
    dpj = DPJ(np.array([[[0]], [[1]]], np.uint8), [0.25, 0.75], 2)
    out = synthesize(dpj, (200, 200), seed=9).levels
    assert abs(out.mean() - 0.75) < 0.01


def test_same_seed_same_matrix_different_seed_differs():
    dpj = estimate_dpj(photo_levels("gravel", 4), (3, 3), 4, wrap=True)
    a = synthesize(dpj, (128, 96), seed=42).levels
    b = synthesize(dpj, (128, 96), seed=42).levels
    c = synthesize(dpj, (128, 96), seed=43).levels
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_dead_ends_never_raise_and_are_counted():
    # a non-stationary hand DPJ: after "0 1" nothing continues, and rows cannot stack
    configs = np.array([[[0, 1], [1, 1]], [[1, 0], [0, 0]]], np.uint8)
    result = synthesize(DPJ(configs, [0.5, 0.5], 2), (30, 30), seed=0)
    assert result.levels.shape == (30, 30)
    assert result.repairs > 0


def test_progress_reaches_one_and_cancel_stops():
    dpj = estimate_dpj(photo_levels("gravel", 4), (2, 2), 4)
    seen = []
    synthesize(dpj, (600, 300), seed=1, progress=seen.append)
    assert seen == sorted(seen) and seen[-1] == 1.0 and len(seen) > 1
    stop = threading.Event()
    calls = []

    def progress(fraction):
        calls.append(fraction)
        stop.set()

    with pytest.raises(Cancelled):
        synthesize(dpj, (600, 300), seed=1, progress=progress, cancel=stop.is_set)
    assert len(calls) == 1


@pytest.mark.parametrize("shape", [(1, 10), (10, 1), (0, 5)])
def test_size_smaller_than_the_window_is_refused(shape):
    dpj = estimate_dpj(photo_levels("gravel", 4), (2, 2), 4)
    with pytest.raises(InputError):
        synthesize(dpj, shape)


def test_empty_or_negative_dpj_is_refused():
    with pytest.raises(InputError):
        synthesize(DPJ.empty((2, 2), 3), (10, 10))
    with pytest.raises(InputError):
        synthesize(DPJ(np.zeros((1, 2, 2), np.uint8), [-1.0], 2), (10, 10))


@given(st.integers(2, 4), st.integers(1, 3), st.integers(1, 3), st.data())
@settings(max_examples=40, deadline=None)
def test_any_dpj_synthesises_without_raising_or_hanging(levels, u, v, data):
    """Hand-entered DPJs can be anything (non-stationary, sparse, a single entry): the sampler
    always returns a full matrix of valid levels, repairing dead ends as it must."""
    n = data.draw(st.integers(1, min(12, levels ** (u * v))))
    codes = data.draw(st.lists(st.integers(0, levels ** (u * v) - 1), min_size=n, max_size=n,
                               unique=True))
    probs = data.draw(st.lists(st.floats(0.01, 1.0), min_size=n, max_size=n))
    dpj = DPJ.from_codes(np.array(codes), np.array(probs), levels, (u, v))
    h, w = data.draw(st.integers(v, 24)), data.draw(st.integers(u, 24))
    result = synthesize(dpj, (h, w), seed=data.draw(st.integers(0, 2**32)))
    assert result.levels.shape == (h, w) and result.levels.max() < levels
    assert result.repairs >= 0 and result.redraws >= 0


@pytest.mark.parametrize("tileable", [False, True])
def test_the_bands_a_draw_is_cut_in_change_nothing(monkeypatch, tileable):
    """A draw runs band by band (progress, cancel, and rows_final so a tone can start on the
    first rows: with it, at least FINAL_BANDS bands); the matrix is the same however many."""
    dpj = estimate_dpj(quantize(data.grass(), 4, "lloyd").levels, (3, 3), 4, wrap=True)
    whole = synthesize(dpj, (120, 90), seed=3, tileable=tileable).levels
    told = []
    banded = synthesize(dpj, (120, 90), seed=3, tileable=tileable,
                        rows_final=lambda lv, n: told.append(n)).levels
    assert len(told) >= synthesis.FINAL_BANDS and np.array_equal(whole, banded)
    monkeypatch.setattr(synthesis, "ROWS_PER_CALL_PIXELS", 90 * 3)     # a band a row
    assert np.array_equal(whole, synthesize(dpj, (120, 90), seed=3, tileable=tileable).levels)


def test_a_derived_dpj_is_made_once_while_its_dpj_lives():
    """What is made from a DPJ (its transpose, the coarsest scale's sub-window laws) is kept
    with it, so the kernel tables built for it are found again (not rebuilt each draw)."""
    dpj = estimate_dpj(quantize(data.brick(), 2, "lloyd").levels, (3, 3), 2)
    made = []

    def make(d):
        made.append(d)
        return d.marginal(rows=slice(0, 2), cols=slice(0, 2))
    first = synthesis.derived(dpj, "test", make)
    assert synthesis.derived(dpj, "test", make) is first and made == [dpj]
    other = DPJ(dpj.configs, dpj.probs, dpj.levels)                # equal, but another DPJ
    assert synthesis.derived(other, "test", make) is not first and len(made) == 2
    tables = synthesis._tables(first)
    assert synthesis._tables(synthesis.derived(dpj, "test", make)) is tables
