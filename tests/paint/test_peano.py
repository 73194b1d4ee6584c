"""Peano sub-regions (thesis §3.3.3a, Fig. 3.5–3.6): the Hilbert scan and dominance expressions."""

import doctest

import numpy as np
import pytest

from texeditor.paint import peano
from texeditor.errors import InputError
from texeditor.paint.peano import DominanceError, assign_levels, dominance_ranks, parse_dominance

THESIS = "6:7(2(1,2(2,3)),6:7(4,5,6:7(6,7),8))"


def test_doctests():
    assert doctest.testmod(peano, optionflags=doctest.NORMALIZE_WHITESPACE).failed == 0


# -- the scan -------------------------------------------------------------------------------------

def classic_hilbert(n, d):
    """Wikipedia's d2xy, an independent statement of the Hilbert curve on an n × n grid."""
    x = y = 0
    s, t = 1, d
    while s < n:
        rx = 1 & (t // 2)
        ry = 1 & (t ^ rx)
        if ry == 0:
            if rx == 1:
                x, y = s - 1 - x, s - 1 - y
            x, y = y, x
        x, y, t, s = x + s * rx, y + s * ry, t // 4, s * 2
    return y, x


@pytest.mark.parametrize("n", [1, 2, 4, 8, 16])
def test_on_a_power_of_two_square_it_is_the_hilbert_curve(n):
    assert peano.scan_order(n, n).tolist() == [list(classic_hilbert(n, d)) for d in range(n * n)]


@pytest.mark.parametrize("rows, cols", [(1, 1), (1, 7), (6, 1), (2, 3), (3, 5), (5, 3), (6, 10),
                                        (7, 7), (9, 4), (12, 30), (31, 17)])
def test_any_grid_is_covered_once_without_jumps(rows, cols):
    order = peano.scan_order(rows, cols)
    assert len(order) == rows * cols
    assert len({tuple(c) for c in order.tolist()}) == rows * cols
    assert order[0].tolist() == [0, 0]
    steps = np.abs(np.diff(order, axis=0))
    assert (steps.max(axis=1) == 1).all()                  # neighbours (8-connected)
    diagonal = (steps.sum(axis=1) == 2).sum()
    if rows % 2 == 0 and cols % 2 == 0:
        assert diagonal == 0
    assert diagonal <= 1


def test_the_scan_can_stop_early_and_refuses_huge_grids():
    assert peano.scan_order(64, 64, limit=5).tolist() == peano.scan_order(64, 64)[:5].tolist()
    with pytest.raises(InputError, match="too many"):
        peano.scan_order(4096, 4096)


def test_cells_cover_the_canvas_from_a_corner():
    assert peano.cell_grid((10, 7), 3) == (4, 3)
    assert peano.cell_grid((10, 7), 3, top=4, left=1, down=1) == (1, 2)
    boxes = peano.cell_boxes(np.array([[0, 0], [3, 2]]), 3, 0, 0, (10, 7))
    assert boxes.tolist() == [[0, 0, 3, 3], [9, 6, 10, 7]]       # the last cell is cut
    for bad in ((0,), (3, 10, 0), (3, 0, 7)):
        with pytest.raises(InputError):
            peano.cell_grid((10, 7), *bad)


# -- dominance expressions -------------------------------------------------------------------------

def test_the_thesis_example_parses_into_its_tree():
    tree = parse_dominance(" 6 : 7 ( 2(1, 2(2,3)), 6:7(4, 5, 6:7(6,7), 8) ) ")
    assert str(tree) == THESIS
    assert tree.head == (6, 7) and [str(i) for i in tree.items] == ["2(1,2(2,3))",
                                                                    "6:7(4,5,6:7(6,7),8)"]
    assert tree.regions() == set(range(1, 9))
    assert tree.items[1].position == 23 and tree.position == 1


def test_the_thesis_example_gives_three_degrees_of_luminosity():
    assert dominance_ranks(parse_dominance(THESIS)) == {1: 0, 2: 1, 3: 0, 4: 0, 5: 0, 6: 2,
                                                        7: 2, 8: 0}
    assert assign_levels(THESIS, 1, 3) == {1: 1, 2: 2, 3: 1, 4: 1, 5: 1, 6: 3, 7: 3, 8: 1}
    assert assign_levels(THESIS, 1, 7) == {1: 1, 2: 4, 3: 1, 4: 1, 5: 1, 6: 7, 7: 7, 8: 1}
    assert assign_levels(THESIS, 0, 2) == {1: 0, 2: 1, 3: 0, 4: 0, 5: 0, 6: 2, 7: 2, 8: 0}


@pytest.mark.parametrize("text, levels", [
    ("5", {5: 3}),                                   # alone: the brightest there is
    ("1(2,3)", {1: 3, 2: 1, 3: 1}),
    ("1(2(3))", {1: 3, 2: 2, 3: 1}),
    ("1(2(3), 4)", {1: 3, 2: 2, 3: 1, 4: 1}),
    ("1:2:3", {1: 3, 2: 3, 3: 3}),
    ("4(1:2, 3)", {1: 1, 2: 1, 3: 1, 4: 3}),
    ("2(1, 2, 3)", {1: 1, 2: 3, 3: 1}),              # Lj listed in its own group, as printed
])
def test_small_expressions(text, levels):
    assert assign_levels(text, 1, 3) == levels


def check_levels_satisfy(tree, levels):
    """Every relation of the tree holds for these levels: equal heads, heads above their items
    (an item headed by the group's own head is checked as a group of its own)."""
    for node in tree.walk():
        top = {levels[i] for i in node.head}
        assert len(top) == 1
        for item in node.items:
            if not set(item.head) & set(node.head):
                assert all(levels[i] < min(top) for i in item.regions())


@pytest.mark.parametrize("text", [THESIS, "9(8(7(6)),5:4(3,2(1)))", "3:1(2)",
                                  "10(1,2,3,4,5,6,7,8,9)", "1(2:3(4),5(6:7))"])
def test_assigned_levels_satisfy_every_relation(text):
    tree = parse_dominance(text)
    check_levels_satisfy(tree, assign_levels(text, 1, 15))


@pytest.mark.parametrize("text, position, problem", [
    ("6 : 7(2(1, 2(2,3), 6 : 7(4,5,6 : 7(6,7),8)", 42, "never closed"),   # as printed in 1984
    ("", 0, "empty"),
    ("   ", 3, "empty"),
    ("2()", 2, "number was expected, found ')'"),
    ("2(1,)", 4, "number was expected"),
    ("2(1 3)", 4, "',' or ')' was expected, found '3'"),
    ("1(2))", 4, "unbalanced ')'"),
    ("1(2)x", 4, "should end here, found 'x'"),
    ("a(1)", 0, "found 'a'"),
    ("0(1)", 0, "numbered from 1"),
    ("1::2", 2, "found ':'"),
    ("1:(2)", 2, "found '('"),
    ("1(2;3)", 3, "found ';'"),
    ("-1", 0, "found '-'"),
])
def test_malformed_expressions_point_at_the_offending_character(text, position, problem):
    with pytest.raises(DominanceError) as info:
        parse_dominance(text)
    err = info.value
    assert err.position == position and problem in err.problem
    lines = str(err).splitlines()
    assert lines[-2] == text and lines[-1] == " " * position + "^"


@pytest.mark.parametrize("text, position", [
    ("1(2(1))", 4),               # 1 > 2 > 1
    ("1:2(3(2))", 6),             # 1 = 2 > 3 > 2
    ("1(2(3), 3:1)", 4),          # 3 = 1 but 1 > 2 > 3
    ("1(2), 2(1)", 4),            # two trees side by side are not one expression
])
def test_contradictions_and_forests_are_refused(text, position):
    with pytest.raises(DominanceError) as info:
        assign_levels(text, 1, 7)
    assert info.value.position == position


def test_a_cycle_through_separate_groups_is_found():
    with pytest.raises(DominanceError, match="contradict"):
        assign_levels("9(1(2), 3:2(4), 4:5(1))", 1, 15)


def test_too_few_levels_for_the_ranks():
    with pytest.raises(InputError, match="3 degrees of luminosity but levels 2..3"):
        assign_levels(THESIS, 2, 3)
    with pytest.raises(InputError):
        assign_levels(THESIS, 3, 2)


def test_deep_chains_need_no_recursion():
    text = "".join(f"{i}(" for i in range(1, 150)) + "150" + ")" * 149
    levels = assign_levels(text, 0, 149)
    assert levels[1] == 149 and levels[150] == 0
    long = "1(" + ",".join(str(i) for i in range(2, 800)) + ")"
    assert assign_levels(long, 1, 2)[1] == 2
    with pytest.raises(DominanceError, match="longer"):
        parse_dominance("1" * 5000)
