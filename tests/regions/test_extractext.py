"""EXTRACTEXT and the local operators of thesis §3.4 on small hand-made grids (issue 5).

Grids are written as the thesis draws them: one character per point, '.' for the background 0;
masks are shown with '#' for a marked point. Edge cases: points on the border, regions touching
the canvas's edge, nested holes, regions without neighbours, moves onto themselves or off the
canvas.
"""

import doctest

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY
from tests.support.regions import T, grid, grids, marks, same
from texeditor.regions import extractext as regions
from texeditor.errors import InputError
from texeditor.regions.extractext import (change_level, compresser, copy, delete, difference, enclosed,
                               etendre, extract_neighbours, extract_partial,
                               extract_region_in_region, extract_regions_in_region, extractext,
                               fill, flip, move, neighbour_labels, rotate, scale, select,
                               shift_mask, transfert, translate, trouver, valeur)


T.flags.writeable = False          # every operator must leave its input alone


def test_the_docstring_examples_hold():
    assert doctest.testmod(regions, optionflags=doctest.NORMALIZE_WHITESPACE).failed == 0


# -- EXTRACTEXT ----------------------------------------------------------------------------------

def test_extractext_marks_the_connected_region():
    assert same(extractext(T, (1, 1)), """
        . . . . . . . .
        . # # # # # . .
        . # . . . # . .
        . # . . . # . .
        . # . . . # . .
        . # # # # # . .
        . . . . . . . .
        . . . . . . . .""")


def test_extractext_global_scope_marks_every_point_of_the_level():
    assert same(extractext(T, (3, 3), scope="global"), """
        . . . . . . . .
        . . . . . . . .
        . . . . . . . .
        . . . # . . . .
        . . . . . . . .
        . . . . . . . #
        . . . . . . . #
        . . . . . . # #""")
    assert extractext(T, (3, 3)).sum() == 1


def test_extractext_from_a_border_point_and_a_corner():
    outer = extractext(T, (0, 0))
    assert outer[0].all() and outer[:, 0][:7].all() and not outer[2, 2]
    assert outer.sum() == 64 - 16 - 8 - 1 - 4 - 4      # all but the ring, its hole, 2s and 3s
    assert same(extractext(T, (7, 7)), """
        . . . . . . . .
        . . . . . . . .
        . . . . . . . .
        . . . . . . . .
        . . . . . . . .
        . . . . . . . #
        . . . . . . . #
        . . . . . . # #""")


def test_extractext_point2_translates_the_presence_matrix_and_drops_what_leaves():
    moved = extractext(T, (1, 7), (5, 1))                  # the 2s of the right edge
    assert np.argwhere(moved).tolist() == [[5, 1], [6, 1]]
    off = extractext(T, (7, 0), (7, -1))                   # half leaves on the left
    assert np.argwhere(off).tolist() == [[7, 0]]
    assert np.argwhere(extractext(T, (7, 0), (7, -1), wrap=True)).tolist() == [[7, 0], [7, 7]]
    assert not extractext(T, (7, 0), (20, 20)).any()       # wholly off the canvas


def test_connectivity_4_or_8():
    diagonal = grid("""
        1 . .
        . 1 .
        . . 1""")
    assert extractext(diagonal, (0, 0)).sum() == 1
    assert extractext(diagonal, (0, 0), connectivity=8).sum() == 3
    assert extractext(diagonal, (0, 1)).sum() == 3            # the zeros: two 4-regions of 3
    assert extractext(diagonal, (0, 1), connectivity=8).sum() == 6


@pytest.mark.parametrize("call, message", [
    (lambda: extractext(T, (8, 0)), r"point1 \(8, 0\) is outside the 8×8 canvas"),
    (lambda: extractext(T, (0, -1)), "outside"),
    (lambda: extractext(T, (0, 0), scope="local"), "scope must be"),
    (lambda: extractext(T, (0, 0), connectivity=6), "connectivity must be 4"),
    (lambda: extractext(T, (0.5, 0)), "two integers"),
    (lambda: extractext(np.zeros((2, 2, 2)), (0, 0)), "2-D"),
    (lambda: extractext(np.full((2, 2), 300), (0, 0)), "levels 0..255"),
    (lambda: fill(T, (0, 0), 256), "not a level"),
    (lambda: transfert(T, np.ones((2, 2), bool), 1), "shape"),
    (lambda: select(T, (0, 0), kind="lasso"), "unknown extraction 'lasso'"),
    (lambda: flip(T, T > 0, "diagonal"), "axis must be"),
    (lambda: scale(T, T > 0, 0), "positive"),
])
def test_bad_input_is_an_input_error_a_user_can_act_on(call, message):
    with pytest.raises(InputError, match=message):
        call()


