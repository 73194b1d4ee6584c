"""The fractal Actions: a relief canvas and an IFS motif, replayed bit for bit, undone, checked."""

import numpy as np
import pytest

from texeditor.errors import FormatError, InputError
from texeditor.fractal.actions import FractalRelief, IFSMotif
from texeditor.fractal.ifs import ifs_attractor
from texeditor.recipe.codec import action_from_json
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.relief.shading import palette_grey

from tests.support.fractal import EXAMPLES, history


@pytest.mark.parametrize("action", EXAMPLES, ids=lambda a: a.TYPE)
def test_replay_is_bit_identical_and_undo_restores(action):
    h = history()
    before = h.document.levels.copy()
    h.apply(action)
    after = h.document.levels.copy()
    again = replay([action_from_json(a.to_json()) for a in h.applied], {})
    assert np.array_equal(again.levels, after) and again.result_hash() == h.document.result_hash()
    h.undo()
    assert np.array_equal(h.document.levels, before)
    h.redo()
    assert np.array_equal(h.document.levels, after)


def test_a_relief_canvas_has_g_levels_rising_in_grey():
    h = History()
    h.apply(FractalRelief(64, 40, seed=2, roughness=0.6, levels=7))
    doc = h.document
    assert doc.shape == (40, 64) and doc.num_levels == 7
    assert set(np.unique(doc.levels)) == set(range(7))
    assert np.all(np.diff(palette_grey(doc.palette)) > 0)          # level order is height order


def test_the_motif_paints_the_attractor_in_its_box_and_nothing_else():
    h = history()
    before = h.document.levels.copy()
    motif = IFSMotif("sierpinski", 20, 16, 17, level=3, seed=1, points=30_000)
    h.apply(motif)
    changed = h.document.levels != before
    mask = ifs_attractor("sierpinski", (17, 17), points=30_000, seed=1) > 0
    top, left = 20 - 8, 16 - 8
    expect = np.zeros_like(changed)
    expect[top:top + 17, left:left + 17] = mask & (before[top:top + 17, left:left + 17] != 3)
    assert np.array_equal(changed, expect)
    assert (h.document.levels[changed] == 3).all()


def test_a_motif_needs_a_canvas_and_an_existing_level():
    with pytest.raises(InputError):
        History().apply(IFSMotif("tree", 0, 0, 10, level=1))
    with pytest.raises(InputError):
        history().apply(IFSMotif("tree", 5, 5, 10, level=9))


@pytest.mark.parametrize("params", [
    dict(type="ifs_motif", motif="oak", row=0, col=0, size=8, level=1),
    dict(type="ifs_motif", motif="tree", row=0, col=0, size=10**6, level=1),
    dict(type="ifs_motif", motif="tree", row=0, col=0, size=8, level=1, points=10**9),
    dict(type="ifs_motif", motif=None, row=0, col=0, size=8, level=1),
    dict(type="fractal_relief", width=10**6, height=4),
    dict(type="fractal_relief", width=8, height=8, roughness=float("nan")),
    dict(type="fractal_relief", width=8, height=8, roughness=3.0),
    dict(type="fractal_relief", width=8, height=8, levels=1)])
def test_hostile_parameters_are_clear_errors(params):
    """A log with them is refused on reading (FormatError naming the step and the value)."""
    with pytest.raises(FormatError, match=params["type"]):
        action_from_json({"version": 1, **params})
