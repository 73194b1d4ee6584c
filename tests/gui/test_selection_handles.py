"""The Extract tool's transform handles, driven by real mouse events on the canvas: corner drags
scale, the knob and the band around the box rotate, the inside moves, Esc cancels."""

import math

import numpy as np
import pytest
from PySide6 import QtCore, QtGui, QtTest, QtWidgets

from app.tools.handles import Change, scale_factor, turn_angle
from app.tools.regions import GHOST_REST_MS, ExtractTool, ghost_overlay
from texeditor.regions import actions as ra
from texeditor.regions import extractext as regions
from texeditor.recipe.actions import NewCanvas, SetLevels

from .support import cell_pos, click, move, press_key

LEFT = QtCore.Qt.MouseButton.LeftButton
NONE = QtCore.Qt.MouseButton.NoButton
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier
NO_MODIFIER = QtCore.Qt.KeyboardModifier.NoModifier
Type = QtCore.QEvent.Type
Shape = QtCore.Qt.CursorShape


@pytest.fixture
def board(window):
    """A 40×30 canvas, G = 4: a 4×4 square of level 2 at x, y 8..11 and an L of level 3 (a bar
    at x 24..25, y 16..21 and a foot at x 26..28, y 20..21); the Extract tool is current."""
    window.submit(NewCanvas(40, 30, 4))
    window.submit(SetLevels(8, 8, 4, 4, 2))
    window.submit(SetLevels(16, 24, 6, 2, 3))
    window.submit(SetLevels(20, 26, 2, 3, 3))
    window.canvas.fit()
    press_key(window, QtCore.Qt.Key.Key_E)
    assert isinstance(window.tool, ExtractTool)
    QtTest.QTest.qWait(100)    # the tool dock's new options resize (and refit) the canvas
    return window


def at(canvas, p: QtCore.QPointF) -> QtCore.QPoint:
    """The canvas widget position of a point in cell coordinates."""
    return canvas.mapFromScene(canvas.view.mapViewToScene(p))


def send(canvas, kind, pos, button, buttons, modifiers=NO_MODIFIER) -> None:
    widget = canvas.viewport()
    ev = QtGui.QMouseEvent(kind, QtCore.QPointF(pos), QtCore.QPointF(widget.mapToGlobal(pos)),
                           button, buttons, modifiers)
    QtWidgets.QApplication.sendEvent(widget, ev)


def press_and_move(canvas, path, modifiers=NO_MODIFIER) -> None:
    """Press at the first point (cell coordinates) and move through the others, button held."""
    send(canvas, Type.MouseButtonPress, at(canvas, path[0]), LEFT, LEFT, modifiers)
    for p in path[1:]:
        QtTest.QTest.qWait(25)         # pyqtgraph drops moves faster than its rate limit
        send(canvas, Type.MouseMove, at(canvas, p), NONE, LEFT, modifiers)


def release(canvas, p, modifiers=NO_MODIFIER) -> None:
    send(canvas, Type.MouseButtonRelease, at(canvas, p), LEFT, NONE, modifiers)


def line(a: QtCore.QPointF, b: QtCore.QPointF, steps: int = 5) -> list[QtCore.QPointF]:
    return [a + (b - a) * (k / steps) for k in range(steps + 1)]


def arc(centre, start, degrees: float, steps: int = 6) -> list[QtCore.QPointF]:
    """Points turning ``start`` about ``centre`` counter-clockwise on screen (y down)."""
    d = start - centre
    out = []
    for k in range(steps + 1):
        t = math.radians(degrees * k / steps)
        out.append(centre + QtCore.QPointF(d.x() * math.cos(t) + d.y() * math.sin(t),
                                           -d.x() * math.sin(t) + d.y() * math.cos(t)))
    return out


def select(board, x, y):
    click(board.canvas.viewport(), cell_pos(board.canvas, x, y))
    frame = board.tool.frame
    assert frame.isVisible()
    return frame


