"""The Grain rendering dock (thesis §5.3, §5.4.1): the texture's grain shape, size and orientation,
a grain of its own for any level, its explosion and compression, with a live preview; each
committed setting is one Action.

A texture is "its DPJ, its grain and density parameters and its actions" (§5.4.2): the dock edits
*the* RenderGrains step of the log — the last one since the texture was synthesised. With none,
the first setting appends one; after that, a new setting replaces that step and the edits made
after it are replayed on the new canvas (the main window's edit_step, in the worker). So Ctrl+Z
always returns to the normalised texture, whatever the number of settings tried.
"""

from __future__ import annotations

import time

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor import warmup
from texeditor.errors import TexeditorError
from texeditor.paint.grains import GrainType, grain_spec
from texeditor.texture.grain_render import (LATTICES, MAX_COMPRESSION, MAX_EXPLOSION, MAX_GRAIN,
                                            OVERLAP_RULES, check_size, parse_level_grains)
from texeditor.texture.actions import RenderGrains

from .images import qimage_from_rgb
from .widgets import scrolled

SHAPES = [("Square", "square"), ("Rectangle", "rectangle"), ("Circle / ellipse", "circle"),
          ("Diamond", "diamond"), ("Hexagon (honeycomb)", "hexagon"),
          ("Regular polygon", "polygon"), ("Line", "line"), ("Drawn grain", "bitmap")]
OVERLAPS = [("Later grain wins", "last"), ("Highest level", "max"), ("Lowest level", "min")]
LATTICE_NAMES = [("Automatic", "auto"), ("Grid", "grid"), ("Honeycomb", "honeycomb")]
PREVIEW = 200                 # preview side, pixels (shown 1:1: the real grain)
PREVIEW_DELAY_MS = 40
COMMIT_DELAY_MS = 600         # a setting typed or stepped with keys is committed after a pause
LARGE_PIXELS = 16 * 2**20     # an output beyond 4096² is called large before it is made
WORKER_COST = 1e7             # render_cost (~0.3 s per 10^8) above which the render runs in the
WORKER_PIXELS = 2**22         # worker with progress and Cancel; also any output over 4 M pixels
assert [v for _, v in OVERLAPS] == list(OVERLAP_RULES) and [v for _, v in LATTICE_NAMES] == \
    list(LATTICES)


def output_text(action: RenderGrains, texture_shape: tuple[int, int]) -> str:
    """What a render will make, and why, said before it is made: "Output 4608×3584 px: 9×7
    pixels a point of the 512×512 texture (grain 8 px, explosion 1.9×1)…", with a warning when
    the picture is large or beyond the canvas limits."""
    lat = action.grain_lattice()
    h, w = texture_shape
    oh, ow = lat.shape(texture_shape)
    why = [f"{action.shape} grain {action.size} px"]
    if action.level_grains:
        why.append("own grains for levels " + ", ".join(map(str, action.level_masks())))
    if action.explosion_x != 1 or action.explosion_y != 1:
        why.append(f"explosion {action.explosion_x:g}×{action.explosion_y:g}")
    if action.compression or action.compression_x:
        why.append(f"compression {action.compression_text()}")
    scale = f"{lat.pitch_x}×" if lat.pitch_x == lat.pitch_y else f"{lat.pitch_x}×{lat.pitch_y}"
    text = (f"Output <b>{ow}×{oh}</b> px: {scale} the {w}×{h} texture ({', '.join(why)}); one "
            f"grain every {lat.pitch_x}×{lat.pitch_y} px" + (", odd rows shifted" if
                                                            lat.row_offset else ""))
    try:
        check_size(texture_shape, lat)
    except TexeditorError as exc:
        return text + f"<br><span style='color:#b00020'>{exc}</span>"
    if oh * ow > LARGE_PIXELS:
        text += (f"<br><span style='color:#b35c00'>Large: {oh * ow / 2**20:.0f} M pixels; "
                 "rendering and every later step will be slower. Smaller grains or less "
                 "explosion make a smaller picture.</span>")
    return text