# -- the helpers: TRANSFERT, VALEUR, ETENDRE, COMPRESSER, TROUVER, DIFFERENCE --------------------

def test_transfert_writes_a_level_or_copies_values():
    mask = extractext(T, (3, 3), scope="global")
    assert same(transfert(T, mask, 5)[5:], """
        . 1 1 1 1 1 . 5
        . . . . . . . 5
        2 2 . . . . 5 5""")
    values = np.full(T.shape, 4, np.uint8)
    assert (transfert(T, mask, values)[mask] == 4).all()
    assert np.array_equal(transfert(T, np.zeros_like(mask), 5), T)


def test_valeur_etendre_compresser_trouver_difference():
    assert valeur(T, (3, 3)) == 3 and valeur(T, (7, 0)) == 2
    dot = extractext(T, (3, 3))
    assert etendre(dot).sum() == 5 and etendre(dot, connectivity=8).sum() == 9
    corner = np.zeros((3, 3), bool)
    corner[0, 0] = True
    assert same(etendre(corner), """
        # # .
        # . .
        . . .""")
    ring = extractext(T, (1, 1))
    assert np.array_equal(compresser(ring), ring)          # a one-point-thick ring is all frontier
    block = np.ones((4, 5), bool)
    assert same(compresser(block), """
        # # # # #
        # . . . #
        # . . . #
        # # # # #""")
    plus = marks("""
        . # .
        # # #
        . # .""")
    assert same(compresser(plus), """
        . # .
        # . #
        . # .""")
    assert compresser(plus, connectivity=8).sum() == 5
    assert trouver(ring) == (1, 1) and trouver(np.zeros((3, 3), bool)) is None
    assert trouver(extractext(T, (7, 7))) == (5, 7)
    assert np.array_equal(difference(etendre(dot), dot), etendre(dot) & ~dot)


# -- fill, translate, copy -----------------------------------------------------------------------

def test_fill_is_remplir_at_3_2_with_7():
    out = fill(T, (3, 2), 7)                               # the zeros inside the ring
    assert same(out, """
        . . . . . . . .
        . 1 1 1 1 1 . 2
        . 1 7 7 7 1 . 2
        . 1 7 3 7 1 . .
        . 1 7 7 7 1 . .
        . 1 1 1 1 1 . 3
        . . . . . . . 3
        2 2 . . . . 3 3""")
    assert np.array_equal(fill(out, (3, 2), 7), out)       # idempotent
    assert np.array_equal(fill(T, (3, 3), 3), T)           # same level: nothing changes


def test_fill_from_the_border_and_globally():
    assert same(fill(T, (0, 0), 4)[:2], """
        4 4 4 4 4 4 4 4
        4 1 1 1 1 1 4 2""")
    assert same(fill(T, (0, 7), 4)[2], "4 1 . . . 1 4 2")
    out = fill(T, (7, 0), 6, scope="global")
    assert out[1, 7] == out[2, 7] == out[7, 0] == out[7, 1] == 6


def test_translate_moves_the_region_and_leaves_the_background():
    out = translate(T, (1, 7), (0, 6))                     # the 2s, one up and one left
    assert same(out[:4], """
        . . . . . . 2 .
        . 1 1 1 1 1 2 .
        . 1 . . . 1 . .
        . 1 . 3 . 1 . .""")
    assert same(translate(T, (3, 3), (3, 4), fill=5)[3], ". 1 . 5 3 1 . .")


def test_translate_onto_itself_changes_nothing():
    for p in [(0, 0), (1, 1), (3, 3), (7, 7)]:
        assert np.array_equal(translate(T, p, p), T)
        assert np.array_equal(copy(T, p, p), T)


