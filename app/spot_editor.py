"""The spot editor (thesis §3.3.3b, fig. 3.7–3.9): build an envelope by pointing the ends of its
axes, see the real spot it gives, keep it in the spot library.

It sits before the Spot tool: the tool places what the editor holds (its envelope, perturbation
and seed). The editor only builds engine objects (`texeditor.spots.envelope`); it never touches the
document.

Gestures in the drawing area: click the two ends of the equator (or drag from one to the other);
drag a handle to move an end or to set a meridian's place and half-width; double-click to add a
meridian there (Shift+double-click: a parallel); right-click a handle to remove it. In Contour
mode, drag to draw the outline freehand.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.errors import TexeditorError
from texeditor.spots.library import SpotLibrary
from texeditor.spots.envelope import (APPROXIMATING, DEFAULT_KIND, KINDS, MIN_GAP, Envelope,
                                     Perturbation, real_spot)

from .params_form import SeedEdit, new_seed
from .widgets import scrolled

HANDLE = 6                      # handle radius, screen pixels
GRID = 5                        # envelope points between grid lines
KIND_NAMES = {"linear": "Straight lines", "bezier_curve": "Bézier curve",
              "uniform_bspline": "B-spline", "catmull_rom": "Catmull–Rom",
              "interpolating_spline": "Interpolating spline", "fractal_curve": "Fractal curve"}
KIND_TIPS = {"linear": "Straight lines from point to point",
             "bezier_curve": "One Bézier curve whose control polygon is the points: every point "
                             "pulls the whole outline",
             "uniform_bspline": "A uniform cubic B-spline on the points: moving a point changes "
                                "only the outline near it",
             "catmull_rom": "A smooth curve through every point (Catmull–Rom); files made before "
                            "this name existed called it Bézier",
             "interpolating_spline": "A periodic cubic spline through every point; files made "
                                     "before this name existed called it B-spline",
             "fractal_curve": "A fractal Bézier curve through every point (projected IFS, "
                              "Guérin): smooth at roughness 0, rougher towards 100 %"}
CONTROL_COLOUR = QtGui.QColor(255, 255, 255, 90)
INTERIOR_NAMES = {"none": "None", "holes": "Holes", "levels": "Level patches",
                  "relief": "Relief (lit top left)"}
EQUATOR_COLOUR = QtGui.QColor(255, 150, 40)
MERIDIAN_COLOUR = QtGui.QColor(90, 200, 255)
PARALLEL_COLOUR = QtGui.QColor(130, 220, 120)
OUTLINE_COLOUR = QtGui.QColor(255, 255, 255, 200)
BACKGROUND = QtGui.QColor(43, 43, 43)
T_MARGIN = 0.01                 # meridians keep this far from the ends and from each other
DEFAULT_PALETTE = np.array([[46, 40, 36], [92, 80, 68], [128, 112, 94], [156, 140, 118],
                            [184, 170, 148], [212, 200, 180]], np.uint8)


def _round(v: float) -> float:
    return round(float(v), 2)


class EnvelopeView(QtWidgets.QWidget):
    """The drawing area: the envelope's axes and handles over the real spot it gives.

    ``changed`` fires on every edit (live, while dragging); the view owns the envelope.
    """

    changed = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setMinimumSize(260, 220)
        self.setSizePolicy(QtWidgets.QSizePolicy.Policy.Expanding,
                           QtWidgets.QSizePolicy.Policy.Expanding)
        self.setMouseTracking(True)
        self.setFocusPolicy(QtCore.Qt.FocusPolicy.ClickFocus)
        self.envelope: Envelope | None = None
        self.mode = "axes"                      # or "contour"
        self.span = 64.0                        # envelope points across the smaller side
        self.origin = np.zeros(2)               # the envelope point at the middle of the area
        self.perturbation = Perturbation()
        self.seed = 0
        self.colours = DEFAULT_PALETTE             # the preview's colours: the level the tool
        self.level, self.shift = 4, 1              # fills with, and its shifted points
        self.pending_a: tuple[float, float] | None = None   # first equator end, clicked
        self.pointer: tuple[float, float] | None = None
        self.hovered = None
        self.selected = None
        self._drag = None
        self._press = None
        self._stroke: list[tuple[float, float]] = []
        self._preview: tuple[QtGui.QImage, int, int] | None = None
        self.problem = ""

    # -- state ------------------------------------------------------------------------------------
    def set_envelope(self, envelope: Envelope | None) -> None:
        self.envelope = envelope
        self.pending_a = None
        self.selected = None
        self.refresh()

    def set_mode(self, mode: str) -> None:
        self.mode = mode
        self.pending_a = None
        self._stroke = []
        self.update()

    def refresh(self) -> None:
        """Recompute the real spot's preview and tell the editor."""
        self._preview, self.problem = None, ""
        if self.envelope is not None:
            try:
                stamp = real_spot(self.envelope, self.perturbation, seed=self.seed)
                self._preview = (_stamp_image(stamp, self.colour), stamp.top, stamp.left)
            except TexeditorError as exc:
                self.problem = str(exc)
        self.update()
        self.changed.emit()

    def fit(self) -> None:
        """Zoom so the envelope fills about two thirds of the area."""
        if self.envelope is not None:
            top, left, bottom, right = self.envelope.bbox()
            extent = max(bottom - top, right - left, 8.0)
            self.span = float(np.clip(extent * 1.35, 16.0, 4000.0))
            self.origin = np.array([(top + bottom) / 2, (left + right) / 2])
            self.update()

    def colour(self, steps: int):
        """The colour of a point moved ``steps`` shifts from the fill level."""
        level = min(max(self.level + steps * self.shift, 0), len(self.colours) - 1)
        return tuple(int(c) for c in self.colours[level])

    # -- coordinates ------------------------------------------------------------------------------
    def _k(self) -> float:
        return min(self.width(), self.height()) / self.span

    def _centre_of_view(self) -> np.ndarray:
        return self.origin

    def to_screen(self, p) -> QtCore.QPointF:
        c, k = self._centre_of_view(), self._k()
        return QtCore.QPointF(self.width() / 2 + (p[1] - c[1]) * k,
                              self.height() / 2 + (p[0] - c[0]) * k)

    def to_envelope(self, pos: QtCore.QPointF) -> tuple[float, float]:
        c, k = self._centre_of_view(), self._k()
        return (_round(c[0] + (pos.y() - self.height() / 2) / k),
                _round(c[1] + (pos.x() - self.width() / 2) / k))

    # -- handles ----------------------------------------------------------------------------------
    def handles(self) -> list[tuple[tuple, np.ndarray]]:
        """(key, point) of every handle: ("a",), ("b",), ("m", i, side), ("p", i, end)."""
        env = self.envelope
        if env is None or env.contour is not None:
            return []          # a drawn contour's equator follows from it: nothing to drag
        out = [(("a",), np.asarray(env.a)), (("b",), np.asarray(env.b))]
        for i, m in enumerate(env.meridians):
            out += [(("m", i, "left"), env.at(m.t, m.left)),
                    (("m", i, "right"), env.at(m.t, -m.right))]
        for i, p in enumerate(env.parallels):
            out += [(("p", i, 0), env.at(p.t0, p.offset)), (("p", i, 1), env.at(p.t1, p.offset))]
        return out

    def handle_at(self, pos: QtCore.QPointF):
        best, where = None, HANDLE + 3
        for key, point in reversed(self.handles()):      # meridians before the equator's ends
            d = math.dist((pos.x(), pos.y()), _xy(self.to_screen(point)))
            if d < where:
                best, where = key, d
        return best

    # -- editing ----------------------------------------------------------------------------------
    def place_equator(self, a, b) -> None:
        """The equator from a to b, with a main meridian across its middle (a quarter of its
        length each side): a shape to drag from, rather than a line with no width."""
        if math.dist(a, b) < 1.0:
            return
        half = _round(math.dist(a, b) / 4)
        self.set_envelope(self._same_kind(Envelope(a, b).with_meridian(0.5, half, half,
                                                                        main=True)))

    def _same_kind(self, envelope: Envelope) -> Envelope:
        """A new envelope drawn with the outline kind (and fractal roughness) shown."""
        old = self.envelope
        if old is None:
            return envelope.with_kind(DEFAULT_KIND)
        if old.kind == "fractal_curve":
            return envelope.with_fractal(old.roughness, old.seed)
        return envelope.with_kind(old.kind)

    def try_envelope(self, make) -> bool:
        """Show the envelope ``make()`` builds, or say why it cannot be (a Bézier curve on too
        many points, say) and keep the one shown."""
        try:
            envelope = make()
        except TexeditorError as exc:
            self.problem = str(exc)
            self.update()
            return False
        self.set_envelope(envelope)
        return True

    def move_handle(self, key, p) -> None:
        env = self.envelope
        try:
            if key[0] in ("a", "b"):
                env = self._moved_end(env, key[0], p)
            elif key[0] == "m":
                env = self._moved_meridian(env, key[1], key[2], p)
            else:
                env = self._moved_parallel(env, key[1], key[2], p)
        except TexeditorError:
            return                      # an impossible position: the handle stays where it was
        if env is not None and env != self.envelope:
            self.envelope = env
            self.refresh()

    @staticmethod
    def _moved_end(env, end, p):
        other = env.b if end == "a" else env.a
        if math.dist(p, other) < 1.0:
            return None
        return replace(env, **{end: p})

    @staticmethod
    def _moved_meridian(env, i, side, p):
        t, offset = env.frame_of(p)
        ts = [m.t for m in env.meridians]
        lo = (ts[i - 1] if i > 0 else 0.0) + T_MARGIN
        hi = (ts[i + 1] if i + 1 < len(ts) else 1.0) - T_MARGIN
        t = _round(min(max(t, lo), hi)) if lo < hi else ts[i]
        if any(abs(t - u) < MIN_GAP for j, u in enumerate(ts) if j != i):
            t = ts[i]
        width = _round(max(offset if side == "left" else -offset, 0.0))
        return env.with_moved_meridian(i, t=t, **{side: width})

    @staticmethod
    def _moved_parallel(env, i, end, p):
        t, offset = env.frame_of(p)
        par = env.parallels[i]
        sign = 1 if par.offset > 0 else -1
        offset = _round(sign * max(sign * offset, 0.5))
        if end == 0:
            new = replace(par, offset=offset, t0=_round(min(max(t, 0.0), par.t1 - T_MARGIN)))
        else:
            new = replace(par, offset=offset, t1=_round(max(min(t, 1.0), par.t0 + T_MARGIN)))
        return replace(env, parallels=env.parallels[:i] + (new,) + env.parallels[i + 1:])

    def add_meridian_at(self, p) -> None:
        """A new meridian through p: its place along the equator, p's distance on p's side, the
        outline's width on the other (so the shape changes only where the user pointed)."""
        env = self.envelope
        if env is None or env.contour is not None:
            return
        t, offset = env.frame_of(p)
        if not T_MARGIN <= t <= 1 - T_MARGIN or any(abs(t - m.t) < T_MARGIN
                                                      for m in env.meridians):
            return
        left, right = env.width_at(t)
        if offset >= 0:
            left = offset
        else:
            right = -offset
        self.try_envelope(lambda: env.with_meridian(_round(t), _round(left), _round(right)))

    def add_parallel_at(self, p) -> None:
        env = self.envelope
        if env is None or env.contour is not None:
            return
        t, offset = env.frame_of(p)
        if abs(offset) < 0.5:
            return
        t0, t1 = max(t - 0.15, 0.0), min(t + 0.15, 1.0)
        self.try_envelope(lambda: env.with_parallel(_round(offset), _round(t0), _round(t1)))

    def remove(self, key) -> None:
        env = self.envelope
        if key is None or env is None:
            return
        if key[0] == "m":
            self.set_envelope(env.without_meridian(key[1]))
        elif key[0] == "p":
            self.set_envelope(env.without_parallel(key[1]))

    # -- mouse ------------------------------------------------------------------------------------
    def mousePressEvent(self, ev):
        pos = ev.position()
        p = self.to_envelope(pos)
        self._press = pos
        if ev.button() == QtCore.Qt.MouseButton.RightButton:
            self.remove(self.handle_at(pos))
            return
        if ev.button() != QtCore.Qt.MouseButton.LeftButton:
            return
        if self.mode == "contour":
            self._drag, self._stroke = ("contour",), [p]
            return
        if self.envelope is None:                  # placing the equator: first end, then second
            if self.pending_a is None:
                self.pending_a = p
                self._drag = ("equator",)
            else:
                a, self.pending_a = self.pending_a, None
                self.place_equator(a, p)
            self.update()
            return
        key = self.handle_at(pos)
        if key is not None:
            self._drag = self.selected = key
        self.update()

    def mouseMoveEvent(self, ev):
        pos = ev.position()
        p = self.to_envelope(pos)
        self.pointer = p
        if self._drag is None:
            self.hovered = self.handle_at(pos)
            self._set_cursor()
            self.update()
            return
        if self._drag[0] == "contour":
            if math.dist(p, self._stroke[-1]) >= 0.5:
                self._stroke.append(p)
        elif self._drag[0] != "equator":
            self.move_handle(self._drag, p)
        self.update()

    def mouseReleaseEvent(self, ev):
        drag, self._drag = self._drag, None
        if drag is None or ev.button() != QtCore.Qt.MouseButton.LeftButton:
            return
        p = self.to_envelope(ev.position())
        if drag[0] == "contour":
            self._finish_contour()
        elif drag[0] == "equator" and self.pending_a is not None:
            if math.dist(_xy(ev.position()), _xy(self._press)) > 2 * HANDLE:
                a, self.pending_a = self.pending_a, None       # dragged from one end to the other
                self.place_equator(a, p)
        self.update()

    def mouseDoubleClickEvent(self, ev):
        if ev.button() != QtCore.Qt.MouseButton.LeftButton or self.mode != "axes":
            return
        if self.envelope is None:
            return
        p = self.to_envelope(ev.position())
        if ev.modifiers() & QtCore.Qt.KeyboardModifier.ShiftModifier:
            self.add_parallel_at(p)
        else:
            self.add_meridian_at(p)

    def _set_cursor(self) -> None:
        """A hand over a handle, a cross where a click draws (the equator, a contour)."""
        shape = QtCore.Qt.CursorShape
        if self.hovered is not None:
            self.setCursor(shape.OpenHandCursor)
        elif self.mode == "contour" or self.envelope is None:
            self.setCursor(shape.CrossCursor)
        else:
            self.unsetCursor()

    def keyPressEvent(self, ev):
        if ev.key() in (QtCore.Qt.Key.Key_Delete, QtCore.Qt.Key.Key_Backspace):
            self.remove(self.selected)
            return
        super().keyPressEvent(ev)

    def wheelEvent(self, ev):
        steps = ev.angleDelta().y() / 120
        self.span = float(np.clip(self.span * 0.85 ** steps, 8.0, 4000.0))
        self.update()

    def leaveEvent(self, ev):
        self.pointer = None
        self.hovered = None
        self.update()

    def _finish_contour(self) -> None:
        from skimage.measure import approximate_polygon
        stroke, self._stroke = self._stroke, []
        if len(stroke) < 3:
            return
        points = approximate_polygon(np.asarray(stroke), tolerance=0.35)[:-1] \
            if len(stroke) > 8 else np.asarray(stroke)
        self.try_envelope(lambda: self._same_kind(Envelope.from_contour(np.round(points, 2))))

    # -- painting ---------------------------------------------------------------------------------
    def paintEvent(self, ev):
        p = QtGui.QPainter(self)
        p.fillRect(self.rect(), BACKGROUND)
        self._paint_grid(p)
        if self._preview is not None:
            image, top, left = self._preview
            k = self._k()
            corner = self.to_screen((top - 0.5, left - 0.5))
            p.drawImage(QtCore.QRectF(corner.x(), corner.y(), image.width() * k,
                                      image.height() * k), image)
        p.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing, True)
        if self.envelope is not None:
            self._paint_envelope(p)
        self._paint_gesture(p)
        self._paint_hint(p)
        p.end()

    def _paint_grid(self, p) -> None:
        k = self._k()
        step = GRID
        while step * k < 10:
            step *= 2
        c = self._centre_of_view()
        lo = self.to_envelope(QtCore.QPointF(0, 0))
        hi = self.to_envelope(QtCore.QPointF(self.width(), self.height()))
        minor = QtGui.QPen(QtGui.QColor(255, 255, 255, 18), 1)
        major = QtGui.QPen(QtGui.QColor(255, 255, 255, 40), 1)
        for v in np.arange(math.floor(lo[1] / step) * step, hi[1] + step, step):
            p.setPen(major if round(v / step) % 5 == 0 else minor)
            x = self.to_screen((c[0], v)).x()
            p.drawLine(QtCore.QLineF(x, 0, x, self.height()))
        for v in np.arange(math.floor(lo[0] / step) * step, hi[0] + step, step):
            p.setPen(major if round(v / step) % 5 == 0 else minor)
            y = self.to_screen((v, c[1])).y()
            p.drawLine(QtCore.QLineF(0, y, self.width(), y))

    def _paint_envelope(self, p) -> None:
        env = self.envelope
        pen = QtGui.QPen(OUTLINE_COLOUR, 1.2, QtCore.Qt.PenStyle.DashLine)
        p.setPen(pen)
        p.setBrush(QtCore.Qt.BrushStyle.NoBrush)
        if env.kind in APPROXIMATING:        # the polygon the curve follows
            p.setPen(QtGui.QPen(CONTROL_COLOUR, 1, QtCore.Qt.PenStyle.DotLine))
            p.drawPolygon(QtGui.QPolygonF([self.to_screen(q) for q in env.control_points()]))
            p.setPen(pen)
        outline = env.outline(step=max(0.5, 2.0 / self._k()))
        if len(outline) >= 2:
            p.drawPolygon(QtGui.QPolygonF([self.to_screen(q) for q in outline]))
        p.setPen(QtGui.QPen(EQUATOR_COLOUR, 2))
        p.drawLine(self.to_screen(env.a), self.to_screen(env.b))
        main = env.main_index
        for i, m in enumerate(env.meridians):
            p.setPen(QtGui.QPen(MERIDIAN_COLOUR, 2.5 if i == main else 1.3))
            p.drawLine(self.to_screen(env.at(m.t, m.left)), self.to_screen(env.at(m.t, -m.right)))
        p.setPen(QtGui.QPen(PARALLEL_COLOUR, 1.5))
        for par in env.parallels:
            p.drawLine(self.to_screen(env.at(par.t0, par.offset)),
                       self.to_screen(env.at(par.t1, par.offset)))
        for key, point in self.handles():
            self._paint_handle(p, key, self.to_screen(point), main)

    def _paint_handle(self, p, key, at: QtCore.QPointF, main) -> None:
        colour = {"a": EQUATOR_COLOUR, "b": EQUATOR_COLOUR, "m": MERIDIAN_COLOUR,
                  "p": PARALLEL_COLOUR}[key[0]]
        lit = key == self.hovered or key == self.selected
        p.setPen(QtGui.QPen(QtGui.QColor(20, 20, 20), 1.2))
        p.setBrush(colour.lighter(150) if lit else colour)
        r = HANDLE + (1.5 if lit else 0)
        if key[0] in ("a", "b"):
            p.drawRect(QtCore.QRectF(at.x() - r, at.y() - r, 2 * r, 2 * r))
        elif key[0] == "p":
            p.drawPolygon(QtGui.QPolygonF([QtCore.QPointF(at.x(), at.y() - r),
                                           QtCore.QPointF(at.x() + r, at.y()),
                                           QtCore.QPointF(at.x(), at.y() + r),
                                           QtCore.QPointF(at.x() - r, at.y())]))
        else:
            if key[1] != main:
                r -= 1.5
            p.drawEllipse(at, r, r)

    def _paint_gesture(self, p) -> None:
        if self.pending_a is not None:
            p.setPen(QtGui.QPen(EQUATOR_COLOUR, 2, QtCore.Qt.PenStyle.DashLine))
            a = self.to_screen(self.pending_a)
            if self.pointer is not None:
                p.drawLine(a, self.to_screen(self.pointer))
            p.setBrush(EQUATOR_COLOUR)
            p.drawRect(QtCore.QRectF(a.x() - HANDLE, a.y() - HANDLE, 2 * HANDLE, 2 * HANDLE))
        if len(self._stroke) > 1:
            p.setPen(QtGui.QPen(OUTLINE_COLOUR, 1.5))
            p.drawPolyline(QtGui.QPolygonF([self.to_screen(q) for q in self._stroke]))

    def hint(self) -> str:
        if self.mode == "contour":
            return "Drag to draw the spot's outline; release to close it."
        if self.envelope is None:
            return ("Click the second end of the equator." if self.pending_a is not None else
                    "Click the two ends of the equator (or drag from one to the other).")
        if self.problem:
            return self.problem
        return ("Drag a handle · double-click: add a meridian (Shift: a parallel) · "
                "right-click a handle: remove it · wheel: zoom")

    def _paint_hint(self, p) -> None:
        """What to do next, on a dark band so it reads over the grid and the spot."""
        flags = int(QtCore.Qt.AlignmentFlag.AlignLeft | QtCore.Qt.TextFlag.TextWordWrap)
        rect = QtCore.QRectF(8, 5, self.width() - 16, 60)
        text = p.boundingRect(rect, flags, self.hint())
        p.fillRect(QtCore.QRectF(0, 0, self.width(), text.bottom() + 5), QtGui.QColor(0, 0, 0, 150))
        p.setPen(QtGui.QColor(225, 225, 225) if not self.problem else QtGui.QColor(255, 150, 130))
        p.drawText(rect, flags, self.hint())


