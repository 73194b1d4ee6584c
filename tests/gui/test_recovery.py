"""Crash recovery end to end: real app processes are killed after N actions; the next start
reads their journals and restores exactly those N actions in the window's task runner (the
window stays live; Cancel keeps the journal for the next start), after one dialog offers them."""

import os
import subprocess
import sys
import textwrap
import threading

import numpy as np
from PySide6 import QtWidgets

from app.recovery import RecoveryDialog, offer_recovery
from texeditor.recipe.actions import SetLevels
from texeditor.recipe.history import History
from texeditor.recipe.journal import THUMB_CROP, THUMB_SIDE, orphans

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHILD = textwrap.dedent("""
    import os, signal, sys, time
    from PySide6 import QtWidgets
    app = QtWidgets.QApplication([])
    from app.main_window import MainWindow
    from texeditor.recipe.actions import NewCanvas, SetLevels
    from texeditor.recipe.history import History
    n = int(sys.argv[1])
    window = MainWindow()
    window.show()
    window.set_history(History())
    window.submit(NewCanvas(40, 30, 4))
    for k in range(n - 1):
        window.submit(SetLevels(k, 2 * k, 3, 5, 1 + k % 3))
        app.processEvents()
    pause = time.monotonic() + float(sys.argv[2])    # the edits pause: the journal's thumbnail
    while time.monotonic() < pause:
        app.processEvents()
        time.sleep(0.01)
    os.kill(os.getpid(), signal.SIGKILL)    # a crash: no close, no cleanup
""")


def crash(n: int, pause: float = 0.0) -> None:
    """A texeditor process that makes ``n`` steps, waits ``pause`` seconds and dies, leaving
    its journal."""
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    proc = subprocess.run([sys.executable, "-c", CHILD, str(n), str(pause)], env=env, capture_output=True,
                          timeout=120, cwd=ROOT)
    assert proc.returncode == -9, proc.stderr.decode()[-2000:]


def expected_levels(n: int):
    levels = np.zeros((30, 40), np.uint8)
    for k in range(n - 1):
        levels[k:k + 3, 2 * k:2 * k + 5] = 1 + k % 3
    return levels


class Seen:
    """What a recovery dialog showed (it is deleted once answered)."""

    def __init__(self, dialog):
        self.text = dialog.findChild(QtWidgets.QLabel).text()
        self.rows = dialog.list.count()
        self.list_shown = dialog.list.isVisible()
        self.ticked = [dialog.list.item(k).checkState().name for k in range(self.rows)]
        self.thumbnails = [item.thumbnail for item in dialog.found]
        self.picture_shown = dialog.picture.isVisible()
        self.picture = dialog.picture.pixmap().toImage() if self.picture_shown else None
        self.row_texts = [dialog.list.item(k).text() for k in range(self.rows)]
        self.icons = [not dialog.list.item(k).icon().isNull() for k in range(self.rows)]


def answering(monkeypatch, act):
    """The recovery dialog shows, ``act(dialog)`` clicks in it; returns what each one showed."""
    seen = []

    def run(dialog):
        dialog.show()
        seen.append(Seen(dialog))
        act(dialog)
    monkeypatch.setattr(RecoveryDialog, "open", run)
    return seen


def offered(window, make_window=None):
    """offer_recovery, waited for (reading, the dialog, the restores); what ``otherwise`` saw."""
    otherwise = []
    assert offer_recovery(window, make_window, otherwise=lambda: otherwise.append(1))
    assert window.runner.busy and "Reading" in window.task_label.text()   # in the worker
    assert window.runner.wait(60_000)
    return otherwise


