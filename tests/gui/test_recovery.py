"""Crash recovery end to end: real app processes are killed after N actions; the next start
offers their work back in one dialog and restores exactly those N actions, in the window's task
runner (the window stays live; Cancel keeps the journal for the next start)."""

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
from texeditor.recipe.journal import orphans

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHILD = textwrap.dedent("""
    import os, signal, sys
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
    os.kill(os.getpid(), signal.SIGKILL)    # a crash: no close, no cleanup
""")


def crash(n: int) -> None:
    """A texeditor process that makes ``n`` steps and dies, leaving its journal."""
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    proc = subprocess.run([sys.executable, "-c", CHILD, str(n)], env=env, capture_output=True,
                          timeout=120, cwd=ROOT)
    assert proc.returncode == -9, proc.stderr.decode()[-2000:]


def expected_levels(n: int):
    levels = np.zeros((30, 40), np.uint8)
    for k in range(n - 1):
        levels[k:k + 3, 2 * k:2 * k + 5] = 1 + k % 3
    return levels


def answering(monkeypatch, act):
    """The recovery dialog shows, ``act(dialog)`` clicks in it; returns the dialogs seen."""
    seen = []

    def run(dialog):
        dialog.show()
        seen.append(dialog)
        act(dialog)
        return dialog.result()
    monkeypatch.setattr(RecoveryDialog, "exec", run)
    return seen


def ticked(dialog):
    return [dialog.list.item(k).checkState().name for k in range(dialog.list.count())]


def test_a_killed_app_is_restored_exactly_up_to_its_last_action(window, monkeypatch, qtbot):
    crash(6)
    assert len(orphans()) == 1
    seen = answering(monkeypatch, lambda d: d.restore_button.click())
    assert offer_recovery(window) == 1
    assert "6 steps" in seen[0].findChild(QtWidgets.QLabel).text()
    assert not seen[0].list.isVisible()                  # one texture: no list to tick
    assert window.runner.busy and "Restoring" in window.task_label.text()    # in the worker
    assert window.runner.wait(60_000)
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


def test_discarding_forgets_the_journal(window, monkeypatch):
    crash(6)
    before = window.history.applied
    answering(monkeypatch, lambda d: d.discard_button.click())
    assert offer_recovery(window) == 0
    assert window.history.applied == before and orphans() == []


def test_not_now_keeps_every_journal_for_the_next_start(window, monkeypatch):
    crash(3)
    crash(5)
    before = window.history.applied
    seen = answering(monkeypatch, lambda d: d.later_button.click())
    assert offer_recovery(window) == 0
    assert window.history.applied == before and len(orphans()) == 2
    answering(monkeypatch, lambda d: d.reject())          # Esc: the same
    assert offer_recovery(window) == 0 and len(orphans()) == 2
    assert ticked(seen[0]) == ["Checked", "Checked"]


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
    assert offer_recovery(window, make_window) == 2
    assert seen[0].list.count() == 2 and "2 unsaved textures" in \
        seen[0].findChild(QtWidgets.QLabel).text()
    assert window.runner.wait(60_000) and extra and extra[0].runner.wait(60_000)
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
    assert offer_recovery(window, None) == 1
    assert window.runner.wait(60_000)
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
    assert offer_recovery(window) == 0 and len(orphans()) == 2


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


def test_a_cancelled_restore_keeps_the_journal_and_the_window_as_it_was(window, monkeypatch):
    crash(6)
    before = window.history.applied
    release = held_replay(monkeypatch)
    answering(monkeypatch, lambda d: d.restore_button.click())
    assert offer_recovery(window) == 1
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
    assert offer_recovery(window, make_window) == 1
    window.submit(SetLevels(0, 0, 4, 4, 2))    # the user goes on meanwhile
    mine = window.history.applied
    release.set()
    assert window.runner.wait(60_000)
    assert window.history.applied == mine      # kept, and the restored work is elsewhere
    assert len(extra) == 1 and np.array_equal(extra[0].document.levels, expected_levels(4))
    assert orphans() == []
    extra[0].mark_clean()
    extra[0].close()
