"""Real input events for the GUI tests: wheel notches and mouse drags sent to a widget.

Drags are sent as raw QMouseEvents: QTest turns a second press near the first, within the
double-click interval, into a double click, which is not what a drag is. Moves are spaced in time
because pyqtgraph drops mouse moves faster than its rate limit (as a real mouse never sends).
"""

from PySide6 import QtCore, QtGui, QtTest, QtWidgets

NO_MODIFIER = QtCore.Qt.KeyboardModifier.NoModifier


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