def test_a_killed_app_is_restored_exactly_up_to_its_last_action(window, monkeypatch, qtbot):
    crash(6)
    assert len(orphans()) == 1
    seen = answering(monkeypatch, lambda d: d.restore_button.click())
    assert offered(window) == []
    assert "6 steps" in seen[0].text
    assert not seen[0].list_shown                         # one texture: no list to tick
    assert len(window.history.applied) == 6
    assert np.array_equal(window.document.levels, expected_levels(6))
    assert window.is_modified() and "*" in window.windowTitle()
    assert orphans() == []                     # offered once, then gone
    window.undo()                              # the restored steps are undoable, to the start
    while window.can_undo():
        window.undo()
    assert not window.document.levels.any()
    window.submit(SetLevels(0, 0, 2, 2, 3))    # and the window edits on
    assert window.document.levels[:2, :2].tolist() == [[3, 3], [3, 3]]


def test_the_dialog_shows_the_texture_as_it_was_last_shown(window, monkeypatch):
    crash(5, pause=2.5)               # the thumbnail is taken once the edits pause (1 s)
    seen = answering(monkeypatch, lambda d: d.restore_button.click())
    offered(window)
    [thumb] = seen[0].thumbnails
    shown = window.canvas.shown_crop(THUMB_CROP)          # the restored texture, as shown now
    assert np.array_equal(thumb, shown) and shown.shape == (30, 40, 3)
    assert len(np.unique(thumb.reshape(-1, 3), axis=0)) == 4    # all four levels were painted
    assert seen[0].picture_shown and seen[0].picture.width() == 2 * THUMB_SIDE
    scale = 2 * THUMB_SIDE / 40                            # enlarged without smoothing
    for y, x in ((0, 0), (5, 9), (29, 39)):
        colour = seen[0].picture.pixelColor(int((x + 0.5) * scale), int((y + 0.5) * scale))
        assert colour.getRgb()[:3] == tuple(thumb[y, x])


def test_several_textures_are_listed_with_their_thumbnails(window, monkeypatch):
    crash(3)                          # killed at once: no thumbnail yet
    crash(4, pause=2.5)
    seen = answering(monkeypatch, lambda d: d.later_button.click())
    offered(window)
    assert seen[0].rows == 2 and not seen[0].picture_shown      # a list, no large picture
    icons = {text.split(", ")[-1]: icon for text, icon in zip(seen[0].row_texts, seen[0].icons)}
    assert icons == {"3 steps": False, "4 steps": True}
    assert len(orphans()) == 2                                  # Not now: both kept


def test_discarding_forgets_the_journal(window, monkeypatch):
    crash(6)
    before = window.history.applied
    answering(monkeypatch, lambda d: d.discard_button.click())
    assert offered(window) == [1]                        # the start-up texture instead
    assert window.history.applied == before and orphans() == []
    assert offer_recovery(window) is False               # nothing left to offer


def test_not_now_keeps_every_journal_for_the_next_start(window, monkeypatch):
    crash(3)
    crash(5)
    before = window.history.applied
    seen = answering(monkeypatch, lambda d: d.later_button.click())
    assert offered(window) == [1]
    assert window.history.applied == before and len(orphans()) == 2
    answering(monkeypatch, lambda d: d.reject())          # Esc: the same
    assert offered(window) == [1] and len(orphans()) == 2
    assert seen[0].ticked == ["Checked", "Checked"]


def test_two_crashed_windows_are_offered_in_one_dialog_each_restored_in_its_own(
        window, monkeypatch, qtbot):
    crash(3)
    crash(5)
    extra = []

    def make_window():
        from app.main_window import MainWindow
        win = MainWindow()
        win.show()
        extra.append(win)
        return win
    seen = answering(monkeypatch, lambda d: d.restore_button.click())
    assert offered(window, make_window) == []
    assert seen[0].rows == 2 and seen[0].list_shown and "2 unsaved textures" in seen[0].text
    assert extra and extra[0].runner.wait(60_000)
    steps = sorted([len(window.history.applied), len(extra[0].history.applied)])
    assert steps == [3, 5] and orphans() == []
    for win in (window, extra[0]):
        n = len(win.history.applied)
        assert np.array_equal(win.document.levels, expected_levels(n)) and win.is_modified()
    extra[0].mark_clean()
    extra[0].close()


