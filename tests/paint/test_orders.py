"""Fill orders (issue 21 item 6, thesis §3.3.1, Fig. 3.4): the television scan, polar, spiral and
Peano orders on small hand-made regions, a texture laid along them, and Peano sub-regions
numbered along them."""

import doctest

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY
from texeditor.errors import InputError
from texeditor.paint import orders
from texeditor.paint.actions import LayAlongOrder, PeanoLevels
from texeditor.paint.orders import fill_order, lay_along
from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.recipe.document import Document
from texeditor.recipe.history import History


def test_doctests():
    assert doctest.testmod(orders).failed == 0


def cells(order):
    return [tuple(p) for p in order.tolist()]


# -- the orders on hand-made regions ---------------------------------------------------------------

def test_tv_is_row_after_row_left_to_right():
    mask = np.array([[0, 1, 1], [1, 0, 0], [1, 1, 0]], bool)
    assert cells(fill_order(mask, "tv")) == [(0, 1), (0, 2), (1, 0), (2, 0), (2, 1)]


def test_spiral_of_a_3x3_block():
    """Out of the middle: right, then turning clockwise on screen — down, left, left, up, up,
    right, right."""
    assert cells(fill_order(np.ones((3, 3), bool), "spiral")) == [
        (1, 1), (1, 2), (2, 2), (2, 1), (2, 0), (1, 0), (0, 0), (0, 1), (0, 2)]


def test_spiral_of_a_5x5_block_goes_ring_after_ring_without_jumps():
    order = cells(fill_order(np.ones((5, 5), bool), "spiral"))
    assert order[:9] == [(2, 2), (2, 3), (3, 3), (3, 2), (3, 1), (2, 1), (1, 1), (1, 2), (1, 3)]
    assert order[9:] == [(1, 4), (2, 4), (3, 4), (4, 4), (4, 3), (4, 2), (4, 1), (4, 0), (3, 0),
                         (2, 0), (1, 0), (0, 0), (0, 1), (0, 2), (0, 3), (0, 4)]
    steps = np.abs(np.diff(np.array(order), axis=0)).sum(axis=1)
    assert (steps == 1).all()                              # each cell next to the one before


def test_polar_order_by_angle_then_radius():
    """A 3×5 block about its middle (1, 2): counter-clockwise on screen from the ray to the
    right; on one ray, nearest first."""
    assert cells(fill_order(np.ones((3, 5), bool), "polar")) == [
        (1, 2),                          # the centre
        (1, 3), (1, 4),                  # 0°, radius 1 then 2
        (0, 4),                          # 26.6°
        (0, 3),                          # 45°
        (0, 2),                          # 90°
        (0, 1),                          # 135°
        (0, 0),                          # 153.4°
        (1, 1), (1, 0),                  # 180°
        (2, 0),                          # 206.6°
        (2, 1),                          # 225°
        (2, 2),                          # 270°
        (2, 3),                          # 315°
        (2, 4)]                          # 333.4°


def test_polar_and_spiral_about_a_given_centre():
    block = np.ones((2, 2), bool)
    assert cells(fill_order(block, "spiral", centre=(0, 0))) == [(0, 0), (0, 1), (1, 1), (1, 0)]
    assert cells(fill_order(block, "polar", centre=(1, 0))) == [(1, 0), (1, 1), (0, 1), (0, 0)]


def test_peano_on_4x4():
    """The Hilbert curve of Fig. 3.5, as the docs number it: 1 2 15 16 / 4 3 14 13 / …"""
    assert cells(fill_order(np.ones((4, 4), bool), "peano")) == [
        (0, 0), (0, 1), (1, 1), (1, 0), (2, 0), (3, 0), (3, 1), (2, 1),
        (2, 2), (3, 2), (3, 3), (2, 3), (1, 3), (1, 2), (0, 2), (0, 3)]


def test_peano_of_a_region_follows_its_bounding_box_curve():
    mask = np.zeros((6, 7), bool)
    mask[2:6, 3:7] = True
    mask[3, 4] = False
    expected = [(r + 2, c + 3) for r, c in cells(fill_order(np.ones((4, 4), bool), "peano"))
                if (r, c) != (1, 1)]
    assert cells(fill_order(mask, "peano")) == expected


@PROPERTY
@given(mask=st.lists(st.booleans(), min_size=42, max_size=42).map(
           lambda v: np.array(v).reshape(6, 7)),
       order=st.sampled_from(orders.ORDERS),
       centre=st.one_of(st.none(), st.tuples(st.integers(-3, 9), st.integers(-3, 9))))
def test_every_order_lists_each_point_of_the_region_once(mask, order, centre):
    listed = cells(fill_order(mask, order, centre))
    assert sorted(listed) == cells(fill_order(mask, "tv"))


