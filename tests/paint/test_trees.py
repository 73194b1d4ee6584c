"""Dominance trees placed on screen (issue 21 item 4, thesis §3.3.3a, Fig. 3.6): vertices with a
grain each, levels that make every vertex brighter than those under it, the dominant grains
drawn over the dominated ones, several trees mixed on one canvas."""

import doctest

import numpy as np
import pytest

from texeditor.errors import InputError
from texeditor.paint import trees
from texeditor.paint.actions import DominanceTree
from texeditor.paint.grains import GrainType
from texeditor.paint.trees import tree_expression, vertex_levels
from texeditor.recipe.actions import NewCanvas, replace_params
from texeditor.recipe.codec import action_from_json
from texeditor.recipe.document import Document
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay


def test_doctests():
    assert doctest.testmod(trees).failed == 0


def grain(shape, size):
    return GrainType(shape=shape, size=size)


# -- the tree and its levels -----------------------------------------------------------------------

@pytest.mark.parametrize("parents, text", [
    ([-1], "1"), ([-1, 0, 0, 1], "1(2(4),3)"), ([-1, 0, 1, 2], "1(2(3(4)))"),
    ([-1, 0, 0, 0, 2, 2], "1(2,3(5,6),4)")])
def test_the_expression_of_vertices_placed_with_their_parents(parents, text):
    assert tree_expression(parents) == text


@pytest.mark.parametrize("parents, message", [
    ([], "one root"), ([0, -1], "one root"), ([-1, -1], "one root"), ([-1, 2, 0], "before it"),
    ([-1] + list(range(201)), "200 vertices deep")])
def test_malformed_parent_lists_are_refused(parents, message):
    with pytest.raises(InputError, match=message):
        tree_expression(parents)


def test_levels_follow_the_ranks():
    """Fig. 3.6's shape on five vertices: 1 over 2 and 3, 2 over 4 and 5 — ranks 2, 1, 0, 0, 0,
    spread over levels 1..5 as 5, 3, 1, 1, 1."""
    assert vertex_levels("1(2(4,5),3)", 5, 1, 5) == ([5, 3, 1, 1, 1], [2, 1, 0, 0, 0])
    assert vertex_levels("1:2(3)", 3, 0, 3) == ([3, 3, 0], [1, 1, 0])     # ':' equal vertices


@pytest.mark.parametrize("text, count", [("1(2)", 3), ("1(2,2)", 2), ("2(1,3)", 2),
                                          ("1(1,2)", 2)])
def test_each_vertex_is_named_once(text, count):
    with pytest.raises(InputError, match="each of its"):
        trees.vertex_tree(text, count)


# -- drawing -------------------------------------------------------------------------------------

def test_a_small_tree_drawn_with_its_levels():
    """Root (4, 4) a square of 5, its children a square of 3 at (4, 6) and a point at (1, 1):
    the root gets level 3, the children 1; the root's square covers its child's where they
    overlap, and the point's level 1 shows at (1, 1)."""
    doc = Document.new(10, 9, 4)
    doc.apply(DominanceTree(points=((4, 4), (4, 6), (1, 1)), expression="1(2,3)",
                            grains="square 5, square 3, square 1"))
    expected = np.zeros((9, 10), np.uint8)
    expected[3:6, 5:8] = 1                     # the child's square
    expected[2:7, 2:7] = 3                     # the root's, over it
    expected[1, 1] = 1
    assert np.array_equal(doc.levels, expected)


def test_the_dominant_grain_covers_the_dominated_even_when_placed_first():
    """A point at the root and a square of 3 under it on the same cell: the brighter point
    stays on top, in the middle of its child's square."""
    doc = Document.new(5, 5, 3)
    doc.apply(DominanceTree(points=((2, 2), (2, 2)), expression="1(2)",
                            grains="square 1, square 3"))
    expected = np.zeros((5, 5), np.uint8)
    expected[1:4, 1:4] = 1
    expected[2, 2] = 2
    assert np.array_equal(doc.levels, expected)


