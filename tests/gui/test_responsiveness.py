"""The window never freezes and never loses work: an edit of a past step replays in the worker
(a GUI timer keeps ticking; Cancel restores exactly; edits meanwhile are refused), acquisition
computes in the background with the latest setting winning, and closing the window asks about
a DPJ editor's unsaved changes."""

import threading
import time

import numpy as np
import pytest
from PySide6 import QtCore, QtWidgets

from texeditor.recipe.actions import SetLevels, SetPalette, Synthesize
from texeditor.recipe.document import dpj_ref
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay

from .support import CTRL, LEFT, new_dpj, paint, set_probability, type_into

SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier
STEP_SECONDS = 0.003          # each replayed patch is slowed so the replay takes about a second


@pytest.fixture
def long_log(window, small_dpj, monkeypatch):
    """The window on a 300-step log (a synthesis, patches, palettes), step 1 clicked; every
    SetLevels.apply then sleeps a little and says on which thread and when it ran."""
    ref = dpj_ref(small_dpj)
    rng = np.random.default_rng(5)
    actions = [Synthesize(ref, 96, 80, 7)]
    for k in range(299):
        if k % 50 == 49:
            actions.append(SetPalette(tuple((g, g, g) for g in sorted(rng.integers(0, 256, 4)))))
        else:
            r, c = (int(x) for x in rng.integers(0, 76, 2))
            actions.append(SetLevels(r, c, 4, 4, int(rng.integers(0, 4))))
    window.set_history(History.from_log(actions, {ref: small_dpj}))
    dock = window.history_dock
    QtWidgets.QApplication.processEvents()
    dock.view.scrollToTop()
    from PySide6.QtTest import QTest
    QTest.mouseClick(dock.view.viewport(), LEFT, pos=dock.row_rect(0).center())
    assert window.history.index == 1
    applied = []
    original = SetLevels.apply

    def slow_apply(self, doc, prepared=None):
        applied.append((threading.current_thread() is threading.main_thread(),
                        time.perf_counter()))
        time.sleep(STEP_SECONDS)
        original(self, doc, prepared)
    monkeypatch.setattr(SetLevels, "apply", slow_apply)
    return applied


def ticking(qtbot):
    """A 10 ms timer on the GUI thread; the list of its tick times."""
    ticks = []
    timer = QtCore.QTimer(interval=10)
    timer.timeout.connect(lambda: ticks.append(time.perf_counter()))
    timer.start()
    return timer, ticks


def apply_new_seed(qtbot, window, seed="4242"):
    dock = window.history_dock
    type_into(qtbot, dock.form.editor("seed").edit, seed)
    qtbot.mouseClick(dock.apply_button, LEFT)


def fingerprint(window):
    h, doc = window.history, window.history.document
    return (h.actions, h.index, doc.levels.tobytes(), doc.palette.tobytes(), dict(h.memory),
            window.canvas.levels.tobytes())


def test_edit_and_replay_runs_in_the_worker_while_the_gui_ticks(qtbot, window, long_log,
                                                                  small_dpj):
    timer, ticks = ticking(qtbot)
    fractions = []
    window.runner.progress.connect(fractions.append)
    apply_new_seed(qtbot, window)
    assert window.progress.isVisible() and not window.history_dock.view.isEnabled()
    assert window.runner.wait(60_000)
    timer.stop()
    assert len(long_log) == 299 - 5                       # each patch replayed once...
    assert not any(on_gui for on_gui, _ in long_log)      # ...and never on the GUI thread
    first, last = long_log[0][1], long_log[-1][1]
    during = [t for t in ticks if first < t < last]
    assert len(during) >= 10                              # the window stayed live meanwhile
    assert fractions and fractions == sorted(fractions) and fractions[-1] == 1.0
    history = window.history
    assert history.actions[0].seed == 4242 and history.index == len(history.actions) == 300
    expected = replay(history.actions, {dpj_ref(small_dpj): small_dpj})
    assert np.array_equal(history.document.levels, expected.levels)
    assert np.array_equal(history.document.palette, expected.palette)
    assert np.array_equal(window.canvas.levels, expected.levels)
    assert "replayed" in window.statusBar().currentMessage()
    assert window.history_dock.view.isEnabled() and not window.progress.isVisible()


