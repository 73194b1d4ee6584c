"""RenderGrains, Mix, Incrust and DoubleLevels as Actions (issue 9): JSON, replay, undo, the
canvas size change seen by the log optimiser, later steps replayed after an edit, files."""

import json

import numpy as np
import pytest

from tests.support import REFS, TINY, TINY_DPJS
from tests.support.texture import EXAMPLES, SYNTH, SYNTH3, T, history_of
from texeditor.texture import composition
from texeditor.markov import doubling
from texeditor.texture import grain_render as gr
from texeditor.recipe.actions import REGISTRY, NewCanvas, SetLevels, SetPalette, Synthesize
from texeditor.recipe.codec import action_from_json
from texeditor.errors import FormatError, InputError
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.markov.levels import load_image
from texeditor.recipe.logopt import optimize, trace
from texeditor.resources import ROOT
from texeditor.texture.actions import (TEXTURE_ACTIONS, DoubleLevels, Incrust, Mix, MixTextures,
                                      RenderGrains)
from texeditor.recipe.sources import recipe_of, render_recipe
from texeditor.recipe.texturefile import load_texture, save_texture


def test_every_texture_action_is_registered_with_its_effect():
    assert all(REGISTRY[cls.TYPE] is cls for cls in TEXTURE_ACTIONS)
    assert {type(a) for a in EXAMPLES} == set(TEXTURE_ACTIONS)
    assert RenderGrains.EFFECT == "canvas" and DoubleLevels.EFFECT == "other"
    assert Mix.EFFECT == Incrust.EFFECT == "levels"


@pytest.mark.parametrize("action", EXAMPLES, ids=lambda a: a.TYPE)
def test_json_round_trip(action):
    obj = json.loads(json.dumps(action.to_json()))
    assert action_from_json(obj) == action
    assert action.label()


@pytest.mark.parametrize("obj, what", [
    ({"shape": "blob"}, "shape"), ({"size": 0}, "size"), ({"overlap": "sum"}, "overlap"),
    ({"explosion_x": 0.5}, "explosion_x"), ({"compression": 0.95}, "compression"),
    ({"compression_x": 1.0}, "compression_x"),
    ({"lattice": "hex"}, "lattice"), ({"shape": "bitmap", "bitmap": "xyz"}, "drawn grain")])
def test_bad_grain_parameters_are_refused_on_load(obj, what):
    with pytest.raises(FormatError, match=what):
        action_from_json({"type": "render_grains", "version": 1, **obj})


# -- RenderGrains ----------------------------------------------------------------------------------

def test_render_grains_makes_a_larger_canvas_of_grains():
    history = history_of(T, extra=[RenderGrains("circle", 4)])
    doc = history.document
    assert doc.shape == (8, 12) == RenderGrains("circle", 4).canvas_shape(T.shape)
    assert np.array_equal(doc.levels, gr.render(T, "circle", 4))
    assert doc.num_levels == 3


def test_undo_of_render_grains_gives_back_the_normalised_texture():
    history = history_of(T, extra=[RenderGrains("hexagon", 6, explosion_x=2)])
    rendered = history.document.levels.copy()
    history.undo()
    assert np.array_equal(history.document.levels, T)
    history.redo()
    assert np.array_equal(history.document.levels, rendered)


def test_editing_the_grain_size_replays_the_later_edits_on_the_new_canvas():
    history = history_of(T, extra=[RenderGrains("square", 2), SetLevels(0, 0, 1, 3, 2),
                                   SetPalette(((0, 0, 0), (90, 90, 90), (250, 0, 0)))])
    k = 1 + int((T > 0).sum())                            # the RenderGrains step
    assert isinstance(history.actions[k], RenderGrains)
    history.replace(k, RenderGrains("square", 4, explosion_y=2))
    doc = history.document
    assert doc.shape == (16, 12)
    expect = gr.render(T, "square", 4, explosion_y=2)
    expect[0, :3] = 2                                     # the later SetLevels, replayed
    assert np.array_equal(doc.levels, expect)
    assert doc.palette[2].tolist() == [250, 0, 0]          # and the palette change after it


