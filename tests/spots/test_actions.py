"""Spot placements as Actions (issue 7): place, scatter, delete; JSON, replay, undo, the library."""

import json

import numpy as np
import pytest

from tests.support import REFS, TINY, TINY_DPJS
from tests.support.spots import DISC, canvas, delete
from texeditor.recipe.actions import NewCanvas, SetLevels, Synthesize, param_specs
from texeditor.recipe.codec import action_from_json
from texeditor.errors import FormatError, InputError, ReplayError
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.recipe.logopt import optimize
from texeditor.spots.actions import (DeleteSpot, PlaceSpot, ScatterSpots, placed_spots,
                                    replay_without, spot_at, spot_ref)
from texeditor.spots.library import FILE_NAME, SpotLibrary, standard_spots
from texeditor.spots.envelope import Envelope, Perturbation, Placement, real_spot

LONG = Envelope.ellipse(20, 8).dumps()


# -- PlaceSpot -------------------------------------------------------------------------------------

def test_a_placed_spot_writes_its_level_on_its_points_only():
    history = canvas()
    history.apply(PlaceSpot(DISC, 10, 20, level=2))
    levels = history.document.levels
    stamp = real_spot(Envelope.loads(DISC), placement=Placement((10, 20)))
    expected = np.zeros_like(levels)
    expected[stamp.top:stamp.top + stamp.shape[0], stamp.left:stamp.left + stamp.shape[1]] = \
        np.where(stamp.mask, 2, 0)
    assert np.array_equal(levels, expected) and 100 < (levels == 2).sum() < 125
    assert levels[10, 20] == 2 and levels[10, 27] == 0


def test_turn_and_scale_follow_the_placement():
    history = canvas(64, 64)
    history.apply(PlaceSpot(LONG, 32, 32, angle=90, scale=2, level=1))
    rows, cols = np.nonzero(history.document.levels)
    assert rows.max() - rows.min() > 35 and cols.max() - cols.min() < 18   # now standing up


@pytest.mark.parametrize("rule, inside, alone", [("over", 2, 2), ("under", 3, 2), ("max", 3, 2),
                                                ("min", 2, 0)])
def test_blend_rules_superpose_spots(rule, inside, alone):
    history = canvas()
    history.apply(PlaceSpot(DISC, 16, 20, level=3))
    history.apply(PlaceSpot(DISC, 16, 26, level=2, blend=rule))
    levels = history.document.levels
    assert levels[16, 23] == inside                  # where the two overlap
    assert levels[16, 30] == alone                   # over the background (0 is its minimum)
    assert levels[16, 15] == 3


def test_json_round_trip_labels_and_bad_envelopes():
    for action in [PlaceSpot(DISC, 3.5, -2, angle=30, scale=0.5, seed=9, level=2, contour=0.2,
                             interior="holes", density=0.3, blend="under", wrap=True),
                   ScatterSpots(LONG, 12, seed=4, top=0, left=0, height=10, width=20, scale=0.5,
                                scale_max=1.5, level=1, level_max=3, fractal=0.2),
                   DeleteSpot(1, "0123456789abcdef", 3)]:
        text = json.dumps(action.to_json())
        assert action_from_json(json.loads(text)) == action
        assert action.label() and all(spec.doc for spec in param_specs(action))
    with pytest.raises(InputError, match="zero length"):
        PlaceSpot('{"a":[0,0],"b":[0,0]}', 1, 1)
    bad = PlaceSpot(DISC, 1, 1).to_json() | {"envelope": "{oops"}
    with pytest.raises(FormatError, match="not valid JSON"):
        action_from_json(bad)
    for wrong, message in [({"fill": "paint"}, "fill"), ({"blend": "mix"}, "blend"),
                           ({"interior": "cracks"}, "interior"), ({"fill": "dpj"}, "DPJ")]:
        with pytest.raises(InputError, match=message):
            PlaceSpot(DISC, 1, 1, **wrong)


def test_a_flat_envelope_or_a_missing_level_is_refused_and_changes_nothing():
    history = canvas(levels=3)
    flat = Envelope((0.0, 0.0), (0.0, 9.0)).dumps()
    before = history.document.levels.copy()
    with pytest.raises(InputError, match="no width"):
        history.apply(PlaceSpot(flat, 5, 5))
    with pytest.raises(InputError, match="does not exist"):
        history.apply(PlaceSpot(DISC, 5, 5, level=3))
    assert np.array_equal(history.document.levels, before) and history.index == 1


