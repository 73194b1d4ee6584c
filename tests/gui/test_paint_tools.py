"""The painting tools with real mouse and key events: Brush, Spray, Grain, the zone tools, the
brush presets, the grain editor and the Peano dialog — asserting on the document."""

import json

import numpy as np
import pytest
from PySide6 import QtCore, QtGui, QtTest, QtWidgets

from app.tools.brush import BrushTool, SprayTool
from app.tools.grain import GrainTool
from app.tools.zone import ScrambleTool, ZoneTool
from texeditor.paint.actions import (DuplicateZone, PeanoLevels, PlaceGrains, ScrambleFrontier,
                                     Stroke)

from .support import cell_pos, click, press_key

LEFT = QtCore.Qt.MouseButton.LeftButton
NONE = QtCore.Qt.MouseButton.NoButton
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier
NO_MOD = QtCore.Qt.KeyboardModifier.NoModifier


@pytest.fixture(autouse=True)
def user_data(tmp_path, monkeypatch):
    """Grain and brush libraries in a temporary folder, never the user's own."""
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path / "data"))
    return tmp_path / "data"


def send(widget, kind, pos, button, buttons, modifiers=NO_MOD):
    ev = QtGui.QMouseEvent(kind, QtCore.QPointF(pos), QtCore.QPointF(widget.mapToGlobal(pos)),
                           button, buttons, modifiers)
    QtWidgets.QApplication.sendEvent(widget, ev)


def press(canvas, cell, modifiers=NO_MOD):
    QtTest.QTest.qWait(30)            # let a tool change settle the layout (and the view)
    send(canvas.viewport(), QtCore.QEvent.Type.MouseButtonPress, cell_pos(canvas, *cell), LEFT,
         LEFT, modifiers)


def move_to(canvas, cell, modifiers=NO_MOD):
    QtTest.QTest.qWait(15)            # pyqtgraph drops moves faster than 100 per second
    send(canvas.viewport(), QtCore.QEvent.Type.MouseMove, cell_pos(canvas, *cell), NONE, LEFT,
         modifiers)


def release(canvas, cell, modifiers=NO_MOD):
    send(canvas.viewport(), QtCore.QEvent.Type.MouseButtonRelease, cell_pos(canvas, *cell),
         LEFT, NONE, modifiers)


def stroke(canvas, cells, modifiers=NO_MOD):
    """A drag through the given cells (x, y) with the left button, as a hand would do it."""
    press(canvas, cells[0], modifiers)
    for cell in cells[1:]:
        move_to(canvas, cell, modifiers)
    release(canvas, cells[-1], modifiers)


def tool(window, kind):
    return next(t for t in window.tools if type(t) is kind)


def last(window):
    return window.history.actions[window.history.index - 1]


# -- Brush and Spray -------------------------------------------------------------------------------

def test_b_selects_the_brush_and_a_drag_paints_one_stroke(window, qtbot):
    press_key(window, QtCore.Qt.Key.Key_B)
    brush = window.tool
    assert isinstance(brush, BrushTool) and window.tool_dock.title.text().startswith("Brush")
    before, steps = window.document.levels.copy(), window.history.index
    window.palette_dock.swatches.current = 3
    stroke(window.canvas, [(4, 20), (20, 20), (44, 21), (58, 20)])     # fast: far apart events
    assert window.history.index == steps + 1
    action = last(window)
    assert isinstance(action, Stroke) and action.level == 3 and action.size == 3
    levels = window.document.levels
    assert (levels[20, 5:58] == 3).all()                   # no gaps between the events
    changed = np.argwhere(levels != before)
    assert changed[:, 0].min() >= 18 and changed[:, 0].max() <= 22
    window.undo()
    assert (window.document.levels == before).all()


def test_the_stroke_shows_in_the_preview_and_reaches_the_document_on_release(window, qtbot):
    window.set_tool(tool(window, BrushTool))
    canvas, before = window.canvas, window.document.levels.copy()
    window.palette_dock.swatches.current = 2
    press(canvas, (10, 10))
    for x in (14, 20, 30):
        move_to(canvas, (x, 12))
    preview = canvas.stroke_preview
    assert preview.isVisible() and (preview.snapshot()[11:14, 10:30] != 0).any()
    assert (window.document.levels == before).all()          # nothing written yet
    release(canvas, (30, 12))
    assert not preview.snapshot().any() and not preview.tiles
    assert (window.document.levels[11:13, 12:30] == 2).all()


