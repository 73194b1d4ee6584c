"""Texture sources (recipes) made from several DPJs, at any depth: Mix, Incrust and the spot
texture fill with a two-DPJ source and a nested one; `.texture` and bank round trips (the bank
entry deleted afterwards); version-1 logs migrated bit for bit; malformed references and the
limits refused with clear messages."""

import io
import json
import sqlite3
import zipfile

import numpy as np
import pytest

from tests.support import DATA, REFS, TINY, TINY_DPJS, all_windows_dpj
from texeditor.recipe import sources
from texeditor.recipe.cache import Cache
from texeditor.recipe.actions import NewCanvas, SetLevels, Synthesize, dpj_refs
from texeditor.recipe.codec import action_from_json
from texeditor.bank.store import Bank
from texeditor.texture.composition import convert_levels, fit, mix
from texeditor.recipe.document import dpj_ref
from texeditor.errors import FormatError, InputError, ReplayError
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.spots.actions import PlaceSpot, ScatterSpots, spot_ref
from texeditor.spots.envelope import Envelope
from texeditor.texture.actions import Incrust, Mix
from texeditor.recipe.sources import (MAX_RECIPE_DEPTH, MAX_RECIPE_DPJS, bank_source, parse_recipe, recipe_of, synthesis_recipe)
from texeditor.recipe.texturefile import (load_texture, parse_texture, read_texture, save_texture,
                                   texture_bytes)

THIRD_DPJ = all_windows_dpj(2, (1, 2), seed=3)
THIRD = dpj_ref(THIRD_DPJ)
ALL = {**TINY, THIRD: THIRD_DPJ}
DISC = Envelope.ellipse(10, 10).dumps()

# Two DPJs, flat: a G = 3 synthesis of REFS[1] with spots of a G = 2 texture of REFS[0].
FLAT = recipe_of([Synthesize(REFS[1], 9, 7, 1),
                  ScatterSpots(DISC, 3, seed=2, scale=0.4, fill="dpj", dpj=REFS[0])])
FLAT_REFS = (REFS[1], REFS[0])
# Depth 2: a G = 2 synthesis of a third DPJ, mixed with FLAT, whose step names FLAT's DPJs.
NESTED = recipe_of([Synthesize(THIRD, 7, 5, 4), Mix(FLAT, FLAT_REFS, op2="max")])
NESTED_REFS = (THIRD, REFS[1], REFS[0])
SOURCES = [(FLAT, FLAT_REFS), (NESTED, NESTED_REFS)]

OLD_LOG = DATA / "recipe_steps_v1.json"
OLD_HASH = "f64556dc30ee6ac300cda309ad7e85014efc383d0f5539526c8122d263db67f6"
OLD_SPOT_REFS = ("61534f292aa91fea", "3c2a2667ef2efee0")


@pytest.fixture(autouse=True)
def fresh_memos(monkeypatch):
    """Every test synthesises its sources itself: no memo from another test hides a missing
    DPJ."""
    monkeypatch.setattr(sources, "_RECIPES", Cache(max_items=6))


def levels_of(recipe: str) -> tuple[np.ndarray, int]:
    """A recipe's texture by a plain replay of its log with every test DPJ at hand."""
    doc = replay(parse_recipe(recipe), ALL)
    return doc.levels, doc.num_levels


def canvas(levels: int, width: int = 16, height: int = 12, fill: int = 1) -> History:
    """A History on a canvas of level ``fill`` that holds none of the sources' DPJs yet."""
    history = History()
    history.apply(NewCanvas(width, height, levels))
    history.apply(SetLevels(0, 0, height, width, fill))
    return history


def stored(history: History, refs) -> History:
    for ref in refs:
        history.document.dpjs.setdefault(ref, ALL[ref])
    return history


# -- the parameter kind and what a log names -------------------------------------------------------