def test_replay_equals_live_and_undo_restores():
    history = canvas(base=1)
    steps = [PlaceSpot(DISC, 8, 8, level=2, seed=1, contour=0.3, fractal=0.2),
             PlaceSpot(LONG, 20, 30, angle=20, level=3, interior="levels", density=0.4, shift=-2),
             ScatterSpots(DISC, 15, seed=2, scale=0.3, scale_max=0.7, level=2, level_max=3,
                          blend="under", wrap=True)]
    states = [history.document.levels.copy()]
    for step in steps:
        history.apply(step)
        states.append(history.document.levels.copy())
    assert np.array_equal(replay(history.actions, {}).levels, states[-1])
    for k in range(3, 0, -1):
        history.undo()
        assert np.array_equal(history.document.levels, states[k - 1])


def test_fill_with_the_document_texture_read_elsewhere():
    history = canvas(48, 32)
    history.apply(SetLevels(0, 0, 32, 24, 1))
    history.apply(SetLevels(0, 24, 32, 24, 3))
    history.apply(PlaceSpot(DISC, 16, 10, fill="document", source_row=16, source_col=36))
    levels = history.document.levels
    assert levels[16, 10] == 3 and levels[16, 2] == 1


def test_fill_with_a_lower_level_texture_from_a_dpj():
    history = History()
    history.add_dpj(TINY_DPJS[0])
    history.apply(NewCanvas(40, 30, 4))
    history.apply(PlaceSpot(Envelope.ellipse(24, 20).dumps(), 15, 20, fill="dpj", dpj=REFS[0],
                            seed=3))
    inside = history.document.levels[10:20, 14:26]
    assert set(np.unique(inside)) == {0, 1}           # the DPJ's own two levels
    assert np.array_equal(replay(history.actions, TINY).levels, history.document.levels)
    three = History()
    three.add_dpj(TINY_DPJS[1])
    three.apply(NewCanvas(10, 10, 2))
    with pytest.raises(InputError, match="G = 3"):
        three.apply(PlaceSpot(DISC, 5, 5, fill="dpj", dpj=REFS[1]))


def test_wrap_brings_a_spot_back_on_the_other_side():
    history = canvas(40, 40)
    history.apply(PlaceSpot(DISC, 20, 0, level=1, wrap=True))
    levels = history.document.levels
    assert levels[20, 0] == 1 and levels[20, 39] == 1 and levels[20, 20] == 0


# -- ScatterSpots ----------------------------------------------------------------------------------

def test_scatter_places_count_spots_in_the_region_with_their_own_seeds():
    action = ScatterSpots(DISC, 30, seed=7, top=5, left=10, height=20, width=30, scale=0.4,
                          scale_max=1.2, level=1, level_max=3, contour=0.3)
    spots = action.spots((64, 64))
    assert len(spots) == 30 and len({s.seed for s in spots}) == 30
    centres = np.array([s.placement.centre for s in spots])
    assert (centres[:, 0] >= 5).all() and (centres[:, 0] < 25).all()
    assert (centres[:, 1] >= 10).all() and (centres[:, 1] < 40).all()
    assert {s.level for s in spots} == {1, 2, 3}
    scales = [s.placement.scale for s in spots]
    assert min(scales) >= 0.4 and max(scales) <= 1.2
    assert action.spots((64, 64)) == ScatterSpots(**action.__dict__).spots((64, 64))
    other = ScatterSpots(DISC, 30, seed=8, top=5, left=10, height=20, width=30)
    assert other.spots((64, 64))[0].placement != spots[0].placement


def test_scatter_over_the_canvas_and_its_checks():
    history = canvas(64, 48)
    history.apply(ScatterSpots(DISC, 40, seed=1, scale=0.5, level=2))
    assert 0.2 < (history.document.levels == 2).mean() < 0.8
    with pytest.raises(InputError, match="none of them"):
        ScatterSpots(DISC, 3, top=0)
    with pytest.raises(InputError, match="below"):
        ScatterSpots(DISC, 3, scale=2, scale_max=1)
    with pytest.raises(InputError, match="below"):
        ScatterSpots(DISC, 3, level=3, level_max=1)


# -- DeleteSpot ------------------------------------------------------------------------------------

def test_delete_restores_what_was_under_and_keeps_later_spots():
    history = canvas(base=1)
    history.apply(PlaceSpot(DISC, 16, 16, level=2, contour=0.2, seed=5))      # step 2
    history.apply(PlaceSpot(DISC, 16, 24, level=3))                          # step 3, over it
    with_both = history.document.levels.copy()
    delete(history, 2)
    levels = history.document.levels
    assert not (levels == 2).any()                       # the deleted spot is gone
    assert np.array_equal(levels == 3, with_both == 3)   # the later spot is untouched
    assert levels[16, 12] == 1                           # the background came back
    fresh = canvas(base=1)
    fresh.apply(PlaceSpot(DISC, 16, 24, level=3))
    assert np.array_equal(levels, fresh.document.levels)
    history.undo()
    assert np.array_equal(history.document.levels, with_both)