def test_brackets_change_the_size_and_the_spray_paints_a_cloud(window, qtbot):
    press_key(window, QtCore.Qt.Key.Key_A)
    spray = window.tool
    assert isinstance(spray, SprayTool) and spray.brush.size == 16
    press_key(window, QtCore.Qt.Key.Key_BracketLeft)
    press_key(window, QtCore.Qt.Key.Key_BracketLeft)
    assert spray.brush.size == 13                        # 16 - 2 - 1: steps of about 10 %
    press_key(window, QtCore.Qt.Key.Key_BracketRight)
    assert spray.brush.size == 14
    spray.opts.density.setValue(25)
    spray.opts.random.setChecked(True)
    spray.opts.choices.setText("2, 3")
    canvas = window.canvas
    window.submit(PeanoLevels(cell=64, expression="1", low=0, high=0))     # a blank canvas
    stroke(canvas, [(8, 24), (20, 24), (32, 24), (44, 24), (56, 24)])
    action = last(window)
    assert action.distribution == "cloud" and action.density == 0.25 and action.size == 14
    band = window.document.levels[19:30, 10:54]
    painted = band > 0
    assert set(np.unique(band[painted]).tolist()) == {2, 3}
    assert 0.3 < painted.mean() < 0.95                     # a cloud, not a solid band
    assert (window.document.levels[:15] == 0).all() and (window.document.levels[34:] == 0).all()


def test_a_stroke_across_the_seam_of_the_tiled_view_wraps(window, qtbot):
    window.set_tool(tool(window, BrushTool))
    window.submit(PeanoLevels(cell=64, expression="1", low=0, high=0))
    press_key(window, QtCore.Qt.Key.Key_W)
    assert window.canvas.tiled
    window.palette_dock.swatches.current = 1
    stroke(window.canvas, [(58, 10), (62, 10), (66, 10), (70, 10)])    # the seam is at x = 64
    row = window.document.levels[10]
    assert row[58:].all() and row[:6].all() and not row[12:52].any()
    assert last(window).wrap


def test_choosing_a_preset_in_the_brush_dock_loads_its_tool(window, qtbot):
    dock = window.brush_dock
    names = [b.name for b in dock.brushes]
    view = dock.list
    dock.show()
    dock.raise_()
    qtbot.waitExposed(view)
    item = view.item(names.index("Diamond 9"))
    view.scrollToItem(item)
    QtTest.QTest.mouseClick(view.viewport(), LEFT, NO_MOD, view.visualItemRect(item).center())
    assert isinstance(window.tool, BrushTool) and window.tool.brush.shape == "diamond"
    assert window.tool.brush.size == 9
    item = view.item(names.index("Spray 16"))
    view.scrollToItem(item)
    QtTest.QTest.mouseClick(view.viewport(), LEFT, NO_MOD, view.visualItemRect(item).center())
    assert isinstance(window.tool, SprayTool)


def test_saving_a_preset_keeps_it_in_the_user_folder(window, qtbot, user_data):
    window.set_tool(tool(window, SprayTool))
    window.tool.opts.size_box.setValue(40)
    window.brush_dock.save_current("Wide spray")
    data = json.loads((user_data / "brushes.json").read_text())
    assert [b["name"] for b in data["items"]] == ["Wide spray"] and data["items"][0]["size"] == 40
    assert window.brush_dock.brushes[-1].name == "Wide spray"


# -- Grain -----------------------------------------------------------------------------------------

def pick_grain(window, name):
    """Click a grain in the Grain stamps dock: it becomes the Grain tool's grain."""
    dock = window.grain_dock
    dock.show()
    dock.raise_()
    view = dock.list
    QtTest.QTest.qWait(20)
    item = view.item([g.name for g in tool(window, GrainTool).grains].index(name))
    view.scrollToItem(item)
    QtTest.QTest.mouseClick(view.viewport(), LEFT, NO_MOD, view.visualItemRect(item).center())
    assert isinstance(window.tool, GrainTool) and window.tool.grain.name == name


@pytest.mark.parametrize("name, box", [("Square 3", (1, 1, 2, 2)), ("Square 5", (2, 2, 3, 3)),
                                       ("Rectangle 6×3", (1, 3, 2, 3))])
def test_a_click_places_a_grain_centred_at_the_pointer(window, qtbot, name, box):
    press_key(window, QtCore.Qt.Key.Key_G)
    assert isinstance(window.tool, GrainTool)
    pick_grain(window, name)
    window.submit(PeanoLevels(cell=64, expression="1", low=0, high=0))
    window.palette_dock.swatches.current = 2
    click(window.canvas.viewport(), cell_pos(window.canvas, 30, 20))
    action = last(window)
    assert isinstance(action, PlaceGrains) and action.points == ((20, 30),)
    up, left, down, right = box
    levels = window.document.levels
    assert (levels[20 - up:20 + down, 30 - left:30 + right] == 2).all()
    assert levels.astype(bool).sum() == (up + down) * (left + right)


