"""Bank entries and recipes as texture sources (issues 7 and 9): a spot filled with another
texture's recipe, a composition from a bank entry; replay, files, old logs, bad recipes, G."""

import json
import sqlite3

import numpy as np
import pytest

from tests.support import REFS, TINY, TINY_DPJS
from texeditor.recipe.actions import NewCanvas, SetLevels, Synthesize
from texeditor.recipe.codec import action_from_json
from texeditor.bank.store import Bank, BankError
from texeditor.texture.composition import convert_levels, fit
from texeditor.errors import FormatError, InputError, ReplayError
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.spots.actions import DeleteSpot, PlaceSpot, ScatterSpots, spot_ref
from texeditor.spots.envelope import Envelope
from texeditor.texture.actions import Incrust, Mix
from texeditor.recipe.sources import bank_source, recipe_of, render_recipe, synthesis_recipe
from texeditor.recipe.texturefile import load_texture, save_texture

DISC = Envelope.ellipse(12, 12).dumps()
SMALL = '{"a":[0.0,-3.0],"b":[0.0,3.0],"kind":"bspline","meridians":[[0.5,2.0,2.0,true]],' \
        '"parallels":[]}'
SYNTH2 = synthesis_recipe(REFS[0], 6, 5, 3)                    # 6×5, G = 2, from a DPJ
DRAWN4 = recipe_of([NewCanvas(5, 4, 4), SetLevels(0, 0, 2, 5, 3), SetLevels(2, 1, 2, 2, 1)])

# Placements as logs wrote them before texture fills existed (no "texture" parameter).
OLD_PLACE = {"type": "place_spot", "version": 1, "envelope": SMALL, "row": 5.0, "col": 6.0,
             "angle": 0.0, "scale": 1.0, "seed": 3, "level": 2, "fill": "level", "dpj": None,
             "source_row": None, "source_col": None, "contour": 0.0, "frequency": 6,
             "fractal": 0.0, "roughness": 0.5, "interior": "none", "density": 0.0,
             "grain": 3.0, "shift": 1, "blend": "over", "wrap": False}
OLD_SCATTER = {"type": "scatter_spots", "version": 1, "envelope": SMALL, "count": 3, "seed": 1,
               "top": None, "left": None, "height": None, "width": None, "angle": 0.0,
               "angle_spread": 180.0, "scale": 1.0, "scale_max": None, "level": 1,
               "level_max": None, "fill": "dpj", "dpj": REFS[0], "contour": 0.0,
               "frequency": 6, "fractal": 0.0, "roughness": 0.5, "interior": "none",
               "density": 0.0, "grain": 3.0, "shift": 1, "blend": "over", "wrap": False}


def canvas(levels: int = 4, width: int = 40, height: int = 30) -> History:
    history = History()
    history.document.dpjs.update(TINY)
    history.apply(NewCanvas(width, height, levels))
    return history


def spot_points(action, shape):
    """(rows, cols) of the canvas points spot 0 of ``action`` covers (inside the canvas)."""
    stamp = action.stamp(0, shape)
    rows, cols = np.nonzero(stamp.mask)
    return rows + stamp.top, cols + stamp.left


def tiled(texture, rows, cols):
    return texture[rows % texture.shape[0], cols % texture.shape[1]]


# -- a spot filled with a recipe's texture ---------------------------------------------------------

def test_a_spot_shows_the_recipes_texture_where_it_lands_and_replays_identically():
    history = canvas(4)
    spot = PlaceSpot(DISC, 15, 20, fill="texture", texture=DRAWN4)
    history.apply(spot)
    levels = history.document.levels
    rows, cols = spot_points(spot, levels.shape)
    texture, g = render_recipe(DRAWN4, {})
    assert g == 4 and np.array_equal(levels[rows, cols], tiled(texture, rows, cols))
    outside = np.ones(levels.shape, bool)
    outside[rows, cols] = False
    assert not levels[outside].any()
    assert replay(history.actions, {}).result_hash() == history.document.result_hash()
    assert "another texture" in spot.label()
    history.undo()
    assert not history.document.levels.any()


