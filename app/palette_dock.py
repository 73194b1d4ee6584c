"""The palette dock: the G levels as swatches, the current level and its hue, saturation and
value, and the grey-scale controls.

It turns clicks into a current level and colour edits into palettes the main window submits as
SetPalette Actions; while a slider is dragged it only previews on the canvas (digest §8: the
extremes of the grey scale are also the contrast control). While the tools paint on the colour
plates, it shows and edits the plate colours instead (the main window says which).
"""

from __future__ import annotations

import colorsys

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from .widgets import scrolled, tight_vertically

SWATCH = 34        # pixels per swatch side
COLUMNS = 8        # swatches per row (G ≤ 16: at most two rows)
COMMIT_DELAY_MS = 350


def grey_scale(levels: int, darkest: int, lightest: int, contrast: int) -> np.ndarray:
    """G greys from ``darkest`` to ``lightest``; contrast -100..100 bends the ramp into an S
    (positive: middle levels pushed towards the extremes) or flattens it towards mid-grey."""
    t = np.linspace(0.0, 1.0, levels)
    a = np.exp(1.5 * contrast / 100.0)
    curved = t**a / (t**a + (1 - t) ** a)
    grey = np.round(darkest + (lightest - darkest) * curved)
    return np.repeat(np.clip(grey, 0, 255).astype(np.uint8)[:, None], 3, axis=1)


def fit_grey_scale(palette, contrast_hint: int = 0) -> tuple[int, int, int]:
    """The (darkest, lightest, contrast) whose grey_scale() is nearest the palette's greys (its
    luminance, for a colour palette): the sliders' state derived from the document. Among equal
    fits (two levels have no middle to bend) the contrast nearest ``contrast_hint`` wins."""
    pal = np.asarray(palette, np.float64).reshape(-1, 3)
    grey = np.round(pal @ np.array([0.299, 0.587, 0.114]))
    darkest, lightest = int(grey[0]), int(grey[-1])
    if len(grey) < 3 or darkest == lightest:
        return darkest, lightest, int(contrast_hint)
    cs = np.arange(-100, 101)
    t = np.linspace(0.0, 1.0, len(grey))[None, :]
    a = np.exp(1.5 * cs / 100.0)[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        curved = t**a / (t**a + (1 - t) ** a)
    ramps = np.clip(np.round(darkest + (lightest - darkest) * curved), 0, 255)
    error = np.abs(ramps - grey[None, :]).max(axis=1)
    best = np.flatnonzero(error == error.min())
    return darkest, lightest, int(cs[best[np.argmin(np.abs(cs[best] - contrast_hint))]])


def hsv_of(rgb) -> tuple[float, float, float]:
    """(hue in degrees 0..360, saturation 0..100 %, value 0..100 %) of an RGB colour 0..255."""
    h, s, v = colorsys.rgb_to_hsv(*(int(c) / 255.0 for c in rgb))
    return h * 360.0, s * 100.0, v * 100.0


def rgb_of(hsv) -> tuple[int, int, int]:
    """The RGB colour 0..255 of (hue°, saturation %, value %), each component rounded."""
    h, s, v = hsv
    return tuple(int(round(c * 255)) for c in colorsys.hsv_to_rgb((h % 360) / 360.0, s / 100.0,
                                                                    v / 100.0))


def text_colour(rgb) -> QtGui.QColor:
    r, g, b = (int(c) for c in rgb)
    return QtGui.QColor("black") if 0.299 * r + 0.587 * g + 0.114 * b > 140 else QtGui.QColor("white")


class SwatchBar(QtWidgets.QWidget):
    """The swatches, numbered by level; click selects, double-click asks for a new colour."""

    levelClicked = QtCore.Signal(int)
    levelDoubleClicked = QtCore.Signal(int)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.palette_rgb = np.zeros((2, 3), np.uint8)
        self.current = 1
        self.setSizePolicy(QtWidgets.QSizePolicy.Policy.Preferred,
                           QtWidgets.QSizePolicy.Policy.Fixed)
        self.setToolTip("Click: current level · Double-click: edit the colour")

    def set_palette(self, palette: np.ndarray) -> None:
        self.palette_rgb = np.asarray(palette, np.uint8)
        self.current = min(self.current, len(self.palette_rgb) - 1)
        self.setFixedHeight(self.sizeHint().height())
        self.update()

    def swatch_rect(self, level: int) -> QtCore.QRect:
        row, col = divmod(level, COLUMNS)
        return QtCore.QRect(2 + col * (SWATCH + 4), 2 + row * (SWATCH + 4), SWATCH, SWATCH)

    def sizeHint(self) -> QtCore.QSize:
        rows = (len(self.palette_rgb) + COLUMNS - 1) // COLUMNS
        return QtCore.QSize(COLUMNS * (SWATCH + 4) + 4, rows * (SWATCH + 4) + 4)

    def level_at(self, pos: QtCore.QPoint) -> int | None:
        for level in range(len(self.palette_rgb)):
            if self.swatch_rect(level).contains(pos):
                return level
        return None

    def paintEvent(self, ev):
        p = QtGui.QPainter(self)
        p.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing, False)
        font = p.font()
        font.setBold(True)
        p.setFont(font)
        for level, rgb in enumerate(self.palette_rgb):
            rect = self.swatch_rect(level)
            p.fillRect(rect, QtGui.QColor(*(int(c) for c in rgb)))
            p.setPen(QtGui.QPen(self.palette().color(QtGui.QPalette.ColorRole.Mid), 1))
            p.drawRect(rect.adjusted(0, 0, -1, -1))
            p.setPen(text_colour(rgb))
            p.drawText(rect, QtCore.Qt.AlignmentFlag.AlignCenter, str(level))
            if level == self.current:
                p.setPen(QtGui.QPen(self.palette().color(QtGui.QPalette.ColorRole.Highlight), 3))
                p.drawRect(rect.adjusted(-1, -1, 0, 0))
        p.end()

    def mousePressEvent(self, ev):
        level = self.level_at(ev.position().toPoint())
        if level is not None and ev.button() == QtCore.Qt.MouseButton.LeftButton:
            self.current = level
            self.update()
            self.levelClicked.emit(level)

    def mouseDoubleClickEvent(self, ev):
        level = self.level_at(ev.position().toPoint())
        if level is not None:
            self.levelDoubleClicked.emit(level)


