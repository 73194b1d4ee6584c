"""The grain editor (thesis §3.3.3a): a grain shown enlarged, its shape and size set in a form or
drawn point by point, saved to the grain library (standard grains and the user's own; listed in
the Grain stamps dock, app.grain_stamps_dock).

Grain characteristics are defined here, "at a larger scale than the texture", before the Grain
tool places grains by their centre of gravity; saved grains go to the user data folder.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.paint import grains
from texeditor.errors import TexeditorError
from texeditor.paint.grains import GrainLibrary, GrainType

SHAPES = [("Square", "square"), ("Rectangle", "rectangle"), ("Circle / ellipse", "circle"),
          ("Diamond", "diamond"), ("Hexagon", "hexagon"), ("Regular polygon", "polygon"),
          ("Line", "line"), ("Drawn", "bitmap")]
LEVEL_MODES = [("The palette's current level", "palette"), ("A fixed level", "fixed"),
               ("The drawing's own levels", "own")]
CENTRE = QtGui.QColor(230, 40, 40)
EMPTY = (QtGui.QColor(62, 62, 62), QtGui.QColor(74, 74, 74))


def grain_image(grain: GrainType, palette, level: int, cell: int = 1,
                box: tuple[int, int] | None = None) -> QtGui.QImage:
    """The grain's points in their palette colours, ``cell`` pixels per point, transparent
    around (centred in ``box`` points when given): list icons and the editor's picture."""
    mask = grain.mask()
    values = grain.values(level)
    h, w = mask.shape
    bh, bw = box or (h, w)
    top, left = max(0, (bh - h) // 2), max(0, (bw - w) // 2)
    rgba = np.zeros((max(bh, h), max(bw, w), 4), np.uint8)
    pal = np.asarray(palette, np.uint8)
    colours = pal[np.minimum(values, len(pal) - 1)]
    rgba[top:top + h, left:left + w][mask, :3] = colours[mask]
    rgba[top:top + h, left:left + w][mask, 3] = 255
    rgba = np.repeat(np.repeat(rgba, cell, axis=0), cell, axis=1)
    rgba = np.ascontiguousarray(rgba)
    image = QtGui.QImage(rgba.data, rgba.shape[1], rgba.shape[0], 4 * rgba.shape[1],
                         QtGui.QImage.Format.Format_RGBA8888)
    return image.copy()


def grain_icon(grain: GrainType, palette, level: int, side: int = 40) -> QtGui.QIcon:
    """A square icon of the grain, enlarged to whole pixels per point: light on dark like the
    brush presets, or in the palette's colours for a grain that keeps its own levels."""
    mask = grain.mask()
    n = max(mask.shape)
    cell = max(1, min(3, (side - 4) // n))      # one scale for all: sizes compare at a glance
    if not (grain.own_levels and grain.level is None):
        palette, level = [(0, 0, 0), (230, 230, 230)], 1
        grain = grain.replace(level=None, own_levels=False)
    pixmap = QtGui.QPixmap(side, side)
    pixmap.fill(QtGui.QColor(40, 40, 40))
    p = QtGui.QPainter(pixmap)
    image = grain_image(grain, palette, level, cell, (n, n))
    if image.width() > side:
        image = image.scaled(side - 4, side - 4, QtCore.Qt.AspectRatioMode.KeepAspectRatio)
    p.drawImage((side - image.width()) // 2, (side - image.height()) // 2, image)
    p.end()
    return QtGui.QIcon(pixmap)


class GrainView(QtWidgets.QWidget):
    """The grain enlarged, point by point, with its centre of gravity (red cross) and the
    point that lands on the clicked cell (red square). A drawn grain is painted here: left
    button with the drawing level, right button erases."""

    drawn = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setMinimumSize(280, 280)
        self.setSizePolicy(QtWidgets.QSizePolicy.Policy.Expanding,
                           QtWidgets.QSizePolicy.Policy.Expanding)
        self.levels = np.zeros((1, 1), np.uint8)     # what is shown: levels, 0 = empty
        self.grain_mask = np.zeros((1, 1), bool)
        self.palette_rgb = np.array([[0, 0, 0], [255, 255, 255]], np.uint8)
        self.editable = False
        self.draw_level = 1
        self._erase = False

    def show_grain(self, levels: np.ndarray, mask: np.ndarray, palette, editable: bool) -> None:
        self.levels, self.grain_mask = levels, mask
        self.palette_rgb = np.asarray(palette, np.uint8)
        self.editable = editable
        self.setCursor(QtCore.Qt.CursorShape.CrossCursor if editable
                       else QtCore.Qt.CursorShape.ArrowCursor)
        self.update()

    def _geometry(self) -> tuple[float, float, float]:
        h, w = self.grain_mask.shape
        cell = max(2.0, min((self.width() - 8) / w, (self.height() - 8) / h))
        return cell, (self.width() - cell * w) / 2, (self.height() - cell * h) / 2

    def cell_at(self, pos: QtCore.QPointF) -> tuple[int, int] | None:
        cell, x0, y0 = self._geometry()
        r, c = int((pos.y() - y0) // cell), int((pos.x() - x0) // cell)
        h, w = self.grain_mask.shape
        return (r, c) if 0 <= r < h and 0 <= c < w else None

    def paintEvent(self, ev):
        p = QtGui.QPainter(self)
        p.fillRect(self.rect(), QtGui.QColor(43, 43, 43))
        cell, x0, y0 = self._geometry()
        h, w = self.grain_mask.shape
        pal = self.palette_rgb
        for r in range(h):
            for c in range(w):
                rect = QtCore.QRectF(x0 + c * cell, y0 + r * cell, cell, cell)
                if self.grain_mask[r, c]:
                    colour = pal[min(int(self.levels[r, c]), len(pal) - 1)]
                    p.fillRect(rect, QtGui.QColor(*(int(v) for v in colour)))
                else:                                   # empty: a checker, as transparency
                    p.fillRect(rect, EMPTY[(r + c) % 2])
        p.setPen(QtGui.QPen(QtGui.QColor(128, 128, 128, 140), 1))
        right, bottom = x0 + w * cell, y0 + h * cell
        for r in range(h + 1):
            p.drawLine(QtCore.QPointF(x0, y0 + r * cell), QtCore.QPointF(right, y0 + r * cell))
        for c in range(w + 1):
            p.drawLine(QtCore.QPointF(x0 + c * cell, y0), QtCore.QPointF(x0 + c * cell, bottom))
        if self.grain_mask.any():
            cy, cx = grains.centre_of_gravity(self.grain_mask)
            ay, ax = grains.anchor(self.grain_mask)
            p.setPen(QtGui.QPen(CENTRE, 2))
            p.drawRect(QtCore.QRectF(x0 + ax * cell + 1, y0 + ay * cell + 1, cell - 2, cell - 2))
            x, y = x0 + (cx + 0.5) * cell, y0 + (cy + 0.5) * cell
            arm = max(4.0, cell * 0.35)
            p.drawLine(QtCore.QPointF(x - arm, y), QtCore.QPointF(x + arm, y))
            p.drawLine(QtCore.QPointF(x, y - arm), QtCore.QPointF(x, y + arm))
        p.end()

    def mousePressEvent(self, ev):
        self._erase = ev.button() == QtCore.Qt.MouseButton.RightButton
        self._paint_at(ev.position())

    def mouseMoveEvent(self, ev):
        if ev.buttons():
            self._paint_at(ev.position())

    def _paint_at(self, pos) -> None:
        if not self.editable:
            return
        cell = self.cell_at(pos)
        if cell is None:
            return
        value = 0 if self._erase else self.draw_level
        if self.levels[cell] != value:
            self.levels[cell] = value
            self.grain_mask = self.levels > 0
            self.update()
            self.drawn.emit()


class GrainEditor(QtWidgets.QDialog):
    """Define a grain: its shape, size, orientation and level, or draw it; keep it in the library.

    Signals: ``chosen(GrainType)`` (Use for the Grain tool), ``libraryChanged()``.
    """

    chosen = QtCore.Signal(object)
    libraryChanged = QtCore.Signal()

    def __init__(self, library: GrainLibrary, grain: GrainType, palette, level: int,
                 parent=None):
        super().__init__(parent)
        self.setWindowTitle("Grain editor")
        self.library = library
        self.palette_rgb = np.asarray(palette, np.uint8)
        self.level = level
        self.drawing = np.zeros((9, 9), np.uint8)
        self._loading = False
        self.view = GrainView()
        self.view.drawn.connect(self._drawing_changed)
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)

        left = QtWidgets.QVBoxLayout()
        left.addWidget(self.view, 1)
        left.addWidget(self.info)
        form = QtWidgets.QFormLayout()
        self.name = QtWidgets.QLineEdit()
        form.addRow("Name", self.name)
        self.shape_box = QtWidgets.QComboBox()
        for text, value in SHAPES:
            self.shape_box.addItem(text, value)
        form.addRow("Shape", self.shape_box)
        self.size_box = self._spin(1, grains.MAX_GRAIN_SIZE, " pt", "Diameter in points")
        form.addRow("Size", self.size_box)
        self.aspect = self._spin(7, 1600, " %", "Height as a share of the width "
                                                "(rectangles, ellipses, diamonds, polygons)")
        form.addRow("Aspect", self.aspect)
        self.sides = self._spin(grains.MIN_SIDES, grains.MAX_SIDES, "", "Sides of the polygon")
        form.addRow("Sides", self.sides)
        self.angle = self._spin(-180, 180, "°", "Orientation, counter-clockwise")
        form.addRow("Angle", self.angle)
        self.level_mode = QtWidgets.QComboBox()
        for text, value in LEVEL_MODES:
            self.level_mode.addItem(text, value)
        form.addRow("Painted with", self.level_mode)
        self.fixed_level = self._spin(0, grains.MAX_LEVEL, "", "The grain's own level")
        form.addRow("Level", self.fixed_level)

        self.draw_box = QtWidgets.QGroupBox("Drawing")
        draw = QtWidgets.QFormLayout(self.draw_box)
        self.pen_level = self._spin(1, grains.MAX_LEVEL, "", "Left button paints this level; "
                                                             "the right button erases")
        draw.addRow("Pen level", self.pen_level)
        self.grid_size = self._spin(3, grains.MAX_BITMAP_SIDE, " pt", "Size of the drawing area")
        draw.addRow("Area", self.grid_size)
        buttons = QtWidgets.QHBoxLayout()
        self.clear_button = QtWidgets.QPushButton("Clear")
        self.clear_button.clicked.connect(self.clear_drawing)
        buttons.addWidget(self.clear_button)
        draw.addRow(buttons)
        self.draw_hint = QtWidgets.QLabel("Choose “Drawn” to paint a grain of your own, "
                                          "starting from the current shape.")
        self.draw_hint.setWordWrap(True)

        right = QtWidgets.QVBoxLayout()
        right.addLayout(form)
        right.addWidget(self.draw_box)
        right.addWidget(self.draw_hint)
        right.addStretch(1)
        self.use_button = QtWidgets.QPushButton("Use for the Grain tool")
        self.use_button.setDefault(True)
        self.save_button = QtWidgets.QPushButton("Save to library")
        self.delete_button = QtWidgets.QPushButton("Delete from library")
        close = QtWidgets.QPushButton("Close")
        self.use_button.clicked.connect(self.use)
        self.save_button.clicked.connect(self.save)
        self.delete_button.clicked.connect(self.delete)
        close.clicked.connect(self.close)
        for b in (self.use_button, self.save_button, self.delete_button, close):
            right.addWidget(b)
        layout = QtWidgets.QHBoxLayout(self)
        layout.addLayout(left, 1)
        layout.addLayout(right)

        for w in (self.size_box, self.aspect, self.sides, self.angle, self.fixed_level):
            w.valueChanged.connect(self.refresh)
        self.shape_box.currentIndexChanged.connect(self._shape_changed)
        self.level_mode.currentIndexChanged.connect(self.refresh)
        self.pen_level.valueChanged.connect(lambda v: setattr(self.view, "draw_level", v))
        self.grid_size.valueChanged.connect(self._resize_drawing)
        self.set_grain(grain)
        self.resize(680, 460)

    @staticmethod
    def _spin(lo, hi, suffix, tip) -> QtWidgets.QSpinBox:
        s = QtWidgets.QSpinBox()
        s.setRange(lo, hi)
        s.setSuffix(suffix)
        s.setToolTip(tip)
        return s

    # -- the grain in the form --------------------------------------------------------------------
    def set_grain(self, grain: GrainType) -> None:
        self._loading = True
        self.name.setText(grain.name)
        self.shape_box.setCurrentIndex(self.shape_box.findData(grain.shape))
        self.size_box.setValue(grain.size)
        self.aspect.setValue(round(grain.aspect * 100))
        self.sides.setValue(grain.sides)
        self.angle.setValue(round(grain.angle) if grain.angle <= 180 else round(grain.angle) - 360)
        mode = "fixed" if grain.level is not None else "own" if grain.own_levels else "palette"
        self.level_mode.setCurrentIndex(self.level_mode.findData(mode))
        self.fixed_level.setValue(grain.level if grain.level is not None else self.level)
        self._geometric = grain.shape if grain.shape != "bitmap" else "circle"
        if grain.shape == "bitmap":
            self._load_drawing(grains.bitmap_levels(grain.bitmap))
        self._loading = False
        self.refresh()

    def grain(self) -> GrainType:
        """The grain the form describes (InputError when it describes none)."""
        shape, mode = self.shape_box.currentData(), self.level_mode.currentData()
        bitmap = grains.format_bitmap(self.drawing) if shape == "bitmap" else None
        size = max(grains.parse_bitmap(bitmap).shape) if bitmap else self.size_box.value()
        return GrainType(self.name.text().strip() or "My grain", shape, size,
                         self.aspect.value() / 100, self.sides.value(),
                         float(self.angle.value()) if shape != "bitmap" else 0.0,
                         self.fixed_level.value() if mode == "fixed" else None,
                         mode == "own" and shape == "bitmap", bitmap)

    def refresh(self) -> None:
        if self._loading:
            return
        shape = self.shape_box.currentData()
        drawn = shape == "bitmap"
        for w in (self.aspect,):
            w.setEnabled(shape in ("rectangle", "circle", "diamond", "hexagon", "polygon"))
        self.sides.setEnabled(shape == "polygon")
        self.size_box.setEnabled(not drawn)
        self.angle.setEnabled(not drawn)
        own = self.level_mode.findData("own")
        self.level_mode.model().item(own).setEnabled(drawn)
        if not drawn and self.level_mode.currentIndex() == own:
            self.level_mode.setCurrentIndex(self.level_mode.findData("palette"))
        self.fixed_level.setEnabled(self.level_mode.currentData() == "fixed")
        self.draw_box.setVisible(drawn)
        self.draw_hint.setVisible(not drawn)
        try:
            grain = self.grain()
        except TexeditorError as exc:
            self.info.setText(f"<span style='color:#c33'>{exc}</span>")
            self.view.show_grain(self.drawing, self.drawing > 0, self.palette_rgb, drawn)
            return
        if drawn:
            self.view.show_grain(self.drawing, self.drawing > 0, self.palette_rgb, True)
        else:
            self.view.show_grain(grain.values(self.level), grain.mask(), self.palette_rgb, False)
        mask = grain.mask()
        cy, cx = grains.centre_of_gravity(mask)
        self.info.setText(f"{int(mask.sum())} points in a {mask.shape[1]}×{mask.shape[0]} box; "
                          f"centre of gravity at x {cx:.1f}, y {cy:.1f}. The red square lands "
                          f"on the clicked cell.")
        stored = self.library.is_standard(grain.name)
        self.delete_button.setEnabled(not stored)
        self.save_button.setToolTip("Standard grains are kept as they are: give yours a new "
                                    "name" if stored else "Keep this grain in your library")

    def _shape_changed(self) -> None:
        if self._loading:
            return
        shape = self.shape_box.currentData()
        if shape != "bitmap":
            self._geometric = shape
        elif not self.drawing.any():
            self._draw_from(self._geometric)
        self.refresh()

    def _draw_from(self, shape: str) -> None:
        """Switching to “Drawn” starts from the shape that was there (then edit it point by
        point)."""
        grain = GrainType("start", shape, min(self.size_box.value(), grains.MAX_BITMAP_SIDE - 2),
                          self.aspect.value() / 100, self.sides.value(),
                          float(self.angle.value()))
        pen = self.fixed_level.value() if self.level_mode.currentData() == "fixed" \
            else self.pen_level.value()
        self._load_drawing(np.where(grain.mask(), max(1, pen), 0).astype(np.uint8))

    def _load_drawing(self, levels: np.ndarray) -> None:
        n = max(self.grid_size.minimum(), *levels.shape)
        n = min(n + 2, grains.MAX_BITMAP_SIDE)
        self.drawing = np.zeros((n, n), np.uint8)
        h, w = levels.shape
        t, l = (n - h) // 2, (n - w) // 2
        self.drawing[t:t + h, l:l + w] = levels[:n, :n]
        was = self._loading
        self._loading = True
        self.grid_size.setValue(n)
        self._loading = was

    def _resize_drawing(self, n: int) -> None:
        if self._loading:
            return
        old = self.drawing
        new = np.zeros((n, n), np.uint8)
        h, w = min(n, old.shape[0]), min(n, old.shape[1])
        new[:h, :w] = old[:h, :w]
        self.drawing = new
        self.refresh()

    def _drawing_changed(self) -> None:
        self.drawing = self.view.levels
        self.refresh()

    def clear_drawing(self) -> None:
        self.drawing[:] = 0
        self.refresh()

    # -- buttons -----------------------------------------------------------------------------------
    def _checked_grain(self) -> GrainType | None:
        try:
            return self.grain()
        except TexeditorError as exc:
            QtWidgets.QMessageBox.warning(self, "Not a grain yet", str(exc))
            return None

    def use(self) -> None:
        grain = self._checked_grain()
        if grain is not None:
            self.chosen.emit(grain)

    def save(self) -> None:
        grain = self._checked_grain()
        if grain is None:
            return
        try:
            self.library.save(grain)
        except TexeditorError as exc:
            QtWidgets.QMessageBox.warning(self, "Cannot save this grain", str(exc))
            return
        self.libraryChanged.emit()
        self.chosen.emit(grain)
        self.info.setText(f"Saved “{grain.name}” in {self.library.path}.")

    def delete(self) -> None:
        name = self.name.text().strip()
        try:
            self.library.remove(name)
        except TexeditorError as exc:
            QtWidgets.QMessageBox.warning(self, "Cannot delete this grain", str(exc))
            return
        self.libraryChanged.emit()
        self.info.setText(f"Deleted “{name}” from your library.")
