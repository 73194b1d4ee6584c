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
from texeditor.recipe import journal as journal_module
from texeditor.recipe.journal import (MAX_THUMB_BYTES, NEW_SUFFIX, THUMB_SIDE, Journal, orphans,
                                     recover, thumbnail_of)


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


def _killed_after(tmp_path, n: int, compact_bytes: int | None = None):
    """A forked process journals ``n`` edits and dies hard; the orphan it leaves."""
    pid = os.fork()
    if pid == 0:                     # the child: work, journal each step, then die hard
        try:
            if compact_bytes is not None:
                journal_module.COMPACT_BYTES = compact_bytes
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
    return path


def test_a_killed_process_leaves_an_orphan_that_recovers_exactly_n_actions(tmp_path):
    n = 7
    path = _killed_after(tmp_path, n)
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


def _journal_with_photo(tmp_path):
    history = _history()
    photo = np.random.default_rng(5).integers(0, 256, (20, 24, 3), dtype=np.uint8)
    from texeditor.recipe.exemplars import exemplar_ref
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs, source="/tmp/w.texture",
                  exemplars={exemplar_ref(photo): photo})
    return history, journal, {exemplar_ref(photo): photo}


def _fresh_size(tmp_path, history, photos=None) -> int:
    """The size of a journal of this log written afresh (a save's reset)."""
    journal = Journal(tmp_path / "fresh")
    journal.reset(history.applied, history.document.dpjs, source="/tmp/w.texture",
                  exemplars=photos)
    size = journal.path.stat().st_size
    journal.discard()
    return size


def test_a_long_journal_is_written_afresh_and_recovers_the_same(tmp_path, monkeypatch):
    """Undo and redo, thumbnails: a session's churn grows a journal without end; written
    afresh it stays within twice the size of its log's, and recovers the same."""
    monkeypatch.setattr(journal_module, "COMPACT_BYTES", 6000)
    history, journal, photos = _journal_with_photo(tmp_path)
    started = recover(journal.path).started
    sizes = [journal.path.stat().st_size]
    for k, action in enumerate(_edits(40) + [SetLevels(1, 1, 4, 4, 2)] * 500):
        history.apply(action)
        journal.sync(history.applied, history.document.dpjs, photos)
        if k >= 40:                                 # then undo, as a hesitating painter does
            history.undo()
            journal.sync(history.applied, history.document.dpjs, photos)
        if k % 50 == 0:
            journal.thumbnail(np.full((9, 9), k // 50, np.uint8))
        sizes.append(journal.path.stat().st_size)
    written = sum(np.diff(sizes).clip(0))
    assert sizes[-1] <= 2 * _fresh_size(tmp_path, history, photos) + 400 < written / 3
    assert orphans(tmp_path) == [] and not list(tmp_path.glob("*" + NEW_SUFFIX))  # locked, tidy
    got = recover(journal.path)
    assert got.actions == history.applied and got.source == "/tmp/w.texture"
    assert got.started == started and got.changes == 40 + 2 * 500   # what it held, carried
    assert set(got.dpjs) == set(history.document.dpjs) and set(got.exemplars) == set(photos)
    assert np.array_equal(got.thumbnail, np.full((9, 9), 10, np.uint8))
    assert np.array_equal(replay(got.actions, got.dpjs).levels, history.document.levels)
    history.undo()                              # and the journal goes on after it
    journal.sync(history.applied, history.document.dpjs, photos)
    assert recover(journal.path).actions == history.applied


def test_a_process_killed_after_its_journal_was_written_afresh_leaves_it_whole(tmp_path):
    path = _killed_after(tmp_path, 120, compact_bytes=3000)
    expected = _history()
    for action in _edits(120):
        expected.apply(action)
    got = recover(path)
    assert got.actions == expected.applied and got.changes == 120
    assert len(path.read_bytes().splitlines()) < 60        # written afresh: fewer records


def test_a_failed_rewrite_leaves_the_journal_as_it_was(tmp_path, monkeypatch):
    monkeypatch.setattr(journal_module, "COMPACT_BYTES", 3000)
    history = _history()
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs)

    def full_disk(src, dst):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(journal_module.os, "replace", full_disk)
    for action in _edits(60):
        history.apply(action)
        journal.sync(history.applied, history.document.dpjs)
    assert not list(tmp_path.glob("*" + NEW_SUFFIX))
    got = recover(journal.path)
    assert got.actions == history.applied and got.changes == 60


def test_what_a_rewrite_cut_short_left_is_swept_only_once_its_writer_is_dead(tmp_path):
    dead = tmp_path / ("1-dead" + NEW_SUFFIX)
    dead.write_bytes(b'{"kind":"start"')
    holder = journal_module._locked(tmp_path / ("2-live" + NEW_SUFFIX), "wb")   # a live one:
    journal = Journal(tmp_path)              # a window opens its journal     locked by its writer
    assert not dead.exists() and (tmp_path / ("2-live" + NEW_SUFFIX)).exists()
    assert orphans(tmp_path) == []           # never taken for a journal
    holder.close()
    journal.discard()


def _forbid_encoding(monkeypatch) -> None:
    """From now on, a DPJ or photo encoded again (not copied as written) fails the test."""
    def encoded_again(*args):
        raise AssertionError("a DPJ or photo was encoded again")
    monkeypatch.setattr(journal_module, "exemplar_png", encoded_again)
    monkeypatch.setattr(journal_module.DPJ, "to_bytes", encoded_again)


def test_a_rewrite_copies_the_photos_and_dpjs_as_they_were_written(tmp_path, monkeypatch):
    """Encoding five 1024² photos again took 0.7 s on the GUI thread: a rewrite copies their
    records instead (and the journal still recovers them)."""
    history, journal, photos = _journal_with_photo(tmp_path)

    _forbid_encoding(monkeypatch)
    monkeypatch.setattr(journal_module, "COMPACT_BYTES", 1000)
    for action in _edits(150):
        history.apply(action)
        journal.sync(history.applied, history.document.dpjs, photos)
    monkeypatch.undo()                         # (recovery checks a DPJ's bytes by encoding it)
    got = recover(journal.path)
    assert got.changes == 150 and got.actions == history.applied
    assert len(journal.path.read_bytes().splitlines()) < 140          # it was written afresh
    [(ref, photo)] = photos.items()
    assert np.array_equal(got.exemplars[ref], photo) and set(got.dpjs) == set(
        history.document.dpjs)


def test_a_save_starts_the_journal_afresh_copying_what_it_still_uses(tmp_path, monkeypatch):
    history, journal, photos = _journal_with_photo(tmp_path)
    other = np.zeros((8, 8), np.uint8)
    from texeditor.recipe.exemplars import exemplar_ref
    journal.sync(history.applied, history.document.dpjs, {**photos, exemplar_ref(other): other})

    _forbid_encoding(monkeypatch)
    history.apply(_edits(1)[0])
    journal.reset(history.applied, history.document.dpjs, source="/tmp/saved.texture",
                  exemplars=photos)              # saved: the other photo is no longer used
    monkeypatch.undo()
    got = recover(journal.path)
    assert got.actions == history.applied and got.changes == 0
    assert got.source == "/tmp/saved.texture"
    assert set(got.exemplars) == set(photos) and set(got.dpjs) == set(history.document.dpjs)
    assert len(journal.path.read_bytes().splitlines()) == 4     # start, photo, dpj, log


def test_a_damaged_changes_count_counts_as_none(tmp_path):
    import json
    history = _history()
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs)
    lines = journal.path.read_bytes().splitlines()
    journal.discard()
    for value, expected in (("7", 0), (-5, 0), (True, 0), (10**30, 0), (1.5, 0), (7, 7)):
        start = {**json.loads(lines[0]), "changes": value}
        path = tmp_path / "damaged.journal"
        path.write_bytes(b"\n".join([json.dumps(start).encode(), *lines[1:]]) + b"\n")
        got = recover(path)
        assert got.changes == expected and got.actions == history.applied