def test_the_nested_recipe_is_really_two_deep_and_uses_three_dpjs():
    inner = parse_recipe(NESTED)[1]
    assert isinstance(inner, Mix) and isinstance(parse_recipe(inner.source)[1], ScatterSpots)
    assert dpj_refs(parse_recipe(NESTED)) == list(NESTED_REFS)
    assert dpj_refs([Mix(NESTED, NESTED_REFS)]) == list(NESTED_REFS)
    assert levels_of(FLAT)[1] == 3 and levels_of(NESTED)[1] == 2


@pytest.mark.parametrize("action, refs", [
    (Mix(FLAT, FLAT_REFS, op2="xor"), FLAT_REFS),
    (Mix(NESTED, tuple(reversed(NESTED_REFS))), NESTED_REFS),
    (Incrust(FLAT, FLAT_REFS, mask="texture", levels="1", mask_source=NESTED,
             mask_dpjs=NESTED_REFS), NESTED_REFS),
    (PlaceSpot(DISC, 3, 4, fill="texture", texture=NESTED, texture_dpjs=NESTED_REFS),
     NESTED_REFS),
    (ScatterSpots(DISC, 2, fill="texture", texture=FLAT, texture_dpjs=FLAT_REFS), FLAT_REFS)],
    ids=lambda a: getattr(a, "TYPE", ""))
def test_multi_dpj_steps_round_trip_through_json(action, refs):
    obj = json.loads(json.dumps(action.to_json()))
    assert obj["version"] == 2
    assert action_from_json(obj) == action
    assert set(dpj_refs([action])) == set(refs)


def test_a_spot_whose_recipe_needs_one_dpj_keeps_its_version_1_json():
    one = PlaceSpot(DISC, 3, 4, fill="texture", texture=synthesis_recipe(REFS[0], 4, 4, 1),
                    texture_dpjs=(REFS[0],))
    obj = one.to_json()
    assert obj["version"] == 1 and obj["dpj"] == REFS[0] and "texture_dpjs" not in obj
    assert action_from_json(obj) == one


# -- Mix, Incrust and the spot fill with a two-DPJ and a nested source -----------------------------

@pytest.mark.parametrize("recipe, refs", SOURCES, ids=["two DPJs", "nested"])
def test_mix_with_a_multi_dpj_source(recipe, refs):
    history = stored(canvas(3), refs)
    before = history.document.levels.copy()
    history.apply(Mix(recipe, refs, op2="xor"))
    t2, g2 = levels_of(recipe)
    expected = mix(before, fit(t2, before.shape), levels=3, levels2=g2, op2="xor")
    assert np.array_equal(history.document.levels, expected)
    assert not np.array_equal(expected, before)
    assert replay(history.actions, ALL).result_hash() == history.document.result_hash()


@pytest.mark.parametrize("recipe, refs", SOURCES, ids=["two DPJs", "nested"])
def test_incrust_with_multi_dpj_source_and_mask(recipe, refs):
    history = stored(canvas(3), NESTED_REFS)
    before = history.document.levels.copy()
    mask_recipe, mask_refs = SOURCES[0] if recipe == NESTED else SOURCES[1]
    history.apply(Incrust(recipe, refs, mask="texture", levels="1", mask_source=mask_recipe,
                          mask_dpjs=mask_refs))
    t2, g2 = levels_of(recipe)
    m, _ = levels_of(mask_recipe)
    t2 = convert_levels(fit(t2, before.shape), g2, 3)
    expected = np.where(fit(m, before.shape) == 1, t2, before)
    assert np.array_equal(history.document.levels, expected)
    assert (fit(m, before.shape) == 1).any() and (fit(m, before.shape) != 1).any()


def test_the_nested_source_is_the_composition_of_its_parts():
    """The depth-2 recipe's texture, from its parts replayed one by one."""
    third = replay([Synthesize(THIRD, 7, 5, 4)], ALL).levels
    flat, g = levels_of(FLAT)
    expected = mix(third, fit(flat, third.shape), levels=2, levels2=g, op2="max")
    assert np.array_equal(levels_of(NESTED)[0], expected)


