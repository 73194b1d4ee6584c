"""Actions: parameters, JSON through the registry, labels, the edit-form helpers, Synthesize's memo."""

import json

import numpy as np
import pytest

from tests.support import REFS, TINY, TINY_DPJS
from texeditor.markov import synthesis
from texeditor.recipe.actions import (REGISTRY, CropCanvas, NewCanvas, ResizeCanvas, SetLevels, SetPalette, Synthesize, action_params, param_specs, register, replace_params)
from texeditor.recipe.codec import action_from_json
from texeditor.recipe.document import Document
from texeditor.recipe.history import History
from texeditor.errors import Cancelled, FormatError, InputError

EXAMPLES = [
    NewCanvas(8, 6, 4), NewCanvas(2, 3, 2, ((1, 2, 3), (4, 5, 6))),
    Synthesize(REFS[0], 16, 12, 7), SetPalette(((0, 0, 0), (255, 0, 0))),
    SetLevels(-1, 2, 3, 4, 1), CropCanvas(1, 1, 2, 2), ResizeCanvas(5, 9, 2),
]


@pytest.mark.parametrize("action", EXAMPLES, ids=lambda a: a.TYPE)
def test_json_round_trip(action):
    obj = json.loads(json.dumps(action.to_json()))
    assert obj["type"] == action.TYPE and obj["version"] == action.VERSION
    assert action_from_json(obj) == action


def test_labels_are_short_and_human():
    assert Synthesize(REFS[0], 512, 512, 7).label() == "Synthesise 512×512, seed 7"
    assert NewCanvas(64, 32, 4).label() == "New canvas 64×32, G = 4"
    assert SetLevels(3, 4, 1, 1, 2).label() == "Set (3, 4) to 2"
    assert all(len(a.label()) < 60 for a in EXAMPLES)


def test_actions_are_immutable_and_hashable():
    a = SetLevels(0, 0, 1, 1, 1)
    with pytest.raises(AttributeError):
        a.value = 2
    assert len({a, SetLevels(0, 0, 1, 1, 1)}) == 1


def test_parameters_are_normalised_to_plain_values():
    pal = NewCanvas(2, 2, 2, np.array([[0, 0, 0], [9, 9, 9]], np.uint8)).palette
    assert pal == ((0, 0, 0), (9, 9, 9)) and type(pal[0][0]) is int
    assert SetLevels(np.int64(1), 0, 1, 1, 0).top == 1


@pytest.mark.parametrize("make, message", [
    (lambda: NewCanvas(0, 4, 2), "width = 0 is out of range"),
    (lambda: NewCanvas(4, 4, 17), "levels = 17"),
    (lambda: NewCanvas(16384, 16384, 2), "more than"),
    (lambda: NewCanvas(4, 4, 3, ((0, 0, 0), (1, 1, 1))), "2 colours for G = 3"),
    (lambda: NewCanvas(4.0, 4, 2), "width must be an integer"),
    (lambda: NewCanvas(True, 4, 2), "width must be an integer"),
    (lambda: SetPalette(((0, 0, 256), (0, 0, 0))), "out of range 0..255"),
    (lambda: SetPalette(((0, 0), (0, 0, 0))), "three components"),
    (lambda: Synthesize("nothex", 4, 4, 0), "16 hex digits"),
    (lambda: Synthesize(REFS[0], 4, 4, -1), "seed = -1"),
    (lambda: SetLevels(0, 0, 1, 1, 16), "value = 16"),
])
def test_bad_parameters_are_input_errors(make, message):
    with pytest.raises(InputError, match=message):
        make()


@pytest.mark.parametrize("obj, message", [
    ([], "must be a JSON object"),
    ({"type": "explode", "version": 1}, "unknown action type 'explode'"),
    ({"type": None}, "unknown action type"),
    ({"type": "set_levels"}, "no integer version"),
    ({"type": "set_levels", "version": 2}, "version 2 is not supported"),
    ({"type": "set_levels", "version": 0}, "version 0 is not supported"),
    ({"type": "set_levels", "version": 1, "top": 0}, "lacks parameters"),
    ({"type": "crop_canvas", "version": 1, "top": 0, "left": 0, "height": 1, "width": 1,
      "evil": 1}, "unexpected parameters \\['evil'\\]"),
    ({"type": "crop_canvas", "version": 1, "top": "0", "left": 0, "height": 1, "width": 1},
     "top must be an integer"),
    ({"type": "resize_canvas", "version": 1, "height": 1e9, "width": 1}, "height must be"),
    ({"type": "set_palette", "version": 1, "palette": [[0, 0, 0]] * 40}, "2..16 colours"),
])
def test_malformed_json_is_a_format_error(obj, message):
    with pytest.raises(FormatError, match=message):
        action_from_json(obj)