def grain_step(history) -> int | None:
    """The index of the texture's grain step: the last RenderGrains applied since the last
    synthesis or new canvas (None when the texture is still normalised)."""
    for i in range(history.index - 1, -1, -1):
        action = history.actions[i]
        if isinstance(action, RenderGrains):
            return i
        if action.EFFECT == "reset":
            return None
    return None


class ValueSlider(QtWidgets.QWidget):
    """A slider for a number (``scale`` steps per unit) with its value written beside it."""

    changed = QtCore.Signal()
    released = QtCore.Signal()

    def __init__(self, lo: float, hi: float, scale: int = 1, fmt: str = "{:g}", suffix=""):
        super().__init__()
        self.scale, self.fmt, self.suffix = scale, fmt, suffix
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        self.slider = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        self.slider.setRange(round(lo * scale), round(hi * scale))
        self.slider.setPageStep(max(1, scale // 2) if scale > 1 else 2)
        self.label = QtWidgets.QLabel()
        width = max(len(self._text(v)) for v in (lo, hi, (lo + hi) / 3))
        self.label.setMinimumWidth(QtGui.QFontMetrics(self.label.font()).horizontalAdvance(
            "0" * (width + 1)))
        self.label.setAlignment(QtCore.Qt.AlignmentFlag.AlignRight
                                | QtCore.Qt.AlignmentFlag.AlignVCenter)
        row.addWidget(self.slider, 1)
        row.addWidget(self.label)
        self.slider.valueChanged.connect(self._moved)
        self.slider.sliderReleased.connect(self.released)
        self._moved()

    def _text(self, value: float) -> str:
        return self.fmt.format(value) + self.suffix

    def _moved(self) -> None:
        self.label.setText(self._text(self.value()))
        self.changed.emit()

    def value(self) -> float:
        v = self.slider.value() / self.scale
        return int(v) if self.scale == 1 else v

    def set_value(self, value: float) -> None:
        self.slider.setValue(round(value * self.scale))


class GrainRenderingDock(QtWidgets.QDockWidget):
    """Grain shape, size, orientation; explosion across and down; compression and overlap."""

    def __init__(self, window):
        super().__init__("Grain rendering", window)
        self.setObjectName("GrainDensityDock")          # the name saved layouts know
        self.main_window = window
        self._loading = False
        self._base_key = None
        self._base = None               # (levels, palette) of the normalised texture
        self._bitmap: str | None = None
        self._shown_step = object()     # nothing shown yet
        self._rendering: RenderGrains | None = None   # a render running in the worker
        self._level_grains: dict[int, GrainType] = {}   # the levels with a grain of their own
        self._level_widgets: list[tuple[QtWidgets.QLabel, QtWidgets.QComboBox,
                                        QtWidgets.QSpinBox]] = []
        self._build()
        self.show_action(None)
        self._preview_timer = self._timer(PREVIEW_DELAY_MS, self.update_preview)
        self._commit_timer = self._timer(COMMIT_DELAY_MS, self.commit)
        self.visibilityChanged.connect(lambda shown: shown and self.refresh())
        # a task that ends without changing the history (a cancelled replay of the grain step)
        # must still put the controls back on the document; after the task's own callback
        window.runner.finished.connect(self._refresh_soon)

    # -- construction ------------------------------------------------------------------------------
    def _build(self) -> None:
        body = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(body)
        layout.setContentsMargins(6, 6, 6, 6)
        grain = QtWidgets.QGroupBox("Grain (§5.3.1)")
        form = QtWidgets.QFormLayout(grain)
        self.shape_box = QtWidgets.QComboBox()
        for text, value in SHAPES:
            self.shape_box.addItem(text, value)
        self.shape_box.setToolTip("The shape every point of the normalised texture is drawn with; "
                              "hexagons sit on a honeycomb, continuous in both directions")
        self.size_slider = ValueSlider(1, 32, suffix=" px")
        self.size_slider.setToolTip("Grain diameter in pixels")
        self.angle = ValueSlider(-90, 90, suffix="°")
        self.angle.setToolTip("Orientation: turns every grain counter-clockwise")
        self.aspect = ValueSlider(0.25, 4, 20, "{:.2f}")
        self.aspect.setToolTip("Height ÷ width of a rectangle or an ellipse")
        self.sides = QtWidgets.QSpinBox()
        self.sides.setRange(3, 12)
        self.sides.setValue(5)
        self.sides.setToolTip("Vertices of the regular polygon")
        self.from_tool = QtWidgets.QPushButton("Use the Grain tool's grain")
        self.from_tool.setToolTip("Copy the shape, size, orientation (and drawing) of the grain "
                                  "chosen in the Grain stamps dock")
        form.addRow("Shape", self.shape_box)
        form.addRow("Size", self.size_slider)
        form.addRow("Orientation", self.angle)
        form.addRow("Aspect", self.aspect)
        form.addRow("Sides", self.sides)
        form.addRow(self.from_tool)
        self.per_level = QtWidgets.QGroupBox("Grain per level (§5.3)")
        self.per_level.setToolTip("A level may be drawn with its own grain (a point's state "
                                  "selects its primitive); the others use the grain above")
        self.level_rows = QtWidgets.QGridLayout(self.per_level)
        self.level_rows.setColumnStretch(1, 1)
        density = QtWidgets.QGroupBox("Density (§5.3.2)")
        form = QtWidgets.QFormLayout(density)
        self.explode_x = ValueSlider(1, MAX_EXPLOSION / 2, 10, "{:.1f}", "×")
        self.explode_x.setToolTip("Explosion across: blank space between grains (1× = touching)")
        self.explode_y = ValueSlider(1, MAX_EXPLOSION / 2, 10, "{:.1f}", "×")
        self.explode_y.setToolTip("Explosion down: blank space between rows of grains")
        self.compression = ValueSlider(0, MAX_COMPRESSION, 100, "{:.2f}")
        self.compression.setToolTip("Brings grains together until they overlap; strong, it turns "
                                    "a grain texture into a spot texture")
        self.compression_x = ValueSlider(0, MAX_COMPRESSION, 100, "{:.2f}")
        self.compression_x.setToolTip("Compression across, when it differs from the one down")
        self.same_compression = QtWidgets.QCheckBox("Same as down")
        self.same_compression.setChecked(True)
        self.same_compression.setToolTip("Uncheck to compress across and down apart (along one "
                                         "axis only, as explosion can)")
        self.overlap = QtWidgets.QComboBox()
        for text, value in OVERLAPS:
            self.overlap.addItem(text, value)
        self.overlap.setToolTip("Where compressed grains overlap, which level shows")
        self.lattice = QtWidgets.QComboBox()
        for text, value in LATTICE_NAMES:
            self.lattice.addItem(text, value)
        self.lattice.setToolTip("Automatic: a honeycomb for hexagons, a grid for the others")
        form.addRow("Explosion across", self.explode_x)
        form.addRow("Explosion down", self.explode_y)
        form.addRow("Compression down", self.compression)
        form.addRow("Compression across", self.compression_x)
        form.addRow("", self.same_compression)
        form.addRow("Overlap", self.overlap)
        form.addRow("Lattice", self.lattice)
        self.natural = QtWidgets.QPushButton("Grains touching")
        self.natural.setToolTip("Explosion 1×, no compression")
        form.addRow(self.natural)

        self.preview = QtWidgets.QLabel()
        self.preview.setFixedSize(PREVIEW, PREVIEW)
        self.preview.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.preview.setFrameShape(QtWidgets.QFrame.Shape.StyledPanel)
        self.preview.setToolTip("The top-left corner of the texture with these grains, at 100 %")
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)
        self.info.setTextFormat(QtCore.Qt.TextFormat.RichText)
        layout.addWidget(self.preview, 0, QtCore.Qt.AlignmentFlag.AlignHCenter)
        layout.addWidget(self.info)
        layout.addWidget(grain)
        layout.addWidget(self.per_level)
        layout.addWidget(density)
        layout.addStretch(1)
        self.setWidget(scrolled(body))

        for slider in (self.size_slider, self.angle, self.aspect, self.explode_x, self.explode_y,
                       self.compression, self.compression_x):
            slider.changed.connect(self._edited)
            slider.released.connect(self.commit)
        for combo in (self.shape_box, self.overlap, self.lattice):
            combo.currentIndexChanged.connect(self._edited_now)
        self.sides.valueChanged.connect(self._edited)
        self.same_compression.toggled.connect(self._link_toggled)
        self.from_tool.clicked.connect(self.use_tool_grain)
        self.natural.clicked.connect(self.make_natural)
        self._enable_fields()

    def _timer(self, ms: int, slot) -> QtCore.QTimer:
        timer = QtCore.QTimer(self)
        timer.setSingleShot(True)
        timer.setInterval(ms)
        timer.timeout.connect(slot)
        return timer

    # -- the settings ------------------------------------------------------------------------------
    def params(self) -> dict:
        shape = self.shape_box.currentData()
        return {"shape": shape, "size": self.size_slider.value(), "aspect": self.aspect.value(),
                "sides": self.sides.value(), "angle": float(self.angle.value()),
                "explosion_x": self.explode_x.value(), "explosion_y": self.explode_y.value(),
                "compression": self.compression.value(), "compression_x": self._across(),
                "overlap": self.overlap.currentData(),
                "lattice": self.lattice.currentData(),
                "bitmap": self._bitmap if shape == "bitmap" else None,
                "level_grains": ", ".join(f"{level}: {grain_spec(grain)}" for level, grain in
                                          sorted(self._level_grains.items())) or None}

    def _across(self) -> float | None:
        """The compression across, None while it is the same as down."""
        return None if self.same_compression.isChecked() else self.compression_x.value()

    def action(self) -> RenderGrains | None:
        """The RenderGrains of the current settings (None, explained below the preview, if the
        settings cannot make one)."""
        try:
            return RenderGrains(**self.params())
        except TexeditorError as exc:
            self.info.setText(f"<span style='color:#b00020'>{exc}</span>")
            return None

    def show_action(self, action: RenderGrains | None) -> None:
        """Set the controls from a grain step (or the defaults for a normalised texture)."""
        action = action or RenderGrains("square", 1)
        self._loading = True
        try:
            self.shape_box.setCurrentIndex(max(0, self.shape_box.findData(action.shape)))
            self.size_slider.set_value(min(action.size, 32))
            self.angle.set_value(max(-90.0, min(90.0, action.angle)))
            self.aspect.set_value(action.aspect)
            self.sides.setValue(min(action.sides, 12))
            self.explode_x.set_value(action.explosion_x)
            self.explode_y.set_value(action.explosion_y)
            self.compression.set_value(action.compression)
            self.same_compression.setChecked(action.compression_x is None)
            self.compression_x.set_value(action.compression if action.compression_x is None
                                         else action.compression_x)
            self.overlap.setCurrentIndex(self.overlap.findData(action.overlap))
            self.lattice.setCurrentIndex(self.lattice.findData(action.lattice))
            self._bitmap = action.bitmap or self._bitmap
            self._level_grains = parse_level_grains(action.level_grains)
            self._show_level_grains()
        finally:
            self._loading = False
        self._enable_fields()

    def _enable_fields(self) -> None:
        shape = self.shape_box.currentData()
        self.aspect.setEnabled(shape in ("rectangle", "circle", "polygon", "hexagon", "diamond"))
        self.sides.setEnabled(shape == "polygon")
        self.compression_x.setEnabled(not self.same_compression.isChecked())
        if self.same_compression.isChecked():          # the slider across shows the same value
            self.compression_x.set_value(self.compression.value())
        bitmap_ok = shape != "bitmap" or self._bitmap is not None
        self.shape_box.setToolTip("" if bitmap_ok else "Draw or choose a grain in the Grain stamps dock, "
                              "then press “Use the Grain tool's grain”")

    def _link_toggled(self, same: bool) -> None:
        """Unlinking changes no picture (across keeps the value down has) until a slider moves;
        linking again makes across follow down at once."""
        if same:
            self._edited_now()
        elif not self._loading:
            self._enable_fields()

    def _edited(self) -> None:
        if self._loading:
            return
        self._enable_fields()
        self.update_info()
        self._preview_timer.start()
        self._commit_timer.start()

    def _edited_now(self) -> None:
        """A choice in a list is one decision: preview and commit at once."""
        if self._loading:
            return
        self._enable_fields()
        self.update_preview()
        self.commit()

    # -- a grain per level (§5.3) -----------------------------------------------------------------
    def set_levels(self, palette) -> None:
        """One row per level 1..G-1 (level 0 is the background: it draws no grain), each with
        the level's colour."""
        palette = np.asarray(palette, np.uint8)
        if len(self._level_widgets) != len(palette) - 1:
            for widgets in self._level_widgets:
                for w in widgets:
                    self.level_rows.removeWidget(w)
                    w.setParent(None)
                    w.deleteLater()
            self._level_widgets = [self._level_row(k) for k in range(1, len(palette))]
            self._show_level_grains()
        for k, (swatch, _, _) in enumerate(self._level_widgets, start=1):
            r, g, b = (int(v) for v in palette[k])
            ink = "black" if r * 0.3 + g * 0.59 + b * 0.11 > 128 else "white"
            swatch.setStyleSheet(f"background: rgb({r},{g},{b}); color: {ink};")

    def _level_row(self, level: int):
        swatch = QtWidgets.QLabel(str(level))
        swatch.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        swatch.setMinimumWidth(28)
        shape = QtWidgets.QComboBox()
        shape.setSizeAdjustPolicy(
            QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        shape.setMinimumContentsLength(10)
        shape.addItem("The grain above", None)
        for text, value in SHAPES[:-1]:
            shape.addItem(text, value)
        shape.setToolTip(f"The grain of the points of level {level}")
        size = QtWidgets.QSpinBox()
        size.setRange(1, MAX_GRAIN)
        size.setSuffix(" px")
        size.setToolTip(f"Diameter of level {level}'s grain")
        size.setEnabled(False)
        for column, w in enumerate((swatch, shape, size)):
            self.level_rows.addWidget(w, level - 1, column)
        shape.currentIndexChanged.connect(lambda _=0, k=level: self._level_shape(k))
        size.valueChanged.connect(lambda _=0, k=level: self._level_size(k))
        return swatch, shape, size

    def _show_level_grains(self) -> None:
        """Rows from the table (a drawn grain, set in the History, shows as such)."""
        loading, self._loading = self._loading, True
        try:
            for k, (_, shape, size) in enumerate(self._level_widgets, start=1):
                grain = self._level_grains.get(k)
                if grain is not None and shape.findData(grain.shape) < 0:
                    shape.addItem("Drawn grain", grain.shape)
                shape.setCurrentIndex(0 if grain is None else shape.findData(grain.shape))
                size.setValue(self.size_slider.value() if grain is None else grain.size)
                size.setEnabled(grain is not None)
        finally:
            self._loading = loading

    def _level_shape(self, level: int) -> None:
        if self._loading:
            return
        _, shape_box, size = self._level_widgets[level - 1]
        shape = shape_box.currentData()
        size.setEnabled(shape is not None)
        if shape is None:
            self._level_grains.pop(level, None)
        elif getattr(self._level_grains.get(level), "shape", None) != shape:
            old = self._level_grains.get(level) or GrainType(
                shape=shape, size=size.value(), aspect=self.aspect.value(),
                sides=self.sides.value(), angle=float(self.angle.value()))
            self._level_grains[level] = old.replace(shape=shape, bitmap=None)
        self._edited_now()

    def _level_size(self, level: int) -> None:
        if self._loading or level not in self._level_grains:
            return
        size = self._level_widgets[level - 1][2].value()
        self._level_grains[level] = self._level_grains[level].replace(size=size)
        self._edited()

    def use_tool_grain(self) -> None:
        from .tools.grain import GrainTool
        tool = next((t for t in self.main_window.tools if isinstance(t, GrainTool)), None)
        if tool is None:
            return
        grain = tool.grain
        self._bitmap = grain.bitmap
        params = {**self.params(), "shape": grain.shape, "size": grain.size,
                  "aspect": grain.aspect, "sides": grain.sides, "angle": grain.angle,
                  "bitmap": grain.bitmap}
        try:
            self.show_action(RenderGrains(**params))
        except TexeditorError as exc:
            self.main_window.show_error("This grain cannot draw the texture", exc)
            return
        self._edited_now()

    def make_natural(self) -> None:
        self._loading = True
        self.explode_x.set_value(1)
        self.explode_y.set_value(1)
        self.compression.set_value(0)
        self.compression_x.set_value(0)
        self._loading = False
        self._edited_now()

    # -- following the document --------------------------------------------------------------------
    def editing(self) -> bool:
        """True while settings of the user's are on their way to the document (waiting for a
        pause, a slider held, a render running): the controls then show them, not the log."""
        return (self._commit_timer.isActive() or self._rendering is not None
                or any(s.slider.isSliderDown() for s in (
                    self.size_slider, self.angle, self.aspect, self.explode_x, self.explode_y,
                    self.compression, self.compression_x)))

    def drop_pending(self) -> None:
        """Forget settings still waiting for their pause, before the history goes back (undo, a
        step clicked): committed after it, they would drop the steps just undone (as Krita
        drops a stroke in progress on undo)."""
        self._commit_timer.stop()

    def _refresh_soon(self) -> None:
        """After a task: once the event loop is back (never on a dock deleted meanwhile, as a
        window closed while its task ended is)."""
        QtCore.QTimer.singleShot(0, self, self.refresh)

    def refresh(self) -> None:
        """After any change of the history (and after a task ends, a cancelled one included):
        the controls show the document's grain step — derived from the log every time, never
        kept from an earlier setting — unless the user's settings are on their way."""
        history = self.main_window.history
        if history is None:
            return
        i = grain_step(history)
        step = history.actions[i] if i is not None else None
        self.set_levels(history.document.palette)
        if not self.editing():
            self._shown_step = step
            self.show_action(step)
        if self.isVisible():
            self._preview_timer.start()

    def normalised(self):
        """(levels, palette) of the texture before its grain step (the current one if none)."""
        history = self.main_window.history
        i = grain_step(history)
        if i is None:
            doc = history.document
            return doc.levels, doc.palette
        key = (id(history), tuple(history.actions[:i]))
        if key != self._base_key:
            from texeditor.recipe.replay import replay
            doc = replay(history.actions[:i], history.document.dpjs)
            self._base_key, self._base = key, (doc.levels.copy(), doc.palette)
        return self._base

    def update_preview(self) -> None:
        action = self.action()
        if action is None or self.main_window.history is None:
            return
        if warmup.pending("gui"):           # a first start compiles the grain kernel: not here
            self._preview_timer.start()
            return
        try:
            levels, palette = self.normalised()
        except TexeditorError as exc:
            self.info.setText(str(exc))
            return
        if not levels.size:
            self.preview.clear()
            return
        lat = action.grain_lattice()
        rows = min(levels.shape[0], PREVIEW // lat.pitch_y + 3)
        cols = min(levels.shape[1], PREVIEW // lat.pitch_x + 3)
        try:
            picture = action.render(levels[:rows, :cols])
        except TexeditorError as exc:
            self.info.setText(str(exc))
            return
        rgb = np.asarray(palette)[picture[:PREVIEW, :PREVIEW]]
        self.preview.setPixmap(QtGui.QPixmap.fromImage(qimage_from_rgb(rgb)))
        self.info.setText(output_text(action, levels.shape))

    def update_info(self) -> None:
        """Say the output size of the settings, at once (as a slider moves)."""
        action = self.action()
        if action is None or self.main_window.history is None:
            return
        try:
            levels, _palette = self.normalised()
        except TexeditorError as exc:
            self.info.setText(str(exc))
            return
        if levels.size:
            self.info.setText(output_text(action, levels.shape))

    def showEvent(self, ev) -> None:
        super().showEvent(ev)
        self._preview_timer.start()

    # -- committing --------------------------------------------------------------------------------
    def commit(self) -> None:
        """Make the settings the texture's grain step: append one, or replace it and replay."""
        self._commit_timer.stop()
        window = self.main_window
        action = self.action()
        if (action is None or window.history is None or not window.document.levels.size
                or not window.isVisible()):
            return
        if window.runner.busy:             # a synthesis or replay is running: try again soon
            self._commit_timer.start()
            return
        i = grain_step(window.history)
        if i is None:
            if action.mask().shape == (1, 1) and action.grain_lattice().shape((1, 1)) == (1, 1):
                return                     # one pixel a point: the texture already looks so
            base = window.document.levels.copy(), window.document.palette
            if self.slow(action, base[0].shape):
                self._render_in_worker(action, *base)
            elif window.submit(action):
                self._base_key = (id(window.history), tuple(window.history.actions[:-1]))
                self._base = base
        elif window.history.actions[i] != action:
            window.edit_step(i, action)    # replayed in the worker, with progress and Cancel

    @staticmethod
    def slow(action: RenderGrains, texture_shape) -> bool:
        """Whether a render may take over ~0.3 s (then it runs in the worker)."""
        oh, ow = action.grain_lattice().shape(texture_shape)
        return action.render_cost(texture_shape) > WORKER_COST or oh * ow > WORKER_PIXELS

    def _render_in_worker(self, action: RenderGrains, levels, palette) -> None:
        """Render in the window's worker (progress, Cancel/Esc), then submit the action with
        its picture; Cancel, or a document changed meanwhile, leaves the document as it is."""
        window = self.main_window
        history, applied, start = window.history, window.history.applied, time.perf_counter()
        oh, ow = action.grain_lattice().shape(levels.shape)
        self._rendering = action

        def done(picture) -> None:
            self._rendering = None
            if window.history is not history or history.applied != applied:
                window.statusBar().showMessage("The texture changed during the grain rendering: "
                                               "it was not applied.", 8000)
                self.refresh()
                return
            action.use_result(levels, picture)
            if window.submit(action):
                self._base_key = (id(history), tuple(history.actions[:-1]))
                self._base = levels, palette
                window.statusBar().showMessage(
                    f"Grains rendered: {ow}×{oh} px in {time.perf_counter() - start:.1f} s.",
                    8000)

        def cancelled() -> None:
            self._rendering = None
            window.statusBar().showMessage("Grain rendering cancelled: the document is "
                                           "unchanged.", 8000)
            self.refresh()

        def failed(exc) -> None:
            self._rendering = None
            self.refresh()
            window.show_error("Cannot render the grains", exc)

        window.runner.run(f"Rendering grains ({ow}×{oh} px)…",
                          lambda progress, cancel: action.render(levels, progress, cancel),
                          done, on_cancel=cancelled, on_error=failed)