@pytest.mark.parametrize("recipe, refs", SOURCES, ids=["two DPJs", "nested"])
def test_a_spot_filled_with_a_multi_dpj_source(recipe, refs):
    history = stored(canvas(3, 24, 20, fill=0), refs)
    spot = PlaceSpot(DISC, 9, 11, fill="texture", texture=recipe, texture_dpjs=refs)
    history.apply(spot)
    stamp = spot.stamp(0, history.document.shape)
    rows, cols = np.nonzero(stamp.mask)
    rows, cols = rows + stamp.top, cols + stamp.left
    t2, g2 = levels_of(recipe)
    t2 = convert_levels(t2, g2, 3)
    expected = t2[rows % t2.shape[0], cols % t2.shape[1]]
    assert np.array_equal(history.document.levels[rows, cols], expected)
    assert replay(history.actions, ALL).result_hash() == history.document.result_hash()


@pytest.mark.parametrize("missing", NESTED_REFS)
def test_a_step_whose_deep_dpj_is_missing_changes_nothing(missing):
    history = stored(canvas(3), [r for r in NESTED_REFS if r != missing])
    with pytest.raises(InputError, match=f"{missing} of a texture recipe is not part"):
        history.apply(Mix(NESTED, NESTED_REFS))
    assert history.index == 2


# -- files and the bank ----------------------------------------------------------------------------

def composed() -> History:
    """A texture using both sources in all three steps, its own DPJ REFS[1] current."""
    history = History()
    history.apply(Synthesize(history.add_dpj(TINY_DPJS[1]), 20, 16, 9))
    stored(history, NESTED_REFS)
    history.apply(Mix(NESTED, NESTED_REFS, op2="xor"))
    history.apply(Incrust(FLAT, FLAT_REFS, mask="texture", levels="1", mask_source=NESTED,
                          mask_dpjs=NESTED_REFS))
    history.apply(PlaceSpot(DISC, 8, 9, fill="texture", texture=NESTED,
                            texture_dpjs=NESTED_REFS))
    return history


def test_a_texture_file_carries_every_dpj_at_every_depth(tmp_path):
    history = composed()
    path = tmp_path / "nested.texture"
    save_texture(path, history)
    tex = read_texture(path)
    assert set(tex.dpjs) == set(NESTED_REFS)
    assert tex.manifest.dpj == REFS[1] and THIRD in tex.manifest.dpjs
    again, _ = load_texture(path)                      # replays and checks the hash
    assert again.document.result_hash() == history.document.result_hash()


def test_a_file_without_a_deep_dpj_is_refused(tmp_path):
    history = composed()
    del history.document.dpjs[THIRD]
    with pytest.raises(InputError, match=THIRD):
        texture_bytes(history.document, history.applied)


def test_a_file_missing_a_dpj_named_only_deep_down_is_refused():
    """The third DPJ is used only inside NESTED's own Mix: taken out of the file (member and
    manifest), the file names a DPJ it does not hold."""
    history = composed()
    data, _ = texture_bytes(history.document, history.applied)
    with zipfile.ZipFile(io.BytesIO(data)) as zf:
        members = {i.filename: zf.read(i) for i in zf.infolist()}
    manifest = json.loads(members["manifest.json"])
    manifest["dpjs"] = [r for r in manifest["dpjs"] if r != THIRD]
    members["manifest.json"] = json.dumps(manifest).encode()
    del members[f"dpjs/{THIRD}.npz"]
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        for name, content in members.items():
            zf.writestr(name, content)
    with pytest.raises(FormatError, match=f"uses DPJs \\['{THIRD}'\\] that the file does not"):
        parse_texture(buf.getvalue(), "cut.texture")


@pytest.fixture
def bank(tmp_path):
    with Bank(tmp_path / "bank.sqlite", builtins=False) as b:
        yield b


def two_syntheses(bank) -> int:
    """What was refused before: an entry that is a composition of two syntheses."""
    history = History()
    history.apply(Synthesize(history.add_dpj(TINY_DPJS[0]), 10, 8, 1))
    stored(history, [REFS[1]])
    history.apply(Mix(synthesis_recipe(REFS[1], 5, 5, 2), (REFS[1],), op2="max"))
    return bank.add(history, "two syntheses", tags=["composed"])