def test_hovering_shows_the_grain_where_a_click_would_put_it(window, qtbot):
    window.set_tool(tool(window, GrainTool))
    from .support import move
    move(window.canvas.viewport(), cell_pos(window.canvas, 12, 9))
    overlay = window.canvas.overlay
    assert overlay.isVisible()
    rect = overlay.mapRectToView(overlay.boundingRect())
    assert rect.center().x() == pytest.approx(12.5, abs=0.6)
    assert rect.center().y() == pytest.approx(9.5, abs=0.6)


def test_shift_drag_places_grains_along_the_path(window, qtbot):
    window.set_tool(tool(window, GrainTool))
    grains = window.tool
    pick_grain(window, "Point")
    grains.opts.spacing.setValue(10)
    grains.opts.jitter.setValue(0)
    window.submit(PeanoLevels(cell=64, expression="1", low=0, high=0))
    steps = window.history.index
    stroke(window.canvas, [(5, 30), (25, 30), (50, 30)], SHIFT)
    assert window.history.index == steps + 1
    action = last(window)
    assert action.spacing == 10 and action.jitter == 0
    assert sorted(map(tuple, np.argwhere(window.document.levels))) == \
        [(30, 5), (30, 15), (30, 25), (30, 35), (30, 45)]


def test_a_plain_drag_places_one_grain_where_it_is_released(window, qtbot):
    window.set_tool(tool(window, GrainTool))
    pick_grain(window, "Point")
    window.submit(PeanoLevels(cell=64, expression="1", low=0, high=0))
    stroke(window.canvas, [(5, 5), (15, 12), (22, 17)])
    assert sorted(map(tuple, np.argwhere(window.document.levels))) == [(17, 22)]


def test_the_grain_editor_draws_saves_and_uses_a_grain(window, qtbot, user_data):
    window.set_tool(tool(window, GrainTool))
    grains = window.tool
    grains.options()
    QtTest.QTest.mouseClick(window.grain_dock.edit_button, LEFT)
    editor = grains.editor
    qtbot.waitExposed(editor)
    editor.shape_box.setCurrentIndex(editor.shape_box.findData("bitmap"))
    editor.clear_drawing()
    view = editor.view
    editor.pen_level.setValue(3)
    n = view.grain_mask.shape[0]
    for r, c in [(1, 1), (1, 2), (2, 2), (3, 3)]:            # a little zigzag, with the mouse
        cell, x0, y0 = view._geometry()
        pos = QtCore.QPoint(int(x0 + (c + 0.5) * cell), int(y0 + (r + 0.5) * cell))
        QtTest.QTest.mouseClick(view, LEFT, NO_MOD, pos)
    assert n >= 4 and view.levels.astype(bool).sum() == 4
    editor.name.setText("Zigzag")
    editor.level_mode.setCurrentIndex(editor.level_mode.findData("own"))
    QtTest.QTest.mouseClick(editor.save_button, LEFT)
    saved = json.loads((user_data / "grains.json").read_text())["items"]
    assert saved[0]["name"] == "Zigzag" and saved[0]["bitmap"] == "330/030/003"
    assert grains.grain.name == "Zigzag" and "Zigzag" in [g.name for g in grains.grains]
    editor.close()
    window.submit(PeanoLevels(cell=64, expression="1", low=0, high=0))
    click(window.canvas.viewport(), cell_pos(window.canvas, 20, 20))
    levels = window.document.levels
    assert sorted(map(tuple, np.argwhere(levels))) == [(19, 19), (19, 20), (20, 20), (21, 21)]
    assert set(levels[levels > 0].tolist()) == {3}


def test_the_grains_menu_lists_the_library_and_selects_a_grain(window, qtbot):
    menu = window.menu("GrainStampsMenu")
    menu.aboutToShow.emit()
    entry = next(a for a in menu.actions() if a.text() == "Hexagon 8")
    entry.trigger()
    assert isinstance(window.tool, GrainTool) and window.tool.grain.shape == "hexagon"


# -- zones -----------------------------------------------------------------------------------------

