"""Grey-level doubling (issue 9, thesis §4.5): children 2b and 2b + 1 only, the photo's 2G-level
histogram reproduced, the fallback contexts, determinism and the table as a DPJ."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY
from texeditor.markov import doubling
from texeditor.markov.dpj import DPJ
from texeditor.errors import InputError
from texeditor.markov.levels import load_image, quantize
from texeditor.resources import ROOT, bundled_dpj

GRAVEL = load_image(ROOT / "images" / "gravel.png")


@pytest.fixture(scope="module")
def table4():
    return doubling.learn(GRAVEL, 4, "lloyd", name="gravel")


def histogram(levels, n):
    return np.bincount(levels.ravel(), minlength=n) / levels.size


def test_refinement_splits_each_level_of_the_photos_quantisation():
    for method in ("band", "lloyd"):
        r = doubling.refine(GRAVEL, 4, method)
        assert np.array_equal(r.parents, quantize(GRAVEL, 4, method).levels)
        assert np.array_equal(r.children // 2, r.parents)
        assert set(np.unique(r.children)) == set(range(8))
        assert r.palette.shape == (8, 3)
        greys = r.palette[:, 0].astype(int)
        assert np.all(np.diff(greys) > 0)              # the children's greys keep their order


def test_the_table_is_a_3x3_dpj_at_2g_levels(table4):
    assert table4.window == (3, 3) and table4.levels == 8
    assert abs(table4.total - 1) < 1e-12
    assert table4.meta["parent_levels"] == 4 and table4.meta["source"] == "doubling table"
    assert doubling.check_table(table4) == 4
    again = DPJ.from_bytes(table4.to_bytes())
    t = quantize(GRAVEL, 4, "lloyd").levels[:40, :40]
    assert np.array_equal(doubling.double_levels(t, again, 3).levels,
                          doubling.double_levels(t, table4, 3).levels)


@PROPERTY
@given(g=st.integers(2, 4), seed=st.integers(0, 2**32),
       hw=st.tuples(st.integers(1, 12), st.integers(1, 12)), data=st.data())
def test_every_point_becomes_one_of_its_two_children(g, seed, hw, data):
    """Erratum: the children of b are 2b and 2b + 1 (never 2b − 1)."""
    table = TABLES[g]
    flat = data.draw(st.lists(st.integers(0, g - 1), min_size=hw[0] * hw[1],
                              max_size=hw[0] * hw[1]))
    t = np.array(flat, np.uint8).reshape(hw)
    out = doubling.double_levels(t, table, seed)
    assert out.levels.dtype == np.uint8 and out.levels.shape == t.shape
    assert np.array_equal(out.levels // 2, t)
    assert sum(out.contexts) == t.size


TABLES = {g: doubling.learn(GRAVEL[:96, :96], g, "band") for g in (2, 3, 4)}


def test_doubling_the_photos_own_levels_gives_back_its_histogram(table4):
    r = doubling.refine(GRAVEL, 4, "lloyd")
    out = doubling.double_levels(r.parents, table4, seed=5)
    assert np.abs(histogram(out.levels, 8) - histogram(r.children, 8)).sum() < 0.02
    assert out.contexts[0] > 0.99 * r.parents.size        # the 8-neighbour law nearly always


def test_a_synthesised_texture_doubles_to_a_histogram_close_to_the_photos(table4):
    """G = 4 synthesis from the bundled gravel DPJ, doubled to 8 levels: each level splits into
    its children in the photo's proportions, so the 2G histogram is as close to the photo's as
    the synthesis's own G-level histogram is (doubling adds almost nothing to the gap)."""
    from texeditor.markov.synthesis import synthesize
    dpj = DPJ.load(bundled_dpj("gravel-3x3-g4"))
    t = synthesize(dpj, (96, 96), seed=1).levels
    out = doubling.double_levels(t, table4, seed=1).levels
    photo = doubling.refine(GRAVEL, 4, "lloyd")
    for b in range(4):
        upper = (out == 2 * b + 1).sum() / (t == b).sum()
        assert abs(upper - (photo.children == 2 * b + 1).sum() / (photo.parents == b).sum()) < 0.08
    parent_gap = np.abs(histogram(t, 4) - histogram(photo.parents, 4)).sum()
    child_gap = np.abs(histogram(out, 8) - histogram(photo.children, 8)).sum()
    assert child_gap < parent_gap + 0.04 and child_gap < 0.1


def test_within_a_parent_the_split_follows_the_neighbours(table4):
    """Dark surroundings favour the darker child: the table is used, not a coin toss."""
    dark = np.zeros((30, 30), np.uint8)
    dark[1::3, 1::3] = 1                                   # level-1 points among level 0
    bright = np.full((30, 30), 3, np.uint8)
    bright[1::3, 1::3] = 1                                 # level-1 points among level 3
    lo = doubling.double_levels(dark, table4, 0).levels[1::3, 1::3]
    hi = doubling.double_levels(bright, table4, 0).levels[1::3, 1::3]
    assert (lo == 2).mean() > (hi == 2).mean() + 0.3


def test_unseen_neighbourhoods_fall_back_to_smaller_contexts():
    """A table learnt from stripes knows few neighbourhoods: others use 4 neighbours, then the
    level alone; a level the photo never had splits evenly."""
    photo = np.tile(np.repeat([0, 80, 160, 240], 4)[None], (16, 1)).astype(np.uint8)
    photo[::2] += 10                                       # children differ inside each stripe
    table = doubling.learn(photo, 2, "band")
    rng = np.random.default_rng(0)
    t = rng.integers(0, 2, (40, 40)).astype(np.uint8)
    out = doubling.double_levels(t, table, 0)
    eight, four, own, none = out.contexts
    assert own > 0 and eight + four + own + none == t.size and none == 0
    assert np.array_equal(out.levels // 2, t)


def test_a_level_the_photo_never_showed_splits_evenly():
    photo = np.tile(np.array([[0, 255]], np.uint8), (8, 4))
    table = doubling.learn(photo, 2, "band")
    keep = table.configs[:, 1, 1] // 2 == 0                # forget level 1 altogether
    table = DPJ(table.configs[keep], table.probs[keep] / table.probs[keep].sum(), 4)
    t = np.ones((50, 50), np.uint8)
    out = doubling.double_levels(t, table, 9)
    assert out.contexts[3] == t.size
    assert 0.4 < (out.levels == 3).mean() < 0.6


def test_same_seed_same_texture(table4):
    t = quantize(GRAVEL, 4, "lloyd").levels[:64, :64]
    a, b = (doubling.double_levels(t, table4, 11).levels for _ in range(2))
    assert np.array_equal(a, b)
    assert not np.array_equal(a, doubling.double_levels(t, table4, 12).levels)


def test_errors():
    with pytest.raises(InputError, match="2G"):
        doubling.learn(GRAVEL, 9)
    with pytest.raises(InputError, match="G = 2"):
        doubling.double_levels(np.array([[0, 2]], np.uint8), TABLES[2])
    with pytest.raises(InputError, match="3x3"):
        doubling.check_table(DPJ.load(bundled_dpj("brick-2x3-g4")))
    with pytest.raises(InputError, match="3x3"):
        doubling.learn(GRAVEL[:2, :20], 2)