def test_a_bank_entry_of_two_dpjs_is_a_source(bank, tmp_path):
    entry = two_syntheses(bank)
    source = bank_source(bank, entry)
    assert source.refs == (REFS[0], REFS[1]) and set(source.dpjs) == set(source.refs)
    entry_levels = bank.render(entry).levels
    history = canvas(2, 20, 15)
    source.store(history.document)
    history.apply(Incrust(source.recipe, source.refs, mask="levels", levels="0-1"))
    assert np.array_equal(history.document.levels, fit(entry_levels, (15, 20)))
    path = tmp_path / "from the bank.texture"
    save_texture(path, history)
    bank.trash(entry)
    bank.purge()
    again, _ = load_texture(path)
    assert again.document.result_hash() == history.document.result_hash()


def test_a_nested_texture_goes_to_the_bank_and_comes_back_as_a_deeper_source(bank, tmp_path):
    history = composed()
    entry = bank.add(history, "nested")
    assert set(bank.recipe(entry).dpjs) == set(NESTED_REFS)
    assert bank.render(entry).result_hash() == history.document.result_hash()
    source = bank_source(bank, entry)             # its steps' recipes are now two levels down
    assert set(source.refs) == set(NESTED_REFS)
    user = canvas(3, 14, 10)
    source.store(user.document)
    user.apply(Mix(source.recipe, source.refs, op2="max"))
    user.apply(PlaceSpot(DISC, 5, 6, fill="texture", texture=source.recipe,
                         texture_dpjs=source.refs))
    path = tmp_path / "deeper.texture"
    save_texture(path, user)
    bank.trash(entry)
    bank.purge()
    assert bank.entries() == []
    again, _ = load_texture(path)
    assert again.document.result_hash() == user.document.result_hash()
    assert set(again.document.dpjs) == set(NESTED_REFS)
    again_entry = bank.add(again, "deeper")
    assert bank.render(again_entry).result_hash() == user.document.result_hash()


# -- version-1 logs --------------------------------------------------------------------------------

def test_a_version_1_log_loads_replays_bit_for_bit_and_is_saved_as_version_2(tmp_path):
    """tests/data/recipe_steps_v1.json was written by the code before "refs" existed (Mix,
    Incrust and texture spots naming one DPJ in source_dpj / mask_dpj / dpj)."""
    old = json.loads(OLD_LOG.read_text())["actions"]
    steps = [action_from_json(obj) for obj in old]
    mixed, incrust = steps[1], steps[2]
    assert mixed.source_dpjs == (REFS[0],) and incrust.source_dpjs == (REFS[1],)
    assert incrust.mask_dpjs == (REFS[0],) and steps[3].texture_dpjs == (REFS[0],)
    history = History.from_log(steps, TINY)
    assert history.document.result_hash() == OLD_HASH
    assert tuple(spot_ref(a) for a in steps[3:]) == OLD_SPOT_REFS
    assert [a.to_json() for a in steps[3:]] == old[3:]        # placements keep their JSON
    path = tmp_path / "migrated.texture"
    save_texture(path, history)
    saved = read_texture(path)
    new = [a.to_json() for a in saved.actions]
    assert [o["version"] for o in new] == [Synthesize.VERSION, 2, 2, 1, 1]   # upgraded on load
    assert new[2]["mask_dpjs"] == [REFS[0]] and "mask_dpj" not in new[2]
    again, _ = load_texture(path)
    assert again.document.result_hash() == OLD_HASH


@pytest.mark.parametrize("obj, what", [
    ({"type": "mix", "version": 1, "source": FLAT, "source_dpj": REFS[1]}, "uses DPJ"),
    ({"type": "mix", "version": 1, "source": FLAT, "source_dpj": REFS[1],
      "source_dpjs": list(FLAT_REFS)}, "version 1 has no parameter 'source_dpjs'"),
    ({"type": "mix", "version": 3, "source": FLAT}, "version 3 is not supported"),
    ({"type": "place_spot", "version": 1, "envelope": DISC, "row": 1, "col": 1,
      "fill": "level", "texture_dpjs": []}, "version 1 has no parameter")])