def test_the_current_dpj_is_recovered_when_it_changed_without_a_step(tmp_path, monkeypatch):
    """A DPJ edited and used (History.add_dpj: no step) is what the next synthesis draws from;
    the journal records it, so restored work synthesises from it, not from the log's last
    synthesis's DPJ — through an undo, a rewrite of the journal, and a damaged record."""
    history = _history()
    first = history.document.dpj_ref
    journal = Journal(tmp_path)
    journal.reset(history.applied, history.document.dpjs, current=history.document.dpj_ref)
    edited = history.add_dpj(estimate_dpj(np.random.default_rng(2).integers(0, 3, (30, 30)),
                                          (2, 2), 3))
    assert edited != first
    journal.sync(history.applied, history.document.dpjs, current=history.document.dpj_ref)
    got = recover(journal.path)
    assert got.current == edited and got.actions == history.applied
    restored = History.from_log(got.actions, got.dpjs, current=got.current)
    assert restored.document.dpj_ref == edited
    assert History.from_log(got.actions, got.dpjs).document.dpj_ref == first    # as it was

    history.apply(SetLevels(0, 0, 3, 3, 1))             # a step after it keeps it current
    journal.sync(history.applied, history.document.dpjs, current=history.document.dpj_ref)
    assert recover(journal.path).current == edited
    monkeypatch.setattr(journal_module, "COMPACT_BYTES", 10)
    journal._afresh = 0
    history.apply(SetLevels(1, 1, 3, 3, 2))
    journal.sync(history.applied, history.document.dpjs, current=history.document.dpj_ref)
    got = recover(journal.path)                          # written afresh: still there
    assert journal.path.read_bytes().count(b'"kind":"log"') == 1
    assert got.current == edited and got.actions == history.applied

    with open(journal.path, "ab") as f:                  # a record naming no DPJ it holds
        f.write(b'{"kind":"current","ref":"0000"}\n')
    assert recover(journal.path).current == edited