def test_translate_partly_off_the_canvas_loses_the_part_outside():
    out = translate(T, (5, 7), (6, 7))                     # the 3-corner one row down
    assert same(out[5:], """
        . 1 1 1 1 1 . .
        . . . . . . . 3
        2 2 . . . . . 3""")
    assert same(translate(T, (7, 0), (7, -1))[7], "2 . . . . . 3 3")
    assert same(translate(T, (7, 0), (7, -1), wrap=True)[7], "2 . . . . . 3 2")


def test_translate_overlapping_itself():
    line = grid("1 1 1 . .")
    assert same(translate(line, (0, 0), (0, 1)), ". 1 1 1 .")
    assert same(translate(line, (0, 2), (0, 0)), "1 . . . .")   # by (0, -2): two points off


def test_copy_keeps_the_source():
    out = copy(T, (3, 3), (6, 4))
    assert out[3, 3] == 3 and out[6, 4] == 3 and (out != T).sum() == 1
    ring_copy = copy(T, (1, 1), (3, 3))          # overlaps the source, reaches the far corner
    assert same(ring_copy, """
        . . . . . . . .
        . 1 1 1 1 1 . 2
        . 1 . . . 1 . 2
        . 1 . 1 1 1 1 1
        . 1 . 1 . 1 . 1
        . 1 1 1 1 1 . 1
        . . . 1 . . . 1
        2 2 . 1 1 1 1 1""")


def test_move_with_a_multi_level_selection():
    inside = extract_regions_in_region(T, (1, 1))
    out = move(T, inside, (0, 3), fill=1)                  # hole and dot, moved right by 3
    assert same(out[1:6], """
        . 1 1 1 1 1 . 2
        . 1 1 1 1 . . .
        . 1 1 1 1 . 3 .
        . 1 1 1 1 . . .
        . 1 1 1 1 1 . 3""")


# -- the four extractions ------------------------------------------------------------------------

NESTED = grid("""
    1 1 1 1 1 1 1
    1 2 2 2 2 2 1
    1 2 . . . 2 1
    1 2 . 3 . 2 1
    1 2 . . . 2 1
    1 2 2 2 2 2 1
    1 1 1 1 1 1 1
""")


def test_region_in_region_picks_the_first_embedded_region():
    assert same(extract_region_in_region(T, (1, 1)), """
        . . . . . . . .
        . . . . . . . .
        . . # # # . . .
        . . # . # . . .
        . . # # # . . .
        . . . . . . . .
        . . . . . . . .
        . . . . . . . .""")
    # nested holes, region touching every edge of the canvas: one level down at a time
    assert np.array_equal(extract_region_in_region(NESTED, (0, 0)), extractext(NESTED, (1, 1)))
    assert np.array_equal(extract_region_in_region(NESTED, (1, 1)), extractext(NESTED, (2, 2)))
    assert np.array_equal(extract_region_in_region(NESTED, (2, 2)), NESTED == 3)
    assert not extract_region_in_region(NESTED, (3, 3)).any()          # encloses nothing


def test_regions_in_region_takes_everything_enclosed():
    inner = np.zeros(NESTED.shape, bool)
    inner[1:6, 1:6] = True
    assert np.array_equal(extract_regions_in_region(NESTED, (0, 0)), inner)
    assert extract_regions_in_region(NESTED, (1, 1)).sum() == 9
    assert same(extract_regions_in_region(T, (1, 1))[1:6, :6], """
        . . . . . .
        . . # # # .
        . . # # # .
        . . # # # .
        . . . . . .""")
    assert not extract_regions_in_region(T, (7, 7)).any()


def test_a_pocket_open_to_the_canvas_edge_is_not_enclosed():
    cup = grid("""
        1 . 1
        1 . 1
        1 1 1""")
    assert not extract_regions_in_region(cup, (2, 2)).any()
    assert not extract_region_in_region(cup, (2, 2)).any()
    closed = np.pad(cup, ((1, 0), (0, 0)), constant_values=1)
    assert np.argwhere(extract_regions_in_region(closed, (0, 0))).tolist() == [[1, 1], [2, 1]]


