"""History.pending_replace: an edit of a past step replayed away from the history (in a worker
thread), then committed; Cancel and a history changed meanwhile leave everything as it was."""

import threading

import numpy as np
import pytest

from tests.support import REFS, SETTINGS, TINY, long_log
from texeditor.recipe.actions import SetLevels, replace_params
from texeditor.errors import Cancelled, InputError
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay


def built(options=None, n: int = 60) -> History:
    history = History.from_log(long_log(n), TINY, **(options or {}))
    history.goto(1)                        # as the history dock does: click step 1, then edit
    return history


def fingerprint(history: History) -> tuple:
    doc = history.document
    return (history.actions, history.index, doc.levels.tobytes(), doc.palette.tobytes(),
            doc.dpj_ref, doc.actions, dict(history.memory))


def in_thread(work):
    """Run ``work()`` in another thread, as the TaskRunner does; its exception is re-raised."""
    outcome = {}

    def target():
        try:
            outcome["result"] = work()
        except BaseException as exc:      # noqa: BLE001 - handed back to the test
            outcome["error"] = exc
    thread = threading.Thread(target=target)
    thread.start()
    thread.join()
    if "error" in outcome:
        raise outcome["error"]
    return outcome["result"]


@pytest.mark.parametrize("options", SETTINGS)
def test_a_pending_edit_replayed_in_a_thread_equals_the_synchronous_replay(options):
    history, twin = built(options), built(options)
    new = replace_params(history.actions[0], seed=9)
    edit = history.pending_replace(0, new, to_end=True)
    seen = []
    in_thread(lambda: edit.run(progress=seen.append))
    assert history.index == 1                             # nothing changed before the commit
    history.commit(edit)
    twin.replace(0, new)
    twin.goto(len(twin.actions))
    edited = [new] + list(history.actions[1:])
    expected = replay(edited, TINY)
    assert history.index == len(edited) and history.actions == tuple(edited)
    for doc in (history.document, twin.document):
        assert np.array_equal(doc.levels, expected.levels)
        assert np.array_equal(doc.palette, expected.palette)
    assert seen == sorted(seen) and seen[-1] == 1.0
    history.goto(5)                                        # undo after the commit still holds
    assert np.array_equal(history.document.levels, replay(edited[:5], TINY).levels)


@pytest.mark.parametrize("options", SETTINGS)
def test_cancel_midway_leaves_the_history_exactly_as_it_was(options):
    history = built(options)
    before = fingerprint(history)
    edit = history.pending_replace(0, replace_params(history.actions[0], seed=9), to_end=True)
    steps = []
    with pytest.raises(Cancelled):
        in_thread(lambda: edit.run(progress=steps.append, cancel=lambda: len(steps) > 20))
    assert 0 < steps[-1] < 1
    assert fingerprint(history) == before
    with pytest.raises(InputError, match="not been replayed"):
        history.commit(edit)
    assert fingerprint(history) == before
    history.goto(len(history.actions))                     # the old log still replays
    assert np.array_equal(history.document.levels, replay(history.actions, TINY).levels)


def test_a_history_changed_meanwhile_refuses_the_commit():
    history = built()
    edit = history.pending_replace(0, replace_params(history.actions[0], seed=9), to_end=True)
    edit.run()
    history.apply(SetLevels(0, 0, 2, 2, 1))               # drops the redo tail the edit replayed
    after = fingerprint(history)
    with pytest.raises(InputError, match="changed while this edit was replayed"):
        history.commit(edit)
    assert fingerprint(history) == after


def test_a_step_the_edit_makes_invalid_is_named_and_changes_nothing():
    history = built(n=10)
    before = fingerprint(history)
    edit = history.pending_replace(0, replace_params(history.actions[0], dpj=REFS[1]),
                                   to_end=True)           # three levels: a palette of two fails
    with pytest.raises(InputError, match=r"after this edit, step 8 \(.*\) fails"):
        edit.run()
    assert fingerprint(history) == before


def test_the_replay_keeps_within_the_memory_budgets():
    history = built(dict(undo_memory=2_000, snapshot_every=1, snapshot_memory=5_000), n=80)
    edit = history.pending_replace(0, replace_params(history.actions[0], seed=9), to_end=True)
    edit.run()
    snapshot_bytes = sum(s.nbytes for s in edit.snaps.values())
    record_bytes = sum(sum(a.nbytes for a in atoms) for atoms in edit.records.values())
    assert 0 < snapshot_bytes <= 5_000 and record_bytes <= 2_000
    assert max(edit.records) == 79                         # the steps nearest the end are kept
    history.commit(edit)
    assert history.memory["snapshots"] <= 5_000 and history.memory["undo_records"] <= 2_000
