"""The scan direction in the window, as a session: acquire a DPJ by columns (made stationary),
the Synthesis dock proposes that scan and draws the transposed texture, draw again by rows,
undo back through both to the start; the dock follows the step shown."""

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor.markov.estimation import estimate_dpj
from texeditor.markov.synthesis import synthesize

from .support import synthesise, type_into, undo_to_start

CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
LEFT = QtCore.Qt.MouseButton.LeftButton
Key = QtCore.Qt.Key


def choose(combo, key):
    combo.setCurrentIndex(combo.findData(key))


def test_acquire_by_columns_synthesise_switch_to_rows_and_undo(qtbot, window):
    start = window.document.levels.copy()
    dock = window.synthesis_dock
    assert dock.scan() == "rows"

    qtbot.keyClick(window, Key.Key_I, CTRL)                 # File ▸ Acquire DPJ from image…
    dialog = window.acquire_dialog
    assert dialog.wait() and dialog.scan.currentData() == "rows"
    assert not dialog.scan.isEnabled()                       # a photo model first: rows only
    qtbot.mouseClick(dialog.auto_scales, LEFT)               # one DPJ: unticked, 1 scale, 3×3
    type_into(qtbot, dialog.scales, "1")
    type_into(qtbot, dialog.v, "3")
    choose(dialog.scan, "columns")
    qtbot.mouseClick(dialog.stationary, LEFT)
    assert dialog.wait() and dialog.stationary.isChecked()
    acquired = dialog.dpj
    q = dialog.quantization.levels
    assert acquired.meta["scan"] == "columns" and acquired.meta["stationary"] is True
    assert acquired == estimate_dpj(q, (3, 3), 4, scan="columns", stationary=True,
                                    palette=dialog.quantization.palette)
    assert acquired == estimate_dpj(np.ascontiguousarray(q.T), (3, 3), 4, stationary=True,
                                    palette=dialog.quantization.palette)
    r = acquired.report()
    assert max(r.horizontal_residual, r.vertical_residual) < 1e-9
    text = dialog.info.text()
    assert "scanned by columns, left to right" in text and "made stationary" in text
    dialog.scales.setValue(2)                                # a photo model: rows only
    assert not dialog.scan.isEnabled() and not dialog.stationary.isEnabled()
    dialog.scales.setValue(1)
    assert dialog.wait() and dialog.scan.isEnabled() and dialog.dpj == acquired
    qtbot.mouseClick(dialog.ok_button, LEFT)                 # acquire, and synthesise now
    window.activateWindow()
    qtbot.waitUntil(lambda: QtWidgets.QApplication.activeWindow() is window, timeout=3000)
    assert window.runner.wait(60_000) and not window.errors

    doc = window.document
    step = window.history.actions[-1]
    assert doc.dpj_ref == acquired.ref and dock.scan() == "columns"      # proposed by the DPJ
    assert step.TYPE == "synthesize" and step.scan == "columns" and "scan columns" in step.label()
    h, w = doc.shape
    assert np.array_equal(doc.levels, synthesize(acquired, (w, h), seed=step.seed).levels.T)
    by_columns = doc.levels.copy()

    choose(dock.scan_box, "rows")                            # the same DPJ drawn along rows
    synthesise(qtbot, window, 40, 30, step.seed)
    step_rows = window.history.actions[-1]
    assert step_rows.scan == "rows" and window.document.shape == (30, 40)
    assert np.array_equal(window.document.levels,
                          synthesize(acquired, (30, 40), seed=step.seed).levels)

    qtbot.keyClick(window, Key.Key_Z, CTRL)                  # back to the texture by columns
    assert np.array_equal(window.document.levels, by_columns)
    assert dock.scan() == "columns"                          # the dock shows the step that made it
    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start)
    assert window.history.actions[0].scan == "rows" and dock.scan() == "rows"