def test_the_log_optimiser_knows_the_new_canvas_size():
    actions = [NewCanvas(3, 2, 3), SetLevels(0, 0, 1, 1, 1), SetLevels(1, 1, 1, 2, 2),
               RenderGrains("square", 3, explosion_x=2), SetLevels(0, 0, 100, 100, 1),
               SetLevels(2, 2, 2, 2, 2)]
    known = trace(actions)
    assert known[4].shape == (6, 18) and known[5].shape == (6, 18)
    shorter = optimize(actions)
    assert len(shorter) < len(actions)
    a, b = replay(actions, {}), replay(shorter, {})
    assert a.result_hash() == b.result_hash()


def test_compression_across_only_renders_and_old_steps_keep_both_axes():
    """A step of release 0.1 has no compression_x: its compression still squeezes both axes."""
    old = action_from_json({"type": "render_grains", "version": 1, "shape": "square", "size": 4,
                            "compression": 0.5})
    assert old.compression_x is None and old.grain_lattice() == gr.Lattice(2, 2)
    across = RenderGrains("square", 4, compression=0.0, compression_x=0.5)
    assert across.grain_lattice() == gr.Lattice(4, 2)
    assert across.label() == "Grains: square 4 px, compression 0.5 across, 0 down (last)"
    history = history_of(T, extra=[across])
    assert history.document.shape == (8, 6)
    assert np.array_equal(history.document.levels, gr.render(T, "square", 4, compression=0,
                                                              compression_x=0.5))
    assert replay(history.applied, TINY).result_hash() == history.document.result_hash()


def test_render_grains_too_large_is_refused_and_the_document_kept():
    history = history_of(np.zeros((600, 600), np.uint8), 2, extra=[SetLevels(0, 0, 600, 600, 1)])
    before = history.document.levels.copy()
    with pytest.raises(InputError, match="largest canvas"):
        history.apply(RenderGrains("square", 64))
    assert np.array_equal(history.document.levels, before)


# -- composition -----------------------------------------------------------------------------------

def synth_levels(recipe):
    return render_recipe(recipe, dict(TINY))[0]


def test_mix_with_a_synthesis_of_a_stored_dpj():
    base = np.array([[1, 0, 1, 1, 0, 0]] * 5, np.uint8)
    action = Mix(SYNTH, (REFS[0],), op2="xor")
    history = history_of(base, 2, extra=[action])
    t2 = synth_levels(SYNTH)
    assert np.array_equal(history.document.levels, base ^ t2)
    again = replay(history.applied, TINY)
    assert again.result_hash() == history.document.result_hash()
    history.undo()
    assert np.array_equal(history.document.levels, base)


def test_mix_a_source_of_other_g_and_other_size():
    """A 4×4 G = 3 source mixed into a 5×6 G = 3 canvas: repeated to cover it."""
    base = np.zeros((5, 6), np.uint8)
    history = history_of(base, 3, extra=[Mix(SYNTH3, (REFS[1],), op2="max")])
    t2 = synth_levels(SYNTH3)
    assert np.array_equal(history.document.levels, composition.fit(t2, (5, 6)))


def test_incrust_where_the_documents_own_level_is_background():
    history = history_of(T, 3, extra=[Incrust(SYNTH3, (REFS[1],), mask="levels", levels="0")])
    t2 = synth_levels(SYNTH3)[:2, :3]
    assert np.array_equal(history.document.levels, np.where(T == 0, t2, T))


