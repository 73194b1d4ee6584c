"""History: replay equals live, undo/redo, editing past steps, memory bounds (issue 3)."""

from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY, TINY, draw_action, random_history
from texeditor.recipe.actions import (Action, NewCanvas, ResizeCanvas, SetLevels, SetPalette,
                               Synthesize, param, register, replace_params)
from texeditor.recipe.document import Document
from texeditor.errors import InputError, ReplayError
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.recipe.logopt import optimize

# Memory settings that force every path: records kept, no records (snapshots only), few snapshots.
SETTINGS = [dict(), dict(undo_memory=0, snapshot_every=3), dict(undo_memory=200, snapshot_every=2,
                                                                 snapshot_memory=300)]


def state(doc):
    return doc.levels.copy(), doc.palette.copy(), doc.result_hash()


def same(doc, other):
    return (doc.shape == other.shape and np.array_equal(doc.levels, other.levels)
            and np.array_equal(doc.palette, other.palette)
            and doc.result_hash() == other.result_hash())


# -- properties ----------------------------------------------------------------------------------

@PROPERTY
@given(st.data())
def test_replay_of_the_log_equals_the_live_result(data):
    history = random_history(data)
    again = replay(history.actions, TINY)
    assert same(again, history.document)
    assert again.actions == history.document.actions == history.actions


@PROPERTY
@given(st.data())
def test_optimised_log_replays_to_the_same_result_and_is_never_longer(data):
    history = random_history(data, max_steps=18)
    shorter = optimize(history.actions, TINY)
    assert len(shorter) <= len(history.actions)
    assert same(replay(shorter, TINY), history.document)
    blind = optimize(history.actions)          # without the DPJs: knows fewer palettes
    assert same(replay(blind, TINY), history.document)


@PROPERTY
@given(st.data(), st.sampled_from(SETTINGS))
def test_undo_k_then_redo_k_restores_the_same_matrix(data, options):
    history = random_history(data, **options)
    n = history.index
    final = state(history.document)
    k = data.draw(st.integers(0, n))
    for _ in range(k):
        assert history.undo()
    assert history.index == n - k
    assert same(history.document, replay(history.actions[:n - k], TINY))
    assert history.document.actions == history.actions[:n - k]
    for _ in range(k):
        assert history.redo()
    levels, palette, digest = state(history.document)
    assert np.array_equal(levels, final[0]) and np.array_equal(palette, final[1])
    assert digest == final[2]


@PROPERTY
@given(st.data(), st.sampled_from(SETTINGS))
def test_goto_anywhere_equals_replaying_the_prefix(data, options):
    history = random_history(data, **options)
    for _ in range(3):
        target = data.draw(st.integers(0, len(history.actions)))
        history.goto(target)
        assert same(history.document, replay(history.actions[:target], TINY))


@PROPERTY
@given(st.data(), st.sampled_from(SETTINGS))
def test_editing_an_early_step_equals_building_the_edited_log(data, options):
    history = random_history(data, **options)
    if data.draw(st.booleans()):
        history.goto(data.draw(st.integers(0, history.index)))
    i = data.draw(st.integers(0, len(history.actions) - 1))
    before = replay(history.actions[:i], TINY)
    new = draw_action(data, before)
    edited = list(history.actions)
    edited[i] = new
    index = history.index
    try:
        expected = replay(edited[:index], TINY)
    except ReplayError:
        snapshot = (history.actions, state(history.document))
        with pytest.raises(InputError):
            history.replace(i, new)
        assert history.actions == snapshot[0]          # a refused edit changes nothing
        assert history.document.result_hash() == snapshot[1][2]
        return
    history.replace(i, new)
    assert history.actions == tuple(edited) and history.index == index
    assert same(history.document, expected)
    history.goto(0)
    try:
        history.goto(len(edited))
    except InputError as exc:       # the redo tail may not fit the edit: it stops where it fails
        assert "cannot be redone" in str(exc)
    assert same(history.document, replay(edited[:history.index], TINY))


# -- examples ------------------------------------------------------------------------------------

def test_apply_undo_redo_and_the_redo_tail():
    history = History()
    calls = []
    history.subscribe(lambda change: calls.append(history.index))
    history.apply(NewCanvas(4, 3, 3))
    history.apply(SetLevels(0, 0, 2, 2, 1))
    history.apply(SetLevels(1, 1, 2, 2, 2))
    assert history.undo() and history.can_redo and history.index == 2
    history.apply(SetLevels(2, 3, 1, 1, 2))        # drops the redo tail
    assert not history.can_redo and len(history.actions) == 3
    assert history.document.levels.tolist() == [[1, 1, 0, 0], [1, 1, 0, 0], [0, 0, 0, 2]]
    assert calls == [1, 2, 3, 2, 3]
    while history.undo():
        pass
    assert history.document.shape == (0, 0) and not history.can_undo
    assert history.redo() is True and history.document.shape == (3, 4)


