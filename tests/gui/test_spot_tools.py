"""The spot editor and the Spot tool (issue 7), driven with real mouse and key events."""

import math

import numpy as np
import pytest
from PySide6 import QtCore, QtTest, QtWidgets

from texeditor.spots.actions import DeleteSpot, PlaceSpot, ScatterSpots
from texeditor.spots.envelope import Envelope

from .support import cell_pos, click, drag, mouse, move, press_key, spot_tool

Type = QtCore.QEvent.Type
LEFT, NONE = QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.MouseButton.NoButton


@pytest.fixture(autouse=True)
def own_spot_library(tmp_path, monkeypatch):
    """Saved spots go to a temporary data folder, never the user's own."""
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path / "data"))


def at(view, point) -> QtCore.QPoint:
    """The widget position of an envelope point (row, col) in the editor's drawing area."""
    return view.to_screen(point).toPoint()


def press(widget, pos, button=LEFT):
    mouse(widget, Type.MouseButtonPress, pos, button, button)


def move_held(widget, pos, button=LEFT):
    QtTest.QTest.qWait(5)
    mouse(widget, Type.MouseMove, pos, NONE, button)


def release(widget, pos, button=LEFT):
    mouse(widget, Type.MouseButtonRelease, pos, button, NONE)


def close(a, b, tol=0.8):
    return math.dist(a, b) <= tol


def draw_ellipse_envelope(editor):
    """New envelope: click (0, -20) then (0, 20); the main meridian appears across its middle."""
    view = editor.view
    editor.new_button.click()
    assert editor.envelope is None
    for point in [(0.0, -20.0), (0.0, 20.0)]:
        press(view, at(view, point))
        release(view, at(view, point))
    return view


# -- the editor ------------------------------------------------------------------------------------

def test_build_an_envelope_with_clicks_and_drags(window, qtbot):
    editor = spot_tool(window).editor
    view = draw_ellipse_envelope(editor)
    env = editor.envelope
    assert close(env.a, (0, -20)) and close(env.b, (0, 20))
    assert len(env.meridians) == 1 and env.meridians[0].main
    assert math.isclose(env.meridians[0].left, env.length / 4, abs_tol=0.01)

    # drag the main meridian's left end up and along: the outline follows while dragging
    handle = at(view, env.at(0.5, env.meridians[0].left))
    press(view, handle)
    move_held(view, at(view, (-8.0, 1.0)))
    assert close((editor.envelope.meridians[0].left,), (8.0,))          # live, before release
    move_held(view, at(view, (-15.0, 2.0)))
    release(view, at(view, (-15.0, 2.0)))
    m = editor.envelope.meridians[0]
    assert abs(m.left - 15) < 0.8 and abs(m.t - 0.55) < 0.03
    outline = editor.envelope.outline()
    top = editor.envelope.at(m.t, m.left)
    assert np.min(np.linalg.norm(outline - top, axis=1)) < 1e-6        # through the new end

    # double-click below the equator adds a meridian there; right-click on it removes it
    QtTest.QTest.mouseDClick(view, LEFT, QtCore.Qt.KeyboardModifier.NoModifier,
                             at(view, (6.0, 10.0)))
    env = editor.envelope
    assert len(env.meridians) == 2
    added = env.meridians[1]
    assert abs(added.t - 0.75) < 0.03 and abs(added.right - 6) < 0.8
    press(view, at(view, env.at(added.t, -added.right)), QtCore.Qt.MouseButton.RightButton)
    assert len(editor.envelope.meridians) == 1

    # Shift+double-click adds a parallel
    QtTest.QTest.mouseDClick(view, LEFT, QtCore.Qt.KeyboardModifier.ShiftModifier,
                             at(view, (-6.0, -5.0)))
    assert len(editor.envelope.parallels) == 1 and editor.envelope.parallels[0].offset > 5

    # the outline kind is an option
    editor.kind.setCurrentIndex(editor.kind.findData("bezier_curve"))
    assert editor.envelope.kind == "bezier_curve"


def test_drag_the_equator_and_draw_a_contour_freehand(window, qtbot):
    editor = spot_tool(window).editor
    view = editor.view
    editor.new_button.click()
    drag(view, LEFT, _xy(at(view, (5.0, -10.0))), _xy(at(view, (5.0, 12.0))))
    assert close(editor.envelope.a, (5, -10)) and close(editor.envelope.b, (5, 12))

    editor.contour_button.click()
    ring = [(12 * math.sin(a), 12 * math.cos(a)) for a in np.linspace(0, 2 * math.pi, 40)]
    press(view, at(view, ring[0]))
    for point in ring[1:]:
        move_held(view, at(view, point))
    release(view, at(view, ring[-1]))
    env = editor.envelope
    assert env.contour is not None and 6 <= len(env.contour) <= 40
    assert abs(env.length - 24) < 1.5                    # the equator is the longest chord
    assert abs(env.area() - math.pi * 144) < 0.1 * math.pi * 144