def test_incrust_painted_points_and_a_mask_texture():
    base = np.full((4, 4), 1, np.uint8)
    painted = Incrust(SYNTH3, (REFS[1],), mask="points", points=((0, 0), (3, 2), (9, 9)))
    history = history_of(base, 3, extra=[painted])
    t2 = synth_levels(SYNTH3)
    expect = base.copy()
    expect[0, 0], expect[3, 2] = t2[0, 0], t2[3, 2]
    assert np.array_equal(history.document.levels, expect)

    mask_texture = Incrust(SYNTH3, (REFS[1],), mask="texture", levels="1",
                           mask_source=SYNTH, mask_dpjs=(REFS[0],))
    history = history_of(base, 3, extra=[mask_texture])
    m = synth_levels(SYNTH)[:4, :4]
    assert np.array_equal(history.document.levels, np.where(m == 1, t2, base))


def test_a_composition_is_saved_with_its_sources_dpj_and_replays(tmp_path):
    history = History()
    ref = history.add_dpj(TINY_DPJS[0])
    history.apply(Synthesize(ref, 6, 5, 7))
    history.document.store_dpj(TINY_DPJS[1])
    history.apply(Incrust(SYNTH3, (REFS[1],), mask="levels", levels="1"))
    path = tmp_path / "composed.texture"
    save_texture(path, history)
    again, manifest = load_texture(path)              # replays and checks the hash
    assert again.document.result_hash() == history.document.result_hash()
    assert set(again.document.dpjs) == {REFS[0], REFS[1]}
    assert again.document.dpj_ref == ref               # the source's DPJ did not become current


def test_a_recipe_can_be_any_log():
    recipe = recipe_of([NewCanvas(3, 2, 4), SetLevels(0, 1, 2, 2, 3)])
    history = history_of(np.zeros((2, 3), np.uint8), 4, extra=[Mix(recipe, op2="max")])
    assert history.document.levels.tolist() == [[0, 3, 3], [0, 3, 3]]


@pytest.mark.parametrize("recipe, refs, what", [
    ("not json", (), "not valid JSON"), ('{"steps": []}', (), "actions"),
    ('{"actions": []}', (), "1.."), ('{"actions": [{"type": "nope", "version": 1}]}', (),
                                     "unknown action"),
    (SYNTH, (REFS[1],), "uses DPJ"), (SYNTH, (), "uses DPJ"),
    (SYNTH, (REFS[0], REFS[1]), "does not use DPJ"),
    (recipe_of([Synthesize(REFS[0], 2, 2), Mix(SYNTH3, (REFS[1],))]), (REFS[0],), "uses DPJ")])
def test_bad_recipes_are_refused(recipe, refs, what):
    with pytest.raises(InputError, match=what):
        Mix(recipe, refs)


def test_composition_errors():
    with pytest.raises(InputError, match="unknown operator"):
        Mix(SYNTH, (REFS[0],), op2="nand")
    with pytest.raises(InputError, match="mask"):
        Incrust(SYNTH, (REFS[0],), mask="brush")
    with pytest.raises(InputError, match="recipe"):
        Incrust(SYNTH, (REFS[0],), mask="texture")
    with pytest.raises(InputError, match="1,3-5"):
        Incrust(SYNTH, (REFS[0],), mask="levels", levels="one")
    history = History()
    history.apply(NewCanvas(3, 3, 2))
    with pytest.raises(InputError, match="not part of this document"):
        history.apply(Mix(SYNTH, (REFS[0],)))
    assert history.index == 1


# -- incrustation by blocks and mixes of N textures (issue 21 item 9) -----------------------------

def drawn_recipe(width, height, g, *rects):
    """The recipe of a hand-made texture: a blank canvas and rectangles (top, left, h, w, v)."""
    return recipe_of([NewCanvas(width, height, g), *(SetLevels(*r) for r in rects)])


DIAGONAL = drawn_recipe(2, 2, 2, (0, 0, 1, 1, 1), (1, 1, 1, 1, 1))     # 1 . / . 1
TWOS = drawn_recipe(4, 4, 3, (0, 0, 4, 4, 2))                          # every point 2