def test_unsubscribe_stops_notifications():
    history = History()
    calls = []
    stop = history.subscribe(lambda change: calls.append(1))
    history.apply(NewCanvas(2, 2, 2))
    stop()
    history.apply(NewCanvas(2, 2, 2))
    assert calls == [1]


def test_a_failed_action_leaves_document_and_log_untouched():
    history = History()
    history.apply(NewCanvas(3, 3, 2))
    before = state(history.document)
    with pytest.raises(InputError, match="G = 2"):
        history.apply(SetLevels(0, 0, 1, 1, 5))
    with pytest.raises(InputError, match="colours"):
        history.apply(SetPalette(((0, 0, 0),) * 3))
    assert len(history.actions) == 1 and history.document.result_hash() == before[2]


def test_replace_with_replace_params_keeps_later_strokes():
    history = History()
    history.apply(NewCanvas(6, 6, 4))
    history.apply(SetLevels(0, 0, 6, 6, 1))
    history.apply(SetLevels(2, 2, 2, 2, 3))
    history.replace(1, replace_params(history.actions[1], value=2))
    assert history.document.levels[0, 0] == 2 and history.document.levels[2, 2] == 3
    history.replace(0, replace_params(history.actions[0], width=3))
    assert history.document.shape == (6, 3)


def test_remove_and_insert_steps():
    history = History()
    history.apply(NewCanvas(3, 3, 3))
    history.apply(SetLevels(0, 0, 1, 1, 1))
    history.apply(SetLevels(1, 1, 1, 1, 2))
    history.remove(1)
    assert history.index == 2 and history.document.levels[0, 0] == 0
    history.insert(1, ResizeCanvas(4, 4, 1))
    assert history.index == 3 and history.document.shape == (4, 4)
    assert history.document.levels[3, 3] == 1 and history.document.levels[1, 1] == 2
    with pytest.raises(InputError):
        history.remove(7)


class Counting(SetLevels):
    """A SetLevels that counts how often it is applied (undo must not replay it)."""

    TYPE = "test_counting"
    calls = [0]

    def apply(self, doc, prepared=None):
        Counting.calls[0] += 1
        super().apply(doc, prepared)


def test_undo_at_depth_swaps_records_and_never_replays():
    history = History()
    history.apply(NewCanvas(64, 64, 4))
    for k in range(300):
        history.apply(Counting(k % 60, k % 61, 3, 3, k % 4))
    Counting.calls[0] = 0
    for _ in range(10):
        history.undo()
    history.redo()
    assert Counting.calls[0] == 0


def test_without_records_undo_replays_from_a_near_snapshot():
    history = History(undo_memory=0, snapshot_every=8)
    history.apply(NewCanvas(16, 16, 4))
    for k in range(100):
        history.apply(Counting(k % 14, k % 15, 2, 2, k % 4))
    Counting.calls[0] = 0
    history.undo()
    assert Counting.calls[0] < 8


def test_memory_budgets_are_kept():
    history = History(undo_memory=50_000, snapshot_memory=100_000, snapshot_every=2)
    history.apply(NewCanvas(100, 100, 4))             # 10 kB per full state
    for k in range(60):
        history.apply(ResizeCanvas(100 + k % 2, 100, 1))
    mem = history.memory
    assert mem["undo_records"] <= 50_000 and mem["snapshots"] <= 100_000
    assert mem["snapshot_count"] >= 5                    # thinned, not emptied
    history.goto(0)
    history.goto(61)
    assert history.document.shape == (101, 100)