def test_duplicate_a_zone_then_scramble_its_frontier(window, qtbot):
    press_key(window, QtCore.Qt.Key.Key_D)
    zone_tool = window.tool
    assert isinstance(zone_tool, ZoneTool)
    canvas = window.canvas
    stroke(canvas, [(2, 3), (6, 6), (11, 10)])                  # draw a rectangle
    assert zone_tool.zone.points == ((3, 2), (10, 11))
    source = window.document.levels[3:11, 2:12].copy()
    stroke(canvas, [(5, 5), (20, 15), (35, 25)])                # drag it: a copy
    action = last(window)
    assert isinstance(action, DuplicateZone) and (action.offset_row, action.offset_col) == (20, 30)
    assert (window.document.levels[23:31, 32:42] == source).all()
    assert zone_tool.zone.points == ((23, 32), (30, 41))        # the copy is now the zone

    window.set_tool(tool(window, ScrambleTool))
    scramble = window.tool
    scramble.opts.band.setValue(2)
    scramble.opts.density.setValue(60)
    copied = window.document.levels.copy()
    click(canvas.viewport(), cell_pos(canvas, 36, 27))
    action = last(window)
    assert isinstance(action, ScrambleFrontier) and action.points == ((23, 32), (30, 41))
    changed = window.document.levels != copied
    assert changed.any() and not (changed & ~action.band_mask(copied.shape)).any()


def test_shift_d_is_the_scramble_tool(window, qtbot):
    QtTest.QTest.keyClick(window, QtCore.Qt.Key.Key_D, QtCore.Qt.KeyboardModifier.ShiftModifier)
    assert isinstance(window.tool, ScrambleTool)


def test_a_lasso_zone_follows_the_pointer(window, qtbot):
    window.set_tool(tool(window, ZoneTool))
    zone_tool = window.tool
    zone_tool.opts.kind.setCurrentIndex(zone_tool.opts.kind.findData("lasso"))
    stroke(window.canvas, [(5, 5), (20, 5), (20, 20), (5, 20)])
    assert zone_tool.zone.kind == "lasso" and len(zone_tool.zone.points) == 4
    mask = zone_tool.zone_mask()
    assert mask[10, 10] and not mask[30, 30]


# -- Peano sub-regions -----------------------------------------------------------------------------

def test_the_peano_dialog_points_at_errors_and_applies_levels(window, qtbot):
    dialog = window.open_peano()
    qtbot.waitExposed(dialog)
    dialog.cell.setValue(8)
    edit = dialog.expression
    edit.selectAll()
    QtTest.QTest.keyClicks(edit, "3(1,2")
    assert not dialog.apply_button.isEnabled()
    assert dialog.error.text().splitlines() == ["3(1,2", " " * 5 + "^"]
    assert "never closed" in dialog.problem.text()
    QtTest.QTest.keyClicks(edit, ")")
    assert dialog.error.text() == dialog.problem.text() == "" and dialog.apply_button.isEnabled()
    root = dialog.tree.topLevelItem(0)
    assert root.text(0) == "3" and root.childCount() == 2
    assert root.text(1) == str(window.document.num_levels - 1)
    QtTest.QTest.mouseClick(dialog.apply_button, LEFT)
    action = last(window)
    assert isinstance(action, PeanoLevels) and action.expression == "3(1,2)"
    levels = window.document.levels
    top = window.document.num_levels - 1
    # an 8×6 grid of 8-point cells: the scan starts (0,0), (0,1)... as the dialog draws it
    order = dialog.view.order
    for index, level in {1: 1, 2: 1, 3: top}.items():
        r, c = order[index - 1]
        assert (levels[r * 8:r * 8 + 8, c * 8:c * 8 + 8] == level).all()
    assert dialog.view.total == 48 and len(order) == 48


def test_the_peano_menu_entry_opens_the_dialog(window, qtbot):
    window.act_peano.trigger()
    assert window.peano_dialog.isVisible()
    window.peano_dialog.close()


def test_brackets_resize_the_grain_without_growing_the_library(window, qtbot):
    window.set_tool(tool(window, GrainTool))
    pick_grain(window, "Circle 5")
    count = window.grain_dock.list.count()
    press_key(window, QtCore.Qt.Key.Key_BracketRight)
    press_key(window, QtCore.Qt.Key.Key_BracketRight)
    assert window.tool.grain.size == 7 and window.tool.grain.shape == "circle"
    assert window.grain_dock.list.count() == count
    click(window.canvas.viewport(), cell_pos(window.canvas, 30, 20))
    assert last(window).size == 7


def test_the_preview_keeps_tiles_only_where_the_stroke_goes(qtbot):
    from app.tools.brush import StrokePreview
    preview = StrokePreview((600, 1000))
    rows = np.array([0, 255, 256, 599, 300])
    cols = np.array([0, 999, 256, 5, 700])
    preview.draw(rows, cols, np.arange(1, 6, dtype=np.uint32) | 0xFF000000)
    assert sorted(preview.tiles) == [(0, 0), (0, 3), (1, 1), (1, 2), (2, 0)]
    snap = preview.snapshot()
    assert snap.shape == (600, 1000) and (snap[rows, cols] & 0xFF).tolist() == [1, 2, 3, 4, 5]
    assert np.count_nonzero(snap) == 5
    preview.clear()
    assert not preview.tiles and not preview.snapshot().any()
