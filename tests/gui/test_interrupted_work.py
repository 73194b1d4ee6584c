"""Work interrupted midway: a synthesis that lands after the history moved, a stroke during
which Space or the hand tool is pressed. Nothing the user did may be dropped or land elsewhere."""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtTest

import app.main_window
from app.tools.brush import BrushTool
from texeditor.paint.actions import Stroke
from texeditor.recipe.history import History

from .support import Key, cell_pos, drag, hold, mouse, press_key

LEFT = QtCore.Qt.MouseButton.LeftButton
NONE = QtCore.Qt.MouseButton.NoButton
Type = QtCore.QEvent.Type


def brush(window, level: int) -> None:
    window.set_tool(next(t for t in window.tools if type(t) is BrushTool))
    bar = window.palette_dock.swatches
    QtTest.QTest.mouseClick(bar, LEFT, QtCore.Qt.KeyboardModifier.NoModifier,
                            bar.swatch_rect(level).center())
    assert window.current_level == level


def stroke(window, y: int, level: int) -> None:
    brush(window, level)
    drag(window.canvas.viewport(), LEFT, _xy(window, 4, y), _xy(window, 40, y))


def _xy(window, x, y):
    p = cell_pos(window.canvas, x, y)
    return p.x(), p.y()


def test_a_synthesis_landing_after_an_undo_or_a_stroke_leaves_the_history_as_left(
        qtbot, window, monkeypatch):
    """Ctrl+Z (or a stroke) while a synthesis is drawn: applied on landing, the synthesis would
    drop the steps undone meanwhile (they were lost without a word); it is not applied, the
    status bar says so, the undone steps are still there to redo, and Synthesise again works."""
    stroke(window, 10, 3)
    stroke(window, 20, 1)
    painted, steps = window.document.levels.copy(), len(window.history.actions)
    assert steps == 3 and all(isinstance(a, Stroke) for a in window.history.actions[1:])
    started, gate = hold(monkeypatch, app.main_window, "render_synthesis")
    window.synthesis_dock.seed.set_value(99)
    window.synthesise_from_dock()
    assert started.wait(30) and window.runner.busy
    qtbot.keyClick(window, Key.Key_Z, QtCore.Qt.KeyboardModifier.ControlModifier)
    qtbot.keyClick(window, Key.Key_Z, QtCore.Qt.KeyboardModifier.ControlModifier)
    assert window.history.index == 1
    gate.set()
    assert window.runner.wait(30_000)
    assert window.history.index == 1 and len(window.history.actions) == steps
    assert "not applied" in window.statusBar().currentMessage()
    window.redo()
    window.redo()
    assert np.array_equal(window.document.levels, painted)

    window.synthesise_from_dock()                        # again, nothing moving: applied
    assert window.runner.wait(60_000)
    assert window.history.index == steps + 1
    assert window.history.actions[-1].seed == 99

    started, gate = hold(monkeypatch, app.main_window, "render_synthesis")
    window.synthesis_dock.seed.set_value(5)
    window.synthesise_from_dock()
    assert started.wait(30)
    stroke(window, 30, 2)                                # a stroke while it is drawn
    kept = window.document.levels.copy()
    gate.set()
    assert window.runner.wait(30_000)
    assert np.array_equal(window.document.levels, kept)
    assert isinstance(window.history.actions[-1], Stroke)
    assert not window.errors


def test_space_or_the_hand_tool_mid_stroke_lands_the_stroke_at_its_release(qtbot, window):
    """Space held, or H pressed, while the brush is dragged: the drag stays a stroke until the
    mouse is released, and lands then as one step; it was left open, its ghost on the canvas,
    and landed in whatever document the next drag found (a new one after File ▸ New)."""
    view, canvas = window.canvas.viewport(), window.canvas
    brush(window, 3)
    for interruption in ("space", "hand"):
        steps = window.history.index
        y = 12 if interruption == "space" else 30
        mouse(view, Type.MouseButtonPress, cell_pos(canvas, 4, y), LEFT, LEFT)
        for x in (8, 14, 20):
            qtbot.wait(20)
            mouse(view, Type.MouseMove, cell_pos(canvas, x, y), NONE, LEFT)
        if interruption == "space":
            qtbot.keyPress(view, Key.Key_Space)
        else:
            press_key(window, Key.Key_H)
            assert window.tool.PANS
        for x in (28, 36, 44):
            qtbot.wait(20)
            mouse(view, Type.MouseMove, cell_pos(canvas, x, y), NONE, LEFT)
        assert window.history.index == steps              # still a stroke under way
        mouse(view, Type.MouseButtonRelease, cell_pos(canvas, 44, y), LEFT, NONE)
        assert window.history.index == steps + 1 and not canvas.in_gesture()
        landed = window.history.actions[-1]
        assert isinstance(landed, Stroke) and landed.level == 3
        assert (window.document.levels[y, 4:45] == 3).all()    # the whole drag, before and after
        if interruption == "space":
            qtbot.keyRelease(view, Key.Key_Space)
        else:
            brush(window, 3)
    window.set_tool([t for t in window.tools if t.PANS][0])
    before = canvas.view.viewRange()
    drag(view, LEFT, _xy(window, 30, 30), _xy(window, 10, 10))    # the hand pans: no step
    assert canvas.view.viewRange() != before and isinstance(window.history.actions[-1], Stroke)

    fresh = History()
    fresh.add_dpj(window.document.dpj)
    window.mark_clean()
    window.set_history(fresh)
    assert len(window.history.actions) == 0 and not window.errors


def test_a_long_dpj_name_wraps_and_the_synthesis_dock_never_scrolls_sideways(qtbot, window):
    """A DPJ of a long name (an edited photo-model scale's description is as long) made the
    dock's content 431 points wide in a 340-point dock; after Synthesise it was left scrolled
    sideways, the row labels and Tileable out of sight."""
    from .support import settle
    dpj = window.document.dpj
    named = type(dpj)(dpj.configs, dpj.probs, dpj.levels,
                      meta={**dpj.meta, "name": "a photo of the old harbour wall, west side, taken at low tide in the morning light"})
    window.history.add_dpj(named)
    dock = window.synthesis_dock
    qtbot.waitUntil(lambda: "old harbour" in dock.dpj_label.text())
    window.synthesise_from_dock()
    assert window.runner.wait(60_000)
    settle(window)
    scroll = dock.widget().horizontalScrollBar()
    assert scroll.maximum() == 0 and scroll.value() == 0
    assert dock.widget().widget().minimumSizeHint().width() <= dock.widget().viewport().width()
    assert window.history.actions[-1].dpj == named.ref and not window.errors
