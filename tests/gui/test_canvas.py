"""The canvas alone: palette display, wheel zoom around the cursor, pan, grid and tiled preview."""

import numpy as np
from PySide6 import QtCore

from app.canvas import GRID_MIN_ZOOM, CanvasView

from .events import drag, wheel


def make_canvas(qtbot, shape=(40, 60)):
    canvas = CanvasView()
    qtbot.addWidget(canvas)
    canvas.resize(600, 400)
    canvas.show()
    qtbot.waitExposed(canvas)
    levels = (np.arange(shape[0] * shape[1]) % 4).reshape(shape).astype(np.uint8)
    palette = np.array([[0, 0, 0], [255, 0, 0], [0, 255, 0], [0, 0, 255]], np.uint8)
    canvas.set_image(levels, palette)
    return canvas, levels


def test_shows_levels_through_palette(qtbot):
    canvas, levels = make_canvas(qtbot)
    assert canvas.displayed_colour(1, 0) == (255, 0, 0)
    canvas.set_palette(np.array([[9, 9, 9]] * 4, np.uint8))
    assert canvas.displayed_colour(1, 0) == (9, 9, 9)


def test_wheel_zooms_around_cursor(qtbot):
    canvas, _ = make_canvas(qtbot)
    before = canvas.zoom()
    pos = QtCore.QPoint(200, 150)
    cell_before = canvas.view.mapSceneToView(canvas.mapToScene(pos))
    wheel(canvas.viewport(), pos, 3)
    assert canvas.zoom() > before * 1.5
    cell_after = canvas.view.mapSceneToView(canvas.mapToScene(pos))
    assert abs(cell_after.x() - cell_before.x()) < 0.5 and abs(cell_after.y() - cell_before.y()) < 0.5
    wheel(canvas.viewport(), pos, -3)
    assert abs(canvas.zoom() - before) / before < 0.01


def test_middle_drag_pans_and_left_drag_does_not(qtbot):
    canvas, _ = make_canvas(qtbot)
    canvas.set_zoom(20)
    start = canvas.view.viewRect().center()
    drag(canvas.viewport(), QtCore.Qt.MouseButton.LeftButton, (300, 200), (200, 200))
    assert canvas.view.viewRect().center() == start
    drag(canvas.viewport(), QtCore.Qt.MouseButton.MiddleButton, (300, 200), (200, 200))
    moved = canvas.view.viewRect().center() - start
    assert moved.x() > 3  # dragged left by 100 px = 5 cells at 20 px/cell: the view moves right


def test_space_drag_pans(qtbot):
    canvas, _ = make_canvas(qtbot)
    canvas.set_zoom(20)
    canvas.setFocus()
    start = canvas.view.viewRect().center()
    qtbot.keyPress(canvas, QtCore.Qt.Key.Key_Space)
    drag(canvas.viewport(), QtCore.Qt.MouseButton.LeftButton, (300, 200), (300, 100))
    qtbot.keyRelease(canvas, QtCore.Qt.Key.Key_Space)
    assert canvas.view.viewRect().center().y() - start.y() > 3
    assert not canvas.view.pan_key_held


def test_tiled_preview_and_grid(qtbot):
    canvas, _ = make_canvas(qtbot)
    canvas.set_tiled(True)
    assert canvas.echo.isVisible()
    rect = canvas.view.viewRect()
    assert rect.width() >= 3 * 60 and rect.height() >= 3 * 40 * 0.99
    # a cell of the left neighbour tile folds back into the texture
    scene = canvas.view.mapViewToScene(QtCore.QPointF(-59.5, 0.5))
    assert canvas.cell_at(scene) == (0, 0)
    canvas.set_tiled(False)
    assert not canvas.echo.isVisible()
    canvas.set_zoom(GRID_MIN_ZOOM * 2)
    assert canvas.zoom() > GRID_MIN_ZOOM


def test_hover_reports_cell_and_level(qtbot):
    canvas, levels = make_canvas(qtbot)
    seen = []
    canvas.hovered.connect(seen.append)
    scene = canvas.view.mapViewToScene(QtCore.QPointF(5.5, 2.5))
    pos = canvas.mapFromScene(scene)
    qtbot.mouseMove(canvas.viewport(), pos)
    qtbot.wait(20)
    assert seen and seen[-1] == (5, 2, int(levels[2, 5]))