def test_a_texture_of_another_g_is_mapped_on_the_grey_scale():
    history = canvas(4)
    spot = PlaceSpot(DISC, 15, 20, fill="texture", texture=SYNTH2, texture_dpjs=(REFS[0],))
    history.apply(spot)
    rows, cols = spot_points(spot, history.document.shape)
    texture = convert_levels(render_recipe(SYNTH2, TINY)[0], 2, 4)
    inside = history.document.levels[rows, cols]
    assert set(np.unique(inside)) == {0, 3}           # G = 2 on a G = 4 grey scale
    assert np.array_equal(inside, tiled(texture, rows, cols))

    two = canvas(2)
    spot = PlaceSpot(DISC, 15, 20, fill="texture", texture=DRAWN4)
    two.apply(spot)
    rows, cols = spot_points(spot, two.document.shape)
    texture = convert_levels(render_recipe(DRAWN4, {})[0], 4, 2)
    assert np.array_equal(two.document.levels[rows, cols], tiled(texture, rows, cols))


def test_a_scatter_of_texture_spots_and_a_deletion_replay():
    history = canvas(4)
    history.apply(SetLevels(0, 0, 30, 40, 2))
    history.apply(ScatterSpots(DISC, 8, seed=4, scale=0.5, fill="texture", texture=DRAWN4,
                               blend="max"))
    scattered = history.document.levels.copy()
    assert (scattered == 3).any()
    history.apply(DeleteSpot(2, spot_ref(history.actions[2]), 0))
    assert replay(history.actions, TINY).result_hash() == history.document.result_hash()
    history.apply(DeleteSpot(2, spot_ref(history.actions[2])))
    assert (history.document.levels == 2).all()


def test_a_texture_spot_is_saved_with_its_recipe_and_dpj(tmp_path):
    history = History()
    main = history.add_dpj(TINY_DPJS[1])
    history.apply(Synthesize(main, 30, 20, 5))
    history.document.store_dpj(TINY_DPJS[0])
    history.apply(PlaceSpot(DISC, 10, 12, fill="texture", texture=SYNTH2,
                            texture_dpjs=(REFS[0],)))
    path = tmp_path / "spots.texture"
    save_texture(path, history)
    again, _ = load_texture(path)                       # replays and checks the hash
    assert again.document.result_hash() == history.document.result_hash()
    assert again.actions[-1].texture == SYNTH2 and again.document.dpj_ref == main
    assert set(again.document.dpjs) == {REFS[0], REFS[1]}


def test_old_placements_without_the_texture_parameter_load_unchanged():
    for old in (OLD_PLACE, OLD_SCATTER):
        action = action_from_json(json.loads(json.dumps(old)))
        assert action.texture is None and action.to_json() == old
    assert spot_ref(action_from_json(OLD_PLACE)) == "8392c46bd8722483"   # as before
    history = canvas(4)
    history.apply(action_from_json(OLD_PLACE))
    history.apply(action_from_json(OLD_SCATTER))
    assert history.document.levels[5, 6] == 2


@pytest.mark.parametrize("params, what", [
    (dict(fill="texture"), "needs the recipe"),
    (dict(fill="level", texture=DRAWN4), "goes with a texture fill"),
    (dict(fill="texture", texture="not json"), "not valid JSON"),
    (dict(fill="texture", texture='{"actions": []}'), "1.."),
    (dict(fill="texture", texture=SYNTH2), "uses DPJ"),
    (dict(fill="texture", texture=SYNTH2, texture_dpjs=[REFS[1]]), "uses DPJ"),
    (dict(fill="texture", texture=SYNTH2, dpj=REFS[0]), "not dpj"),
    (dict(fill="level", texture_dpjs=[REFS[0]]), "goes with a texture fill"),
    (dict(fill="texture", texture=recipe_of([Synthesize(REFS[0], 2, 2),
                                               Mix(synthesis_recipe(REFS[1], 2, 2, 0),
                                                   (REFS[1],))]),
          texture_dpjs=[REFS[0]]), "uses DPJ 483b9e9b9227a621")])