def test_a_mask_texture_by_blocks_shows_t2_in_whole_blocks():
    history = history_of(np.zeros((4, 6), np.uint8), 3, extra=[
        Incrust(TWOS, mask="texture", levels="1", mask_source=DIAGONAL, block=2)])
    assert history.document.levels.tolist() == [[2, 2, 0, 0, 2, 2], [2, 2, 0, 0, 2, 2],
                                                 [0, 0, 2, 2, 0, 0], [0, 0, 2, 2, 0, 0]]
    assert history.applied[-1].label().endswith("by blocks of 2")
    assert replay(history.applied, {}).result_hash() == history.document.result_hash()
    history.undo()
    assert not history.document.levels.any()


def test_painted_points_and_the_documents_levels_by_blocks():
    painted = Incrust(TWOS, mask="points", points=((0, 0), (0, 1), (3, 3)), block=2)
    history = history_of(np.zeros((4, 4), np.uint8), 3, extra=[painted])
    # block (0, 0) holds 2 of its 4 points, block (1, 1) 1 of 4
    assert history.document.levels.tolist() == [[2, 2, 0, 0], [2, 2, 0, 0], [0] * 4, [0] * 4]
    own = np.array([[1, 1, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]], np.uint8)
    history = history_of(own, 3, extra=[Incrust(TWOS, mask="levels", levels="1", block=2)])
    assert history.document.levels.tolist() == [[2, 2, 0, 0], [2, 2, 0, 0], [0, 0, 0, 0],
                                                [0, 0, 0, 1]]


def test_an_incrustation_of_release_0_1_has_blocks_of_one_point():
    old = action_from_json({"type": "incrust", "version": 2, "source": TWOS,
                            "source_dpjs": [], "mask": "levels", "levels": "1"})
    assert old.block == 1
    own = np.array([[1, 0], [0, 0]], np.uint8)
    assert history_of(own, 3, extra=[old]).document.levels.tolist() == [[2, 0], [0, 0]]


def test_a_mix_of_three_textures_in_one_expression():
    """The share of white of three black/white textures, on G = 4 (see test_composition): it
    cannot be had from two mixes in a row, which round to the levels in between."""
    t2 = drawn_recipe(5, 1, 4, (0, 2, 1, 3, 3))                  # . . 3 3 3
    t3 = drawn_recipe(5, 1, 2, (0, 3, 1, 2, 1))                  # . . . 1 1 (G = 2)
    base = np.array([[0, 3, 3, 0, 3]], np.uint8)
    action = MixTextures((t2, t3), expression="(0.34 multiply T1) add (0.33 multiply T2) "
                                              "add (0.33 multiply T3)")
    history = history_of(base, 4, extra=[action])
    assert history.document.levels.tolist() == [[0, 1, 2, 2, 3]]
    assert action.label() == "Mix T1…T3: (0.34 multiply T1) add (0.33 multiply T…"
    again = action_from_json(json.loads(json.dumps(action.to_json())))
    assert again == action and again.sources == (t2, t3)
    assert replay(history.applied, {}).result_hash() == history.document.result_hash()
    history.undo()
    assert history.document.levels.tolist() == base.tolist()


def test_a_mix_of_four_textures_with_synthesised_sources_saved_and_reopened(tmp_path):
    history = History()
    ref = history.add_dpj(TINY_DPJS[0])
    history.apply(Synthesize(ref, 6, 5, 7))
    history.document.store_dpj(TINY_DPJS[1])
    action = MixTextures((SYNTH, SYNTH3, DIAGONAL), (REFS[0], REFS[1]),
                         expression="T1 xor T2 xor [T3 min T4]")
    history.apply(action)
    t1 = replay(history.applied[:1], TINY).levels
    t2, t3 = synth_levels(SYNTH), composition.fit(synth_levels(SYNTH3), (5, 6))
    t4 = composition.fit(np.eye(2, dtype=np.uint8), (5, 6))
    # G = 2 target: T3's greys (0, 1/2, 1) count as white from 1/2 up (codes half up)
    expected = t1 ^ t2 ^ np.minimum((t3 >= 1).astype(np.uint8), t4)
    assert np.array_equal(history.document.levels, expected)
    path = tmp_path / "four.texture"
    save_texture(path, history)
    again, _ = load_texture(path)
    assert again.document.result_hash() == history.document.result_hash()