def _xy(point) -> tuple[float, float]:
    return (point.x(), point.y())


def _stamp_image(stamp, colours) -> QtGui.QImage:
    """The real spot as an RGBA picture, one pixel per point (scaled up when painted);
    ``colours`` maps a point's steps (−1, 0, 1…) to its colour."""
    h, w = stamp.shape
    rgba = np.zeros((h, w, 4), np.uint8)
    rgba[stamp.mask, :3] = colours(0)
    for step in np.unique(stamp.steps[stamp.mask]):
        if step:
            rgba[stamp.mask & (stamp.steps == step), :3] = colours(int(step))
    rgba[stamp.mask, 3] = 255
    image = QtGui.QImage(rgba.data, w, h, 4 * w, QtGui.QImage.Format.Format_RGBA8888)
    return image.copy()


class _Slider(QtWidgets.QWidget):
    """A slider with its value shown beside it (percent of a 0..1 quantity)."""

    valueChanged = QtCore.Signal()

    def __init__(self, maximum: int = 100, suffix: str = " %", tip: str = ""):
        super().__init__()
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        self.slider = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        self.slider.setRange(0, maximum)
        self.slider.setMinimumWidth(48)          # never squashed to a bare handle beside a field
        self.label = QtWidgets.QLabel()
        self.label.setMinimumWidth(QtGui.QFontMetrics(self.label.font())
                                   .horizontalAdvance("100 %") + 4)
        self.label.setAlignment(QtCore.Qt.AlignmentFlag.AlignRight
                                | QtCore.Qt.AlignmentFlag.AlignVCenter)
        self.suffix = suffix
        self.slider.valueChanged.connect(self._changed)
        row.addWidget(self.slider, 1)
        row.addWidget(self.label)
        self.setToolTip(tip)
        self._changed()

    def _changed(self) -> None:
        self.label.setText(f"{self.slider.value()}{self.suffix}")
        self.valueChanged.emit()

    def value(self) -> float:
        return self.slider.value() / 100.0

    def set_value(self, value: float) -> None:
        self.slider.setValue(int(round(value * 100)))