def test_corner_drag_to_twice_the_distance_scales_the_square_by_two(board):
    frame = select(board, 9, 9)
    assert frame.box == QtCore.QRectF(8, 8, 4, 4)
    before, steps = board.document.levels.copy(), board.history.index
    centre, corner = frame.box.center(), frame.corners()[2]
    press_and_move(board.canvas, line(corner, centre + (corner - centre) * 2))
    assert board.history.index == steps                   # nothing applied before the release
    ghost = board.canvas.overlay                          # while moving: Qt carries the picture
    shown = ghost.mapRectToParent(ghost.boundingRect())
    assert ghost.isVisible() and ghost.image.shape[:2] == (4, 4) and shown.width() >= 7
    assert abs(shown.center().x() - centre.x()) < 0.5    # scaled about the box's centre
    QtTest.QTest.qWait(GHOST_REST_MS + 150)               # at rest: the engine's exact result
    carried = np.where(board.tool._mask, before + 1, 0).astype(np.uint8)
    rgba, origin = ghost_overlay(board.tool._carry(board.tool._latest, carried),
                                 board.document.palette)
    assert ghost.image.shape[0] >= 7 and np.array_equal(ghost.image, rgba)
    assert ghost.mapRectToParent(ghost.boundingRect()).topLeft() == QtCore.QPointF(*origin)
    assert np.array_equal(board.document.levels, before)  # the ghost has grown, not the doc
    release(board.canvas, centre + (corner - centre) * 2)
    assert board.history.index == steps + 1               # one Action
    action = board.history.applied[-1]
    assert isinstance(action, ra.ScaleSelection) and abs(action.factor - 2) <= 0.05
    expected = regions.scale(before, before == 2, action.factor)
    assert np.array_equal(board.document.levels, expected)
    assert 3 * 16 < np.count_nonzero(expected == 2) <= 5 * 16
    assert board.tool.panel.factor.value() == action.factor   # the panel shows what was used
    assert frame.box.width() >= 7                         # the handles follow the new region
    board.undo()
    assert np.array_equal(board.document.levels, before)


def test_drag_inside_the_box_translates_the_selection_exactly(board):
    frame = select(board, 9, 9)
    before = board.document.levels.copy()
    start = QtCore.QPointF(9.5, 9.5)
    press_and_move(board.canvas, line(start, start + QtCore.QPointF(5, 3)))
    release(board.canvas, start + QtCore.QPointF(5, 3))
    action = board.history.applied[-1]
    assert isinstance(action, ra.Translate)
    assert (action.to_row - action.row, action.to_col - action.col) == (3, 5)
    levels = board.document.levels
    assert (levels[11:15, 13:17] == 2).all() and np.count_nonzero(levels == 2) == 16
    assert np.array_equal(levels == 3, before == 3)
    assert frame.box == QtCore.QRectF(13, 11, 4, 4)       # the selection moved with it
    assert (board.tool.selection["row"], board.tool.selection["col"]) == (12, 14)
    board.undo()
    assert np.array_equal(board.document.levels, before)


def test_knob_drag_with_shift_turns_the_l_as_rotate_selection_does(board):
    frame = select(board, 24, 16)
    assert frame.box == QtCore.QRectF(24, 16, 5, 6)
    engine = board.document.copy().apply(ra.RotateSelection(16, 24, 90))
    before = board.document.levels.copy()
    knob = frame.knob()[1]
    path = arc(frame.box.center(), knob, 88)               # a hand stops short: Shift snaps
    press_and_move(board.canvas, path, SHIFT)
    release(board.canvas, path[-1], SHIFT)
    action = board.history.applied[-1]
    assert isinstance(action, ra.RotateSelection) and action.angle == 90
    assert np.array_equal(board.document.levels, engine.levels)
    assert not np.array_equal(engine.levels, before)
    assert board.tool.panel.angle.value() == 90


def test_drag_in_the_band_outside_the_box_rotates_freely(board):
    frame = select(board, 24, 16)
    before = board.document.levels.copy()
    centre = frame.box.center()
    outside = QtCore.QPointF(frame.box.right() + 10 * frame.px(), centre.y())
    assert frame.zone_at(outside)[0] == "rotate"
    path = arc(centre, outside, 40)
    press_and_move(board.canvas, path)
    release(board.canvas, path[-1])
    action = board.history.applied[-1]
    assert isinstance(action, ra.RotateSelection) and abs(action.angle - 40) < 3
    assert np.array_equal(board.document.levels, regions.rotate(before, before == 3,
                                                                action.angle))