def test_a_deep_tree_spreads_its_levels_and_draws_rank_by_rank():
    """A chain 1 ⊃ 2 ⊃ 3 of diamonds 7, 5 and 3 on one centre, levels 1..3 given the other
    way: the small bright root sits on top of larger dimmer ones — a target."""
    doc = Document.new(9, 9, 8)
    doc.apply(DominanceTree(points=((4, 4),) * 3, expression="3(2(1))", low=2, high=6,
                            grains="diamond 7, diamond 5, diamond 3"))
    d = np.abs(np.arange(9)[:, None] - 4) + np.abs(np.arange(9) - 4)   # diamond distance
    expected = np.select([d <= 1, d <= 2, d <= 3], [6, 4, 2], 0).astype(np.uint8)
    assert np.array_equal(doc.levels, expected)


def test_two_trees_mixed_over_or_brighter():
    first = DominanceTree(points=((2, 2), (2, 4)), expression="1(2)", grains="square 3, square 3",
                          low=1, high=2)
    second = DominanceTree(points=((2, 3),), expression="1", grains="square 3", low=1, high=1)
    over = replay([NewCanvas(7, 5, 3), first, second], {}).levels
    brighter = replay([NewCanvas(7, 5, 3), first, replace_params(second, mix="brighter")],
                      {}).levels
    # the first tree alone: its root (level 2) over its child (level 1): 2 2 2 1 1
    assert over[1:4, 1:6].tolist() == [[2, 1, 1, 1, 1]] * 3
    assert brighter[1:4, 1:6].tolist() == [[2, 2, 2, 1, 1]] * 3      # the root's level kept


def test_from_vertices_round_trips_through_json_and_replays_bit_for_bit():
    action = DominanceTree.from_vertices(
        [(3, 3), (10, 12), (-2, 20), (15, 4)], [-1, 0, 0, 1],
        [grain("hexagon", 6), GrainType(shape="polygon", size=7, sides=5, angle=30.0),
         GrainType(shape="bitmap", size=5, bitmap="010/111/010"), grain("line", 6)],
        wrap=True)
    assert action.expression == "1(2(4),3)"
    assert action.grains == "hexagon 6, polygon 7 sides=5 angle=30, bitmap 5 bitmap=010/111/010, " \
                            "line 6"
    again = action_from_json(action.to_json())
    assert again == action
    log = [NewCanvas(24, 18, 4), action]
    assert np.array_equal(replay(log, {}).levels, replay([log[0], again], {}).levels)
    levels = replay(log, {}).levels
    assert levels[0, 20] == levels[-1, 20] == 1          # the leaf at row -2 wraps to the bottom


def test_undo_of_a_tree_restores_the_canvas_and_redo_brings_it_back():
    history = History()
    history.apply(NewCanvas(16, 12, 4))
    history.apply(DominanceTree(points=((3, 3), (6, 6)), expression="1(2)",
                                grains="circle 5, circle 3"))
    one = history.document.levels.copy()
    history.apply(DominanceTree(points=((8, 12), (4, 12)), expression="2(1)",
                                grains="square 3, square 3", mix="brighter"))
    two = history.document.levels.copy()
    history.undo()
    assert np.array_equal(history.document.levels, one)
    history.redo()
    assert np.array_equal(history.document.levels, two)


@pytest.mark.parametrize("params, message", [
    (dict(points=(), expression="1", grains="square 1"), "1..4096 vertices"),
    (dict(points=((0, 0),), expression="1", grains="square 1, square 2"), "one grain per vertex"),
    (dict(points=((0, 0), (1, 1)), expression="1(3)", grains="square 1, square 1"), "each of"),
    (dict(points=((0, 0),), expression="1", grains="blob 2"), "shape"),
    (dict(points=((0, 0),), expression="1", grains="square 1", mix="add"), "mix"),
    (dict(points=((0, 0),), expression="1(2", grains="square 1"), "never closed")])
def test_bad_trees_are_refused_before_anything_is_drawn(params, message):
    with pytest.raises(InputError, match=message):
        DominanceTree(**params)


def test_a_tree_deeper_than_the_levels_is_refused_on_the_document():
    doc = Document.new(8, 8, 3)
    before = doc.levels.copy()
    with pytest.raises(InputError, match="use more levels"):
        doc.apply(DominanceTree(points=((1, 1), (2, 2), (3, 3)), expression="1(2(3))",
                                grains="square 1, square 1, square 1"))
    with pytest.raises(InputError, match="does not exist"):
        doc.apply(DominanceTree(points=((1, 1),), expression="1", grains="square 1", high=5))
    assert np.array_equal(doc.levels, before)