def test_bad_texture_fills_are_refused(params, what):
    with pytest.raises(InputError, match=what):
        PlaceSpot(DISC, 5, 5, **params)
    obj = PlaceSpot(DISC, 5, 5).to_json() | {"version": 2} | params
    with pytest.raises(FormatError, match=what):
        action_from_json(obj)


def test_a_texture_spot_whose_dpj_is_missing_changes_nothing():
    history = History()
    history.apply(NewCanvas(10, 10, 2))
    with pytest.raises(InputError, match="not part of this document"):
        history.apply(PlaceSpot(DISC, 5, 5, fill="texture", texture=SYNTH2,
                                texture_dpjs=(REFS[0],)))
    assert history.index == 1 and not history.document.levels.any()


# -- bank entries ----------------------------------------------------------------------------------

@pytest.fixture
def bank(tmp_path):
    with Bank(tmp_path / "bank.sqlite", builtins=False) as b:
        yield b


def pebbles(bank, seed: int = 1) -> int:
    """An entry of G = 3: a synthesis from TINY_DPJS[1] with a rectangle of level 2."""
    history = History()
    ref = history.add_dpj(TINY_DPJS[1])
    history.apply(Synthesize(ref, 12, 10, seed))
    history.apply(SetLevels(0, 0, 2, 3, 2))
    return bank.add(history, "pebbles", tags=["stone"])


def test_a_bank_entry_becomes_its_recipe_and_dpj(bank):
    entry = pebbles(bank)
    source = bank_source(bank, entry)
    recipe = bank.recipe(entry)
    assert source.recipe == recipe_of(recipe.actions) and source.refs == (REFS[1],)
    assert source.dpjs == {REFS[1]: TINY_DPJS[1]}
    assert source.levels == 3 and source.name == "pebbles"
    levels, g = render_recipe(source.recipe, source.dpjs)
    assert g == 3 and np.array_equal(levels, bank.render(entry).levels)
    doc = History().document
    source.store(doc)
    assert doc.dpjs == {REFS[1]: TINY_DPJS[1]} and doc.dpj_ref is None


def test_a_composition_from_a_bank_entry_replays_after_the_entry_is_gone(bank, tmp_path):
    entry = pebbles(bank)
    source = bank_source(bank, entry)
    entry_levels = bank.render(entry).levels
    history = canvas(3, 20, 15)
    source.store(history.document)
    history.apply(Incrust(source.recipe, source.refs, mask="levels", levels="0-2"))
    assert np.array_equal(history.document.levels, fit(entry_levels, (15, 20)))
    history.apply(Mix(source.recipe, source.refs, op2="xor"))
    path = tmp_path / "composed.texture"
    save_texture(path, history)
    bank.trash(entry)
    bank.purge()
    pebbles(bank, seed=2)                                 # the bank changes meanwhile
    again, _ = load_texture(path)
    assert again.document.result_hash() == history.document.result_hash()


def test_a_spot_filled_from_a_bank_entry(bank):
    entry = pebbles(bank)
    source = bank_source(bank, entry)
    history = canvas(3)
    source.store(history.document)
    spot = PlaceSpot(DISC, 12, 14, fill="texture", texture=source.recipe,
                     texture_dpjs=source.refs)
    history.apply(spot)
    rows, cols = spot_points(spot, history.document.shape)
    expected = tiled(bank.render(entry).levels, rows, cols)
    assert np.array_equal(history.document.levels[rows, cols], expected)


def test_a_damaged_or_missing_entry_is_refused(bank):
    entry = pebbles(bank)
    with sqlite3.connect(bank.path) as conn:
        conn.execute("UPDATE entries SET sha256 = ? WHERE id = ?", ("0" * 64, entry))
    with pytest.raises(ReplayError, match="damaged"):
        bank_source(bank, entry)
    with pytest.raises(BankError, match="no entry"):
        bank_source(bank, entry + 100)