def test_deleting_a_spot_reveals_a_later_spot_placed_under_it():
    history = canvas()
    history.apply(PlaceSpot(DISC, 16, 16, level=2))
    history.apply(PlaceSpot(DISC, 16, 22, level=3, blend="under"))
    assert history.document.levels[16, 18] == 2
    delete(history, 1)
    assert history.document.levels[16, 18] == 3         # it was always there, underneath


def test_delete_one_spot_of_a_scatter_then_another():
    history = canvas(64, 48)
    scatter = ScatterSpots(DISC, 6, seed=3, scale=0.6, level=1, level_max=3)
    history.apply(scatter)
    assert placed_spots(history.document.actions, (48, 64)) == [(1, i) for i in range(6)]
    delete(history, 1, 2)
    delete(history, 1, 4)
    assert placed_spots(history.document.actions, (48, 64)) == [(1, i) for i in (0, 1, 3, 5)]
    fresh = canvas(64, 48)
    fresh.apply(scatter)
    doc = fresh.document
    assert np.array_equal(history.document.levels,
                          replay_without(doc.actions, doc, {1: {2, 4}}))
    assert np.array_equal(replay(history.actions, {}).levels, history.document.levels)
    with pytest.raises(InputError, match="no spot 7"):
        history.apply(DeleteSpot(1, spot_ref(scatter), 6))


def test_a_spot_deletes_under_a_later_step_that_reads_a_photo():
    """Deleting a spot replays the steps after it: a histogram matched to a photo of the
    document read no photo there, and the deletion failed ('exemplar … is not part of this
    document'; found by a monkey walk of the Models dialogs)."""
    from texeditor.spectral.actions import MatchHistogram
    history = canvas(40, 32)
    history.apply(PlaceSpot(DISC, 12, 14, level=2))
    photo = np.random.default_rng(1).integers(0, 256, (24, 24), dtype=np.uint8)
    history.apply(MatchHistogram(history.add_exemplar(photo)))
    palette = history.document.palette.copy()
    delete(history, 1)
    assert not history.document.levels.any()                  # the spot is gone
    assert np.array_equal(history.document.palette, palette)  # the matched palette stays
    again = replay(history.actions, {}, exemplars=dict(history.document.exemplars))
    assert np.array_equal(again.levels, history.document.levels)


def test_deleting_twice_changes_nothing_more_and_unknown_placements_are_refused():
    history = canvas()
    history.apply(PlaceSpot(DISC, 10, 10, level=2))
    delete(history, 1)
    once = history.document.levels.copy()
    delete(history, 1)
    assert np.array_equal(history.document.levels, once)
    with pytest.raises(InputError, match="not in the log"):
        history.apply(DeleteSpot(0, "0123456789abcdef"))


def test_spot_at_finds_the_latest_visible_spot():
    history = canvas()
    history.apply(PlaceSpot(DISC, 16, 16, level=2))
    history.apply(ScatterSpots(DISC, 3, seed=1, top=14, left=30, height=4, width=4, level=3))
    actions, shape = history.document.actions, history.document.shape
    assert spot_at(actions, shape, (16, 16)) == (1, None)
    k, i = spot_at(actions, shape, (16, 32))
    assert k == 2 and i in range(3)
    assert spot_at(actions, shape, (1, 1)) is None
    delete(history, 1)
    assert spot_at(history.document.actions, shape, (16, 16)) is None


def test_a_deletion_survives_an_earlier_edit_and_a_shifted_log():
    history = canvas(base=1)
    history.apply(SetLevels(0, 0, 4, 4, 3))                                   # step 2
    history.apply(PlaceSpot(DISC, 16, 16, level=2))                          # step 3
    delete(history, 3)
    history.replace(1, SetLevels(0, 0, 8, 8, 3))          # edit a step before both
    assert not (history.document.levels == 2).any() and history.document.levels[7, 7] == 3
    history.remove(2)                                     # the placement is now step 2, not 3
    assert history.actions[-1].step == 3 and not (history.document.levels == 2).any()
    assert np.array_equal(replay(history.actions, {}).levels, history.document.levels)


def test_an_edited_placement_stays_deleted_and_a_removed_one_fails_clearly():
    history = canvas()
    history.apply(PlaceSpot(DISC, 16, 16, level=2))
    delete(history, 1)
    history.replace(1, PlaceSpot(DISC, 16, 30, level=3))
    assert not history.document.levels.any()
    with pytest.raises(InputError, match="not in the log"):
        history.replace(1, SetLevels(0, 0, 1, 1, 1))
    with pytest.raises(ReplayError, match="not in the log"):
        replay([NewCanvas(10, 10, 3), DeleteSpot(1, "0123456789abcdef")], {})


