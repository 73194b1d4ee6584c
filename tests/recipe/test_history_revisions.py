"""An edit of a past step is one undoable change; a step that changes nothing adds no step;
an edit says which later region steps now act on a different region."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY, REFS, SETTINGS, TINY, long_log
from texeditor.recipe.actions import NewCanvas, SetLevels, SetPalette, Synthesize, replace_params
from texeditor.recipe.history import History
from texeditor.regions.actions import Copy, Fill, Translate


def state(history: History) -> tuple:
    doc = history.document
    return (history.actions, history.index, doc.levels.tobytes(), doc.palette.tobytes(),
            doc.dpj_ref, doc.actions)


@pytest.mark.parametrize("options", SETTINGS)
def test_undo_takes_back_an_edit_and_its_replay_then_redo_makes_it_again(options):
    history = History.from_log(long_log(40), TINY, **options)
    before = state(history)
    history.replace(0, Synthesize(REFS[0], 24, 20, 99), to_end=True)
    after = state(history)
    assert after[2] != before[2]                  # the new seed changed every later step's picture
    assert history.undoes_edit and history.can_undo
    history.undo()
    assert state(history) == before               # the old parameters, the old later steps
    assert history.redoes_edit and not history.undoes_edit
    history.redo()
    assert state(history) == after
    history.undo()
    history.undo()                                # then ordinary undo of the last step
    assert history.index == 39 and history.actions == before[0]
    assert history.document.levels.tobytes() == History.from_log(
        long_log(40)[:39], TINY).document.levels.tobytes()


def test_edits_undo_in_reverse_order_and_interleave_with_steps():
    history = History.from_log(long_log(20), TINY)
    s0 = state(history)
    history.replace(0, Synthesize(REFS[0], 24, 20, 5), to_end=True)
    s1 = state(history)
    history.apply(SetLevels(0, 0, 2, 2, 1))
    s2 = state(history)
    history.replace(3, replace_params(history.actions[3], value=1 - history.actions[3].value)
                    if isinstance(history.actions[3], SetLevels) else history.actions[3],
                    to_end=True)
    s3 = state(history)
    for expected in (s2, s1, s0):
        history.undo()
        assert applied(history) == applied_of(expected)
    assert state(history) == s0
    for expected in (s1, s2, s3):
        history.redo()                     # the step undone after the edit comes back too
        assert applied(history) == applied_of(expected)
    assert state(history) == s3


def applied(history: History) -> tuple:
    return applied_of(state(history))


def applied_of(s: tuple) -> tuple:
    """A state without the redo tail: the applied steps, the position, the document."""
    return (s[0][:s[1]],) + s[1:]


def test_a_new_step_after_undoing_an_edit_drops_its_redo():
    history = History.from_log(long_log(10), TINY)
    history.replace(0, Synthesize(REFS[0], 24, 20, 5), to_end=True)
    history.undo()
    history.apply(SetLevels(1, 1, 1, 1, 1))
    assert not history.redoes_edit and not history.can_redo


@PROPERTY
@given(data=st.data())
def test_any_sequence_of_edits_undoes_to_the_start_and_redoes_to_the_end(data):
    history = History.from_log(long_log(12), TINY, snapshot_every=3)
    states = [state(history)]
    for _ in range(data.draw(st.integers(1, 4))):
        i = data.draw(st.integers(0, len(history.actions) - 1))
        action = history.actions[i]
        if isinstance(action, SetLevels):
            new = replace_params(action, value=1 - action.value)
        elif isinstance(action, Synthesize):
            new = replace_params(action, seed=data.draw(st.integers(0, 1000)))
        else:
            new = SetPalette(((0, 0, 0), (255, 255, 255)))
        history.replace(i, new, to_end=True)
        states.append(state(history))
    for expected in reversed(states[:-1]):
        history.undo()
        assert state(history) == expected
    for expected in states[1:]:
        history.redo()
        assert state(history) == expected


# -- a step that changes nothing ------------------------------------------------------------------

def test_a_fill_with_the_regions_own_level_adds_no_step():
    history = History()
    history.apply(NewCanvas(8, 6, 3))
    history.apply(SetLevels(0, 0, 3, 3, 2))
    before = state(history)
    assert history.apply(Fill(1, 1, 2), if_changed=True) is False
    assert state(history) == before
    assert history.apply(Fill(1, 1, 1), if_changed=True) is True
    assert history.index == 3 and history.document.levels[1, 1] == 1
    assert history.apply(SetPalette(tuple(map(tuple, history.document.palette))),
                         if_changed=True) is False
    assert history.apply(Fill(5, 5, 0)) is True             # without if_changed: a step anyway
    assert history.index == 4


def test_a_no_op_keeps_the_redo_tail():
    history = History()
    history.apply(NewCanvas(8, 6, 3))
    history.apply(SetLevels(0, 0, 3, 3, 2))
    history.undo()
    history.apply(Fill(1, 1, 0), if_changed=True)            # background filled with itself
    assert history.can_redo and len(history.actions) == 2


# -- re-targeted region steps --------------------------------------------------------------------

def two_squares() -> History:
    """Level 1 at the left square, 2 at the right; a fill of the left one, a copy of the right."""
    history = History()
    history.apply(NewCanvas(12, 6, 4))
    history.apply(SetLevels(1, 1, 3, 3, 1))
    history.apply(SetLevels(1, 7, 3, 3, 2))
    history.apply(Fill(2, 2, 3))                  # step 4: the left square
    history.apply(Copy(2, 8, 2, 5, wrap=False))   # step 5: the right square, copied left
    history.apply(Fill(5, 0, 1))                  # step 6: the background
    return history


def test_an_edit_marks_the_later_region_steps_that_now_act_on_another_region():
    history = two_squares()
    assert history.retargeted == frozenset()
    history.replace(1, SetLevels(1, 1, 4, 3, 1), to_end=True)   # the left square grows
    assert history.retargeted == {3, 5}           # its fill and the background fill; not the copy
    history.undo()
    assert history.retargeted == frozenset()
    history.redo()
    assert history.retargeted == {3, 5}


def test_an_edit_that_leaves_the_regions_alone_marks_nothing():
    history = two_squares()
    history.replace(2, SetLevels(1, 7, 3, 3, 3), to_end=True)   # same square, another level
    assert 3 not in history.retargeted and 4 not in history.retargeted
    history.replace(1, SetLevels(1, 1, 3, 3, 1), to_end=True)
    assert history.retargeted == frozenset()


def test_marks_follow_the_log_when_later_steps_are_dropped():
    history = two_squares()
    history.replace(1, SetLevels(1, 1, 4, 3, 1), to_end=True)
    history.goto(4)
    history.apply(Translate(2, 2, 0, 0, fill=0))
    assert history.retargeted == {3}
    assert np.array_equal(history.document.levels, History.from_log(
        history.actions, {}).document.levels)