@pytest.mark.parametrize("how", ["escape", "cancel button", "ctrl+z"])
def test_cancel_midway_restores_exactly(qtbot, window, long_log, how):
    before = fingerprint(window)
    apply_new_seed(qtbot, window)
    qtbot.waitUntil(lambda: len(long_log) > 20, timeout=30_000)
    if how == "escape":
        qtbot.keyClick(window, QtCore.Qt.Key.Key_Escape)
    elif how == "cancel button":
        qtbot.mouseClick(window.cancel_button, LEFT)
    else:
        qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    assert window.runner.wait(30_000)
    assert len(long_log) < 200                            # it really stopped midway
    assert fingerprint(window) == before
    assert "cancelled" in window.statusBar().currentMessage()
    assert window.history_dock.view.isEnabled() and window.history_dock.apply_button.isEnabled()


def test_edits_meanwhile_are_refused_politely(qtbot, window, long_log):
    before = fingerprint(window)
    apply_new_seed(qtbot, window)
    qtbot.waitUntil(lambda: len(long_log) > 5, timeout=30_000)
    assert window.submit(SetPalette(np.full((4, 3), 90, np.uint8))) is False
    assert "being replayed" in window.statusBar().currentMessage()
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL | SHIFT)          # redo: refused too
    assert window.acquire() is None and not window.errors
    assert window.runner.busy and fingerprint(window) == before
    assert window.runner.wait(60_000)
    assert window.history.actions[0].seed == 4242 and window.history.index == 300


# -- acquisition -----------------------------------------------------------------------------------

@pytest.fixture
def slow_quantize(monkeypatch):
    """Quantisation (of one DPJ, or of a photo model's scales) as slow as on a large photo;
    returns the (start, end) time of each call."""
    import app.acquire_dialog as module
    calls = []

    def slowed(original):
        def slow(*args, **kwargs):
            start = time.perf_counter()
            time.sleep(0.4)
            result = original(*args, **kwargs)
            calls.append((start, time.perf_counter()))
            return result
        return slow
    for name in ("quantize", "estimate_scales"):
        monkeypatch.setattr(module, name, slowed(getattr(module, name)))
    return calls


def test_acquisition_computes_in_the_background(qtbot, window, slow_quantize):
    timer, ticks = ticking(qtbot)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_I, CTRL)
    dialog = window.acquire_dialog
    assert dialog.busy.isVisible() and not dialog.ok_button.isEnabled()
    qtbot.keyClick(dialog, QtCore.Qt.Key.Key_Return)           # nothing to acquire yet
    assert dialog.isVisible() and dialog.dpj is None
    assert dialog.wait()
    timer.stop()
    start, end = slow_quantize[0]
    assert len([t for t in ticks if start < t < end]) >= 10   # the dialog stayed live
    assert dialog.ok_button.isEnabled() and not dialog.busy.isVisible()
    qtbot.mouseClick(dialog.ok_button, LEFT)
    assert window.runner.wait(60_000)
    assert window.history.document.dpj == dialog.dpj


