"""Shared helpers of the GUI tests: real input events (wheel notches and mouse drags sent to a
widget, clicks, keys), and the gestures several test modules share (a tool, a dialog, typing).

Drags are sent as raw QMouseEvents: QTest turns a second press near the first, within the
double-click interval, into a double click, which is not what a drag is. Moves are spaced in time
because pyqtgraph drops mouse moves faster than its rate limit (as a real mouse never sends).
"""

import threading

import numpy as np
from PySide6 import QtCore, QtGui, QtTest, QtWidgets
from PySide6.QtTest import QTest

from app.tools.spot import SpotTool

NO_MODIFIER = QtCore.Qt.KeyboardModifier.NoModifier
CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
LEFT = QtCore.Qt.MouseButton.LeftButton
Key = QtCore.Qt.Key


def wheel(widget, pos: QtCore.QPoint, notches: int) -> None:
    """Turn the wheel by some notches (120 units each; positive zooms in) at a widget position."""
    ev = QtGui.QWheelEvent(QtCore.QPointF(pos), QtCore.QPointF(widget.mapToGlobal(pos)),
                           QtCore.QPoint(0, 0), QtCore.QPoint(0, 120 * notches),
                           QtCore.Qt.MouseButton.NoButton, NO_MODIFIER,
                           QtCore.Qt.ScrollPhase.NoScrollPhase, False)
    QtWidgets.QApplication.sendEvent(widget, ev)


def mouse(widget, kind, pos, button, buttons) -> None:
    p = QtCore.QPointF(pos)
    ev = QtGui.QMouseEvent(kind, p, QtCore.QPointF(widget.mapToGlobal(pos)), button, buttons,
                           NO_MODIFIER)
    QtWidgets.QApplication.sendEvent(widget, ev)


