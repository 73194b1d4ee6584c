"""Brushes (thesis §3.2.2): footprints, stroke interpolation, spray statistics, random levels,
wrap-around painting, presets."""

import doctest
import json

import numpy as np
import pytest
from skimage.measure import label

from texeditor.paint import brushes
from texeditor.paint.brushes import Brush, BrushLibrary, PathWalker, StrokePainter, paint_stroke
from texeditor.errors import FormatError, InputError


def grid(shape, points, level=1, **kw):
    """Paint a stroke on a blank grid and return it (as ints, for readable asserts)."""
    brush = kw.pop("brush", Brush(size=1, shape="square"))
    rows, cols, values = paint_stroke(brush, shape, points, level, **kw)
    out = np.zeros(shape, int)
    out[rows, cols] = values
    return out


def test_doctests():
    assert doctest.testmod(brushes, optionflags=doctest.NORMALIZE_WHITESPACE).failed == 0


# -- stamps ---------------------------------------------------------------------------------------

def test_one_dab_of_each_shape_lands_on_the_pointer_cell():
    at = [(3, 3)]
    assert (grid((7, 7), at, brush=Brush(size=3, shape="square"))[2:5, 2:5] == 1).all()
    assert grid((7, 7), at, brush=Brush(size=3, shape="square")).sum() == 9
    assert grid((7, 7), at, brush=Brush(size=5, shape="diamond")).tolist() == [
        [0, 0, 0, 0, 0, 0, 0],
        [0, 0, 0, 1, 0, 0, 0],
        [0, 0, 1, 1, 1, 0, 0],
        [0, 1, 1, 1, 1, 1, 0],
        [0, 0, 1, 1, 1, 0, 0],
        [0, 0, 0, 1, 0, 0, 0],
        [0, 0, 0, 0, 0, 0, 0]]
    assert grid((7, 7), at, brush=Brush(size=5, shape="disc")).tolist() == [
        [0, 0, 0, 0, 0, 0, 0],
        [0, 0, 1, 1, 1, 0, 0],
        [0, 1, 1, 1, 1, 1, 0],
        [0, 1, 1, 1, 1, 1, 0],
        [0, 1, 1, 1, 1, 1, 0],
        [0, 0, 1, 1, 1, 0, 0],
        [0, 0, 0, 0, 0, 0, 0]]


def test_an_even_brush_covers_the_cell_and_the_ones_above_left():
    """Size 4: the centre of gravity is a cell corner; the pointer cell is below right of it."""
    g = grid((6, 6), [(3, 3)], brush=Brush(size=4, shape="square"))
    assert g[1:5, 1:5].all() and g.sum() == 16


def test_a_line_brush_at_an_angle():
    assert grid((5, 5), [(2, 2)], brush=Brush(size=5, shape="line")).tolist()[2] == [1] * 5
    assert grid((5, 5), [(2, 2)], brush=Brush(size=5, shape="line", angle=90))[:, 2].all()
    diagonal = grid((5, 5), [(2, 2)], brush=Brush(size=5, shape="line", angle=45))
    assert diagonal.tolist() == [[0, 0, 0, 0, 1],          # 4 cells span 4.2 points; the
                                 [0, 0, 0, 1, 0],          # pointer cell is one of them
                                 [0, 0, 1, 0, 0],
                                 [0, 1, 0, 0, 0],
                                 [0, 0, 0, 0, 0]]


def test_a_bitmap_brush_paints_its_drawing():
    brush = Brush(size=3, shape="bitmap", bitmap="010/111/010")
    assert grid((3, 3), [(1, 1)], brush=brush).tolist() == [[0, 1, 0], [1, 1, 1], [0, 1, 0]]


# -- strokes ---------------------------------------------------------------------------------------

def test_a_stroke_joins_distant_pointer_events_without_gaps():
    g = grid((3, 8), [(1, 0), (1, 7)])
    assert g.tolist()[1] == [1] * 8 and g.sum() == 8
    g = grid((8, 4), [(0, 0), (7, 3)])                  # steep: every row, 8-connected
    assert g[0, 0] == g[7, 3] == 1 and (g.sum(axis=1) >= 1).all()
    assert label(g, connectivity=2).max() == 1


