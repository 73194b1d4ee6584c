"""Models ▸ Flow texture…: noise smoothed along a direction field — a photo's grain (its
structure tensor) or strokes the user draws over the photo — as one step (`flow.FlowTexture`).

The drawing pad shows the photo stretched over the output canvas with the field's direction
drawn as short lines; dragging on it draws a stroke (in output points, so the size may change
after). The preview is the step run in the background on a scratch document, the latest
change winning, as in `models_dialog`; OK applies it (undoable).
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.errors import InputError, TexeditorError
from texeditor.flow import orientation_field, strokes_field
from texeditor.flow.actions import MAX_SEGMENTS, MAX_SIGMA, FlowTexture, strokes_param
from texeditor.flow.field import FIELD_GRID
from texeditor.flow.lic import MAX_LENGTH
from texeditor.flow.texture import LENGTH, SIGMA
from texeditor.recipe.document import Document
from texeditor.spectral.actions import MAX_MODEL_SIDE

from .images import photo_rgb, pixmap, qimage_from_rgb
from .params_form import SeedEdit
from .step_dialog import PREVIEW, StepDialog, photo_box
from .widgets import row, spin_box

GLYPHS = 14             # field lines drawn on the pad, across its longer side
MIN_GAP = 4             # pad pixels between the recorded points of a stroke
ABOUT = ("White noise smoothed along a direction field (line integral convolution): a grain "
         "that follows the photo's own (its structure tensor: wood, hair, grass, brushed "
         "metal) or the strokes you draw on the pad. Greys from the photo; any size.")


class StrokePad(QtWidgets.QWidget):
    """The output canvas as a square: the photo stretched over it, the field as short lines
    and the strokes drawn by dragging, kept as (u, v) in [0, 1] (across, down)."""

    drawn = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setFixedSize(PREVIEW, PREVIEW)
        self.setCursor(QtCore.Qt.CursorShape.CrossCursor)
        self.setToolTip("Drag to draw the direction of the grain; Clear starts again")
        self.background: QtGui.QImage | None = None
        self.strokes: list[list[tuple[float, float]]] = []
        self.glyphs: list[tuple[float, float, float, float]] = []     # (u0, v0, u1, v1)
        self._current: list[tuple[float, float]] | None = None

    def set_background(self, rgb: np.ndarray | None) -> None:
        self.background = None if rgb is None else qimage_from_rgb(rgb)
        self.update()

    def set_glyphs(self, glyphs) -> None:
        self.glyphs = list(glyphs)
        self.update()

    def clear(self) -> None:
        self.strokes, self._current = [], None
        self.update()
        self.drawn.emit()

    def _uv(self, event) -> tuple[float, float]:
        p = event.position()
        return (min(max(p.x() / self.width(), 0.0), 1.0),
                min(max(p.y() / self.height(), 0.0), 1.0))

    def mousePressEvent(self, event):
        if event.button() == QtCore.Qt.MouseButton.LeftButton:
            self._current = [self._uv(event)]
            self.strokes.append(self._current)

    def mouseMoveEvent(self, event):
        if self._current is None:
            return
        u, v = self._uv(event)
        lu, lv = self._current[-1]
        if np.hypot((u - lu) * self.width(), (v - lv) * self.height()) >= MIN_GAP:
            self._current.append((u, v))
            self.update()

    def mouseReleaseEvent(self, event):
        if self._current is None or event.button() != QtCore.Qt.MouseButton.LeftButton:
            return
        self.mouseMoveEvent(event)
        if len(self._current) < 2:
            self.strokes.pop()                       # a click draws no direction
        self._current = None
        self.update()
        self.drawn.emit()

    def paintEvent(self, event):
        painter = QtGui.QPainter(self)
        painter.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing)
        w, h = self.width(), self.height()
        if self.background is not None:
            painter.drawImage(QtCore.QRect(0, 0, w, h), self.background)
        else:
            painter.fillRect(0, 0, w, h, QtGui.QColor(128, 128, 128))
        painter.setPen(QtGui.QPen(QtGui.QColor(255, 230, 80, 200), 1.5))
        for u0, v0, u1, v1 in self.glyphs:
            painter.drawLine(QtCore.QPointF(u0 * w, v0 * h), QtCore.QPointF(u1 * w, v1 * h))
        painter.setPen(QtGui.QPen(QtGui.QColor(230, 40, 60), 3, QtCore.Qt.PenStyle.SolidLine,
                                  QtCore.Qt.PenCapStyle.RoundCap))
        for stroke in self.strokes:
            painter.drawPolyline([QtCore.QPointF(u * w, v * h) for u, v in stroke])
        painter.end()


class FlowDialog(StepDialog):
    """The flow texture's settings, the drawing pad, a live preview and OK."""

    def __init__(self, window):
        super().__init__(window, "Flow texture")
        self.exemplar: np.ndarray | None = None
        self._glyph_cache = None                     # (what the field depends on, its lines)
        self.photo, self.browse = photo_box()
        self.source = QtWidgets.QComboBox()
        self.source.addItem("The photo's grain", "photo")
        self.source.addItem("Strokes drawn on the pad", "strokes")
        self.source.setToolTip("Where the direction comes from; drawing a stroke picks the pad")
        self.greys = QtWidgets.QCheckBox("Greys of the photo")
        self.greys.setChecked(True)
        self.greys.setToolTip("Give the texture the photo's grey distribution (a drawn field); "
                              "otherwise a standard spread")
        h, w = window.document.shape
        self.width_box = spin_box(16, MAX_MODEL_SIDE, w or 256, tip="Points across")
        self.height_box = spin_box(16, MAX_MODEL_SIDE, h or 256, tip="Points down")
        self.seed = SeedEdit(1)
        self.length = spin_box(1, MAX_LENGTH, LENGTH, decimals=1, suffix=" points",
                               tip="Streamline length L: how long the grain is")
        self.sigma = spin_box(0.5, MAX_SIGMA, SIGMA, decimals=1, suffix=" points",
                              tip="Smoothing of the photo's field: larger follows only its "
                                  "broad direction")
        self.tileable = QtWidgets.QCheckBox("Tileable")
        self.tileable.setToolTip("Drawn on the torus: the texture repeats without a seam")
        self.levels = spin_box(2, 16, window.document.num_levels
                               if window.document.levels.size else 8,
                               tip="Number of levels G the texture is cut into")
        self.pad = StrokePad()
        self.clear = QtWidgets.QPushButton("Clear strokes")
        self._layout()
        self._connect()
        self.load_photo()

    def _connect(self) -> None:
        self.photo.currentIndexChanged.connect(self.load_photo)
        self.browse.clicked.connect(self.choose_file)
        for box in (self.width_box, self.height_box, self.levels, self.length, self.sigma):
            box.valueChanged.connect(self.recompute)
        for box in (self.greys, self.tileable):
            box.toggled.connect(self.recompute)
        self.source.currentIndexChanged.connect(self.recompute)
        self.seed.changed.connect(self.recompute)
        self.pad.drawn.connect(self._drawn)
        self.clear.clicked.connect(self.pad.clear)

    def _layout(self) -> None:
        layout, form = self.start(ABOUT)
        form.addRow("Photo", row(self.photo, self.browse, stretch=False))
        form.addRow("Direction", row(self.source, self.greys))
        form.addRow("Size", row(self.width_box, "×", self.height_box, "points", self.tileable))
        form.addRow("Seed", self.seed)
        form.addRow("Length L", row(self.length, "field smoothing", self.sigma))
        form.addRow("Levels G", row(self.levels))
        layout.addLayout(form)
        views = QtWidgets.QGridLayout()
        views.addWidget(QtWidgets.QLabel("Field (drag to draw strokes)"), 0, 0)
        views.addWidget(self.pad, 1, 0)
        views.addWidget(self.clear, 2, 0)
        views.addWidget(QtWidgets.QLabel("Result"), 0, 1)
        views.addWidget(self.result_view, 1, 1)
        layout.addLayout(views)
        self.finish(layout)

    def load_photo(self) -> None:
        self.exemplar, self.note = None, ""
        try:
            self.read_photo()
        except TexeditorError as exc:
            self.pad.set_background(None)
            self._waiting()
            self._failed(exc)
            return
        self.pad.set_background(photo_rgb(self.exemplar))
        self.recompute()

    def _drawn(self) -> None:
        """A stroke drawn (or the strokes cleared): the pad's field is the one to use."""
        if self.pad.strokes and self.source.currentData() != "strokes":
            self.source.setCurrentIndex(self.source.findData("strokes"))   # recomputes
        else:
            self.recompute()

    def strokes(self) -> tuple:
        """The pad's strokes in output points (row, col), as the step's segments."""
        h, w = self.height_box.value(), self.width_box.value()
        return strokes_param([[(v * (h - 1), u * (w - 1)) for u, v in s]
                              for s in self.pad.strokes])

    def action(self, scratch: Document) -> FlowTexture:
        source = self.source.currentData()
        strokes = self.strokes() if source == "strokes" else ()
        if source == "strokes" and not strokes:
            raise InputError("drag on the pad to draw the direction of the grain")
        if len(strokes) // 2 > MAX_SEGMENTS:
            raise InputError(f"the strokes have more than {MAX_SEGMENTS} segments: clear some")
        uses_photo = source == "photo" or self.greys.isChecked()
        ref = scratch.add_exemplar(self.exemplar) if uses_photo else None
        return FlowTexture(source, ref, strokes, self.width_box.value(), self.height_box.value(),
                           self.seed.value(), self.length.value(), self.sigma.value(),
                           self.tileable.isChecked(), self.levels.value())

    def recompute(self) -> None:
        """The field lines on the pad at once, the step on a scratch document in the
        background: the preview is exactly what OK applies."""
        self._waiting()
        self.greys.setEnabled(self.source.currentData() == "strokes")
        self.sigma.setEnabled(self.source.currentData() == "photo")
        if self.exemplar is None:
            return
        scratch = Document()
        try:
            action = self.action(scratch)
            self.pad.set_glyphs(self._cached_glyphs(action))
        except TexeditorError as exc:
            self.pad.set_glyphs(())
            self._failed(exc)
            return
        self.request(action, scratch)

    def _cached_glyphs(self, action: FlowTexture):
        """The pad's field lines, computed again only when the field changes, not for a new
        seed, L or G (they are computed on the GUI thread: up to 0.8 s for a 1024² photo)."""
        key = (id(self.exemplar), action.source, action.sigma, action.tileable, action.height,
               action.width, action.strokes)
        if self._glyph_cache is None or self._glyph_cache[0] != key:
            self._glyph_cache = (key, self._glyphs(action))
        return self._glyph_cache[1]

    def _glyphs(self, action: FlowTexture):
        """Short lines along the step's field on a coarse grid of GLYPHS nodes, in pad
        coordinates (a drawn field computed as the step's, at FIELD_GRID points at most; a
        photo's as the step's: a reduced photo would show another field, brick's joints
        instead of its grain)."""
        h, w = action.height, action.width
        scale = GLYPHS / max(h, w)
        grid = (max(1, round(h * scale)), max(1, round(w * scale)))
        if action.source == "strokes":
            fine = min(1.0, FIELD_GRID / max(h, w))
            theta, _ = strokes_field([[(r * fine, c * fine) for r, c in seg]
                                      for seg in action.segments()],
                                     (max(1, round(h * fine)), max(1, round(w * fine))),
                                     wrap=action.tileable)
            rows = ((np.arange(grid[0]) + 0.5) * theta.shape[0] / grid[0]).astype(int)
            cols = ((np.arange(grid[1]) + 0.5) * theta.shape[1] / grid[1]).astype(int)
            theta = theta[np.ix_(rows, cols)]
        else:
            theta, _ = orientation_field(self.exemplar, grid, sigma=action.sigma,
                                         wrap=action.tileable)
        glyphs = []
        half = 0.35
        for i in range(grid[0]):
            for j in range(grid[1]):
                du, dv = np.cos(theta[i, j]) / grid[1], np.sin(theta[i, j]) / grid[0]
                norm = np.hypot(du, dv) / min(1 / grid[0], 1 / grid[1])
                u, v = (j + 0.5) / grid[1], (i + 0.5) / grid[0]
                du, dv = half * du / norm, half * dv / norm
                glyphs.append((u - du, v - dv, u + du, v + dv))
        return glyphs

    def show_result(self, action, scratch) -> None:
        self.result_view.setPixmap(pixmap(np.asarray(scratch.palette)[scratch.levels], PREVIEW))
        field = "the drawn strokes" if action.source == "strokes" else "the photo's grain"
        self.info.setText(f"Field of {field}{self.note}. Result {scratch.shape[1]}×"
                          f"{scratch.shape[0]}, G = {scratch.num_levels}. OK adds one step "
                          "(undo takes it back).")

    def before_apply(self, action) -> None:
        if action.exemplar is not None:
            self.main_window.history.add_exemplar(self.exemplar)