def test_perturbation_settings_and_seeds_change_the_preview(window, qtbot):
    editor = spot_tool(window).editor
    editor.interior.setCurrentIndex(editor.interior.findData("holes"))
    editor.density.set_value(0.3)
    p = editor.perturbation()
    assert p.interior == "holes" and p.density == 0.3
    before = editor.view._preview[0].copy()
    editor.seed.set_value(editor.seed.value() + 1)
    assert editor.view._preview[0] != before


# -- the Spot tool on the canvas ---------------------------------------------------------------

def test_click_places_the_current_spot_and_a_drag_turns_and_sizes_it(window, qtbot):
    tool = spot_tool(window)
    editor = tool.editor
    editor.load(editor.library.get("Ellipse"))          # an equator of 40 across the screen
    canvas = window.canvas
    steps, level = window.history.index, window.current_level
    seed = editor.seed.value()
    click(canvas.viewport(), cell_pos(canvas, 30, 20))
    action = window.history.actions[-1]
    assert isinstance(action, PlaceSpot) and (action.row, action.col) == (20, 30)
    assert action.seed == seed and editor.seed.value() != seed        # the next spot differs
    assert window.history.index == steps + 1
    assert window.document.levels[20, 30] == level

    tool.opts.scale_box.setValue(0.5)
    a, b = cell_pos(canvas, 10, 30), cell_pos(canvas, 10, 20)         # drag straight up 10
    drag(canvas.viewport(), LEFT, _xy(a), _xy(b))
    action = window.history.actions[-1]
    assert (action.row, action.col) == (30, 10)
    assert abs(action.angle - 90) < 0.5 and abs(action.scale - 10 / 20) < 0.01
    rows, cols = np.nonzero(tool_stamp(action, window).mask)
    assert np.ptp(rows) > np.ptp(cols)                      # the spot now stands up


def tool_stamp(action, window):
    return action.stamp(0, window.document.shape)


def test_hover_shows_the_ghost_and_a_flat_spot_is_refused(window, qtbot):
    tool = spot_tool(window)
    canvas = window.canvas
    move(canvas.viewport(), cell_pos(canvas, 20, 20))
    assert tool.ghost.isVisible() and not tool.ghost.path().isEmpty()
    editor = tool.editor
    flat = Envelope((0.0, -10.0), (0.0, 10.0)).with_meridian(0.5, 0, 0)
    editor.view.set_envelope(flat)
    before, steps = window.document.levels.copy(), window.history.index
    click(canvas.viewport(), cell_pos(canvas, 20, 20))
    assert window.errors and "no width" in window.errors[-1][1]
    assert np.array_equal(window.document.levels, before) and window.history.index == steps


def test_scatter_in_a_rectangle_then_delete_a_spot_and_undo(window, qtbot):
    tool = spot_tool(window)
    canvas = window.canvas
    tool.opts.mode.setCurrentIndex(tool.opts.mode.findData("scatter"))
    tool.opts.count.setValue(12)
    tool.opts.scale_box.setValue(0.3)
    tool.opts.scale_max.setValue(0.3)
    drag(canvas.viewport(), LEFT, _xy(cell_pos(canvas, 5, 5)), _xy(cell_pos(canvas, 40, 30)))
    scatter = window.history.actions[-1]
    assert isinstance(scatter, ScatterSpots) and scatter.count == 12
    assert (scatter.top, scatter.left, scatter.height, scatter.width) == (5, 5, 26, 36)
    scattered = window.document.levels.copy()

    tool.opts.mode.setCurrentIndex(tool.opts.mode.findData("delete"))
    centre = scatter.spots(window.document.shape)[-1].placement.centre
    y, x = (int(round(v)) for v in centre)
    move(canvas.viewport(), cell_pos(canvas, x, y))
    assert tool.ghost.isVisible()                       # the doomed spot is outlined
    click(canvas.viewport(), cell_pos(canvas, x, y))
    deletion = window.history.actions[-1]
    assert isinstance(deletion, DeleteSpot) and deletion.spot == 11
    assert not np.array_equal(window.document.levels, scattered)
    QtTest.QTest.keyClick(window, QtCore.Qt.Key.Key_Z, QtCore.Qt.KeyboardModifier.ControlModifier)
    assert np.array_equal(window.document.levels, scattered)


