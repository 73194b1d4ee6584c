"""Transform handles around a selection on the canvas, as in Krita and GIMP: a box with four corner
handles (scale about the centre), a knob above it and a band around it (rotate), the inside (move).

The frame only turns a drag into a :class:`Change` — a move by whole cells, a zoom factor or an
angle — and draws the box where that change takes it; the tool builds the ghost and the Action.
Sizes are in screen pixels, turned into cells with the item's pixel length each time they are
used, so the handles keep their size on screen at any zoom.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import pyqtgraph as pg
from PySide6 import QtCore, QtGui

HANDLE_PX = 9                        # side of a corner handle
KNOB_PX = 5                          # radius of the rotation knob
KNOB_GAP_PX = 24                     # from the top edge to the knob's centre
BAND_PX = KNOB_GAP_PX + KNOB_PX + 4  # a drag starting this close outside the box rotates
GRAB_PX = 3                          # slack around a handle for the pointer
SNAP_DEGREES = 15.0                  # Shift snaps the angle to these steps
IDENTITY = {"move": (0, 0), "scale": 1.0, "rotate": 0.0}
Shape = QtCore.Qt.CursorShape


@dataclass(frozen=True)
class Change:
    """What a handle drag asks for: ``mode`` "move" (value: (dx, dy) in cells), "scale" (a zoom
    factor) or "rotate" (degrees, counter-clockwise on screen as the engine turns selections)."""

    mode: str
    value: object

    @property
    def is_identity(self) -> bool:
        return self.value == IDENTITY[self.mode]

    def qtransform(self, centre: QtCore.QPointF) -> QtGui.QTransform:
        """The same map on canvas coordinates (x right, y down), about ``centre``."""
        t = QtGui.QTransform()
        if self.mode == "move":
            return t.translate(*self.value)
        t.translate(centre.x(), centre.y())
        if self.mode == "scale":
            t.scale(self.value, self.value)
        else:
            t.rotate(-self.value)         # Qt turns clockwise on a y-down screen
        return t.translate(-centre.x(), -centre.y())


def scale_factor(centre, grab, pointer, lo: float, hi: float) -> float:
    """The zoom a corner drag asks for: the pointer's distance to the centre over the grab's,
    kept in [lo, hi] and rounded to two decimals, as the panel's factor field shows it."""
    start = math.dist((grab.x(), grab.y()), (centre.x(), centre.y()))
    if start == 0:
        return 1.0
    now = math.dist((pointer.x(), pointer.y()), (centre.x(), centre.y()))
    return round(min(max(now / start, lo), hi), 2)


def turn_angle(centre, grab, pointer, snap: bool) -> float:
    """Degrees counter-clockwise on screen from the grab to the pointer about the centre, in
    [-180, 180), rounded to the panel's tenth of a degree; ``snap`` rounds to 15° steps."""
    def heading(p):
        return math.degrees(math.atan2(centre.y() - p.y(), p.x() - centre.x()))
    angle = (heading(pointer) - heading(grab) + 180.0) % 360.0 - 180.0
    if snap:
        angle = SNAP_DEGREES * round(angle / SNAP_DEGREES)
    return round(angle, 1) + 0.0          # never -0.0


@functools.cache
def rotate_cursor() -> QtGui.QCursor:
    """A circular arrow (Qt has no rotation cursor), outlined so it shows on any texture."""
    pixmap = QtGui.QPixmap(24, 24)
    pixmap.fill(QtCore.Qt.GlobalColor.transparent)
    painter = QtGui.QPainter(pixmap)
    painter.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing)
    head = QtGui.QPolygonF([QtCore.QPointF(19.5, 7.5), QtCore.QPointF(12.5, 8.0),
                            QtCore.QPointF(17.5, 1.5)])
    for colour, width in ((QtCore.Qt.GlobalColor.black, 3.5), (QtCore.Qt.GlobalColor.white, 1.5)):
        painter.setPen(QtGui.QPen(colour, width))
        painter.setBrush(QtCore.Qt.BrushStyle.NoBrush)
        painter.drawArc(QtCore.QRectF(4, 4, 16, 16), 60 * 16, 270 * 16)
        painter.setBrush(colour)
        painter.drawPolygon(head)
    painter.end()
    return QtGui.QCursor(pixmap, 12, 12)


