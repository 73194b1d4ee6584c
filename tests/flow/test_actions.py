"""The flow texture as a step: the engine function's picture cut into levels, from a photo's
field or drawn strokes, replayed identical from a file and the JSON log, progress and Cancel
through prepare, hostile parameters refused with a clear message."""

import json

import numpy as np
import pytest

from texeditor import flow_texture
from texeditor.errors import Cancelled, FormatError, InputError
from texeditor.flow.actions import MAX_SEGMENTS, FlowTexture, strokes_param
from texeditor.markov.levels import quantize
from texeditor.recipe.codec import action_from_json
from texeditor.recipe.replay import replay
from texeditor.recipe.texturefile import load_texture, save_texture

from tests.support.spectral import COLOUR, GREY, colour_photo, grey_photo, history

STROKES = ((2, 2), (18, 30), (18, 30), (4, 46))        # two segments: a bent stroke


def cut(picture, levels):
    return quantize(np.round(picture * 255).astype(np.uint8), levels, "lab")


@pytest.mark.parametrize("ref, photo", [(COLOUR, colour_photo()), (GREY, grey_photo())])
def test_a_photos_field_step_is_the_flow_texture_cut_into_levels_and_undoes(ref, photo):
    h = history()
    h.apply(FlowTexture("photo", ref, width=40, height=30, seed=4, length=10, levels=5))
    q = cut(flow_texture((30, 40), photo=photo, seed=4, length=10), 5)
    doc = h.document
    assert doc.shape == (30, 40) and doc.num_levels == 5
    assert np.array_equal(doc.levels, q.levels) and np.array_equal(doc.palette, q.palette)
    h.apply(FlowTexture("photo", ref, width=40, height=30, seed=5, length=10, levels=5))
    assert not np.array_equal(doc.levels, q.levels)
    h.undo()
    h.undo()
    assert doc.shape == (8, 12) and doc.num_levels == 3


def test_a_drawn_field_step_needs_no_photo_and_may_take_its_greys():
    h = history()
    h.apply(FlowTexture("strokes", None, STROKES, width=48, height=24, seed=1, length=8,
                        levels=4))
    strokes = [[(2, 2), (18, 30)], [(18, 30), (4, 46)]]
    q = cut(flow_texture((24, 48), strokes=strokes, seed=1, length=8), 4)
    assert np.array_equal(h.document.levels, q.levels)
    assert np.array_equal(h.document.palette, q.palette)
    h.apply(FlowTexture("strokes", GREY, STROKES, width=48, height=24, seed=1, length=8,
                        levels=4))
    q = cut(flow_texture((24, 48), strokes=strokes, photo=grey_photo(), seed=1, length=8), 4)
    assert np.array_equal(h.document.levels, q.levels)
    assert np.array_equal(h.document.palette, q.palette)


def test_the_texture_follows_the_drawn_direction():
    h = history()
    h.apply(FlowTexture("strokes", None, ((10, 0), (10, 63)), width=64, height=64, seed=2,
                        length=24, tileable=True, levels=8))
    picture = h.document.palette[h.document.levels][..., 0].astype(float)
    a = picture - picture.mean()
    along = (a * np.roll(a, 4, axis=1)).mean() / a.var()
    across = (a * np.roll(a, 4, axis=0)).mean() / a.var()
    assert along > 0.6 and abs(across) < 0.2


def test_a_file_and_the_json_log_replay_the_steps_bit_for_bit(tmp_path):
    h = history()
    h.apply(FlowTexture("photo", COLOUR, width=36, height=20, seed=2, length=12, sigma=3,
                        tileable=True, levels=6))
    h.apply(FlowTexture("strokes", COLOUR, STROKES, width=50, height=26, seed=9, levels=5))
    save_texture(tmp_path / "flow.texture", h)
    again, _ = load_texture(tmp_path / "flow.texture")
    assert again.document.result_hash() == h.document.result_hash()
    assert np.array_equal(again.document.levels, h.document.levels)
    log = [action_from_json(json.loads(json.dumps(a.to_json()))) for a in h.applied]
    assert log == list(h.applied)
    assert np.array_equal(replay(log, {}, exemplars=h.document.exemplars).levels,
                          h.document.levels)


def test_prepare_reports_progress_and_cancels():
    h = history()
    step = FlowTexture("photo", GREY, width=700, height=400, seed=1, length=4, levels=4)
    seen = []
    prepared = step.prepare(h.document, progress=seen.append, cancel=lambda: False)
    assert len(seen) > 1 and seen[-1] == 1.0
    h.apply(step, prepared=prepared)
    assert np.array_equal(h.document.levels, prepared[0])
    with pytest.raises(Cancelled):
        step.prepare(h.document, progress=None, cancel=lambda: True)


def test_strokes_param_rounds_drops_repeats_and_pairs_segments():
    assert strokes_param([[(0.4, 1.6), (0.2, 2.4), (5, 5)], [(9, 9)], [(1, 1), (2, 3)]]) == (
        (0, 2), (5, 5), (1, 1), (2, 3))


def test_labels_are_short():
    assert FlowTexture("strokes", None, STROKES, width=512, height=512, seed=3).label() == \
        "Flow texture (drawn field) 512×512, seed 3, L = 20, G = 8"


@pytest.mark.parametrize("params, message", [
    ({"source": "wind"}, "source must be one of"),
    ({"source": "photo", "exemplar": None}, "needs the photo"),
    ({"source": "photo", "exemplar": GREY}, "takes no strokes"),
    ({"strokes": ()}, "1..1024 segments"),
    ({"strokes": STROKES[:3]}, "even number"),
    ({"strokes": ((1, 1), (1, 1))}, "with a length"),
    ({"strokes": ((0, 0), (5, 5)) * (MAX_SEGMENTS + 1)}, "1..1024 segments"),
    ({"strokes": ((0, 0), (5, 99999))}, "out of range"),
    ({"strokes": ((0, 0), (5.5, 9))}, "must be an integer"),
    ({"strokes": [[0, 0, 0], [1, 2]]}, "each point must be (row, col)"),
    ({"strokes": "0,0 5,5"}, "list of at most"),
    ({"length": float("nan")}, "length = nan"),
    ({"length": 1e9}, "out of range"),
    ({"length": 0}, "out of range"),
    ({"sigma": float("inf")}, "sigma = inf"),
    ({"width": 5000}, "out of range"),
    ({"height": 8}, "out of range"),
    ({"levels": 1}, "out of range"),
    ({"seed": -1}, "seed = -1"),
    ({"exemplar": "../etc/passwd"}, "16 hex digits"),
])
def test_hostile_parameters_are_refused_with_a_clear_message(params, message):
    base = {"source": "strokes", "exemplar": None, "strokes": STROKES, "width": 32,
            "height": 32, "seed": 0}
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        FlowTexture(**{**base, **params})


def test_hostile_json_is_refused_not_crashed():
    good = FlowTexture("strokes", None, STROKES, width=32, height=32, seed=0).to_json()
    for bad in ({**good, "strokes": [[0, 0], [1, float("nan")]]}, {**good, "length": None},
                {**good, "strokes": [[[0, 0]]]}, {**good, "version": 7}):
        with pytest.raises((InputError, FormatError)):
            action_from_json(bad)


def test_a_photo_not_in_the_document_is_a_clear_error():
    h = history()
    with pytest.raises(InputError, match="not part of this document"):
        h.apply(FlowTexture("photo", "0123456789abcdef", width=20, height=20, seed=0))