def test_outline_kinds_placed_in_turn_then_a_refused_bezier_and_undo(window, qtbot):
    tool = spot_tool(window)
    editor, canvas = tool.editor, window.canvas
    editor.load(editor.library.get("Ellipse"))           # four points: a, b, two meridian ends
    start, steps = window.document.levels.copy(), window.history.index
    area = {}
    tool.opts.scale_box.setValue(0.5)                      # 20 × 12 points
    for kind, row in (("catmull_rom", 8), ("uniform_bspline", 24), ("bezier_curve", 40)):
        editor.kind.setCurrentIndex(editor.kind.findData(kind))
        click(canvas.viewport(), cell_pos(canvas, 30, row))     # apart: each spot is a step
        action = window.history.actions[-1]
        assert isinstance(action, PlaceSpot) and action.envelope_model().kind == kind
        assert window.document.levels[row, 30] == window.current_level
        area[kind] = tool_stamp(action, window).area
    # through the points, then following them: a B-spline, then a Bézier curve, keep inside
    assert area["bezier_curve"] < area["uniform_bspline"] < area["catmull_rom"]

    ring = [(30 * math.sin(a), 30 * math.cos(a)) for a in np.linspace(0, 2 * math.pi, 200,
                                                                        endpoint=False)]
    editor.kind.setCurrentIndex(editor.kind.findData("uniform_bspline"))
    editor.view.set_envelope(Envelope.from_contour(ring, "uniform_bspline"))   # 200 points
    editor.kind.setCurrentIndex(editor.kind.findData("bezier_curve"))
    assert editor.envelope.kind == "uniform_bspline"                 # refused, and said why
    assert editor.kind.currentData() == "uniform_bspline" and "B-spline" in editor.view.problem

    for _ in range(3):
        QtTest.QTest.keyClick(window, QtCore.Qt.Key.Key_Z,
                              QtCore.Qt.KeyboardModifier.ControlModifier)
    assert window.history.index == steps and np.array_equal(window.document.levels, start)


def test_scatter_over_the_whole_canvas_with_a_level_range(window, qtbot):
    tool = spot_tool(window)
    tool.opts.mode.setCurrentIndex(tool.opts.mode.findData("scatter"))
    tool.opts.level_max.setValue(3)
    tool.opts.count.setValue(150)                       # many: rasterised in the worker
    tool.opts.scale_box.setValue(0.2)
    tool.opts.scale_max.setValue(0.2)
    window.palette_dock.swatches.current = 1
    steps = window.history.index
    tool.opts.whole.click()
    assert window.runner.wait(30_000)
    action = window.history.actions[-1]
    assert isinstance(action, ScatterSpots) and action.top is None and action.count == 150
    assert (action.level, action.level_max) == (1, 3) and window.history.index == steps + 1


def test_the_library_saves_and_loads_spots(window, qtbot, monkeypatch, tmp_path):
    editor = spot_tool(window).editor
    draw_ellipse_envelope(editor)
    monkeypatch.setattr(QtWidgets.QInputDialog, "getText",
                        lambda *a, **k: ("round stone", True))
    editor.save_button.click()
    assert (tmp_path / "data" / "spots.json").exists()
    names = [editor.spot_list.item(i).text() for i in range(editor.spot_list.count())]
    assert names[-1] == "round stone"
    saved = editor.envelope
    leaf = editor.spot_list.findItems("Leaf", QtCore.Qt.MatchFlag.MatchExactly)[0]
    editor.spot_list.itemClicked.emit(leaf)
    assert editor.envelope.kind == "linear" and editor.envelope != saved
    mine = editor.spot_list.findItems("round stone", QtCore.Qt.MatchFlag.MatchExactly)[0]
    editor.spot_list.itemClicked.emit(mine)
    assert editor.envelope == saved


def test_leaving_the_tool_hides_its_editor_and_ghost(window, qtbot):
    tool = spot_tool(window)
    press_key(window, QtCore.Qt.Key.Key_H)
    assert not tool.dock.isVisible() and tool.ghost is None


def _xy(point):
    return (point.x(), point.y())


def test_a_past_placement_is_edited_in_the_history_dock(window, qtbot):
    tool = spot_tool(window)
    canvas = window.canvas
    click(canvas.viewport(), cell_pos(canvas, 20, 20))
    click(canvas.viewport(), cell_pos(canvas, 40, 25))
    step = window.history.index - 2                     # the first placement (0-based)
    dock = window.history_dock
    dock.view.clicked.emit(dock.model.index(step))
    assert "envelope" not in dock.form.editors          # JSON is not edited as one line...
    shown = [dock.form.form.itemAt(r, QtWidgets.QFormLayout.ItemRole.FieldRole).widget().text()
             for r in range(dock.form.form.rowCount())
             if isinstance(dock.form.form.itemAt(r, QtWidgets.QFormLayout.ItemRole.FieldRole)
                           .widget(), QtWidgets.QLabel)]
    assert any(t.endswith("characters (set by its tool)") for t in shown)   # ...but its size
    dock.form.editor("scale").setValue(0.4)
    dock.apply_button.click()
    assert window.runner.wait(30_000)
    edited = window.history.actions[step]
    assert isinstance(edited, PlaceSpot) and edited.scale == 0.4
    assert isinstance(window.history.actions[step + 1], PlaceSpot)
    assert window.history.index == len(window.history.actions)
    assert not window.errors and tool is window.tool