def test_changing_g_twice_quickly_gives_the_last_setting(qtbot, window, slow_quantize):
    dialog = window.acquire()
    assert dialog.wait()
    qtbot.mouseClick(dialog.auto_scales, LEFT)           # one DPJ, not a photo model
    type_into(qtbot, dialog.scales, "1")
    assert dialog.wait() and dialog.model is None
    shown = []
    dialog.worker.done.connect(lambda out: shown.append(out.dpj.levels))
    type_into(qtbot, dialog.levels, "5")
    qtbot.waitUntil(lambda: dialog.worker.job is not None, timeout=5_000)   # G = 5 computing
    assert not dialog.ok_button.isEnabled() and dialog.dpj is None
    type_into(qtbot, dialog.levels, "6")
    assert not dialog.ok_button.isEnabled()
    assert dialog.wait()
    assert shown == [6]                                   # the stale G = 5 was never shown
    assert dialog.dpj.levels == 6 and dialog.quantization.levels.max() == 5
    assert "G = 6" in dialog.info.text() and dialog.ok_button.isEnabled()
    dialog.reject()


# -- closing with a DPJ editor's unsaved changes ---------------------------------------------------

@pytest.mark.parametrize("answer, closes", [("Cancel", False), ("Discard", True), ("Save", True)])
def test_close_asks_about_a_dirty_dpj_editor(qtbot, window, monkeypatch, tmp_path, answer, closes):
    qtbot.keyClick(window, QtCore.Qt.Key.Key_J, CTRL)              # Edit DPJ…
    editor = window.dpj_editor
    new_dpj(qtbot, editor, 2, 2, 2)
    paint(editor, np.array([[0, 1], [0, 1]], np.uint8))
    set_probability(qtbot, editor, "1")
    assert not editor.undo_stack.isClean()
    editor.close()                                               # hidden, its changes kept
    asked = []
    button = getattr(QtWidgets.QMessageBox.StandardButton, answer)
    monkeypatch.setattr(QtWidgets.QMessageBox, "question",
                        lambda parent, *a, **k: asked.append(parent) or button)
    path = tmp_path / "stripes.dpj"
    monkeypatch.setattr(QtWidgets.QFileDialog, "getSaveFileName", lambda *a, **k: (str(path), ""))
    assert window.close() is closes
    assert asked == [editor]                      # the document itself had nothing unsaved
    assert window.isVisible() is not closes
    assert editor.undo_stack.isClean() is (answer == "Save")
    assert path.exists() is (answer == "Save")
    editor.stop()


def test_a_job_whose_window_closed_meanwhile_ends_quietly(qtbot):
    """The DPJ editor closed while its preview job ran: the job's signals are gone when it
    reports, and the pool thread must end without an exception (nobody is left to tell)."""
    import shiboken6

    from app.synthesis_worker import Job

    for outcome in ("done", "failed", "cancelled"):
        def work(progress, cancel, outcome=outcome):
            progress(0.5)
            if outcome == "failed":
                raise ValueError("boom")
            if outcome == "cancelled":
                job.cancel()
            return 1
        job = Job(work)
        shiboken6.delete(job.signals)
        job.run()                   # raised "Signal source has been deleted" before


def test_a_task_whose_runner_was_deleted_meanwhile_ends_quietly(qtbot):
    """A window (and its TaskRunner) deleted while its task runs: the outcome, queued to the GUI
    thread, arrives for a runner that no longer exists and must not raise in the event loop."""
    import shiboken6

    from app.synthesis_worker import TaskRunner

    called, gate = [], threading.Event()
    runner = TaskRunner()
    runner.run("work", lambda progress, cancel: gate.wait(10) and 1, called.append)
    gate.set()
    shiboken6.delete(runner)            # its pool waits for the job; the outcome is queued
    qtbot.wait(50)                      # raised "Signal source has been deleted" before
    assert called == []


def test_a_preview_whose_editor_was_deleted_meanwhile_ends_quietly(qtbot):
    """The same for the DPJ editor's latest-wins preview jobs."""
    import shiboken6

    from app.dpj_editor.preview import LatestWins

    gate = threading.Event()
    latest = LatestWins(delay_ms=0)
    latest.request(lambda progress, cancel: gate.wait(10) and 1)
    qtbot.waitUntil(lambda: latest.job is not None)
    gate.set()
    shiboken6.delete(latest)
    qtbot.wait(50)