def test_holes_follow_the_dual_connectivity():
    diamond = grid("""
        . 1 .
        1 . 1
        . 1 .""")
    centre = np.zeros((3, 3), bool)
    centre[1, 1] = True
    assert np.array_equal(extract_regions_in_region(diamond, (0, 1), connectivity=8), centre)
    assert not extract_regions_in_region(diamond, (0, 1)).any()        # a lone point at 4
    square = np.pad(np.ones((3, 3), bool), 1)
    square[2, 2] = False
    assert np.array_equal(enclosed(square), ~square & np.pad(np.ones((3, 3), bool), 1))


def test_region_in_region_stays_inside_its_hole():
    # The 2 in the diamond's hole touches the 2 outside through a corner: at 8-connectivity they
    # are one level region, but the embedded region is only the part inside the hole.
    g = grid("""
        2 1 .
        1 2 1
        . 1 .""")
    assert np.argwhere(extract_region_in_region(g, (0, 1), connectivity=8)).tolist() == [[1, 1]]
    assert extractext(g, (1, 1), connectivity=8).sum() == 2


def test_neighbours_are_isolated_one_by_one_in_scan_order():
    masks = extract_neighbours(T, (1, 1))
    assert len(masks) == 2                                  # the outer zeros, then the hole
    assert masks[0][0, 0] and masks[0].sum() == 31
    assert np.array_equal(masks[1], extract_region_in_region(T, (1, 1)))
    assert [m.sum() for m in extract_neighbours(T, (3, 3))] == [8]
    labels = neighbour_labels(T, (7, 6))                    # the corner of 3s
    assert labels[7, 5] == 1 and labels[4, 7] == 1 and labels.max() == 1
    masks = extract_neighbours(T, (5, 7), connectivity=8)
    assert len(masks) == 1 and masks[0][0, 0]               # zeros touch through corners too


def test_neighbours_each_one_separately():
    g = grid("""
        . . 3 3
        1 2 2 .
        . 2 . 4""")
    masks = extract_neighbours(g, (1, 1))
    assert [np.argwhere(m).tolist() for m in masks] == [
        [[0, 0], [0, 1]], [[0, 2], [0, 3]], [[1, 0]], [[1, 3]], [[2, 0]], [[2, 2]]]
    assert np.array_equal(select(g, (1, 1), kind="neighbours"), np.any(masks, axis=0))


def test_a_region_with_no_neighbours():
    flat = np.full((5, 6), 2, np.uint8)
    assert extract_neighbours(flat, (4, 5)) == []
    assert not neighbour_labels(flat, (0, 0)).any()
    assert not extract_partial(flat, (2, 2)).any()
    assert not extract_region_in_region(flat, (2, 2)).any()
    assert not select(flat, (0, 0), kind="neighbours").any()


def test_neighbours_of_every_point_of_a_level():
    labels = neighbour_labels(T, (3, 3), scope="global")    # the dot and the corner of 3s
    assert labels.max() == 2
    assert labels[2, 2] == 1 and labels[4, 7] == 2 and labels[7, 5] == 2


def test_neighbours_reaching_beyond_the_search_window():
    # A 2-block between a long 1-region (top row and far column), and a U of 3s whose two arms
    # enter the search window apart and meet 150 points away, enclosing a strip of zeros.
    g = np.zeros((8, 200), np.uint8)
    g[1:3, 3:5] = 2
    g[0, 2:] = 1
    g[1:, 199] = 1
    g[1, 5:151] = 3
    g[3, 3:151] = 3
    g[2, 150] = 3
    labels = neighbour_labels(g, (1, 3))
    assert labels.max() == 4 and set(np.unique(labels)) == {0, 1, 2, 3, 4}
    assert labels[0, 3] == labels[7, 199] == 1                 # the 1s, found at (0, 3)
    assert labels[1, 2] == labels[7, 0] == labels[2, 198] == 2  # the zeros around everything
    assert labels[1, 5] == labels[3, 3] == labels[2, 150] == 3  # the U, met twice
    assert labels[2, 5] == labels[2, 149] == 4                  # the strip inside the U
    assert [m.sum() for m in extract_neighbours(g, (1, 3))] == [
        (labels == k).sum() for k in (1, 2, 3, 4)]