def test_bad_orders_are_refused():
    with pytest.raises(InputError, match="tv, polar, spiral, peano"):
        fill_order(np.ones((2, 2), bool), "zigzag")
    with pytest.raises(InputError, match="smaller zone"):
        fill_order(np.ones((1, 2**22 + 1), bool), "peano")


# -- a texture laid along an order -----------------------------------------------------------------

def test_a_tv_sequence_laid_along_the_spiral_of_a_3x3_block():
    produced = np.arange(1, 10, dtype=np.uint8).reshape(3, 3)      # 1..9 in television order
    assert lay_along(produced, np.ones((3, 3), bool), "spiral").tolist() == [
        [7, 8, 9],
        [6, 1, 2],
        [5, 4, 3]]


def test_a_sequence_laid_along_a_spiral_becomes_rings():
    """Produced in television order: one 0, eight 1s, sixteen 2s. Along the spiral, ring k has
    8k points: the 1s make ring 1 and the 2s ring 2 — a knot, as in wood."""
    produced = np.array([0] + [1] * 8 + [2] * 16, np.uint8).reshape(5, 5)
    ringed = lay_along(produced, np.ones((5, 5), bool), "spiral")
    ring = np.maximum(abs(np.arange(5)[:, None] - 2), abs(np.arange(5) - 2))
    assert np.array_equal(ringed, ring.astype(np.uint8))


def test_laying_keeps_the_outside_and_the_levels_of_the_zone():
    levels = np.random.default_rng(1).integers(0, 4, (6, 8), dtype=np.uint8)
    mask = np.zeros((6, 8), bool)
    mask[1:5, 2:7] = True
    for order in orders.ORDERS:
        out = lay_along(levels, mask, order, centre=(2, 3))
        assert np.array_equal(out[~mask], levels[~mask])
        assert sorted(out[mask]) == sorted(levels[mask])
    assert np.array_equal(lay_along(levels, mask, "tv"), levels)


# -- the Actions -----------------------------------------------------------------------------------

def test_lay_along_order_replays_and_undoes():
    history = History()
    history.apply(NewCanvas(5, 4, 4))
    for k in range(4):
        history.apply(SetLevels(k, 0, 1, 5, k))                    # one level per row
    before = history.document.levels.copy()
    action = LayAlongOrder("polar", zone="rectangle", points=((0, 1), (2, 3)), centre_row=1,
                           centre_col=2)
    history.apply(action)
    expected = before.copy()
    sequence = before[0:3, 1:4].ravel()                            # the zone, as produced
    polar = [(1, 2), (1, 3), (0, 3), (0, 2), (0, 1), (1, 1), (2, 1), (2, 2), (2, 3)]
    for (r, c), v in zip(polar, sequence):
        expected[r, c] = v
    assert np.array_equal(history.document.levels, expected)
    from texeditor.recipe.replay import replay
    assert np.array_equal(replay(history.applied, {}).levels, expected)
    history.undo()
    assert np.array_equal(history.document.levels, before)
    assert "polar order about (1, 2)" in action.label()


def test_lay_along_order_on_the_whole_canvas_about_its_middle():
    doc = Document.new(3, 3, 16)
    for k in range(9):
        doc.apply(SetLevels(k // 3, k % 3, 1, 1, k + 1))
    doc.apply(LayAlongOrder("spiral"))
    assert doc.levels.tolist() == [[7, 8, 9], [6, 1, 2], [5, 4, 3]]


@pytest.mark.parametrize("params, message", [
    (dict(order="zigzag"), "fill order"),
    (dict(order="polar", points=((0, 0), (1, 1))), "no zone points"),
    (dict(order="polar", zone="lasso", points=((0, 0), (1, 1))), "three points"),
    (dict(order="spiral", centre_row=3), "both")])
def test_lay_along_order_refuses_bad_parameters(params, message):
    with pytest.raises(InputError, match=message):
        LayAlongOrder(**params)


def test_peano_levels_number_the_cells_along_the_chosen_order():
    """A 3×3 grid of 2-point cells: in spiral order cell 1 is the middle one and cell 2 its
    right neighbour; in tv order they are the first two of the top row."""
    def levels_of(order):
        doc = Document.new(6, 6, 4)
        doc.apply(PeanoLevels(cell=2, expression="2(1)", low=1, high=3, order=order))
        return doc.levels

    expected = np.zeros((6, 6), np.uint8)
    expected[2:4, 2:4], expected[2:4, 4:6] = 1, 3
    assert np.array_equal(levels_of("spiral"), expected)
    expected = np.zeros((6, 6), np.uint8)
    expected[0:2, 0:2], expected[0:2, 2:4] = 1, 3
    assert np.array_equal(levels_of("tv"), expected)
    old = PeanoLevels(cell=2, expression="2(1)", low=1, high=3)
    assert old.order == "peano" and "order" not in old.label()
    with pytest.raises(InputError, match="fill order"):
        PeanoLevels(cell=2, expression="1", order="zigzag")
