"""Crash journals: what a dead process leaves is found and rebuilt exactly up to its last action."""

import base64
import json
import os
import signal

import numpy as np

from texeditor import estimate_dpj
from texeditor.recipe.actions import SetLevels, SetPalette, Synthesize
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.recipe.exemplars import exemplar_png
from texeditor.recipe.journal import (MAX_THUMB_BYTES, THUMB_SIDE, Journal, orphans, recover,
                                     thumbnail_of)


def _history():
    history = History()
    ref = history.add_dpj(estimate_dpj(np.random.default_rng(1).integers(0, 3, (30, 30)),
                                       (2, 2), 3))
    history.apply(Synthesize(ref, 32, 24, 5))
    return history


def _edits(n):
    return [SetLevels(k % 20, (2 * k) % 30, 2, 3, k % 3) for k in range(n)]


def test_a_live_journal_is_not_an_orphan_and_discard_removes_it(tmp_path):
    history = _history()
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs)
    assert journal.path.exists() and orphans(tmp_path) == []
    journal.discard()
    assert not journal.path.exists()


def test_a_killed_process_leaves_an_orphan_that_recovers_exactly_n_actions(tmp_path):
    n = 7
    pid = os.fork()
    if pid == 0:                     # the child: work, journal each step, then die hard
        try:
            history = _history()
            journal = Journal(tmp_path)
            journal.reset(history.applied, history.document.dpjs, source="/tmp/a.texture")
            for action in _edits(n):
                history.apply(action)
                journal.sync(history.applied, history.document.dpjs)
            os.kill(os.getpid(), signal.SIGKILL)
        finally:
            os._exit(1)
    os.waitpid(pid, 0)
    [path] = orphans(tmp_path)
    got = recover(path)
    expected = _history()
    for action in _edits(n):
        expected.apply(action)
    assert len(got.actions) == n + 1 and got.source == "/tmp/a.texture"
    assert np.array_equal(replay(got.actions, got.dpjs).levels, expected.document.levels)


def test_undo_edit_and_redo_are_journalled_as_the_log_they_leave(tmp_path):
    history = _history()
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs)
    for action in _edits(5):
        history.apply(action)
        journal.sync(history.applied, history.document.dpjs)
    history.undo()
    journal.sync(history.applied, history.document.dpjs)
    history.replace(2, SetLevels(0, 0, 5, 5, 2))
    journal.sync(history.applied, history.document.dpjs)
    history.apply(SetPalette(((0, 0, 0), (10, 20, 30), (200, 200, 200))))
    journal.sync(history.applied, history.document.dpjs)
    got = recover(journal.path)
    assert got.actions == history.applied
    assert np.array_equal(replay(got.actions, got.dpjs).levels, history.document.levels)


def test_a_line_cut_short_by_the_crash_is_ignored(tmp_path):
    history = _history()
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs)
    for action in _edits(3):
        history.apply(action)
        journal.sync(history.applied, history.document.dpjs)
    done = history.applied
    with open(journal.path, "ab") as f:
        f.write(b'{"kind":"log","keep":4,"append":[{"type":"set_le')   # the crash, mid-write
    assert recover(journal.path).actions == done


def test_reset_after_a_save_starts_the_journal_afresh(tmp_path):
    history = _history()
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs)
    for action in _edits(40):
        history.apply(action)
        journal.sync(history.applied, history.document.dpjs)
    assert len(journal.path.read_bytes().splitlines()) == 2 + 1 + 40   # start, dpj, 41 logs
    journal.reset(history.applied, history.document.dpjs, source="saved.texture")
    assert len(journal.path.read_bytes().splitlines()) == 3            # start, dpj, one log
    got = recover(journal.path)
    assert got.actions == history.applied and got.source == "saved.texture"


def test_the_last_thumbnail_is_recovered_with_the_work(tmp_path):
    history = _history()
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs)
    rng = np.random.default_rng(3)
    first = rng.integers(0, 256, (300, 200, 3), dtype=np.uint8)
    journal.thumbnail(first)
    history.apply(_edits(1)[0])
    journal.sync(history.applied, history.document.dpjs)
    last = rng.integers(0, 256, (90, 7), dtype=np.uint8)         # grey, narrower than a crop
    journal.thumbnail(last)
    got = recover(journal.path)
    assert got.actions == history.applied                        # thumbnails hold no steps
    assert np.array_equal(got.thumbnail, thumbnail_of(last))
    assert np.array_equal(thumbnail_of(first), first[86:214, 36:164][::2, ::2])
    assert thumbnail_of(last).shape == (45, 4)                   # every other point, ≥ 2 a side
    assert max(thumbnail_of(rng.integers(0, 256, (1, 1000), dtype=np.uint8)).shape) <= THUMB_SIDE


def test_a_damaged_thumbnail_is_passed_over_and_the_steps_after_it_still_recover(tmp_path):
    history = _history()
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs)
    good = np.full((64, 64), 77, np.uint8)
    journal.thumbnail(good)
    big = base64.b64encode(exemplar_png(np.zeros((THUMB_SIDE + 1, 8), np.uint8))).decode()
    with open(journal.path, "ab") as f:
        for png in ("not base64!", base64.b64encode(b"\x89PNG\r\n\x1a\n broken").decode(), big,
                    12, "A" * (3 * MAX_THUMB_BYTES)):
            f.write(json.dumps({"kind": "thumbnail", "png": png}).encode() + b"\n")
    for action in _edits(3):
        history.apply(action)
        journal.sync(history.applied, history.document.dpjs)
    got = recover(journal.path)
    assert got.actions == history.applied
    assert np.array_equal(got.thumbnail, good)          # the last readable one


def test_a_journal_without_thumbnails_recovers_none(tmp_path):
    history = _history()
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs)
    assert recover(journal.path).thumbnail is None
