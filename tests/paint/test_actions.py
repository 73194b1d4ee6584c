"""The manual-acquisition Actions: strokes, grains, zones, frontiers, Peano levels — exact grids,
JSON, replay, undo footprints, errors that leave the document intact."""

import json

import numpy as np
import pytest

from texeditor.paint import zones
from texeditor.recipe.codec import action_from_json
from texeditor.paint.brushes import Brush
from texeditor.recipe.document import Document
from texeditor.errors import FormatError, InputError
from texeditor.paint.grains import GrainType
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.paint.actions import (DuplicateZone, PeanoLevels, PlaceGrains, ScrambleFrontier,
                                     Stroke)
from tests.support.paint import EXAMPLES, SPRAY, textured


# -- every action: JSON, replay, undo -----------------------------------------------------------

@pytest.mark.parametrize("action", EXAMPLES, ids=lambda a: a.TYPE)
def test_actions_round_trip_through_json_and_replay_bit_for_bit(action):
    again = action_from_json(json.loads(json.dumps(action.to_json())))
    assert again == action
    doc = textured()
    before = doc.levels.copy()
    doc.apply(action)
    assert (doc.levels != before).any()
    rebuilt = replay(doc.actions, {})
    assert (rebuilt.levels == doc.levels).all()


@pytest.mark.parametrize("action", EXAMPLES, ids=lambda a: a.TYPE)
def test_undo_restores_and_records_only_small_boxes(action):
    history = History(textured())
    before = history.document.levels.copy()
    history.apply(action)
    after = history.document.levels.copy()
    recorded = sum(a.nbytes for a in history._records[history.index - 1])
    assert recorded <= 0.5 * after.size                     # patches, never the whole matrix
    history.undo()
    assert (history.document.levels == before).all()
    history.redo()
    assert (history.document.levels == after).all()


def test_a_short_stroke_on_a_big_canvas_records_a_small_patch():
    history = History(Document.new(1024, 1024, 4))
    history.apply(Stroke(points=((100, 100), (110, 130)), level=2, size=5))
    assert sum(a.nbytes for a in history._records[1]) < 2000


def test_a_stroke_wrapping_round_a_corner_records_four_small_patches():
    history = History(Document.new(512, 512, 4))
    history.apply(Stroke(points=((-3, -3), (4, 4)), level=2, size=3, wrap=True))
    atoms = history._records[1]
    assert len(atoms) == 4 and sum(a.nbytes for a in atoms) < 400
    assert history.document.levels[511, 511] == 2 and history.document.levels[0, 0] == 2


# -- strokes --------------------------------------------------------------------------------------

def test_a_stroke_is_its_brush_and_points():
    brush = Brush("Sq", 3, "square")
    a = Stroke.from_brush(brush, [(2, 1), (2, 6)], 3)
    assert a.brush() == brush.replace(name="Round 5")
    doc = Document.new(8, 5, 4)
    doc.apply(a)
    assert doc.levels.tolist() == [[0] * 8,
                                   [3, 3, 3, 3, 3, 3, 3, 3],
                                   [3, 3, 3, 3, 3, 3, 3, 3],
                                   [3, 3, 3, 3, 3, 3, 3, 3],
                                   [0] * 8]


def test_the_live_preview_paints_exactly_what_the_action_applies():
    a = Stroke(points=((5, 5), (9, 30), (30, 31), (31, 2)), level=2, **SPRAY,
               level_choices="1 2 3", seed=12)
    doc = Document.new(40, 40, 4)
    painter = a.painter(doc.shape)
    preview = np.zeros(doc.shape, np.uint8)
    for p in a.points:
        r, c, v = painter.add(p)
        preview[r, c] = v
    r, c, v = painter.finish()
    preview[r, c] = v
    doc.apply(a)
    assert (doc.levels == preview).all()


def test_levels_beyond_the_palette_are_refused_and_change_nothing():
    doc = Document.new(10, 10, 3)
    for bad in (Stroke(points=((1, 1),), level=3),
                Stroke(points=((1, 1),), level=1, level_choices="1, 5"),
                PlaceGrains(points=((1, 1),), level=4),
                PlaceGrains(points=((1, 1),), level=1, shape="bitmap", own_levels=True,
                            bitmap="19")):
        history = History(doc.copy())
        with pytest.raises(InputError, match="does not exist"):
            history.apply(bad)
        assert not history.document.levels.any()