def test_delete_after_a_synthesis_replays_from_it():
    history = History()
    history.add_dpj(TINY_DPJS[0])
    history.apply(Synthesize(REFS[0], 40, 30, 2))
    base = history.document.levels.copy()
    history.apply(PlaceSpot(DISC, 15, 20, level=1, seed=2))
    history.apply(PlaceSpot(DISC, 5, 5, level=0))
    delete(history, 1)
    assert np.array_equal(history.document.levels[10:20, 14:27], base[10:20, 14:27])
    assert np.array_equal(replay(history.actions, TINY).levels, history.document.levels)


def test_the_log_optimiser_keeps_the_result_of_deletions():
    history = canvas(base=1)
    history.apply(SetLevels(0, 0, 2, 2, 2))
    history.apply(SetLevels(0, 0, 2, 2, 3))                # covers the step before: dropped
    history.apply(PlaceSpot(DISC, 16, 16, level=2))
    history.apply(PlaceSpot(DISC, 16, 22, level=3))
    delete(history, 4)
    shorter = optimize(history.actions)
    assert len(shorter) < len(history.actions)
    assert np.array_equal(replay(shorter, {}).levels, history.document.levels)


# -- the spot library ------------------------------------------------------------------------------

def test_library_saves_in_the_data_folder_and_reads_back(tmp_path, monkeypatch):
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path))
    library = SpotLibrary()
    assert library.names()[:2] == ["Ellipse", "Pebble"] and not library.problems
    env, pert = Envelope.loads(LONG), Perturbation(contour=0.2, interior="holes", density=0.1)
    library.save("my knot", env, pert)
    again = SpotLibrary()
    assert again.get("my knot").envelope == env and again.get("my knot").perturbation == pert
    assert (tmp_path / FILE_NAME).exists()
    again.remove("my knot")
    assert "my knot" not in SpotLibrary().names()
    with pytest.raises(InputError, match="standard"):
        again.save("Ellipse", env)
    with pytest.raises(InputError, match="standard"):
        again.remove("Pebble")
    with pytest.raises(InputError, match="name"):
        again.save("  ", env)


def test_library_skips_bad_entries_and_keeps_a_damaged_file(tmp_path):
    good = {"name": "ok", "envelope": Envelope.loads(DISC).to_json()}
    bad = {"name": "flat", "envelope": {"a": [0, 0], "b": [0, 0]}}
    (tmp_path / FILE_NAME).write_text(json.dumps(
        {"format": "spots", "version": 1, "items": [good, bad]}))
    library = SpotLibrary(tmp_path)
    assert "ok" in library.names() and "flat" not in library.names()
    assert len(library.problems) == 1 and "entry 2" in library.problems[0]
    (tmp_path / FILE_NAME).write_bytes(b"\x00garbage")
    damaged = SpotLibrary(tmp_path)
    assert damaged.names() == [s.name for s in standard_spots()] and damaged.problems
    damaged.save("new", Envelope.loads(DISC))
    assert (tmp_path / f"{FILE_NAME}.damaged-1").read_bytes() == b"\x00garbage"
    assert SpotLibrary(tmp_path).names()[-1] == "new"
    for text in ['{"format": "other", "version": 1, "items": []}',
                 '{"format": "spots", "version": 9, "items": []}', '{"format": "spots"}']:
        (tmp_path / FILE_NAME).write_text(text)
        assert SpotLibrary(tmp_path).problems


def test_every_standard_spot_places_a_spot():
    for entry in standard_spots():
        stamp = real_spot(entry.envelope, entry.perturbation, seed=1)
        assert stamp.area > 0.4 * entry.envelope.area()


def test_a_big_scatter_is_rasterised_ahead_with_progress_and_can_be_cancelled():
    from texeditor.errors import Cancelled
    action = ScatterSpots(DISC, 64, seed=5, scale=0.5)
    seen = []
    action.rasterise((48, 64), progress=seen.append)
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)
    with pytest.raises(Cancelled):
        ScatterSpots(DISC, 64, seed=6).rasterise((48, 64), cancel=lambda: True)


def test_a_log_with_a_deleted_spot_saves_and_reopens(tmp_path):
    from texeditor.recipe.texturefile import load_texture, save_texture

    history = canvas(base=1)
    history.apply(PlaceSpot(DISC, 16, 16, level=2, seed=5))    # step 2
    delete(history, 2)
    save_texture(tmp_path / "deleted.texture", history)
    reopened, _ = load_texture(tmp_path / "deleted.texture")
    assert np.array_equal(reopened.document.levels, history.document.levels)