def test_a_long_replay_copies_few_states_and_keeps_snapshots_spread(monkeypatch):
    """Issue 17: once the snapshot store was full, every later step took a whole-state copy and
    a thinning pass (a 500,000-step log opened in 108 s). Copies stay near one per
    snapshot_every steps, the store within MAX_SNAPSHOTS and evenly spread; any step is reached
    exactly from one of them."""
    from texeditor.recipe import history as history_module
    monkeypatch.setattr(history_module, "MAX_SNAPSHOTS", 16)
    copies = []
    monkeypatch.setattr(Document, "state", lambda self, _s=Document.state, **kw: copies.append(1)
                        or _s(self, **kw))
    n = 4000
    log = [NewCanvas(16, 16, 4)] + [SetLevels(k % 15, (k * 7) % 15, 2, 2, k % 4)
                                    for k in range(n - 1)]
    history = History.from_log(log, {}, undo_memory=0, snapshot_every=8)
    keys = history._snap_keys
    gaps = np.diff(keys)
    assert len(copies) <= 2 * n // 8 and len(keys) <= 16
    assert gaps.max() <= 4 * gaps.min() and n - keys[-1] <= gaps.max()
    for target in (1, 1234, n // 2 + 1, n - 1, n):
        history.goto(target)
        assert same(history.document, replay(log[:target], {}))


def test_history_over_an_existing_document_can_undo_to_empty():
    doc = Document.new(4, 4, 2)
    doc.apply(SetLevels(0, 0, 2, 2, 1))
    history = History(doc)
    assert history.index == 2 and history.document is doc
    history.undo()
    assert history.document.levels.sum() == 0
    history.undo()
    assert history.document.shape == (0, 0)


def test_from_log_turns_a_bad_step_into_a_replay_error():
    with pytest.raises(ReplayError, match="step 2"):
        History.from_log([NewCanvas(2, 2, 2), SetLevels(0, 0, 1, 1, 3)], {})
    with pytest.raises(ReplayError, match="not part of this document"):
        replay([Synthesize("0" * 16, 4, 4, 0)], {})


@register
@dataclass(frozen=True)
class Invert(Action):
    """Level g becomes G-1-g in the first rows (a stand-in for a later issue's tool)."""

    TYPE = "test_invert"
    EFFECT = "levels"
    rows: int = param("int", 1, 100)

    def apply(self, doc, prepared=None):
        mask = np.zeros(doc.shape, bool)
        mask[:self.rows] = True
        doc.write_where(mask, doc.num_levels - 1 - doc.levels)


def test_new_action_type_gets_undo_for_free():
    history = History()
    history.apply(NewCanvas(5, 4, 3))
    history.apply(SetLevels(0, 0, 1, 5, 1))
    history.apply(Invert(2))
    assert history.document.levels[:, 0].tolist() == [1, 2, 0, 0]
    history.undo()
    assert history.document.levels[:, 0].tolist() == [1, 0, 0, 0]
    history.redo()
    assert history.document.levels[:, 0].tolist() == [1, 2, 0, 0]


def test_each_change_says_what_changed_and_where():
    """Issue 18: a view redraws only what a change touched — the kind, what changed (levels,
    palette, dpj, log) and the box of the levels changed (None: everywhere)."""
    from texeditor.recipe.history import EVERYTHING
    seen = []
    history = History()
    history.subscribe(seen.append)
    history.apply(NewCanvas(20, 10, 3))
    assert seen[-1].kind == "apply" and seen[-1].box is None and "levels" in seen[-1].what
    history.apply(SetLevels(2, 3, 4, 5, 1))
    assert seen[-1].what == {"levels", "log"} and seen[-1].box == (2, 3, 4, 5)
    history.apply(SetLevels(8, 15, 9, 9, 2))                 # clipped to the canvas
    assert seen[-1].box == (8, 15, 2, 5) and seen[-1].index == 3
    history.apply(SetPalette(((0, 0, 0), (9, 9, 9), (99, 99, 99))))
    assert seen[-1].what == {"palette", "log"} and seen[-1].box is None
    history.undo()
    assert seen[-1].kind == "undo" and seen[-1].what == {"palette", "log"}
    history.goto(1)                                          # two steps back: both boxes
    assert seen[-1].kind == "goto" and seen[-1].box == (2, 3, 8, 17)
    history.redo()
    assert seen[-1].box == (2, 3, 4, 5) and seen[-1].index == 2
    history.add_dpj(TINY[sorted(TINY)[0]])
    assert seen[-1].kind == "dpj" and seen[-1].what == {"dpj"}
    history.replace(1, SetLevels(0, 0, 1, 1, 2))
    assert seen[-1].kind == "edit" and seen[-1].what == EVERYTHING and seen[-1].box is None


def test_undo_and_redo_past_a_synthesis_do_not_synthesise_again(monkeypatch):
    """The History keeps the slow part of recent steps: a replay from the empty snapshot (the
    synthesis's undo record dropped) takes the synthesis's levels back instead of computing them."""
    from texeditor.markov import synthesis
    ref = sorted(TINY)[0]
    history = History(undo_memory=0)
    history.add_dpj(TINY[ref])
    history.apply(Synthesize(ref, 30, 20, 4))
    history.apply(SetLevels(1, 1, 3, 3, 1))
    expected = history.document.levels.copy()
    monkeypatch.setattr(synthesis, "synthesize", lambda *a, **k: pytest.fail("synthesised"))
    history.undo()
    history.undo()
    history.redo()
    history.redo()
    assert np.array_equal(history.document.levels, expected)
