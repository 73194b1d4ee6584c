"""The History dock's Optimise log… (issue 21, item 10): the dialog lists what the optimiser
would drop, move and merge; Optimise replaces the log in the worker as one undoable change,
and the texture stays the same. Asserts are on the document, its log and what is shown."""

import numpy as np
from PySide6 import QtCore

from texeditor.recipe.actions import SetLevels, SetPalette

from .support import recipe

CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier
LEFT = QtCore.Qt.MouseButton.LeftButton
RED = np.array([[0, 0, 0], [200, 0, 0], [0, 200, 0], [0, 0, 200]], np.uint8)
BLUE = RED[:, ::-1].copy()


def open_dialog(qtbot, window):
    qtbot.mouseClick(window.history_dock.optimise_button, LEFT)
    dialog = window.history_dock.optimise_dialog
    qtbot.waitUntil(dialog.isVisible)
    return dialog


def test_optimise_the_log_then_undo_and_redo_it(qtbot, window):
    start = recipe(window)
    synthesis = window.history.actions[0]
    steps = [SetLevels(0, 0, 4, 6, 1), SetPalette(RED), SetLevels(10, 10, 2, 2, 2),
             SetLevels(0, 6, 4, 6, 1), SetPalette(BLUE)]
    for step in steps:                           # fill, palette, fill, fill, palette
        window.submit(step)
    long = recipe(window)

    dialog = open_dialog(qtbot, window)
    notes = [dialog.notes.item(k).text() for k in range(dialog.notes.count())]
    assert notes == [
        "Dropped step 3 (Set palette (4 colours)): step 6 sets the palette again and nothing "
        "between reads it",
        "Moved step 5 (Set 6×4 at (0, 6) to 1) before step 4 so it merges with step 2",
        "Merged step 2 (Set 6×4 at (0, 0) to 1) and step 5 (Set 6×4 at (0, 6) to 1) into one "
        "step: Set 12×4 at (0, 0) to 1"]
    assert "The 6 steps become 4" in dialog.summary.text()
    qtbot.mouseClick(dialog.optimise_button, LEFT)
    assert window.runner.wait(60_000)
    qtbot.waitUntil(lambda: window.history_dock.view.isEnabled())
    assert window.history.actions == (synthesis, SetLevels(0, 0, 4, 12, 1),
                                      SetLevels(10, 10, 2, 2, 2), SetPalette(BLUE))
    assert recipe(window)[2:] == long[2:]             # the same levels and palette
    assert np.array_equal(window.canvas.levels, window.document.levels)
    assert "Log optimised: 6 steps became 4" in window.statusBar().currentMessage()
    assert window.history_dock.model.rowCount() == 4

    dialog = open_dialog(qtbot, window)               # once more: nothing left to do
    assert "Nothing to do" in dialog.summary.text() and not dialog.optimise_button.isEnabled()
    dialog.reject()
    window.activateWindow()                           # the keys go to the window again
    qtbot.waitUntil(window.isActiveWindow)

    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)   # the whole optimisation, in one step
    assert recipe(window) == long
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL | SHIFT)
    assert window.history.index == 4 and recipe(window)[2:] == long[2:]
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    for _ in steps:                                    # back to the synthesis alone
        qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    assert recipe(window)[1:] == start[1:] and not window.act_undo.isEnabled()
    assert window.history.actions == (synthesis, *steps)      # the long log, as redo tail


def test_optimising_below_undone_steps_drops_them_and_says_so(qtbot, window):
    for step in (SetPalette(RED), SetPalette(BLUE), SetLevels(0, 0, 2, 2, 1)):
        window.submit(step)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)   # the fill is undone: a redo tail
    at_palette = recipe(window)
    dialog = open_dialog(qtbot, window)
    assert "the 1 undone step(s) after the current one go" in dialog.summary.text()
    qtbot.mouseClick(dialog.optimise_button, LEFT)
    assert window.runner.wait(60_000)
    qtbot.waitUntil(lambda: window.history_dock.view.isEnabled())
    assert window.history.actions == (window.history.actions[0], SetPalette(BLUE))
    assert recipe(window)[2:] == at_palette[2:] and not window.act_redo.isEnabled()