def _pen(colour, width: float) -> QtGui.QPen:
    """A pen whose width is in screen pixels, whatever the zoom."""
    pen = QtGui.QPen(QtGui.QColor(*colour), width)
    pen.setCosmetic(True)
    return pen


class TransformFrame(pg.GraphicsObject):
    """The box and handles of a selection, in cell coordinates inside the canvas's view box.

    A left drag that starts on a handle, inside the box or in the band around it is the frame's;
    any other press (and every click) goes on to the view box and the tool, as before. Esc
    during a drag cancels it: ``cancelled`` is emitted and the release emits nothing.
    """

    changing = QtCore.Signal(object)    # a Change, at every move of a drag
    finished = QtCore.Signal(object)    # the final Change, on release
    cancelled = QtCore.Signal()

    OUTLINE = (_pen((20, 20, 20, 200), 3), _pen((255, 255, 255), 1))

    def __init__(self, factor_range: tuple[float, float]):
        super().__init__()
        self.factor_range = factor_range
        self.box = QtCore.QRectF()          # the selection's bounding box; empty: no frame
        self.preview = QtGui.QTransform()   # where the running drag takes the box
        self._drag: tuple[str, QtCore.QPointF] | None = None   # (mode, grab point)
        self.setZValue(20)
        self.setVisible(False)

    def set_box(self, box: QtCore.QRectF | None) -> None:
        """Frame a new box (None: hide); a drag under way ends without a word, since what it
        was dragging has changed."""
        self._end()
        self.prepareGeometryChange()
        self.box = QtCore.QRectF() if box is None else QtCore.QRectF(box)
        self.setVisible(not self.box.isEmpty())
        self.update()

    # -- geometry ----------------------------------------------------------------------------------
    def px(self) -> float:
        """One screen pixel in cells."""
        return self.pixelLength(QtCore.QPointF(1, 0)) or 1.0

    def corners(self) -> list[QtCore.QPointF]:
        """Top-left, top-right, bottom-right, bottom-left, where the running drag puts them."""
        b = self.box
        return [self.preview.map(p) for p in (b.topLeft(), b.topRight(), b.bottomRight(),
                                               b.bottomLeft())]

    def knob(self) -> tuple[QtCore.QPointF, QtCore.QPointF]:
        """The middle of the top edge and the knob's centre, a fixed distance on screen above
        it (along the box's own up when it turns)."""
        top = self.preview.map(QtCore.QPointF(self.box.center().x(), self.box.top()))
        up = top - self.preview.map(self.box.center())
        length = math.hypot(up.x(), up.y())
        up = up / length if length else QtCore.QPointF(0, -1)
        return top, top + up * (KNOB_GAP_PX * self.px())

    def zone_at(self, pos: QtCore.QPointF):
        """(mode, cursor) of the handle or area under ``pos``, or None: corners scale, the knob
        and the band outside the box rotate, the inside moves."""
        if self.box.isEmpty():
            return None
        px = self.px()
        reach = (HANDLE_PX / 2 + GRAB_PX) * px
        for i, corner in enumerate(self.corners()):
            if abs(pos.x() - corner.x()) <= reach and abs(pos.y() - corner.y()) <= reach:
                return "scale", Shape.SizeFDiagCursor if i % 2 == 0 else Shape.SizeBDiagCursor
        knob = self.knob()[1]
        if math.dist((pos.x(), pos.y()), (knob.x(), knob.y())) <= (KNOB_PX + GRAB_PX) * px:
            return "rotate", rotate_cursor()
        if self.box.contains(pos):
            return "move", Shape.SizeAllCursor
        band = BAND_PX * px
        if self.box.adjusted(-band, -band, band, band).contains(pos):
            return "rotate", rotate_cursor()
        return None

    def boundingRect(self) -> QtCore.QRectF:
        if self.box.isEmpty():
            return QtCore.QRectF()
        m = (BAND_PX + HANDLE_PX) * self.px()
        return self.preview.mapRect(self.box).adjusted(-m, -m, m, m)

    def viewTransformChanged(self):
        """A zoom changes the handles' size in cells, hence the bounding box."""
        super().viewTransformChanged()
        self.prepareGeometryChange()

    def paint(self, painter, *args):
        if self.box.isEmpty():
            return
        painter.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing)
        outline = self.preview.map(QtGui.QPolygonF(self.box))
        top, knob = self.knob()
        for pen in self.OUTLINE:
            painter.setPen(pen)
            painter.drawPolygon(outline)
            painter.drawLine(top, knob)
        painter.setPen(self.OUTLINE[0])
        painter.setBrush(QtGui.QColor(255, 255, 255))
        side = HANDLE_PX * self.px()
        for corner in self.corners():
            painter.drawRect(QtCore.QRectF(corner.x() - side / 2, corner.y() - side / 2,
                                           side, side))
        radius = KNOB_PX * self.px()
        painter.drawEllipse(knob, radius, radius)

    # -- pointer and keys --------------------------------------------------------------------------
    def hoverEvent(self, ev):
        """The cursor says what a drag from here does (pyqtgraph's hover, once per move)."""
        zone = None if ev.isExit() or self._panning() else self.zone_at(ev.pos())
        if zone is None:
            self.unsetCursor()
            return
        ev.acceptDrags(QtCore.Qt.MouseButton.LeftButton)
        self.setCursor(zone[1])

    def mouseDragEvent(self, ev):
        """pyqtgraph's drag: claim it at the start if it begins on the frame, preview each move,
        report the release."""
        if ev.isStart():
            left = ev.button() == QtCore.Qt.MouseButton.LeftButton
            zone = self.zone_at(ev.buttonDownPos()) if left and not self._panning() else None
            if zone is None:
                ev.ignore()               # the view box and the tool get it
                return
            self._start(zone[0], ev.buttonDownPos())
        ev.accept()
        if self._drag is None:            # cancelled: wait for the release
            return
        change = self._change(ev.pos(), ev.modifiers())
        if ev.isFinish():
            self._end()
            self.finished.emit(change)
            return
        self.prepareGeometryChange()
        self.preview = change.qtransform(self.box.center())
        self.update()
        self.changing.emit(change)

    def cancel(self) -> None:
        """Drop the running drag (Esc): nothing is committed."""
        if self._drag is not None:
            self._end()
            self.cancelled.emit()

    def eventFilter(self, obj, ev):
        """Esc on the canvas during a drag cancels it, before any Esc shortcut of the window."""
        kinds = (QtCore.QEvent.Type.ShortcutOverride, QtCore.QEvent.Type.KeyPress)
        if self._drag is None or ev.type() not in kinds or ev.key() != QtCore.Qt.Key.Key_Escape:
            return False
        ev.accept()
        if ev.type() == QtCore.QEvent.Type.KeyPress:
            self.cancel()
        return True

    def _panning(self) -> bool:
        """Space is held: a drag pans the canvas, over the frame as anywhere else."""
        return bool(getattr(self.getViewBox(), "pan_key_held", False))

    def _start(self, mode: str, grab: QtCore.QPointF) -> None:
        """Remember what is dragged and from where; listen for Esc until the drag ends."""
        self._drag = (mode, QtCore.QPointF(grab))
        view = self.getViewWidget()
        if view is not None:
            view.installEventFilter(self)

    def _end(self) -> None:
        """Forget the drag and its preview; stop listening for Esc."""
        if self._drag is None:
            return
        self._drag = None
        view = self.getViewWidget()
        if view is not None:
            view.removeEventFilter(self)
        self.prepareGeometryChange()
        self.preview = QtGui.QTransform()
        self.update()

    def _change(self, pos: QtCore.QPointF, modifiers) -> Change:
        """The change the pointer asks for now, measured from the grab point."""
        mode, grab = self._drag
        if mode == "move":
            return Change("move", (round(pos.x() - grab.x()), round(pos.y() - grab.y())))
        centre = self.box.center()
        if mode == "scale":
            return Change("scale", scale_factor(centre, grab, pos, *self.factor_range))
        snap = bool(modifiers & QtCore.Qt.KeyboardModifier.ShiftModifier)
        return Change("rotate", turn_angle(centre, grab, pos, snap))
