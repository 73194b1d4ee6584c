"""One neighbour at a time (LIMITROPHES/ISOLER, thesis Fig. 3.16; issue 21 item 8): the k-th
neighbour of a region selected alone, stored in a selection's recipe, replayed and undone."""

import json

import numpy as np
import pytest

from tests.support.regions import grid, history_of, marks, same
from texeditor.errors import FormatError, InputError
from texeditor.recipe.codec import action_from_json
from texeditor.recipe.replay import replay
from texeditor.regions import extractext as regions
from texeditor.regions import transforms
from texeditor.regions.actions import ChangeLevel, Isometry, RotateSelection, Translate

# The 2s at (1, 1) have three neighbours. ISOLER meets them in the scan order of the ring's
# points: (0, 1) is on the 1s, (1, 0) on the 3s, (3, 2) on the 0s at the bottom right.
N = grid("""
    1 1 1 1
    3 2 2 1
    3 2 2 1
    3 3 . .""")
ONES = marks("""
    # # # #
    . . . #
    . . . #
    . . . .""")
THREES = marks("""
    . . . .
    # . . .
    # . . .
    # # . .""")
ZEROS = marks("""
    . . . .
    . . . .
    . . . .
    . . # #""")


@pytest.mark.parametrize("k, expected", [(1, ONES), (2, THREES), (3, ZEROS)])
def test_each_neighbour_is_selected_alone(k, expected):
    assert np.array_equal(regions.select(N, (1, 1), kind="neighbours", neighbour=k), expected)


def test_the_neighbours_together_and_beyond_the_last():
    assert np.array_equal(regions.select(N, (1, 1), kind="neighbours"), ONES | THREES | ZEROS)
    assert not regions.select(N, (1, 1), kind="neighbours", neighbour=4).any()
    with pytest.raises(InputError, match="goes with the extraction 'neighbours'"):
        regions.select(N, (1, 1), kind="region", neighbour=1)
    with pytest.raises(InputError, match="numbered from 1"):
        regions.select(N, (1, 1), kind="neighbours", neighbour=0)


def test_an_action_on_the_second_neighbour_changes_only_it_and_replays():
    history = history_of(N)
    start = history.document.levels.copy()
    action = ChangeLevel(1, 1, 0, kind="neighbours", neighbour=2)
    history.apply(action)
    assert same(history.document.levels, """
        1 1 1 1
        . 2 2 1
        . 2 2 1
        . . . .""")
    assert action.label() == "Set neighbour 2 of region at (1, 1) to level 0"
    again = action_from_json(json.loads(json.dumps(action.to_json())))
    assert again == action
    assert replay([action_from_json(a.to_json()) for a in history.actions], {}).result_hash() \
        == history.document.result_hash()
    history.undo()
    assert np.array_equal(history.document.levels, start)


def test_moves_and_turns_carry_one_neighbour():
    history = history_of(N)
    history.apply(Translate(1, 1, 1, 2, fill=2, kind="neighbours", neighbour=3))
    assert same(history.document.levels, """
        1 1 1 1
        3 2 2 1
        3 2 2 1
        3 3 2 .""")                                # the 0s moved right, the rightmost lost
    turned = history_of(N)
    turned.apply(RotateSelection(1, 1, 180, fill=2, kind="neighbours", neighbour=1))
    assert np.array_equal(turned.document.levels, regions.rotate(N, ONES, 180, fill=2))
    assert same(turned.document.levels, """
        1 2 2 2
        1 2 2 2
        1 1 1 1
        3 3 . .""")                                # half a turn about (1, 1.5), its box's centre
    whole = history_of(N)
    whole.apply(Isometry(90, 1.5, 1.5, row=1, col=1, kind="neighbours", neighbour=2))
    assert np.array_equal(whole.document.levels, transforms.isometry(N, 90, (1.5, 1.5),
                                                                    mask=THREES))


def test_an_old_step_without_a_neighbour_number_selects_all_of_them():
    """Steps written before issue 21 have no "neighbour": they keep every neighbour."""
    old = action_from_json({"type": "change_level", "version": 1, "row": 1, "col": 1,
                            "value": 0, "kind": "neighbours", "scope": "region",
                            "connectivity": 4})
    assert old.neighbour is None
    assert np.array_equal(old.selection(N), ONES | THREES | ZEROS)


def test_a_neighbour_number_needs_the_neighbours():
    with pytest.raises(InputError, match="goes with kind 'neighbours'"):
        ChangeLevel(1, 1, 0, kind="partial", neighbour=1)
    with pytest.raises(FormatError, match="neighbour = 0"):
        action_from_json({"type": "delete_selection", "version": 1, "row": 0, "col": 0,
                          "kind": "neighbours", "neighbour": 0})


def test_the_picked_region_digest_follows_the_numbered_neighbour():
    """An edit before the step that renumbers the neighbours changes what it picks: History
    marks such steps; the digest is the selected points'."""
    action = ChangeLevel(1, 1, 0, kind="neighbours", neighbour=2)
    changed = N.copy()
    changed[3, 2:] = 3                             # the 0s become 3s: two neighbours left
    assert action.picked_region(N) != action.picked_region(changed)
    assert action.picked_region(N) == action.picked_region(N.copy())