def drag(widget, button, a, b, steps: int = 5) -> None:
    """Press at a, move in steps to b, release: one drag gesture with one button held."""
    none = QtCore.Qt.MouseButton.NoButton
    Type = QtCore.QEvent.Type
    mouse(widget, Type.MouseButtonPress, QtCore.QPoint(*a), button, button)
    for k in range(1, steps + 1):
        p = QtCore.QPoint(a[0] + (b[0] - a[0]) * k // steps, a[1] + (b[1] - a[1]) * k // steps)
        QtTest.QTest.qWait(25)
        mouse(widget, Type.MouseMove, p, none, button)
    mouse(widget, Type.MouseButtonRelease, QtCore.QPoint(*b), button, none)


def move(widget, pos: QtCore.QPoint) -> None:
    """The mouse moves over a widget with no button held (hover)."""
    none = QtCore.Qt.MouseButton.NoButton
    mouse(widget, QtCore.QEvent.Type.MouseMove, pos, none, none)


def cell_pos(canvas, x: float, y: float) -> QtCore.QPoint:
    """The canvas widget position of the centre of cell (x, y)."""
    scene = canvas.view.mapViewToScene(QtCore.QPointF(x + 0.5, y + 0.5))
    return canvas.mapFromScene(scene)


def click(widget, pos: QtCore.QPoint) -> None:
    QtTest.QTest.mouseClick(widget, QtCore.Qt.MouseButton.LeftButton, NO_MODIFIER, pos)


def press_key(widget, key) -> None:
    QtTest.QTest.keyClick(widget, key)


# -- shared by several GUI test modules ----------------------------------------------------------

def spot_tool(window) -> SpotTool:
    press_key(window, QtCore.Qt.Key.Key_S)
    tool = window.tool
    assert isinstance(tool, SpotTool) and tool.dock.isVisible()
    settle(tool.dock)               # the editor's dock takes its place under the canvas
    return tool


def settle(widget, rounds: int = 4):
    """Wait until a widget keeps its size (docks resize with an animation)."""
    size, same = None, 0
    for _ in range(100):
        QtTest.QTest.qWait(20)
        same = same + 1 if widget.size() == size else 0
        size = widget.size()
        if same >= rounds:
            return


def type_into(qtbot, widget, text):
    """Select all in a spin box or line edit with the keyboard and type a new value."""
    widget.setFocus()
    qtbot.keyClick(widget, QtCore.Qt.Key.Key_A, CTRL)
    qtbot.keyClicks(widget, text)


def new_dpj(qtbot, editor, u, v, g):
    """File ▸ New DPJ… in the editor, typed into the dialog."""
    editor.act_new.trigger()
    dialog = editor.new_dialog
    for box, value in ((dialog.u, u), (dialog.v, v), (dialog.levels, g)):
        box.selectAll()
        qtbot.keyClicks(box, str(value))
    qtbot.keyClick(dialog, Key.Key_Return)
    assert editor.dpj.window == (u, v) and editor.dpj.levels == g and len(editor.dpj) == 0


def choose_level(editor, level):
    bar = editor.painter.swatches
    QTest.mouseClick(bar, LEFT, NO_MODIFIER, bar.swatch_rect(level).center())
    assert editor.painter.grid.level == level


def paint(editor, config):
    """Paint a configuration cell by cell with the swatches and mouse clicks on the grid."""
    grid = editor.painter.grid
    for level in np.unique(config):
        choose_level(editor, int(level))
        for r, c in zip(*np.nonzero(config == level)):
            QTest.mouseClick(grid, LEFT, NO_MODIFIER, grid.cell_rect(r, c).center())
    assert np.array_equal(editor.painter.config(), config)


def set_probability(qtbot, editor, text):
    """Type the probability and press Enter: Add/Set."""
    line = editor.painter.probability.spin.lineEdit()
    line.selectAll()
    qtbot.keyClicks(line, text)
    qtbot.keyClick(line, Key.Key_Return)


def recipe(window) -> tuple:
    history = window.history
    return (history.actions, history.index, history.document.levels.tobytes(),
            history.document.palette.tobytes())


def edit_and_apply(qtbot, window, step: int, name: str, text: str) -> tuple:
    """Click a step in the History list, type a new value for one parameter, Apply & replay;
    returns the recipe as it was once the step was clicked (where an undo of the edit goes)."""
    dock = window.history_dock
    qtbot.mouseClick(dock.view.viewport(), QtCore.Qt.MouseButton.LeftButton, pos=dock.row_rect(step).center())
    clicked = recipe(window)
    kind, editor = dock.form.editors[name]
    type_into(qtbot, editor.edit if kind == "seed" else editor, text)
    qtbot.mouseClick(dock.apply_button, QtCore.Qt.MouseButton.LeftButton)
    assert window.runner.wait(60_000)
    qtbot.waitUntil(lambda: window.history_dock.view.isEnabled())
    return clicked


def synthesise(qtbot, window, width, height, seed, scales=None):
    dock = window.synthesis_dock
    type_into(qtbot, dock.width_box, str(width))
    type_into(qtbot, dock.height_box, str(height))
    type_into(qtbot, dock.seed.edit, str(seed))
    if scales is not None:
        type_into(qtbot, dock.scales_box, str(scales))
    qtbot.mouseClick(dock.button, LEFT)
    assert window.runner.wait(120_000)
    assert not window.errors


def undo_to_start(qtbot, window):
    while window.can_undo():
        qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert window.history.index == 1


def fill_a_cell(qtbot, window):
    """Fill tool: a click on a cell whose level is not the current one (a step that changes
    something)."""
    press_key(window, Key.Key_F)
    doc, level = window.document, window.current_level
    ys, xs = np.nonzero(doc.levels != level)
    steps = len(window.history.actions)
    click(window.canvas.viewport(), cell_pos(window.canvas, int(xs[0]), int(ys[0])))
    assert len(window.history.actions) == steps + 1
    assert window.history.actions[-1].TYPE == "fill"


def open_model_dialog(window, qtbot, model: str):
    """Models ▸ the entry of ``model``: the dialog it opens (a StepDialog), once exposed."""
    from app.step_dialog import StepDialog
    [entry] = [a for a in window.menu("ModelsMenu").actions() if a.objectName() == f"act_{model}"]
    entry.trigger()
    dialog = [d for d in window.findChildren(StepDialog) if d.isVisible()][-1]
    qtbot.waitExposed(dialog)
    return dialog


def model_ok(dialog, qtbot):
    """OK once the preview of the latest settings is shown (computed in the background)."""
    assert dialog.wait()
    assert dialog.ok.isEnabled(), dialog.info.text()
    assert not dialog.result_view.pixmap().isNull()
    qtbot.mouseClick(dialog.ok, QtCore.Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: not dialog.isVisible())
    dialog.main_window.activateWindow()      # the window manager's part, offscreen
    qtbot.waitUntil(lambda: dialog.main_window.isActiveWindow())


def hold(monkeypatch, owner, name: str) -> tuple[threading.Event, threading.Event]:
    """Hold ``owner.name`` (a function a worker calls) until released: (started, release) —
    ``started`` is set once the worker is inside it, ``release.set()`` lets it go on."""
    started, release = threading.Event(), threading.Event()
    real = getattr(owner, name)

    def held(*args, **kwargs):
        started.set()
        release.wait(30)
        return real(*args, **kwargs)
    monkeypatch.setattr(owner, name, held)
    return started, release