def _pair(first: QtWidgets.QWidget, second: QtWidgets.QWidget) -> QtWidgets.QWidget:
    """Two fields on one row (the editor also fits under the canvas)."""
    row = QtWidgets.QWidget()
    layout = QtWidgets.QHBoxLayout(row)
    layout.setContentsMargins(0, 0, 0, 0)
    layout.addWidget(first, 3)
    layout.addWidget(second, 2)
    return row


class SpotEditor(QtWidgets.QWidget):
    """The whole editor: mode and outline kind, the drawing area, the real spot's settings and
    the library. ``changed`` fires when the spot the Spot tool would place changes."""

    changed = QtCore.Signal()

    def __init__(self, library: SpotLibrary | None = None, parent=None):
        super().__init__(parent)
        self.library = library if library is not None else SpotLibrary()
        self.view = EnvelopeView()
        self.tabs = QtWidgets.QTabWidget()
        self.tabs.addTab(self._build_real_spot(), "Real spot")
        self.tabs.addTab(self._build_library(), "Library")
        left = QtWidgets.QVBoxLayout()
        left.addLayout(self._build_top())
        left.addWidget(self.view, 1)
        self.body = QtWidgets.QBoxLayout(QtWidgets.QBoxLayout.Direction.LeftToRight, self)
        self.body.setContentsMargins(4, 4, 4, 4)
        self.body.addLayout(left, 3)
        self.body.addWidget(self.tabs, 2)
        self.view.changed.connect(self._view_changed)
        self._loading = False
        self.fill_library()
        self.load(self.library.get("Pebble"))

    def resizeEvent(self, ev):
        """Side by side when docked under the canvas, stacked when docked in a column."""
        wide = self.width() > 1.2 * self.height()
        self.body.setDirection(QtWidgets.QBoxLayout.Direction.LeftToRight if wide
                               else QtWidgets.QBoxLayout.Direction.TopToBottom)
        super().resizeEvent(ev)

    # -- building ---------------------------------------------------------------------------------
    def _build_top(self) -> QtWidgets.QHBoxLayout:
        row = QtWidgets.QHBoxLayout()
        self.new_button = QtWidgets.QToolButton(text="New")   # narrow: the editor fits under a
        #                                                          1280-pixel window's canvas
        self.new_button.setToolTip("Start a new envelope: click the two ends of its equator")
        self.new_button.clicked.connect(self.new_envelope)
        self.axes_button = QtWidgets.QToolButton(text="Axes", checkable=True, checked=True)
        self.axes_button.setToolTip("Build the envelope from its equator and meridians")
        self.contour_button = QtWidgets.QToolButton(text="Contour", checkable=True)
        self.contour_button.setToolTip("Draw the spot's outline freehand")
        group = QtWidgets.QButtonGroup(self)
        group.addButton(self.axes_button)
        group.addButton(self.contour_button)
        self.axes_button.toggled.connect(
            lambda on: self.view.set_mode("axes" if on else "contour"))
        self.kind = QtWidgets.QComboBox()
        self.kind.setSizeAdjustPolicy(
            QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.kind.setMinimumContentsLength(7)            # long names elide: the dock stays narrow
        for kind in KINDS:
            self.kind.addItem(KIND_NAMES[kind], kind)
            self.kind.setItemData(self.kind.count() - 1, KIND_TIPS[kind],
                                  QtCore.Qt.ItemDataRole.ToolTipRole)
        self.kind.setToolTip("How the outline joins the ends of the axes (thesis fig. 3.8, 3.9)")
        self.kind.currentIndexChanged.connect(self._kind_changed)
        self.fit_button = QtWidgets.QToolButton(text="Fit")
        self.fit_button.setToolTip("Zoom the drawing area to the envelope")
        self.fit_button.clicked.connect(self.view.fit)
        for w in (self.new_button, self.axes_button, self.contour_button):
            row.addWidget(w)
        row.addStretch(1)
        row.addWidget(self.kind)
        row.addWidget(self.fit_button)
        return row

    def _build_real_spot(self) -> QtWidgets.QWidget:
        box = QtWidgets.QWidget()
        form = QtWidgets.QFormLayout(box)
        form.setFieldGrowthPolicy(QtWidgets.QFormLayout.FieldGrowthPolicy.AllNonFixedFieldsGrow)
        self.contour = _Slider(tip="How deep the smooth bumps of the contour go")
        self.frequency = QtWidgets.QSpinBox()
        self.frequency.setRange(1, 64)
        self.frequency.setToolTip("How many bumps around the contour")
        self.curve_roughness = _Slider(tip="Roughness of the fractal curve outline (projected "
                                           "IFS): 0 the smooth curve through the points")
        self.curve_roughness.set_value(0.5)
        self.curve_roughness.setEnabled(False)
        self.fractal = _Slider(tip="Fractal roughening of the outline (midpoint displacement)")
        self.roughness = QtWidgets.QDoubleSpinBox()
        self.roughness.setRange(0.0, 1.0)
        self.roughness.setSingleStep(0.05)
        self.roughness.setToolTip("Roughness exponent h: 0 very rough, 1 smooth")
        self.interior = QtWidgets.QComboBox()
        self.interior.setSizeAdjustPolicy(
            QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.interior.setMinimumContentsLength(7)       # its slider keeps room in a narrow dock
        for key, text in INTERIOR_NAMES.items():
            self.interior.addItem(text, key)
        self.interior.setToolTip("Holes: points left out; level patches: points one level "
                                 "off (see Shift)")
        self.density = _Slider(tip="Share of the spot in holes or patches")
        self.grain = QtWidgets.QDoubleSpinBox()
        self.grain.setRange(0.5, 200.0)
        self.grain.setSuffix(" pt")
        self.grain.setToolTip("Size of the holes or patches, in points of the envelope")
        self.shift = QtWidgets.QSpinBox()
        self.shift.setRange(-15, 15)
        self.shift.setValue(1)
        self.shift.setToolTip("Level change of the patches (+1: one level lighter)")
        self.seed = SeedEdit(new_seed())
        self.seed.setToolTip("One envelope, many real spots: each seed gives another")
        self.vary = QtWidgets.QCheckBox("A new seed after each spot placed")
        self.vary.setChecked(True)
        self.frequency.setSuffix(" bumps")
        self.roughness.setPrefix("h ")
        self.shift.setPrefix("shift ")
        self.grain.setPrefix("size ")
        form.addRow("Curve", self.curve_roughness)
        form.addRow("Bumps", _pair(self.contour, self.frequency))
        form.addRow("Fractal", _pair(self.fractal, self.roughness))
        form.addRow("Interior", _pair(self.interior, self.density))
        form.addRow("Patches", _pair(self.grain, self.shift))
        form.addRow("Seed", self.seed)
        form.addRow(self.vary)
        for w in (self.contour, self.fractal, self.density):
            w.valueChanged.connect(self._settings_changed)
        for w in (self.frequency, self.shift):
            w.valueChanged.connect(self._settings_changed)
        for w in (self.roughness, self.grain):
            w.valueChanged.connect(self._settings_changed)
        self.curve_roughness.valueChanged.connect(self._kind_changed)
        self.interior.currentIndexChanged.connect(self._settings_changed)
        self.interior.currentIndexChanged.connect(self._interior_changed)
        self.seed.changed.connect(self._settings_changed)
        return box

    def _build_library(self) -> QtWidgets.QWidget:
        box = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(box)
        self.spot_list = QtWidgets.QListWidget()
        self.spot_list.setToolTip("Click a spot to edit it; standard spots are in italics")
        self.spot_list.itemClicked.connect(lambda item: self.load(self.library.get(
            item.data(QtCore.Qt.ItemDataRole.UserRole))))
        buttons = QtWidgets.QHBoxLayout()
        self.save_button = QtWidgets.QPushButton("Save as…")
        self.save_button.setToolTip("Keep this envelope and its real-spot settings in your "
                                    "library")
        self.save_button.clicked.connect(lambda: self.save_as())
        self.remove_button = QtWidgets.QPushButton("Remove")
        self.remove_button.clicked.connect(self.remove_selected)
        buttons.addWidget(self.save_button)
        buttons.addWidget(self.remove_button)
        buttons.addStretch(1)
        self.library_note = QtWidgets.QLabel()
        self.library_note.setWordWrap(True)
        layout.addWidget(self.spot_list, 1)
        layout.addLayout(buttons)
        layout.addWidget(self.library_note)
        return box

    # -- what the Spot tool reads -----------------------------------------------------------------
    @property
    def envelope(self) -> Envelope | None:
        return self.view.envelope

    def perturbation(self) -> Perturbation:
        return Perturbation(self.contour.value(), self.frequency.value(), self.fractal.value(),
                            round(self.roughness.value(), 2), self.interior.currentData(),
                            self.density.value(), round(self.grain.value(), 2))

    @property
    def shift_value(self) -> int:
        return self.shift.value()

    def spot_placed(self) -> None:
        """The tool placed the current spot: show the next one (a new seed) if asked."""
        if self.vary.isChecked():
            self.seed.set_value(new_seed())

    def set_palette(self, palette, level: int) -> None:
        """Preview in the document's colours: the level the tool fills with (and its shifts)."""
        self.view.colours = np.asarray(palette, np.uint8)
        self.view.level = int(level)
        self.view.refresh()

    # -- editing ----------------------------------------------------------------------------------
    def new_envelope(self) -> None:
        self.axes_button.setChecked(True)
        self.view.set_envelope(None)

    def load(self, entry) -> None:
        """Edit a library entry: its envelope and its real-spot settings."""
        self._loading = True
        p = entry.perturbation
        self.contour.set_value(p.contour)
        self.frequency.setValue(p.frequency)
        self.fractal.set_value(p.fractal)
        self.roughness.setValue(p.h)
        self.interior.setCurrentIndex(self.interior.findData(p.interior))
        self.density.set_value(p.density)
        self.grain.setValue(p.scale)
        self.kind.setCurrentIndex(self.kind.findData(entry.envelope.kind))
        self.curve_roughness.set_value(entry.envelope.roughness)
        self.curve_roughness.setEnabled(entry.envelope.kind == "fractal_curve")
        self._loading = False
        self._interior_changed()
        self.view.perturbation = self.perturbation()
        self.view.seed = self.seed.value()
        self.view.shift = self.shift.value()
        self.view.set_envelope(entry.envelope)
        self.view.fit()

    def _interior_changed(self) -> None:
        """Only the settings the chosen interior uses can be changed."""
        interior = self.interior.currentData()
        self.density.setEnabled(interior != "none")
        self.grain.setEnabled(interior in ("holes", "levels"))
        self.shift.setEnabled(interior in ("levels", "relief"))

    def _kind_changed(self) -> None:
        if self._loading or self.view.envelope is None:
            return
        envelope, kind = self.view.envelope, self.kind.currentData()
        self.curve_roughness.setEnabled(kind == "fractal_curve")
        if not self.view.try_envelope(
                lambda: envelope.with_fractal(self.curve_roughness.value())
                if kind == "fractal_curve" else envelope.with_kind(kind)):
            self._loading = True              # refused: the list shows the kind still drawn
            self.kind.setCurrentIndex(self.kind.findData(envelope.kind))
            self._loading = False

    def _settings_changed(self) -> None:
        if self._loading:
            return
        self.view.perturbation = self.perturbation()
        self.view.seed = self.seed.value()
        self.view.shift = self.shift.value()
        self.view.refresh()

    def _view_changed(self) -> None:
        self.changed.emit()

    # -- library ----------------------------------------------------------------------------------
    def fill_library(self, select: str | None = None) -> None:
        self.spot_list.clear()
        for entry in self.library.entries():
            item = QtWidgets.QListWidgetItem(entry.name)
            item.setData(QtCore.Qt.ItemDataRole.UserRole, entry.name)
            if entry.standard:
                font = item.font()
                font.setItalic(True)
                item.setFont(font)
                item.setToolTip("A standard spot (read-only)")
            self.spot_list.addItem(item)
            if entry.name == select:
                self.spot_list.setCurrentItem(item)
        self.library_note.setText("\n".join(self.library.problems))
        self.library_note.setVisible(bool(self.library.problems))

    def save_as(self, name: str | None = None) -> bool:
        if self.envelope is None:
            QtWidgets.QMessageBox.information(self, "No envelope", "Draw an envelope first.")
            return False
        if name is None:
            name, ok = QtWidgets.QInputDialog.getText(self, "Save spot", "Name of the spot:")
            if not ok or not name.strip():
                return False
        try:
            self.library.save(name, self.envelope, self.perturbation())
        except (TexeditorError, OSError) as exc:
            QtWidgets.QMessageBox.critical(self, "Cannot save this spot", str(exc))
            return False
        self.fill_library(select=name.strip())
        return True

    def remove_selected(self) -> None:
        item = self.spot_list.currentItem()
        if item is None:
            return
        try:
            self.library.remove(item.data(QtCore.Qt.ItemDataRole.UserRole))
        except (TexeditorError, OSError) as exc:
            QtWidgets.QMessageBox.critical(self, "Cannot remove this spot", str(exc))
            return
        self.fill_library()


class SpotEditorDock(QtWidgets.QDockWidget):
    """The spot editor as a dock (it floats too); the Spot tool shows it."""

    def __init__(self, parent=None, library: SpotLibrary | None = None):
        super().__init__("Spot editor", parent)
        self.setObjectName("SpotEditorDock")
        self.editor = SpotEditor(library)
        self.setWidget(scrolled(self.editor))