class PaletteDock(QtWidgets.QDockWidget):
    """Signals: ``committed(palette)`` for a SetPalette action, ``preview(palette)`` while
    dragging (display only), ``currentLevelChanged(level)``."""

    committed = QtCore.Signal(object)
    preview = QtCore.Signal(object)
    currentLevelChanged = QtCore.Signal(int)

    def __init__(self, parent=None):
        super().__init__("Palette", parent)
        self.setObjectName("PaletteDock")
        self.palette_rgb = np.zeros((2, 3), np.uint8)
        self.plates_mode = False
        self._value_labels: dict[QtWidgets.QSlider, QtWidgets.QLabel] = {}
        # among contrasts that give the same greys (rounding), the one this palette was made or
        # first shown with: the same palette always shows the same sliders (undo, redo)
        self._contrast_of: dict[bytes, int] = {}
        body = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(body)
        tight_vertically(layout)
        self.swatches = SwatchBar()
        self.swatches.levelClicked.connect(self._level_clicked)
        self.swatches.levelDoubleClicked.connect(self.edit_colour)
        layout.addWidget(self.swatches)
        self.current_label = QtWidgets.QLabel()
        layout.addWidget(self.current_label)

        self._hsv = (0.0, 0.0, 0.0)   # the current level's colour, exact: only what is moved moves
        row = QtWidgets.QHBoxLayout()
        self.hue, self.saturation, self.value = (
            self._hsv_box(row, name, hi, suffix, k, tip) for k, (name, hi, suffix, tip) in
            enumerate((("H", 359, "°", "Hue of the current level, degrees round the colour "
                        "wheel (0 red, 120 green, 240 blue)"),
                       ("S", 100, " %", "Saturation of the current level: 0 % a grey, 100 % "
                        "the pure hue"),
                       ("V", 100, " %", "Value of the current level: 0 % black, 100 % the "
                        "brightest colour of this hue and saturation"))))
        layout.addLayout(row)
        self._hsv_timer = QtCore.QTimer(self, singleShot=True, interval=COMMIT_DELAY_MS)
        self._hsv_timer.timeout.connect(self._commit_hsv)

        group = self.grey_group = QtWidgets.QGroupBox("Grey scale")
        form = QtWidgets.QFormLayout(group)
        self.darkest = self._slider(0, 255, 0, "Grey of level 0 (the background)")
        self.lightest = self._slider(0, 255, 255, "Grey of the highest level")
        self.contrast = self._slider(-100, 100, 0, "Spread of the middle levels: "
                                                  "+ towards the extremes, − towards mid-grey")
        self.reset_button = QtWidgets.QPushButton("Reset")
        self.reset_button.setToolTip("Reset to a full grey ramp: black to white, contrast 0")
        self.reset_button.clicked.connect(self.reset_grey_scale)
        form.addRow("Darkest", self._with_value(self.darkest))
        form.addRow("Lightest", self._with_value(self.lightest))
        form.addRow("Contrast", self._with_value(self.contrast, self.reset_button))  # a row less:
        #                                  the dock keeps its height beside the History's rows
        layout.addWidget(group)
        layout.addStretch(1)
        body.setSizePolicy(QtWidgets.QSizePolicy.Policy.Preferred,
                           QtWidgets.QSizePolicy.Policy.Maximum)
        self.setWidget(scrolled(body))

        self._commit_timer = QtCore.QTimer(self, singleShot=True, interval=COMMIT_DELAY_MS)
        self._commit_timer.timeout.connect(self._commit_grey_scale)

    # -- building ---------------------------------------------------------------------------------
    def _slider(self, lo, hi, value, tip) -> QtWidgets.QSlider:
        s = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        s.setRange(lo, hi)
        s.setValue(value)
        s.setToolTip(tip)
        s.valueChanged.connect(self._grey_scale_moved)
        s.sliderReleased.connect(self._commit_grey_scale)
        return s

    def _hsv_box(self, row, name, hi, suffix, component, tip) -> QtWidgets.QSpinBox:
        """A spin box for one HSV component (wrapping round for the hue), after its name."""
        spin = QtWidgets.QSpinBox()
        spin.setRange(0, hi)
        spin.setSuffix(suffix)
        spin.setToolTip(tip)
        spin.setWrapping(component == 0)
        spin.valueChanged.connect(lambda v, k=component: self._hsv_moved(k, v))
        label = QtWidgets.QLabel(name)
        label.setToolTip(tip)
        label.setBuddy(spin)
        row.addWidget(label)
        row.addWidget(spin, 1)
        return spin

    def _with_value(self, slider, *after) -> QtWidgets.QWidget:
        """The slider, its value, and ``after`` (widgets) on one row."""
        box = QtWidgets.QWidget()
        row = QtWidgets.QHBoxLayout(box)
        row.setContentsMargins(0, 0, 0, 0)
        label = QtWidgets.QLabel(str(slider.value()))
        label.setMinimumWidth(QtGui.QFontMetrics(label.font()).horizontalAdvance("-100") + 4)
        label.setAlignment(QtCore.Qt.AlignmentFlag.AlignRight | QtCore.Qt.AlignmentFlag.AlignVCenter)
        slider.valueChanged.connect(lambda v: label.setText(str(v)))
        self._value_labels[slider] = label
        row.addWidget(slider, 1)
        row.addWidget(label)
        for widget in after:
            row.addWidget(widget)
        return box

    # -- state from the document --------------------------------------------------------------------
    def set_palette(self, palette) -> None:
        """Show the document's palette (after any change, undo included) without emitting."""
        self.palette_rgb = np.array(palette, np.uint8)
        self.swatches.set_palette(self.palette_rgb)
        grey = self.palette_rgb[:, 0]
        is_grey = bool(np.all(self.palette_rgb == grey[:, None]))
        self.grey_group.setTitle("Grey scale" if is_grey else "Grey scale (replaces the colours)")
        # every slider shows the document's palette (undo, redo, replay, open), never a value
        # kept from an earlier edit; a grey-scale edit still settling (keys, a drag) is left be
        if not (self._commit_timer.isActive()
                or any(s.isSliderDown() for s in (self.darkest, self.lightest, self.contrast))):
            key = self.palette_rgb.tobytes()      # the contrast a palette was made with
            values = fit_grey_scale(self.palette_rgb, self._contrast_of.get(
                key, self.contrast.value()))
            self._contrast_of.setdefault(key, values[2])
            for slider, value in zip((self.darkest, self.lightest, self.contrast), values):
                slider.blockSignals(True)
                slider.setValue(int(value))
                slider.blockSignals(False)
        self._refresh_value_labels()
        self._show_current()

    def set_plates_mode(self, plates: bool) -> None:
        """Show the plate colours (the tools paint on the plates) or the texture's palette;
        the grey scale is the texture's own (plates keep their colours)."""
        self.setWindowTitle("Palette — plate colours" if plates else "Palette")
        self.grey_group.setVisible(not plates)
        self.plates_mode = plates

    def _refresh_value_labels(self) -> None:
        for slider, label in self._value_labels.items():   # valueChanged was blocked
            label.setText(str(slider.value()))

    @property
    def current_level(self) -> int:
        return self.swatches.current

    def _level_clicked(self, level: int) -> None:
        self._show_current()
        self.currentLevelChanged.emit(level)

    def _show_current(self) -> None:
        level = self.swatches.current
        r, g, b = (int(c) for c in self.palette_rgb[level])
        what = "plate" if self.plates_mode else "level"
        self.current_label.setText(f"Current {what} {level}  ·  #{r:02x}{g:02x}{b:02x}")
        if not self._hsv_timer.isActive():
            self._show_hsv()

    def _show_hsv(self) -> None:
        """The HSV controls show the current level's colour (after a click, undo, a replay)."""
        self._hsv = hsv_of(self.palette_rgb[self.swatches.current])
        for box, value in zip((self.hue, self.saturation, self.value), self._hsv):
            box.blockSignals(True)
            box.setValue(int(round(value)) % (box.maximum() + 1))
            box.blockSignals(False)

    # -- edits ------------------------------------------------------------------------------------
    def edit_colour(self, level: int) -> None:
        """Ask for a new colour of one level (a colour dialog); a choice commits a palette."""
        self.swatches.current = level
        self._level_clicked(level)
        old = QtGui.QColor(*(int(c) for c in self.palette_rgb[level]))
        colour = QtWidgets.QColorDialog.getColor(old, self, f"Colour of level {level}")
        if not colour.isValid() or colour == old:
            return
        palette = self.palette_rgb.copy()
        palette[level] = (colour.red(), colour.green(), colour.blue())
        self.committed.emit(palette)

    def grey_scale(self) -> np.ndarray:
        return grey_scale(len(self.palette_rgb), self.darkest.value(), self.lightest.value(),
                          self.contrast.value())

    def reset_grey_scale(self) -> None:
        for slider, value in ((self.darkest, 0), (self.lightest, 255), (self.contrast, 0)):
            slider.blockSignals(True)
            slider.setValue(value)
            slider.blockSignals(False)
        self._refresh_value_labels()
        self._commit_grey_scale()

    def _grey_scale_moved(self, _value) -> None:
        self.preview.emit(self.grey_scale())
        if not any(s.isSliderDown() for s in (self.darkest, self.lightest, self.contrast)):
            self._commit_timer.start()    # keyboard or click steps: one action once they settle

    def flush(self) -> None:
        """Commit a grey-scale or colour edit still settling, before the history goes back
        (undo, a step clicked): landing after it, the edit would drop the steps just undone."""
        if self._commit_timer.isActive():
            self._commit_grey_scale()
        if self._hsv_timer.isActive():
            self._commit_hsv()

    def hsv_palette(self) -> np.ndarray:
        """The palette with the current level in the colour the HSV controls show."""
        palette = self.palette_rgb.copy()
        palette[self.swatches.current] = rgb_of(self._hsv)
        return palette

    def _hsv_moved(self, component: int, value: int) -> None:
        hsv = list(self._hsv)
        hsv[component] = float(value)
        self._hsv = tuple(hsv)
        self.preview.emit(self.hsv_palette())
        self._hsv_timer.start()           # typed or stepped: one action once it settles

    def _commit_hsv(self) -> None:
        self._hsv_timer.stop()
        palette = self.hsv_palette()
        if not np.array_equal(palette, self.palette_rgb):
            self.committed.emit(palette)

    def _commit_grey_scale(self) -> None:
        self._commit_timer.stop()
        palette = self.grey_scale()
        if not np.array_equal(palette, self.palette_rgb):
            self._contrast_of[palette.tobytes()] = self.contrast.value()
            self.committed.emit(palette)