PARTIAL = grid("""
    . . . . . . . .
    . 1 1 1 1 . . .
    . 1 1 1 1 . . .
    . 1 1 2 2 2 . .
    . 1 1 2 2 2 . .
    . . . 2 2 2 . .
    . . . . . . . .
""")


def test_partial_completes_the_covered_region_with_the_cover():
    assert same(extract_partial(PARTIAL, (4, 4)), """
        . . . . . . . .
        . # # # # . . .
        . # # # # . . .
        . # # # # # . .
        . # # # # # . .
        . . . # # # . .
        . . . . . . . .""")
    # on the border: the 2s at the top edge; the first point next to them is the zero on their left
    top = grid("""
        . 2 2 .
        1 2 2 1
        1 1 1 1""")
    assert same(extract_partial(top, (0, 1)), """
        # # # .
        . # # .
        . . . .""")


def test_select_gives_every_kind_as_one_mask():
    for kind, fn in [("region", extractext), ("region_in_region", extract_region_in_region),
                     ("regions_in_region", extract_regions_in_region),
                     ("partial", extract_partial)]:
        for p in [(0, 0), (1, 1), (3, 3), (7, 7)]:
            assert np.array_equal(select(T, p, kind=kind), fn(T, p)), (kind, p)


# -- local manipulations of a selection ----------------------------------------------------------

def test_change_level_and_delete():
    hole = extract_region_in_region(T, (1, 1))
    assert same(change_level(T, hole, 4)[2:5, 1:6], """
        1 4 4 4 1
        1 4 3 4 1
        1 4 4 4 1""")
    ring = extractext(T, (1, 1))
    assert np.array_equal(delete(T, ring), np.where(ring, 0, T))


def test_scale_about_the_centre_of_the_selection():
    g = grid("""
        . . . . . .
        . . . . . .
        . . 1 2 . .
        . . 3 4 . .
        . . . . . .
        . . . . . .""")
    assert same(scale(g, g > 0, 2), """
        . . . . . .
        . 1 1 2 2 .
        . 1 1 2 2 .
        . 3 3 4 4 .
        . 3 3 4 4 .
        . . . . . .""")
    wide = scale(g, g > 0, (1, 2))
    assert same(wide[2:4], """
        . 1 1 2 2 .
        . 3 3 4 4 .""") and not wide[1].any()
    big = scale(g, g > 0, 4)                                # part lands off the canvas
    assert all((big == v).sum() == 9 for v in (1, 2, 3, 4))
    assert np.array_equal(scale(scale(g, g > 0, 2), scale(g, g > 0, 2) > 0, 0.5), g)


def test_rotate_a_selection():
    bar = grid("""
        . . . . .
        . . . . .
        . 1 2 3 .
        . . . . .
        . . . . .""")
    assert same(rotate(bar, bar > 0, 90), """
        . . . . .
        . . 3 . .
        . . 2 . .
        . . 1 . .
        . . . . .""")
    assert same(rotate(bar, bar > 0, -90)[1:4, 2], "1 2 3")
    assert same(rotate(bar, bar > 0, 180)[2], ". 3 2 1 .")
    assert same(rotate(bar, bar > 0, 45, fill=9), """
        . . . . .
        . . . 3 .
        . 9 2 9 .
        . 1 . . .
        . . . . .""")


def test_flip_a_selection_in_place():
    g = grid("""
        1 2 .
        3 . .
        . . 4""")
    motif = (g > 0) & (g < 4)
    assert same(flip(g, motif, "horizontal"), """
        2 1 .
        . 3 .
        . . 4""")
    assert same(flip(g, motif, "vertical"), """
        3 . .
        1 2 .
        . . 4""")
    once = flip(g, motif, "vertical")
    assert np.array_equal(flip(once, (once > 0) & (once < 4), "vertical"), g)


def test_manipulating_an_empty_selection_changes_nothing():
    empty = np.zeros(T.shape, bool)
    for out in (scale(T, empty, 2), rotate(T, empty, 30), flip(T, empty, "vertical"),
                delete(T, empty), change_level(T, empty, 2), move(T, empty, (1, 1))):
        assert np.array_equal(out, T)