def test_an_unticked_texture_is_discarded_and_the_ticked_one_restored(window, monkeypatch):
    crash(3)
    crash(5)

    def untick_the_second(dialog):
        dialog.list.item(1).setCheckState(dialog.list.item(1).checkState().Unchecked)
        assert dialog.restore_button.text() == "Restore 1"
        dialog.restore_button.click()
    answering(monkeypatch, untick_the_second)
    assert offered(window) == []
    assert len(window.history.applied) in (3, 5) and orphans() == []


def test_nothing_ticked_cannot_be_restored(window, monkeypatch):
    crash(3)
    crash(4)

    def untick_all(dialog):
        for k in range(2):
            dialog.list.item(k).setCheckState(dialog.list.item(k).checkState().Unchecked)
        assert not dialog.restore_button.isEnabled()
        dialog.later_button.click()
    answering(monkeypatch, untick_all)
    assert offered(window) == [1] and len(orphans()) == 2


def held_replay(monkeypatch):
    """History.from_log waits for the returned event: a replay caught mid-way."""
    release, original = threading.Event(), History.from_log.__func__

    def slow(cls, *args, **kwargs):
        assert release.wait(30)
        cancel = kwargs.get("cancel")
        if cancel is not None and cancel():
            from texeditor.errors import Cancelled
            raise Cancelled()
        return original(cls, *args, **kwargs)
    monkeypatch.setattr(History, "from_log", classmethod(slow))
    return release


def test_a_cancelled_restore_keeps_the_journal_and_the_window_as_it_was(window, monkeypatch,
                                                                        qtbot):
    crash(6)
    before = window.history.applied
    release = held_replay(monkeypatch)
    answering(monkeypatch, lambda d: d.restore_button.click())
    assert offer_recovery(window)
    qtbot.waitUntil(lambda: "Restoring" in window.task_label.text(), timeout=30_000)
    window.cancel_button.click()               # the status bar's Cancel, as Esc
    release.set()
    assert window.runner.wait(60_000)
    assert window.history.applied == before and len(orphans()) == 1
    assert "offered again" in window.statusBar().currentMessage()


def test_work_begun_while_restoring_is_not_replaced(window, monkeypatch, qtbot):
    crash(4)
    release = held_replay(monkeypatch)
    answering(monkeypatch, lambda d: d.restore_button.click())
    extra = []

    def make_window():
        from app.main_window import MainWindow
        win = MainWindow()
        extra.append(win)
        return win
    assert offer_recovery(window, make_window)
    qtbot.waitUntil(lambda: "Restoring" in window.task_label.text(), timeout=30_000)
    window.submit(SetLevels(0, 0, 4, 4, 2))    # the user goes on meanwhile
    mine = window.history.applied
    release.set()
    assert window.runner.wait(60_000)
    assert window.history.applied == mine      # kept, and the restored work is elsewhere
    assert len(extra) == 1 and np.array_equal(extra[0].document.levels, expected_levels(4))
    assert orphans() == []
    extra[0].mark_clean()
    extra[0].close()


def test_reading_the_journals_can_be_cancelled_and_keeps_them(window, monkeypatch):
    import app.recovery
    crash(3)
    release, read = threading.Event(), app.recovery.recover
    monkeypatch.setattr(app.recovery, "recover", lambda path: release.wait(30) and read(path))
    seen = answering(monkeypatch, lambda d: d.restore_button.click())
    otherwise = []
    assert offer_recovery(window, otherwise=lambda: otherwise.append(1))
    window.runner.cancel()                     # Esc while the journals are read
    release.set()
    assert window.runner.wait(60_000)
    assert otherwise == [1] and seen == [] and len(orphans()) == 1