def test_param_specs_drive_an_edit_form():
    specs = param_specs(SetLevels(1, 2, 3, 4, 1))
    assert [s.name for s in specs] == ["top", "left", "height", "width", "value"]
    assert specs[4].value == 1 and specs[4].kind == "int" and specs[4].maximum == 15
    seed = next(s for s in param_specs(Synthesize) if s.name == "seed")
    assert seed.kind == "seed" and seed.value == 0 and seed.minimum == 0
    assert action_params(ResizeCanvas(3, 4)) == {"height": 3, "width": 4, "fill": 0}


def test_replace_params_validates_like_a_new_action():
    a = Synthesize(REFS[0], 16, 16, 1)
    assert replace_params(a, seed=2) == Synthesize(REFS[0], 16, 16, 2)
    with pytest.raises(InputError, match="seed"):
        replace_params(a, seed=-3)
    with pytest.raises(InputError):
        replace_params(a, colour=3)


def test_register_refuses_a_duplicate_type():
    with pytest.raises(ValueError, match="already registered"):
        register(type("Again", (SetLevels,), {"TYPE": "set_levels"}))
    assert REGISTRY["set_levels"] is SetLevels


def test_set_palette_must_match_g():
    doc = Document.new(2, 2, 3)
    with pytest.raises(InputError, match="G = 3"):
        SetPalette(((0, 0, 0), (1, 1, 1))).apply(doc)


def test_crop_and_resize_canvas():
    doc = Document.new(4, 3, 3)
    doc.apply(SetLevels(0, 0, 3, 4, 1)).apply(SetLevels(1, 1, 1, 1, 2))
    doc.apply(CropCanvas(1, 1, 10, 10))
    assert doc.levels.tolist() == [[2, 1, 1], [1, 1, 1]]
    doc.apply(ResizeCanvas(3, 2, 0))
    assert doc.levels.tolist() == [[2, 1], [1, 1], [0, 0]]
    with pytest.raises(InputError, match="outside"):
        CropCanvas(5, 5, 1, 1).apply(doc)
    with pytest.raises(InputError, match="level 7"):
        ResizeCanvas(4, 4, 7).apply(doc)


def test_synthesize_uses_the_dpj_palette_and_sets_the_current_dpj():
    doc = Document()
    ref = doc.store_dpj(TINY_DPJS[1])
    assert doc.dpj_ref is None
    doc.apply(Synthesize(ref, 7, 5, 3))
    assert doc.shape == (5, 7) and doc.num_levels == 3 and doc.dpj is TINY_DPJS[1]
    expected = synthesis.synthesize(TINY_DPJS[1], (5, 7), seed=3).levels
    assert np.array_equal(doc.levels, expected)


def test_apply_takes_the_result_prepared_elsewhere_as_it_is(monkeypatch):
    """The worker's synthesis is what gets applied: no memo between the thread and the GUI."""
    action = Synthesize(REFS[0], 9, 8, 11)
    levels = action.render_result(TINY[REFS[0]]).levels
    monkeypatch.setattr(synthesis, "synthesize", lambda *a, **k: pytest.fail("synthesised"))
    history = History()
    history.add_dpj(TINY[REFS[0]])
    history.apply(action, prepared=levels)
    assert np.array_equal(history.document.levels, levels)
    assert history.document.dpj_ref == REFS[0]
    with pytest.raises(InputError, match="must be a 9x8 uint8"):
        History(history.document.copy()).apply(action, prepared=levels[:, :5])


def test_apply_without_a_prepared_result_synthesises_and_without_the_dpj_refuses():
    doc = Document()
    doc.add_dpj(TINY[REFS[0]], REFS[0])
    doc.apply(Synthesize(REFS[0], 6, 6, 1))
    assert doc.shape == (6, 6)
    assert np.array_equal(doc.levels, synthesis.synthesize(TINY[REFS[0]], (6, 6), seed=1).levels)
    with pytest.raises(InputError, match="not part of this document"):
        Document().apply(Synthesize(REFS[1], 6, 6, 1))


def test_render_result_checks_the_dpj_and_passes_progress_and_cancel():
    action = Synthesize(REFS[0], 40, 40, 5)
    with pytest.raises(InputError, match="not .* the one"):
        action.render_result(TINY[REFS[1]])
    with pytest.raises(Cancelled):
        action.render_result(TINY[REFS[0]], cancel=lambda: True)
    seen = []
    action.render_result(TINY[REFS[0]], progress=seen.append)
    assert seen and seen[-1] == 1.0


def test_render_result_gives_the_repair_count():
    action = Synthesize(REFS[1], 10, 6, 2)
    result = action.render_result(TINY[REFS[1]])
    assert result.repairs >= 0 and result.levels.shape == (6, 10)