def test_escape_during_a_drag_cancels_it(board):
    frame = select(board, 9, 9)
    before, steps = board.document.levels.copy(), board.history.index
    centre, corner = frame.box.center(), frame.corners()[2]
    target = centre + (corner - centre) * 3
    press_and_move(board.canvas, line(corner, target, 3))
    assert frame.preview != QtGui.QTransform()            # the box follows the drag
    QtTest.QTest.keyClick(board.canvas, QtCore.Qt.Key.Key_Escape)
    press_and_move(board.canvas, [target + QtCore.QPointF(2, 2)])
    release(board.canvas, target + QtCore.QPointF(2, 2))
    assert board.history.index == steps
    assert np.array_equal(board.document.levels, before)
    assert frame.preview == QtGui.QTransform() and frame.box == QtCore.QRectF(8, 8, 4, 4)
    assert board.canvas.overlay.image.shape[:2] == (4, 4)  # the selection again, no ghost


def test_space_drag_over_the_box_pans_instead_of_moving(board):
    frame = select(board, 9, 9)
    steps, view = board.history.index, board.canvas.view.viewRect()
    start = QtCore.QPointF(9.5, 9.5)
    QtTest.QTest.keyPress(board.canvas, QtCore.Qt.Key.Key_Space)
    press_and_move(board.canvas, line(start, start + QtCore.QPointF(5, 3)))
    release(board.canvas, start + QtCore.QPointF(5, 3))
    QtTest.QTest.keyRelease(board.canvas, QtCore.Qt.Key.Key_Space)
    assert board.history.index == steps and frame.box == QtCore.QRectF(8, 8, 4, 4)
    assert board.canvas.view.viewRect() != view


def test_cursor_says_what_a_drag_does_and_handles_keep_their_size_on_screen(board):
    frame = select(board, 9, 9)
    canvas = board.canvas
    viewport = canvas.viewport()

    def cursor_at(p):
        QtTest.QTest.qWait(25)
        move(viewport, p)
        return viewport.cursor().shape()

    for zoom in (canvas.zoom(), 40.0):
        canvas.set_zoom(zoom, center=frame.box.center())
        QtTest.QTest.qWait(25)
        corner = at(canvas, frame.corners()[0])
        assert cursor_at(corner + QtCore.QPoint(4, 4)) == Shape.SizeFDiagCursor
        assert cursor_at(at(canvas, frame.corners()[1]) + QtCore.QPoint(-4, 4)) == \
            Shape.SizeBDiagCursor
        assert cursor_at(corner + QtCore.QPoint(14, 14)) == Shape.SizeAllCursor
        assert cursor_at(at(canvas, frame.knob()[1])) == Shape.BitmapCursor   # rotate
        knob_gap = at(canvas, frame.knob()[1]).y() - at(canvas, frame.knob()[0]).y()
        assert abs(knob_gap + 24) <= 1                    # 24 screen pixels at any zoom
    # a click (no drag) in the box still selects anew
    canvas.fit()
    QtTest.QTest.qWait(25)
    click(viewport, cell_pos(canvas, 25, 18))
    assert frame.box == QtCore.QRectF(24, 16, 5, 6)


def test_gesture_arithmetic():
    c = QtCore.QPointF(0, 0)
    assert scale_factor(c, QtCore.QPointF(1, 1), QtCore.QPointF(3, 3), 0.05, 16) == 3.0
    assert scale_factor(c, QtCore.QPointF(1, 0), QtCore.QPointF(100, 0), 0.05, 16) == 16
    up, left = QtCore.QPointF(0, -1), QtCore.QPointF(-1, 0)
    assert turn_angle(c, up, left, False) == 90.0          # counter-clockwise on screen
    assert turn_angle(c, left, up, False) == -90.0
    assert turn_angle(c, up, QtCore.QPointF(-1, -0.9), True) == 45.0
    assert Change("rotate", 1.0).is_identity is False and Change("scale", 1.0).is_identity
    p = Change("rotate", 90).qtransform(c).map(QtCore.QPointF(1, 0))
    assert (round(p.x(), 9), round(p.y(), 9)) == (0, -1)  # right goes up, as the engine turns