def test_a_thick_fast_stroke_is_a_solid_band():
    g = grid((9, 30), [(4, 2), (4, 27)], brush=Brush(size=5, shape="square", spacing=0.25))
    assert g[2:7, :30].all() and g.sum() == 5 * 30


def test_dabs_fall_every_step_along_the_path_and_at_its_end():
    w = PathWalker(2.0)
    assert w.add((0, 0)) == [(0.0, 0.0)]
    assert w.add((0, 3)) == [(0.0, 2.0)]              # 1 point carried into the next segment
    assert w.add((0, 6)) == [(0.0, 4.0), (0.0, 6.0)]
    assert w.finish() == []                           # a dab fell on the end already
    assert w.add((0, 7)) == [] and w.finish() == [(0.0, 7.0)]
    assert w.add((0, 7)) == []                        # a pointer that does not move adds nothing


def test_spacing_leaves_gaps_in_a_solid_line_when_asked():
    g = grid((1, 12), [(0, 0), (0, 9)], brush=Brush(size=1, shape="square", spacing=3.0))
    assert g.tolist()[0] == [1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0]


def test_the_painter_fed_event_by_event_paints_what_the_whole_stroke_paints():
    brush = Brush(size=9, shape="disc", distribution="cloud", density=0.3, spacing=0.3)
    path = [(10, 10), (12, 17), (20, 30), (21, 31), (40, 35)]
    painter = StrokePainter(brush, (50, 50), 2, choices=(1, 2, 3), seed=5)
    parts = [painter.add(p) for p in path] + [painter.finish()]
    live = np.zeros((50, 50), int)
    for rows, cols, values in parts:
        live[rows, cols] = values
    assert (live == grid((50, 50), path, 2, brush=brush, choices=(1, 2, 3), seed=5)).all()


# -- spray ----------------------------------------------------------------------------------------

def test_spray_density_is_within_binomial_bounds_for_a_fixed_seed():
    brush = Brush(size=41, shape="disc", distribution="cloud", density=0.3)
    n = len(brush.footprint())
    counts = []
    for seed in range(20):
        counts.append(grid((60, 60), [(30, 30)], brush=brush, seed=seed).sum())
    sigma = np.sqrt(n * 0.3 * 0.7)
    assert all(abs(c - 0.3 * n) < 4 * sigma for c in counts)
    mean = np.mean(counts)
    assert abs(mean - 0.3 * n) < 4 * sigma / np.sqrt(len(counts))
    assert len(set(counts)) > 5                       # seeds give different clouds


def test_same_seed_same_cloud_other_seed_other_cloud():
    brush = Brush(size=15, shape="disc", distribution="cloud", density=0.2)
    a = grid((40, 40), [(5, 5), (30, 30)], brush=brush, seed=1)
    assert (a == grid((40, 40), [(5, 5), (30, 30)], brush=brush, seed=1)).all()
    assert (a != grid((40, 40), [(5, 5), (30, 30)], brush=brush, seed=2)).any()


def test_concentration_gathers_points_toward_the_centre_keeping_the_mean():
    brush = Brush(size=31, shape="disc", distribution="cloud", density=0.2, concentration=2)
    fp = brush.footprint()
    assert abs(fp.chance.mean() - 0.2) < 1e-9 and fp.chance.max() == 1.0   # the centre is full
    near = fp.chance[np.hypot(fp.rows, fp.cols) <= 4].mean()
    far = fp.chance[np.hypot(fp.rows, fp.cols) >= 12].mean()
    assert near > 3 * far
    hits = sum(grid((40, 40), [(20, 20)], brush=brush, seed=s) for s in range(30))
    yy, xx = np.mgrid[:40, :40]
    d = np.hypot(yy - 20, xx - 20)
    assert hits[d <= 4].mean() > 3 * hits[(d >= 12) & (d <= 15)].mean()


def test_random_levels_come_from_the_chosen_subset_with_their_weights():
    brush = Brush(size=25, shape="square")
    g = grid((25, 25), [(12, 12)], brush=brush, choices=brushes.parse_levels("1, 3, 3"), seed=4)
    values, counts = np.unique(g, return_counts=True)
    assert values.tolist() == [1, 3]
    assert 0.25 < counts[0] / 625 < 0.42                  # 1/3 expected


