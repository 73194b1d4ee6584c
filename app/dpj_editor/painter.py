"""The probability palette (thesis §5.2.2, Fig. 5.2): paint one window configuration, give it a
probability, put it in the DPJ.

It sits at the start of hand entry: the painted u×v configuration and its probability leave as
``setRequested``/``removeRequested`` signals; the editor turns them into undoable DPJ edits.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from ..palette_dock import SwatchBar, text_colour

GRID_BOX = 240          # pixels of the enlarged grid's longest side
MAX_CELL = 64
SLIDER_STEPS = 1000     # the slider is the coarse control; the spin box takes exact values
LEFT, RIGHT = QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.MouseButton.RightButton


class ConfigGrid(QtWidgets.QWidget):
    """The enlarged u×v window: left click or drag paints the current level, right click picks
    the level under the cursor. ``changed`` after every painted cell; ``levelPicked(level)``."""

    changed = QtCore.Signal()
    levelPicked = QtCore.Signal(int)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.config = np.zeros((2, 2), np.uint8)
        self.palette_rgb = np.array([[0, 0, 0], [255, 255, 255]], np.uint8)
        self.level = 1
        self.setToolTip("Left: paint the current level (click or drag) · Right: pick a level")
        self.setSizePolicy(QtWidgets.QSizePolicy.Policy.Fixed, QtWidgets.QSizePolicy.Policy.Fixed)
        self._resize()

    @property
    def cell(self) -> int:
        return min(MAX_CELL, GRID_BOX // max(self.config.shape))

    def _resize(self) -> None:
        v, u = self.config.shape
        self.setFixedSize(u * self.cell + 1, v * self.cell + 1)

    def set_window(self, window: tuple[int, int]) -> None:
        u, v = window
        if self.config.shape != (v, u):
            self.config = np.zeros((v, u), np.uint8)
            self._resize()
            self.update()

    def set_palette(self, palette) -> None:
        self.palette_rgb = np.asarray(palette, np.uint8)
        self.config = np.minimum(self.config, len(self.palette_rgb) - 1).astype(np.uint8)
        self.update()

    def set_config(self, config) -> None:
        self.config = np.array(config, np.uint8)
        self._resize()
        self.update()
        self.changed.emit()

    def cell_rect(self, row: int, col: int) -> QtCore.QRect:
        return QtCore.QRect(col * self.cell, row * self.cell, self.cell, self.cell)

    def cell_at(self, pos: QtCore.QPoint) -> tuple[int, int] | None:
        row, col = pos.y() // self.cell, pos.x() // self.cell
        v, u = self.config.shape
        return (row, col) if 0 <= row < v and 0 <= col < u else None

    def paint_cell(self, row: int, col: int) -> None:
        if self.config[row, col] != self.level:
            self.config[row, col] = self.level
            self.update(self.cell_rect(row, col))
            self.changed.emit()

    def mousePressEvent(self, ev) -> None:
        cell = self.cell_at(ev.position().toPoint())
        if cell is None:
            return
        if ev.button() == LEFT:
            self.paint_cell(*cell)
        elif ev.button() == RIGHT:
            self.levelPicked.emit(int(self.config[cell]))

    def mouseMoveEvent(self, ev) -> None:
        cell = self.cell_at(ev.position().toPoint())
        if cell is not None and ev.buttons() & LEFT:
            self.paint_cell(*cell)

    def paintEvent(self, ev) -> None:
        p = QtGui.QPainter(self)
        font = p.font()
        font.setPointSizeF(max(7.0, self.cell / 4))
        p.setFont(font)
        lines = QtGui.QPen(QtGui.QColor(120, 120, 120), 1)
        for (row, col), level in np.ndenumerate(self.config):
            rect = self.cell_rect(row, col)
            rgb = self.palette_rgb[min(level, len(self.palette_rgb) - 1)]
            p.fillRect(rect, QtGui.QColor(*(int(c) for c in rgb)))
            p.setPen(lines)
            p.drawRect(rect)
            p.setPen(text_colour(rgb))
            p.drawText(rect, QtCore.Qt.AlignmentFlag.AlignCenter, str(level))
        p.end()


class ProbabilityField(QtWidgets.QWidget):
    """A probability: a spin box for exact values and a slider for quick ones, kept in step."""

    changed = QtCore.Signal(float)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.spin = QtWidgets.QDoubleSpinBox()
        self.spin.setDecimals(8)
        self.spin.setRange(0.0, 1.0)
        self.spin.setSingleStep(0.01)
        self.spin.setToolTip("The probability of the painted configuration (exact entry)")
        self.slider = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        self.slider.setRange(0, SLIDER_STEPS)
        self.slider.setToolTip("Drag for a quick value; type in the box for an exact one")
        self.spin.valueChanged.connect(self._spin_moved)
        self.slider.valueChanged.connect(self._slider_moved)
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        row.addWidget(self.spin)
        row.addWidget(self.slider, 1)

    def value(self) -> float:
        return self.spin.value()

    def set_value(self, p: float) -> None:
        self.spin.setValue(float(p))

    def _spin_moved(self, p: float) -> None:
        self.slider.blockSignals(True)
        self.slider.setValue(round(p * SLIDER_STEPS))
        self.slider.blockSignals(False)
        self.changed.emit(p)

    def _slider_moved(self, k: int) -> None:
        self.spin.setValue(k / SLIDER_STEPS)


class PainterPanel(QtWidgets.QWidget):
    """The grid, the level swatches, the probability and the Add/Set and Remove buttons.

    Digit keys choose the current level. Signals: ``setRequested(config, p)``,
    ``removeRequested(config)``.
    """

    setRequested = QtCore.Signal(object, float)
    removeRequested = QtCore.Signal(object)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.dpj = None
        self.grid = ConfigGrid()
        self.swatches = SwatchBar()
        self.swatches.levelClicked.connect(self.set_level)
        self.grid.levelPicked.connect(self.set_level)
        self.grid.changed.connect(self._show_entry)
        self.level_label = QtWidgets.QLabel()
        self.fill_button = QtWidgets.QPushButton("Fill")
        self.fill_button.setToolTip("Paint every cell with the current level")
        self.fill_button.clicked.connect(self.fill)
        self.clear_button = QtWidgets.QPushButton("Clear")
        self.clear_button.setToolTip("Every cell level 0 (the empty configuration)")
        self.clear_button.clicked.connect(
            lambda: self.grid.set_config(np.zeros_like(self.grid.config)))
        self.entry_label = QtWidgets.QLabel()
        self.entry_label.setWordWrap(True)
        self.probability = ProbabilityField()
        self.set_button = QtWidgets.QPushButton("Add / Set")
        self.set_button.setDefault(True)
        self.set_button.setToolTip("Put the painted configuration in the DPJ with this "
                                   "probability (Enter)")
        self.set_button.clicked.connect(self.request_set)
        self.remove_button = QtWidgets.QPushButton("Remove")
        self.remove_button.setToolTip("Take the painted configuration out of the DPJ")
        self.remove_button.clicked.connect(lambda: self.removeRequested.emit(self.config()))
        self.probability.spin.lineEdit().returnPressed.connect(self.request_set)
        self._layout()
        self.setFocusPolicy(QtCore.Qt.FocusPolicy.StrongFocus)
        self.set_level(1)

    def _layout(self) -> None:
        layout = QtWidgets.QVBoxLayout(self)
        centre = QtWidgets.QHBoxLayout()
        centre.addStretch(1)
        centre.addWidget(self.grid)
        centre.addStretch(1)
        layout.addLayout(centre)
        layout.addWidget(self.swatches)
        tools = QtWidgets.QHBoxLayout()
        tools.addWidget(self.level_label, 1)
        tools.addWidget(self.fill_button)
        tools.addWidget(self.clear_button)
        layout.addLayout(tools)
        layout.addWidget(self.entry_label)
        form = QtWidgets.QFormLayout()
        form.addRow("Probability", self.probability)
        layout.addLayout(form)
        buttons = QtWidgets.QHBoxLayout()
        buttons.addWidget(self.set_button, 1)
        buttons.addWidget(self.remove_button)
        layout.addLayout(buttons)
        layout.addStretch(1)

    # -- state -------------------------------------------------------------------------------------
    def set_dpj(self, dpj) -> None:
        """Follow the DPJ being edited: its window, its palette, the painted entry's probability."""
        self.dpj = dpj
        self.grid.set_window(dpj.window)
        if not np.array_equal(self.swatches.palette_rgb, dpj.palette):
            self.swatches.set_palette(dpj.palette)
            self.grid.set_palette(dpj.palette)
        self.set_level(min(self.grid.level, dpj.levels - 1))
        self._show_entry()

    def config(self) -> np.ndarray:
        return self.grid.config.copy()

    def load(self, config, p: float) -> None:
        """Show an entry of the table: its configuration and probability."""
        self.grid.set_config(config)
        self.probability.set_value(p)

    def set_level(self, level: int) -> None:
        self.grid.level = int(level)
        self.swatches.current = int(level)
        self.swatches.update()
        self.level_label.setText(f"Painting level {level}")

    def fill(self) -> None:
        self.grid.set_config(np.full_like(self.grid.config, self.grid.level))

    def request_set(self) -> None:
        self.setRequested.emit(self.config(), self.probability.value())

    def _show_entry(self) -> None:
        if self.dpj is None:
            return
        p = self.dpj.prob(self.grid.config)
        if p:
            total = self.dpj.total
            self.entry_label.setText(f"In the DPJ: p = {p:.6g} "
                                     f"({100 * p / total:.3g} % of the sum)")
        else:
            self.entry_label.setText("Not in the DPJ yet")
        self.remove_button.setEnabled(bool(p))

    def keyPressEvent(self, ev) -> None:
        text = ev.text().upper()
        if self.dpj is not None and len(text) == 1 and text in "0123456789ABCDEF"[:self.dpj.levels]:
            self.set_level(int(text, 16))
        else:
            super().keyPressEvent(ev)