@pytest.mark.parametrize("bad", [
    {"type": "stroke", "version": 1, "points": [], "level": 1},
    {"type": "stroke", "version": 1, "points": [[0, 0]], "level": 1, "shape": "star"},
    {"type": "stroke", "version": 1, "points": [[0, 0]], "level": 1, "level_choices": "x"},
    {"type": "stroke", "version": 1, "points": [[0, 0]], "level": 1, "density": 2},
    {"type": "place_grains", "version": 1, "points": [[0, 0]], "level": 1, "shape": "bitmap"},
    {"type": "duplicate_zone", "version": 1, "points": [[0, 0]], "offset_row": 1,
     "offset_col": 1},
    {"type": "duplicate_zone", "version": 1, "points": [[0, 0], [1, 1]], "offset_row": 1,
     "offset_col": 1, "zone": "circle"},
    {"type": "scramble_frontier", "version": 1, "points": [[0, 0], [1, 1]], "band": 0},
    {"type": "peano_levels", "version": 1, "cell": 2, "expression": "1(2"},
    {"type": "peano_levels", "version": 1, "cell": 2, "expression": "1", "grain": "blob"},
])
def test_malformed_actions_in_a_file_are_format_errors(bad):
    with pytest.raises(FormatError):
        action_from_json(bad)


# -- grains ----------------------------------------------------------------------------------------

def test_grains_along_a_path_fall_at_the_spacing():
    a = PlaceGrains(points=((5, 2), (5, 20), (15, 20)), level=1, spacing=6.0)
    assert a.centres().tolist() == [[5, 2], [5, 8], [5, 14], [5, 20], [11, 20]]
    doc = Document.new(30, 20, 2)
    doc.apply(PlaceGrains(points=a.points, level=1, spacing=6.0, size=1))
    assert sorted(zip(*np.nonzero(doc.levels))) == [(5, 2), (5, 8), (5, 14), (5, 20), (11, 20)]


def test_jitter_moves_grains_within_its_bound_and_follows_the_seed():
    a = PlaceGrains(points=((20, 2), (20, 60)), level=1, spacing=3.0, jitter=2.0, seed=4)
    base = PlaceGrains(points=a.points, level=1, spacing=3.0).centres()
    moved = a.centres()
    assert np.abs(moved - base).max() == 2 and (moved != base).any()
    assert (a.centres() == moved).all()
    other = PlaceGrains(points=a.points, level=1, spacing=3.0, jitter=2.0, seed=5).centres()
    assert (other != moved).any()


def test_a_library_grain_becomes_an_action():
    grain = GrainType("Hex", "hexagon", 8, angle=30.0, level=2)
    a = PlaceGrains.from_grain(grain, [(10, 10)], level=1)
    assert a.level == 2 and a.shape == "hexagon" and a.angle == 30.0
    free = PlaceGrains.from_grain(grain.replace(level=None), [(10, 10)], level=1)
    assert free.level == 1
    doc = Document.new(20, 20, 4)
    doc.apply(a)
    assert (doc.levels > 0).sum() == grain.mask().sum()


def test_later_grains_lie_over_earlier_ones():
    doc = Document.new(10, 5, 4)
    doc.apply(PlaceGrains(points=((2, 3), (2, 5)), level=1, size=3))
    doc.apply(PlaceGrains(points=((2, 5), (2, 3)), level=2, size=3, shape="bitmap",
                          bitmap="111/111/111", own_levels=False))
    assert doc.levels[2].tolist() == [0, 0, 2, 2, 2, 2, 2, 0, 0, 0]


# -- zones -----------------------------------------------------------------------------------------

def test_duplicating_a_zone_copies_its_levels_by_the_offset():
    doc = textured()
    before = doc.levels.copy()
    doc.apply(DuplicateZone(points=((2, 3), (9, 12)), offset_row=20, offset_col=30))
    assert (doc.levels[22:30, 33:43] == before[2:10, 3:13]).all()
    changed = doc.levels != before
    changed[22:30, 33:43] = False
    assert not changed.any()


def test_a_lasso_zone_copies_only_its_inside():
    doc = Document.new(12, 8, 3)
    doc.apply(PlaceGrains(points=((0, 0),), level=1, size=8, shape="square"))
    doc.apply(DuplicateZone(points=((0, 0), (0, 3), (3, 0)), offset_row=4, offset_col=6,
                            zone="lasso"))
    assert doc.levels[4:8, 6:10].tolist() == [[1, 1, 1, 1], [1, 1, 1, 0], [1, 1, 0, 0],
                                              [1, 0, 0, 0]]