def test_bad_old_json_is_refused(obj, what):
    with pytest.raises(FormatError, match=what):
        action_from_json(obj)


# -- malformed references and limits ---------------------------------------------------------------

FAKE = [f"{i:016x}" for i in range(MAX_RECIPE_DPJS + 1)]


@pytest.mark.parametrize("refs, what", [
    (REFS[0], "must be a list of DPJ references"),
    ([5, REFS[1]], "each of source_dpjs must be a DPJ reference"),
    (["not-a-ref"], "each of source_dpjs must be a DPJ reference"),
    ((REFS[1], REFS[1], REFS[0]), "more than once"),
    (FAKE, f"names {MAX_RECIPE_DPJS + 1} DPJs; at most {MAX_RECIPE_DPJS}"),
    ((REFS[1],), f"uses DPJ {REFS[0]}, which the step does not name"),
    ((*FLAT_REFS, THIRD), f"does not use DPJ {THIRD}")])
def test_malformed_refs_are_refused(refs, what):
    with pytest.raises(InputError, match=what):
        Mix(FLAT, refs)
    obj = {"type": "mix", "version": 2, "source": FLAT, "source_dpjs": refs}
    with pytest.raises(FormatError, match=what):
        action_from_json(json.loads(json.dumps(obj)))


def test_a_source_needing_too_many_dpjs_is_refused():
    recipe = recipe_of([Synthesize(ref, 2, 2) for ref in FAKE])
    with pytest.raises(InputError, match=f"made from {len(FAKE)} DPJs.*at most "
                                         f"{MAX_RECIPE_DPJS}"):
        Mix(recipe, FAKE[:MAX_RECIPE_DPJS])


def nested_text(depth: int) -> str:
    """A recipe ``depth`` levels deep, written as JSON (making its steps would refuse it)."""
    base = Synthesize(REFS[0], 3, 3, 1).to_json()
    text = recipe_of([Synthesize(REFS[0], 3, 3, 1)])
    for _ in range(depth - 1):
        text = json.dumps({"actions": [base, {"type": "mix", "version": 2, "source": text,
                                              "source_dpjs": [REFS[0]], "op2": "xor"}]},
                          separators=(",", ":"))
    return text


def test_recipes_nest_at_most_max_depth():
    deepest = Mix(nested_text(MAX_RECIPE_DEPTH), (REFS[0],))
    history = stored(canvas(2, 4, 4), [REFS[0]])
    history.apply(deepest)
    with pytest.raises(InputError, match=f"nest at most {MAX_RECIPE_DEPTH} deep") as caught:
        Mix(nested_text(MAX_RECIPE_DEPTH + 1), (REFS[0],))
    assert str(caught.value).count("nest at most") == 1 and "action 'mix'" not in str(caught.value)
    obj = {"type": "mix", "version": 2, "source": nested_text(MAX_RECIPE_DEPTH + 1),
           "source_dpjs": [REFS[0]]}
    with pytest.raises(FormatError, match="nest at most"):
        action_from_json(obj)
    Mix(nested_text(2), (REFS[0],))                     # the count starts again afterwards


def test_a_too_deep_bank_entry_is_refused_as_a_source(bank):
    history = stored(canvas(2, 4, 4), [REFS[0]])
    history.apply(Mix(nested_text(MAX_RECIPE_DEPTH), (REFS[0],)))
    entry = bank.add(history, "deep")
    with pytest.raises(InputError, match=f"nest at most {MAX_RECIPE_DEPTH} deep"):
        bank_source(bank, entry)


def test_a_too_long_recipe_is_refused():
    with pytest.raises(InputError, match="at most 16777216 characters"):
        Mix(" " * (2**24 + 1), ())


def test_a_damaged_entry_of_several_dpjs_is_refused(bank):
    entry = two_syntheses(bank)
    with sqlite3.connect(bank.path) as conn:
        conn.execute("UPDATE entries SET sha256 = ? WHERE id = ?", ("0" * 64, entry))
    with pytest.raises(ReplayError, match="damaged"):
        bank_source(bank, entry)