STARTUP = textwrap.dedent("""
    import sys
    from PySide6 import QtWidgets
    import app.recovery
    from app import main
    answer = sys.argv[1]
    app.recovery.RecoveryDialog.open = (lambda self: self.accept()) if answer == "restore" \\
        else (lambda self: self.reject())
    def exec_():                   # the event loop, until the start-up work is done
        window = [w for w in QtWidgets.QApplication.topLevelWidgets()
                  if type(w).__name__ == "MainWindow"][0]
        assert window.runner.wait(120_000)
        window.runner.wait(120_000)
        steps = len(window.history.applied) if window.history is not None else -1
        print("steps", steps, "bank", window.bank_dock.bank is not None,
              "title", window.windowTitle())
        window.mark_clean()
        window.close()
        return 0
    QtWidgets.QApplication.exec = staticmethod(exec_)
    sys.exit(main.run([]))
""")


def test_the_application_offers_the_journal_at_start_up_then_opens_what_was_chosen(tmp_path):
    """`texeditor` itself: Restore shows the 6 restored steps beside the bank; Not now opens
    the bank's start-up texture and keeps the journal for the next start."""
    crash(6)
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    later = subprocess.run([sys.executable, "-c", STARTUP, "later"], env=env,
                           capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert later.returncode == 0, later.stderr[-2000:]
    assert "bank True" in later.stdout and "steps 6 " not in later.stdout
    assert "steps -1" not in later.stdout and len(orphans()) == 1      # kept
    restored = subprocess.run([sys.executable, "-c", STARTUP, "restore"], env=env,
                              capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert restored.returncode == 0, restored.stderr[-2000:]
    assert "steps 6 bank True" in restored.stdout and "*" in restored.stdout
    assert orphans() == []


def test_closing_the_window_under_the_dialog_keeps_every_journal(qtbot, monkeypatch):
    from app.main_window import MainWindow
    crash(3)
    win = MainWindow()
    win.show()
    otherwise = []

    def close_it(dialog):
        dialog.show()
        win.close()                            # the window goes while the dialog is open,
        dialog.reject()                        # then the dialog (Esc, or torn down with it)
    monkeypatch.setattr(RecoveryDialog, "open", close_it)
    assert offer_recovery(win, otherwise=lambda: otherwise.append(1))
    assert win.runner.wait(60_000)
    qtbot.wait(50)
    assert not win.isVisible() and otherwise == [] and len(orphans()) == 1
    win.deleteLater()


def test_a_journal_that_fails_is_started_again_at_the_next_save(window, monkeypatch, tmp_path):
    """A full disk stops the journal (a warning, not an error), and the edits go on without it;
    the journal that failed stays locked, so it is never offered as a crashed window's while
    this one lives. The next save starts a new journal, which records the edits after it."""
    from texeditor.recipe import journal as journal_module
    from texeditor.recipe.journal import recover
    window.submit(SetLevels(0, 0, 4, 4, 1))
    first = window._journal.path
    assert first.exists() and orphans() == [] and not window.journal_label.isVisible()

    def full(*args, **kwargs):
        raise OSError(28, "No space left on device")
    writes = journal_module.Journal.sync
    monkeypatch.setattr(journal_module.Journal, "sync", full)
    window.submit(SetLevels(4, 4, 4, 4, 2))
    assert window._journal is False
    assert "Crash protection is off" in window.statusBar().currentMessage()
    assert window.journal_label.isVisible()          # a warning that stays, not 10 s of text
    window.submit(SetLevels(8, 8, 4, 4, 3))          # edits go on, unrecorded
    window.undo()
    window.redo()
    assert window.document.levels[8, 8] == 3 and window.errors == []
    assert first.exists() and orphans() == []       # still locked: nobody's orphan
    monkeypatch.setattr(journal_module.Journal, "sync", writes)    # room on the disk again
    assert window.save_to(tmp_path / "saved.texture")
    assert window._journal and not first.exists() and not window.journal_label.isVisible()
    second = window._journal.path
    assert second.parent == first.parent
    window.submit(SetLevels(12, 12, 4, 4, 1))
    window.submit(SetLevels(16, 16, 4, 4, 2))
    window.undo()
    got = recover(second)
    assert got.actions == tuple(window.history.applied)
    assert got.changes == 3 and got.source == str(tmp_path / "saved.texture")
    window.mark_clean()
    window.close()
    assert not second.exists() and orphans() == []