def test_duplicating_then_scrambling_the_frontier_changes_only_the_band():
    doc = textured(64, 64)
    doc.apply(DuplicateZone(points=((5, 5), (24, 29)), offset_row=30, offset_col=25))
    copied = doc.levels.copy()
    scramble = ScrambleFrontier(points=((35, 30), (54, 54)), band=4, density=0.4,
                                grain_size=2, seed=8)
    doc.apply(scramble)
    changed = doc.levels != copied
    band = scramble.band_mask(doc.shape)
    assert changed.any() and not (changed & ~band).any()
    assert changed.sum() > 0.1 * band.sum()
    # the band straddles the copy's outline: 2 rings inside, 2 outside
    outline = zones.zone_mask(doc.shape, "rectangle", [(35, 30), (54, 54)])
    assert band[35:37, 32].all() and band[33:35, 32].all() and not band[37, 32]
    assert not band[32, 32] and (band & outline).sum() and (band & ~outline).sum()
    # and it mixes levels from both sides of the frontier
    inside, outside = set(copied[outline & band].tolist()), set(copied[~outline & band].tolist())
    assert set(doc.levels[changed].tolist()) <= inside | outside


def test_the_frontier_band_wraps_with_the_canvas():
    mask = zones.zone_mask((10, 10), "rectangle", [(0, 0), (3, 3)])
    flat = zones.frontier_band(mask, 2)
    assert not flat[9].any() and not flat[:, 9].any()        # the canvas edge is no frontier
    tiled = zones.frontier_band(mask, 2, wrap=True)
    assert tiled[9, :4].all() and tiled[:4, 9].all() and tiled[0, :4].all()


def test_scrambling_keeps_to_the_band_even_with_big_grains_and_wrap():
    doc = textured(30, 30)
    before = doc.levels.copy()
    a = ScrambleFrontier(points=((0, 0), (12, 12)), band=2, density=1.0, grain_size=5, seed=2,
                         wrap=True)
    doc.apply(a)
    assert not ((doc.levels != before) & ~a.band_mask(doc.shape)).any()


# -- Peano sub-regions -----------------------------------------------------------------------------

def test_peano_levels_fill_the_cells_in_scan_order():
    doc = Document.new(8, 8, 4)
    doc.apply(PeanoLevels(cell=2, expression="6:7(2(1,2(2,3)),6:7(4,5,6:7(6,7),8))"))
    # cells of a 4×4 Hilbert scan: 1 (0,0) 2 (0,1) 3 (1,1) 4 (1,0) 5 (2,0) 6 (3,0) 7 (3,1) 8 (2,1)
    expected = np.zeros((4, 4), int)
    for (r, c), level in {(0, 0): 1, (0, 1): 2, (1, 1): 1, (1, 0): 1, (2, 0): 1, (3, 0): 3,
                          (3, 1): 3, (2, 1): 1}.items():
        expected[r, c] = level
    assert (doc.levels == np.kron(expected, np.ones((2, 2), int))).all()


def test_peano_cells_start_where_asked_and_may_hold_a_grain():
    doc = Document.new(12, 10, 8)
    doc.apply(PeanoLevels(cell=3, expression="2(1)", top=1, left=2, low=2, high=5,
                          cells_across=1))
    assert (doc.levels[1:4, 2:5] == 2).all() and (doc.levels[4:7, 2:5] == 5).all()
    assert doc.levels.sum() == 9 * 2 + 9 * 5
    doc = Document.new(12, 10, 8)
    doc.apply(PeanoLevels(cell=5, expression="1", grain="diamond", grain_size=3))
    assert sorted(zip(*np.nonzero(doc.levels))) == [(1, 2), (2, 1), (2, 2), (2, 3), (3, 2)]


def test_peano_errors_name_the_problem():
    doc = Document.new(8, 8, 4)
    with pytest.raises(InputError, match="sub-region 17 but the cut has only 16 cells"):
        doc.apply(PeanoLevels(cell=2, expression="17(1)"))
    with pytest.raises(InputError, match="degrees of luminosity"):
        doc.apply(PeanoLevels(cell=2, expression="1(2(3(4)))"))
    with pytest.raises(InputError, match="does not exist"):
        doc.apply(PeanoLevels(cell=2, expression="1(2)", high=4))
    with pytest.raises(InputError, match="character 5"):
        PeanoLevels(cell=2, expression="1(2(")
    assert not doc.levels.any()


def test_the_grain_preview_places_exactly_what_the_action_places():
    a = PlaceGrains(points=((5, 5), (9, 30), (30, 31), (31, 2)), level=2, shape="circle", size=4,
                    spacing=5.0, jitter=2.5, seed=3, wrap=True)
    doc = Document.new(40, 40, 4)
    painter = a.painter(doc.shape)
    preview = np.zeros(doc.shape, np.uint8)
    for p in a.points:
        r, c, v = painter.add(p)
        preview[r, c] = v
    doc.apply(a)
    assert (doc.levels == preview).all()