def test_inputs_are_never_written():
    before = T.copy()
    mask = extractext(T, (1, 1))
    mask.flags.writeable = False
    for out in (fill(T, (1, 1), 2), translate(T, (1, 1), (2, 2)), copy(T, (1, 1), (2, 2)),
                rotate(T, mask, 90), move(T, mask, (1, 0)), transfert(T, mask, 0)):
        assert out is not T and out.dtype == np.uint8
    assert np.array_equal(T, before)


def test_any_integer_matrix_is_accepted():
    assert np.array_equal(fill(T.astype(np.int64), (0, 0), 4), fill(T, (0, 0), 4))
    assert fill([[0, 1], [1, 1]], (1, 1), 2).tolist() == [[0, 2], [2, 2]]


# -- properties ----------------------------------------------------------------------------------


@st.composite
def grid_and_point(draw, **kw):
    g = draw(grids(**kw))
    p = (draw(st.integers(0, g.shape[0] - 1)), draw(st.integers(0, g.shape[1] - 1)))
    return g, p


@PROPERTY
@given(grid_and_point(), st.integers(0, 3), st.sampled_from(["region", "global"]),
       st.sampled_from([4, 8]))
def test_fill_is_idempotent(gp, value, scope, connectivity):
    g, p = gp
    once = fill(g, p, value, scope=scope, connectivity=connectivity)
    assert np.array_equal(fill(once, p, value, scope=scope, connectivity=connectivity), once)
    region = extractext(g, p, scope=scope, connectivity=connectivity)
    assert (once[region] == value).all() and np.array_equal(once[~region], g[~region])


@PROPERTY
@given(grid_and_point(), st.data(), st.sampled_from([4, 8]))
def test_translate_keeps_the_moved_regions_point_count_inside_the_canvas(gp, data, connectivity):
    g, p = gp
    region = extractext(g, p, connectivity=connectivity)
    t, l, b, r = regions.bbox(region)
    h, w = g.shape
    dr = data.draw(st.integers(-t, h - b))                  # the moved region stays inside
    dc = data.draw(st.integers(-l, w - r))
    fill_level = data.draw(st.integers(0, 3))
    out = translate(g, p, (p[0] + dr, p[1] + dc), fill=fill_level, connectivity=connectivity)
    landed = shift_mask(region, (dr, dc))
    assert landed.sum() == region.sum()
    assert (out[landed] == g[p]).all()
    assert (out[region & ~landed] == fill_level).all()
    assert np.array_equal(out[~region & ~landed], g[~region & ~landed])
    assert (out == g[p]).sum() >= region.sum()


@PROPERTY
@given(grid_and_point(), st.integers(-12, 12), st.integers(-12, 12), st.booleans())
def test_copy_writes_the_moved_region_and_nothing_else(gp, dr, dc, wrap):
    g, p = gp
    region = extractext(g, p)
    landed = shift_mask(region, (dr, dc), wrap=wrap)
    out = copy(g, p, (p[0] + dr, p[1] + dc), wrap=wrap)
    assert (out[landed] == g[p]).all() and np.array_equal(out[~landed], g[~landed])
    if wrap:
        assert landed.sum() == region.sum()


@PROPERTY
@given(grid_and_point(max_side=9), st.sampled_from([4, 8]), st.sampled_from(["region", "global"]))
def test_extractions_are_consistent(gp, connectivity, scope):
    g, p = gp
    kw = dict(scope=scope, connectivity=connectivity)
    region = extractext(g, p, **kw)
    inside = extract_regions_in_region(g, p, **kw)
    embedded = extract_region_in_region(g, p, **kw)
    assert not (inside & region).any() and not (embedded & ~inside).any()
    assert embedded.any() == inside.any()
    if embedded.any():
        assert len(np.unique(g[embedded])) == 1
    masks = extract_neighbours(g, p, **kw)
    ring = etendre(region, connectivity=connectivity) & ~region
    union = np.zeros_like(region)
    for m in masks:
        assert not (m & union).any() and (m & ring).any() and not (m & region).any()
        assert len(np.unique(g[m])) == 1
        union |= m
    assert (union | ~ring).all()                           # every ring point is in a neighbour
    partial = extract_partial(g, p, **kw)
    assert np.array_equal(partial, masks[0] | region) if masks else not partial.any()
