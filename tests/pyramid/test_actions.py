"""Heeger–Bergen as a step: the engine function's output cut into levels, progress and
Cancel through prepare (the worker's path), replayed identical from a file, refused sizes."""

import numpy as np
import pytest

from texeditor.errors import Cancelled, InputError
from texeditor.markov.levels import quantize
from texeditor.pyramid import heeger_bergen
from texeditor.pyramid.actions import HeegerBergen
from texeditor.recipe.texturefile import load_texture, save_texture

from tests.support.spectral import COLOUR, GREY, colour_photo, grey_photo, history


@pytest.mark.parametrize("ref, photo", [(COLOUR, colour_photo()), (GREY, grey_photo())])
def test_the_step_is_heeger_bergen_cut_into_levels_and_undoes(ref, photo):
    h = history()
    h.apply(HeegerBergen(ref, 40, 24, seed=6, iterations=3, levels=5))
    picture = heeger_bergen(photo, (24, 40), seed=6, iterations=3)
    q = quantize(picture, 5, "lab")
    doc = h.document
    assert doc.shape == (24, 40) and doc.num_levels == 5
    assert np.array_equal(doc.levels, q.levels) and np.array_equal(doc.palette, q.palette)
    h.apply(HeegerBergen(ref, 40, 24, seed=7, iterations=3, levels=5))
    assert not np.array_equal(doc.levels, q.levels)                   # the seed draws another
    h.undo()
    h.undo()
    assert doc.shape == (8, 12) and doc.num_levels == 3


def test_prepare_reports_progress_per_iteration_and_cancels():
    h = history()
    step = HeegerBergen(COLOUR, 32, 32, seed=1, iterations=4, levels=4)
    seen = []
    prepared = step.prepare(h.document, progress=seen.append, cancel=lambda: False)
    assert seen == [0.25, 0.5, 0.75, 1.0]
    h.apply(step, prepared=prepared)
    assert np.array_equal(h.document.levels, prepared[0])
    calls = []

    def cancel():
        calls.append(1)
        return len(calls) > 2                        # the user presses Cancel during the third

    with pytest.raises(Cancelled):
        step.prepare(h.document, progress=None, cancel=cancel)


def test_a_file_replays_the_step_identical(tmp_path):
    h = history()
    h.apply(HeegerBergen(COLOUR, 36, 20, seed=2, iterations=2, levels=6))
    save_texture(tmp_path / "hb.texture", h)
    again, _ = load_texture(tmp_path / "hb.texture")
    assert again.document.result_hash() == h.document.result_hash()
    assert np.array_equal(again.document.levels, h.document.levels)


@pytest.mark.parametrize("size", [(15, 40), (40, 15), (5000, 40)])
def test_sizes_the_pyramid_cannot_hold_are_refused(size):
    with pytest.raises(InputError):
        HeegerBergen(GREY, *size)