@pytest.mark.parametrize("make, what", [
    (lambda: MixTextures((SYNTH,), (REFS[0],), expression="T1 max T2"), "2..7 texts"),
    (lambda: MixTextures((TWOS, DIAGONAL), expression="T1 max T2"), "does not use T3"),
    (lambda: MixTextures((TWOS, DIAGONAL), expression="T1 max T2 max T5"), "names T5"),
    (lambda: MixTextures((SYNTH, DIAGONAL), (), expression="T1 max T2 max T3"),
     "T2 uses DPJ"),
    (lambda: MixTextures((TWOS, DIAGONAL), (REFS[0],)), "no texture uses DPJ"),
    (lambda: MixTextures((TWOS, "not json")), "T3: .*not valid JSON"),
])
def test_bad_mixes_are_refused(make, what):
    with pytest.raises(InputError, match=what):
        make()


def test_a_block_must_be_a_whole_number_of_points():
    with pytest.raises(InputError, match="block = 0"):
        Incrust(TWOS, mask="levels", levels="1", block=0)


# -- doubling --------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def table():
    photo = load_image(ROOT / "images" / "gravel.png")[:80, :80]
    return doubling.learn(photo, 3, "band", name="gravel")


def test_double_levels_action(table, tmp_path):
    base = np.array([[0, 1, 2, 2], [1, 2, 0, 1], [2, 2, 1, 0]], np.uint8)
    history = history_of(base, 3)
    ref = history.document.store_dpj(table)
    history.apply(DoubleLevels(ref, 5))
    doc = history.document
    assert doc.num_levels == 6 and np.array_equal(doc.palette, table.palette)
    assert np.array_equal(doc.levels // 2, base)
    assert np.array_equal(doc.levels, doubling.double_levels(base, table, 5).levels)
    path = tmp_path / "doubled.texture"
    save_texture(path, history)
    again, _ = load_texture(path)
    assert again.document.result_hash() == doc.result_hash()
    history.undo()
    assert doc.num_levels == 3 and np.array_equal(doc.levels, base)


def test_double_levels_given_its_levels_then_replayed_after_an_earlier_edit(table):
    """A window doubles in its worker and applies the levels as ``prepared``; an edit of an
    earlier step then replays the doubling on the new levels (no cache hands back the old)."""
    base = np.array([[0, 1, 2, 2], [1, 2, 0, 1], [2, 2, 1, 0]], np.uint8)
    history = history_of(base, 3)
    ref = history.document.store_dpj(table)
    action = DoubleLevels(ref, 5)
    history.apply(action, prepared=action.doubled(history.document))
    assert np.array_equal(history.document.levels, doubling.double_levels(base, table, 5).levels)
    other = history_of(base, 3)
    other.document.store_dpj(table)
    with pytest.raises(InputError, match="4x3 uint8"):
        other.apply(action, prepared=np.zeros((2, 2), np.uint8))
    history.insert(len(history.actions) - 1, SetLevels(0, 0, 1, 4, 0))    # before the doubling
    edited = base.copy()
    edited[0] = 0
    assert np.array_equal(history.document.levels // 2, edited)
    assert np.array_equal(history.document.levels,
                          doubling.double_levels(edited, table, 5).levels)


def test_double_levels_needs_the_tables_g(table):
    history = history_of(np.ones((3, 3), np.uint8), 4)
    ref = history.document.store_dpj(table)
    before = history.document.result_hash()
    with pytest.raises(InputError, match="G = 3 levels"):
        history.apply(DoubleLevels(ref))
    assert history.document.result_hash() == before