def test_parse_levels():
    assert brushes.parse_levels("  ") is None and brushes.parse_levels(None) is None
    assert brushes.parse_levels("2 5,7") == (2, 5, 7)
    for bad in ("1;2", "a", "1,,", "16"):
        with pytest.raises(InputError):
            brushes.parse_levels(bad)


# -- wrap-around ----------------------------------------------------------------------------------

@pytest.mark.parametrize("centre, rows, cols", [
    ((0, 4), {5, 0, 1}, {3, 4, 5}),           # top edge
    ((5, 4), {4, 5, 0}, {3, 4, 5}),           # bottom edge
    ((3, 0), {2, 3, 4}, {7, 0, 1}),           # left edge
    ((3, 7), {2, 3, 4}, {6, 7, 0}),           # right edge
    ((0, 0), {5, 0, 1}, {7, 0, 1}),           # top-left corner
    ((5, 7), {4, 5, 0}, {6, 7, 0}),           # bottom-right corner
    ((0, 7), {5, 0, 1}, {6, 7, 0}),           # top-right corner
    ((5, 0), {4, 5, 0}, {7, 0, 1}),           # bottom-left corner
])
def test_a_dab_on_an_edge_or_corner_continues_on_the_opposite_side(centre, rows, cols):
    g = grid((6, 8), [centre], brush=Brush(size=3, shape="square"), wrap=True)
    assert {(r, c) for r, c in zip(*np.nonzero(g))} == {(r, c) for r in rows for c in cols}
    clipped = grid((6, 8), [centre], brush=Brush(size=3, shape="square"))
    assert clipped.sum() < 9


def test_a_stroke_leaving_the_canvas_comes_back_on_the_other_side():
    g = grid((4, 8), [(1, 5), (1, 11)], wrap=True)          # the pointer leaves at the right
    assert g[1].tolist() == [1, 1, 1, 1, 0, 1, 1, 1]
    g = grid((4, 8), [(-1, 2), (2, 2)], wrap=True)          # comes in from above
    assert g[:, 2].tolist() == [1, 1, 1, 1]
    g = grid((4, 8), [(1, 5), (1, 11)])                      # without wrap: clipped
    assert g[1].tolist() == [0, 0, 0, 0, 0, 1, 1, 1]


def test_later_dabs_win_where_the_stroke_crosses_itself():
    rows, cols, values = brushes.last_wins(np.array([0, 0, 1]), np.array([0, 0, 1]),
                                           np.array([1, 2, 3], np.uint8), (2, 2))
    assert sorted(zip(rows.tolist(), cols.tolist(), values.tolist())) == [(0, 0, 2), (1, 1, 3)]


# -- presets ---------------------------------------------------------------------------------------

def test_brush_validation_and_json():
    b = Brush("Mine", 7, "diamond", angle=30, distribution="cloud", density=0.5)
    assert Brush.from_json(json.loads(json.dumps(b.to_json()))) == b
    for bad in ({"size": 0}, {"shape": "star"}, {"distribution": "airbrush"},
                {"density": 1.5}, {"spacing": 0.0}, {"size": True}, {"bitmap": "11"},
                {"shape": "bitmap", "bitmap": "1x"}):
        with pytest.raises(InputError):
            Brush(**bad)
    with pytest.raises(InputError):
        Brush.from_json({"size": 3, "colour": "red"})


def test_brush_library_saves_user_presets_beside_the_standard_ones(tmp_path, monkeypatch):
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path))
    lib = BrushLibrary()
    assert lib.path == tmp_path / "brushes.json" and lib.user() == []
    names = [b.name for b in lib.all()]
    assert "Spray 16" in names and len(names) == len(set(names))
    lib.save(Brush("Big spray", 40, distribution="cloud", density=0.05))
    lib.save(Brush("Big spray", 48, distribution="cloud", density=0.05))   # replaces
    assert [b.size for b in BrushLibrary().user()] == [48]
    with pytest.raises(InputError):
        lib.save(Brush("Spray 16"))
    lib.remove("Big spray")
    assert lib.user() == []
    assert [p.name for p in tmp_path.iterdir()] == ["brushes.json"]       # no temporary left
    lib.path.write_text('{"format": "texeditor-brushes", "version": 1, "items": [{"size": -1}]}')
    with pytest.raises(FormatError, match="brush 1"):
        lib.user()
    lib.path.write_text("not json")
    with pytest.raises(FormatError):
        lib.user()
