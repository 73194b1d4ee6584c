"""The Spot tool (thesis §3.3.3b): compose spots on the canvas — place the spot of the spot
editor (a drag turns and sizes it), scatter many in a rectangle, delete one.

Every gesture becomes one Action of `texeditor.spots.actions`. The ghost of the spot under the
pointer (or of the spot about to be deleted) is a vector outline drawn over the canvas; the
document only changes when an Action is submitted. A "Bank texture…" fill opens the bank
picker; the chosen entry becomes a recipe (`texture_actions.bank_source`) the placements carry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.errors import TexeditorError
from texeditor.spots.actions import DeleteSpot, PlaceSpot, ScatterSpots, spot_at, spot_ref
from texeditor.spots.envelope import Placement, placed_outline

from ..bank_picker import choose_bank_entry, load_bank_source
from ..spot_editor import SpotEditorDock
from . import Tool

MODES = [("Place", "place"), ("Scatter", "scatter"), ("Delete", "delete")]
FILLS = [("Current level", "level"), ("Texture (Ctrl+click: source)", "document"),
         ("DPJ texture", "dpj"), ("Bank texture…", "texture")]
BANK_NOTE = ("Spots are filled with the entry's texture, read where each spot lands and repeated. "
             "An entry of another number of levels G has its levels mapped onto the document's "
             "on the grey scale.")
BLENDS = [("Over", "over"), ("Under (background only)", "under"), ("Max of levels", "max"),
          ("Min of levels", "min")]
HINTS = {"place": "Click to place the spot; drag from its centre to turn and size it.",
         "scatter": "Drag a rectangle to scatter spots in it, or scatter over the whole canvas.",
         "delete": "Click a spot to delete it; what was under it comes back."}
GHOST = QtGui.QColor(120, 220, 255)
DOOMED = QtGui.QColor(255, 90, 70)
MIN_DRAG = 1.5                 # cells: a shorter drag places like a click
WORKER_COUNT = 100             # scatters of this many spots are rasterised in the worker


@dataclass(frozen=True)
class SpotSettings:
    """The Spot tool's settings (the spot itself is the spot editor's)."""

    mode: str = "place"              # MODES
    scale: float = 1.0               # size (1: as drawn in the editor)
    angle: int = 0                   # turn, degrees counter-clockwise
    fill: str = "level"              # FILLS
    blend: str = "over"              # BLENDS
    wrap: bool = False
    count: int = 40                  # Scatter: how many spots,
    scale_max: float = 1.0           # the largest size (the smallest is ``scale``),
    spread: int = 180                # turns vary by ± this around ``angle``,
    level_max: int = 0               # levels from the current one up to this one


class SpotOptions(QtWidgets.QWidget):
    """Mode, size and turn, fill and blend, wrap; the scatter settings; a way to the editor."""

    def __init__(self, tool: "SpotTool"):
        super().__init__()
        self.tool = tool
        form = QtWidgets.QFormLayout(self)
        form.setContentsMargins(0, 0, 0, 0)
        self.mode = _combo(MODES, "Place one spot, scatter many, or delete one")
        self.scale_box = _double(0.05, 16.0, 1.0, 0.1, "×", "Size (1: as drawn in the editor)")
        self.angle = QtWidgets.QSpinBox()
        self.angle.setRange(-180, 180)
        self.angle.setSuffix("°")
        self.angle.setWrapping(True)
        self.angle.setToolTip("Turn, counter-clockwise")
        self.fill = _combo(FILLS, "What fills the spot: the current level, the document's own "
                                  "texture read elsewhere, a texture synthesised from the DPJ, "
                                  "or the texture of a bank entry")
        self.texture_label = QtWidgets.QLabel("no entry")
        self.texture_button = QtWidgets.QToolButton()
        self.texture_button.setText("Choose…")
        self.texture_button.setToolTip("Choose the bank entry whose texture fills the spots")
        self.texture_button.clicked.connect(tool.choose_texture)
        self.texture_row = QtWidgets.QWidget()
        row = QtWidgets.QHBoxLayout(self.texture_row)
        row.setContentsMargins(0, 0, 0, 0)
        row.addWidget(self.texture_label, 1)
        row.addWidget(self.texture_button)
        self.blend = _combo(BLENDS, "How a spot meets what is already there")
        self.wrap = QtWidgets.QCheckBox("Wrap around the edges")
        self.wrap.setToolTip("A spot crossing an edge comes back on the other side")
        form.addRow("Mode", self.mode)
        form.addRow("Size", self.scale_box)
        form.addRow("Turn", self.angle)
        form.addRow("Fill", self.fill)
        form.addRow("Texture", self.texture_row)
        form.addRow("Blend", self.blend)
        form.addRow(self.wrap)

        self.scatter_box = QtWidgets.QGroupBox("Scatter")
        sform = QtWidgets.QFormLayout(self.scatter_box)
        self.count = QtWidgets.QSpinBox()
        self.count.setRange(1, 10_000)
        self.count.setValue(40)
        self.count.setToolTip("How many spots")
        self.scale_max = _double(0.05, 16.0, 1.0, 0.1, "×", "Largest size (the smallest is Size)")
        self.spread = QtWidgets.QSpinBox()
        self.spread.setRange(0, 180)
        self.spread.setValue(180)
        self.spread.setSuffix("°")
        self.spread.setToolTip("Turns vary by up to ± this much around Turn")
        self.level_max = QtWidgets.QSpinBox()
        self.level_max.setRange(0, 15)
        self.level_max.setToolTip("Levels from the current one up to this one (a level fill)")
        self.whole = QtWidgets.QPushButton("Scatter over the canvas")
        self.whole.clicked.connect(tool.scatter_everywhere)
        sform.addRow("Count", self.count)
        sform.addRow("Sizes up to", self.scale_max)
        sform.addRow("Turn spread", self.spread)
        sform.addRow("Levels up to", self.level_max)
        sform.addRow(self.whole)
        form.addRow(self.scatter_box)

        self.editor_button = QtWidgets.QPushButton("Spot editor…")
        self.editor_button.setToolTip("Show the spot editor: the envelope and its real spots")
        self.editor_button.clicked.connect(tool.show_editor)
        form.addRow(self.editor_button)
        self.hint = QtWidgets.QLabel()
        self.hint.setWordWrap(True)
        form.addRow(self.hint)
        for name, widget in (("mode", self.mode), ("scale", self.scale_box), ("angle", self.angle),
                             ("fill", self.fill), ("blend", self.blend), ("wrap", self.wrap),
                             ("count", self.count), ("scale_max", self.scale_max),
                             ("spread", self.spread), ("level_max", self.level_max)):
            tool.model.bind(name, widget)
        self.mode.currentIndexChanged.connect(self.mode_changed)
        self.fill.currentIndexChanged.connect(tool.fill_changed)
        self.mode_changed()
        self._form = form
        self.show_texture_row(False)

    def show_texture_row(self, shown: bool) -> None:
        self.texture_row.setVisible(shown)
        self._form.labelForField(self.texture_row).setVisible(shown)

    def mode_changed(self) -> None:
        mode = self.tool.settings.mode
        self.scatter_box.setVisible(mode == "scatter")
        self.hint.setText(HINTS[mode])


def _combo(items, tip: str) -> QtWidgets.QComboBox:
    box = QtWidgets.QComboBox()
    for text, value in items:
        box.addItem(text, value)
    box.setToolTip(tip)
    return box


def _double(lo, hi, value, step, suffix, tip) -> QtWidgets.QDoubleSpinBox:
    box = QtWidgets.QDoubleSpinBox()
    box.setRange(lo, hi)
    box.setDecimals(2)
    box.setSingleStep(step)
    box.setValue(value)
    box.setSuffix(suffix)
    box.setToolTip(tip)
    return box


def levels_note(source, levels: int) -> str:
    """What becomes of a texture source's levels in a document of G = ``levels``."""
    if source.levels == levels:
        return (f"Spots show “{source.name}” as it is: it has G = {levels} levels, like the "
                "document.")
    return (f"“{source.name}” has G = {source.levels} levels, the document {levels}: its levels "
            "are mapped onto the document's on the grey scale (the background stays 0, the top "
            "level the top).")


def _path(outline: np.ndarray) -> QtGui.QPainterPath:
    """A closed path in view coordinates from an outline in (row, col) point coordinates (the
    point (r, c) is the centre of cell (c, r), at (c + 0.5, r + 0.5))."""
    path = QtGui.QPainterPath()
    path.addPolygon(QtGui.QPolygonF([QtCore.QPointF(c + 0.5, r + 0.5) for r, c in outline]))
    path.closeSubpath()
    return path


class SpotTool(Tool):
    NAME = "Spot"
    SHORTCUT = "S"
    TIP = "Place the spot of the spot editor (drag: turn and size), scatter many, delete one"
    SETTINGS = SpotSettings

    def __init__(self, window):
        super().__init__(window)
        self.dock: SpotEditorDock | None = None           # made on first use
        self.source: tuple[int, int] | None = None       # where a texture fill is read
        self.ghost: QtWidgets.QGraphicsPathItem | None = None
        self._shown_by_tool = False
        self._unsubscribe = None
        self._colours = None          # (palette, level) the editor's preview was drawn with
        self.texture = None           # the bank entry of a texture fill, as a TextureSource
        self.picker = None            # the bank picker while it is open
        self.last_fill = "level"      # the fill chosen before "Bank texture…", to go back to

    @property
    def editor(self):
        return self._ensure_dock().editor

    def _ensure_dock(self) -> SpotEditorDock:
        """The spot editor's dock, made (hidden) on first use."""
        if self.dock is None:
            self._make_dock()
        return self.dock

    def _make_dock(self) -> None:
        window = self.main_window
        self.dock = SpotEditorDock(window)
        # Under the canvas only: the left column keeps the tool options tall, and the right-hand
        # docks keep their height (at 1280×800 an editor under them cut History to four rows).
        window.setCorner(QtCore.Qt.Corner.BottomLeftCorner,
                         QtCore.Qt.DockWidgetArea.LeftDockWidgetArea)
        window.setCorner(QtCore.Qt.Corner.BottomRightCorner,
                         QtCore.Qt.DockWidgetArea.RightDockWidgetArea)
        window.addDockWidget(QtCore.Qt.DockWidgetArea.BottomDockWidgetArea, self.dock)
        self.dock.hide()
        if hasattr(window, "palette_dock"):
            window.palette_dock.currentLevelChanged.connect(self._sync_colours)

    def build_options(self):
        self.opts = SpotOptions(self)
        self.opts.mode.currentIndexChanged.connect(lambda: self._set_ghost(None))
        return self.opts

    @property
    def mode(self) -> str:
        return self.settings.mode

    # -- activation ---------------------------------------------------------------------------
    def activate(self) -> None:
        self.options()
        self._ensure_dock()
        if not self.dock.isVisible():
            self.show_editor()
            self._shown_by_tool = True
        if self.ghost is None:
            self.ghost = QtWidgets.QGraphicsPathItem()
            self.ghost.setZValue(20)
            self.main_window.canvas.view.addItem(self.ghost)
        self._unsubscribe = self.main_window.history.subscribe(self._sync_colours)
        self._sync_colours()

    def deactivate(self) -> None:
        super().deactivate()
        if self.ghost is not None:
            self.main_window.canvas.view.removeItem(self.ghost)
            self.ghost = None
        if self._unsubscribe is not None:
            self._unsubscribe()
            self._unsubscribe = None
        if self._shown_by_tool and self.dock is not None:
            self.dock.hide()
            self._shown_by_tool = False

    def show_editor(self) -> None:
        self._ensure_dock().show()
        self.dock.raise_()
        if not self.dock.isFloating():
            QtCore.QTimer.singleShot(0, self.dock, self._size_dock)

    def _size_dock(self) -> None:
        """A third of the window under the canvas (once the layout has taken the new dock)."""
        height = max(260, min(330, self.main_window.height() * 2 // 5))
        self.main_window.resizeDocks([self.dock], [height], QtCore.Qt.Orientation.Vertical)

    # -- gestures -----------------------------------------------------------------------------
    def click(self, cell, modifiers):
        x, y = cell
        mode = self.mode
        if mode == "place":
            ctrl = modifiers & QtCore.Qt.KeyboardModifier.ControlModifier
            if ctrl and self.settings.fill == "document":
                self.source = (y, x)
                self.opts.hint.setText(f"The texture is read from ({y}, {x}) for the next spot.")
                return
            self.place(y, x)
        elif mode == "delete":
            self.delete_at(y, x)

    def drag(self, cell, modifiers):
        mode = self.mode
        x0, y0 = cell
        x, y = cell
        try:
            while True:
                x, y = yield
                if mode == "place":
                    self._show_spot(y0, x0, *self._turn_and_size(y - y0, x - x0))
                elif mode == "scatter":
                    self._show_rect(y0, x0, y, x)
        except GeneratorExit:
            self._set_ghost(None)
            if mode == "place":
                self.place(y0, x0, *self._turn_and_size(y - y0, x - x0))
            elif mode == "scatter" and (x, y) != (x0, y0):
                self.scatter(min(y0, y), min(x0, x), abs(y - y0) + 1, abs(x - x0) + 1)
            elif mode == "delete":
                self.delete_at(y0, x0)
            raise

    def hover(self, cell):
        self._sync_colours()        # another document, or colours changed elsewhere
        if cell is None or self.ghost is None:
            self._set_ghost(None)
            return
        x, y = cell
        if self.mode == "place":
            self._show_spot(y, x, self.settings.angle, self.settings.scale)
        elif self.mode == "delete":
            self._show_doomed(y, x)
        else:
            self._set_ghost(None)

    def _turn_and_size(self, dy: float, dx: float) -> tuple[float, float]:
        """From a drag vector: the turn that points the equator's end b along it and the size
        that puts b at its tip (a short drag keeps the options' turn and size)."""
        env = self.editor.envelope
        if env is None or math.hypot(dy, dx) < MIN_DRAG:
            return float(self.settings.angle), float(self.settings.scale)
        d = np.subtract(env.b, env.a)
        own = math.degrees(math.atan2(-d[0], d[1]))
        angle = (math.degrees(math.atan2(-dy, dx)) - own + 180) % 360 - 180
        scale = min(max(math.hypot(dy, dx) / (env.length / 2), 0.05), 16.0)
        return round(angle, 1), round(scale, 3)

    # -- the texture of a texture fill ------------------------------------------------------------
    def fill_changed(self) -> None:
        """Show the texture row for a texture fill; the first time, choose its entry."""
        fill = self.settings.fill
        self.opts.show_texture_row(fill == "texture")
        if fill != "texture":
            self.last_fill = fill
        elif self.texture is None:
            self.choose_texture()

    def choose_texture(self) -> None:
        """Open the bank picker; the chosen entry is read in the worker. Cancelled, or the entry
        failing to load, with no texture yet: the fill goes back to the one chosen before."""
        self.picker = choose_bank_entry(self.main_window, lambda bank, entry_id: load_bank_source(
            self.main_window, bank, entry_id, self._texture_loaded, self._texture_refused),
            note=BANK_NOTE)
        self.picker.rejected.connect(self._texture_refused)
        self.picker.finished.connect(lambda _r: setattr(self, "picker", None))

    def _texture_refused(self) -> None:
        """No texture to fill with: a texture fill without one goes back to the previous fill
        (not when the user has meanwhile chosen another fill, or has a texture already)."""
        if self.texture is None and self.settings.fill == "texture":
            self.model.update(fill=self.last_fill)

    def _texture_loaded(self, source) -> None:
        self.texture = source
        self.opts.texture_label.setText(source.name)
        note = levels_note(source, self.document.num_levels)
        self.opts.texture_label.setToolTip(note)
        self.opts.hint.setText(note)
        self.main_window.statusBar().showMessage(note, 8000)

    # -- actions ----------------------------------------------------------------------------------
    def _spot_params(self) -> dict | None:
        """The parameters shared by a placement and a scatter, or None (and a message)."""
        env = self.editor.envelope
        if env is None:
            self.main_window.show_error("No spot to place", ValueError(
                "Draw an envelope in the spot editor first (click the ends of its equator)."))
            return None
        p = self.editor.perturbation()
        params = dict(envelope=env.dumps(), contour=p.contour, frequency=p.frequency,
                      fractal=p.fractal, roughness=p.h, interior=p.interior, density=p.density,
                      grain=p.scale, shift=self.editor.shift_value,
                      fill=self.settings.fill, blend=self.settings.blend,
                      wrap=self.settings.wrap)
        if params["fill"] == "dpj":
            if self.document.dpj_ref is None:
                self.main_window.show_error("No DPJ", ValueError(
                    "This document has no DPJ to synthesise a texture from: acquire one first."))
                return None
            params["dpj"] = self.document.dpj_ref
        elif params["fill"] == "texture":
            if self.texture is None:
                self.main_window.show_error("No texture", ValueError(
                    "Choose the bank entry that fills the spots first (Fill: Bank texture…)."))
                return None
            self.texture.store(self.document)
            params.update(texture=self.texture.recipe, texture_dpjs=self.texture.refs)
        return params

    def place(self, row: int, col: int, angle: float | None = None,
              scale: float | None = None) -> bool:
        params = self._spot_params()
        if params is None:
            return False
        if params["fill"] == "document" and self.source is not None:
            params.update(source_row=self.source[0], source_col=self.source[1])
        try:
            action = PlaceSpot(row=row, col=col, seed=self.editor.seed.value(),
                               angle=float(self.settings.angle if angle is None else angle),
                               scale=float(self.settings.scale if scale is None else scale),
                               level=self.main_window.current_level, **params)
        except TexeditorError as exc:
            self.main_window.show_error("Cannot place this spot", exc)
            return False
        if self.main_window.submit(action):
            self.editor.spot_placed()
            return True
        return False

    def scatter(self, top=None, left=None, height=None, width=None) -> bool:
        params = self._spot_params()
        if params is None:
            return False
        level = self.main_window.current_level
        s = self.settings
        level_max = s.level_max
        lo, hi = s.scale, s.scale_max
        try:
            action = ScatterSpots(count=s.count, seed=self.editor.seed.value(),
                                  top=top, left=left, height=height, width=width,
                                  angle=float(s.angle), angle_spread=float(s.spread),
                                  scale=min(lo, hi), scale_max=max(lo, hi) if hi != lo else None,
                                  level=level, level_max=level_max if level_max > level else None,
                                  **params)
        except TexeditorError as exc:
            self.main_window.show_error("Cannot scatter these spots", exc)
            return False
        if action.count < WORKER_COUNT:
            return self._submit_scatter(action)
        return self._scatter_in_worker(action)

    def _submit_scatter(self, action) -> bool:
        if self.main_window.submit(action):
            self.editor.spot_placed()
            return True
        return False

    def _scatter_in_worker(self, action) -> bool:
        """Many spots: rasterise them in the worker (progress, Cancel), then apply on the GUI
        thread, which only writes the points."""
        window, history = self.main_window, self.main_window.history
        if window.runner.busy:
            return False
        shape = self.document.shape
        window.runner.run(f"Scattering {action.count} spots…",
                          lambda progress, cancel: action.rasterise(shape, progress, cancel),
                          lambda _: history is window.history and self._submit_scatter(action),
                          on_cancel=lambda: window.statusBar().showMessage(
                              "Scatter cancelled: the document is unchanged.", 8000),
                          on_error=lambda exc: window.show_error("Cannot scatter these spots",
                                                                 exc))
        return True

    def scatter_everywhere(self) -> None:
        self.scatter()

    def delete_at(self, row: int, col: int) -> bool:
        actions = self.document.actions
        found = spot_at(actions, self.document.shape, (row, col))
        if found is None:
            self.main_window.statusBar().showMessage("No spot here to delete.", 4000)
            return False
        step, spot = found
        self._set_ghost(None)
        return self.main_window.submit(DeleteSpot(step, spot_ref(actions[step]), spot))

    # -- the ghost ---------------------------------------------------------------------------------
    def _show_spot(self, row, col, angle, scale) -> None:
        env = self.editor.envelope
        if env is None or self.ghost is None:
            return
        try:
            outline = placed_outline(env, self.editor.perturbation(), self.editor.seed.value(),
                                     Placement((row, col), angle, scale))
        except TexeditorError:
            return
        level = self.main_window.current_level
        colour = QtGui.QColor(*(int(c) for c in self._level_colour(level)))
        colour.setAlpha(140)
        self._set_ghost(_path(outline), GHOST, colour)

    def _show_rect(self, y0, x0, y1, x1) -> None:
        path = QtGui.QPainterPath()
        path.addRect(QtCore.QRectF(min(x0, x1), min(y0, y1), abs(x1 - x0) + 1, abs(y1 - y0) + 1))
        self._set_ghost(path, GHOST, QtGui.QColor(120, 220, 255, 40))

    def _show_doomed(self, row, col) -> None:
        found = spot_at(self.document.actions, self.document.shape, (row, col))
        if found is None:
            self._set_ghost(None)
            return
        step, spot = found
        action = self.document.actions[step]
        outline = action.outline(0 if spot is None else spot, self.document.shape)
        self._set_ghost(_path(outline), DOOMED, QtGui.QColor(255, 90, 70, 70))

    def _set_ghost(self, path, pen_colour=None, brush=None) -> None:
        if self.ghost is None:
            return
        if path is None:
            self.ghost.setVisible(False)
            return
        pen = QtGui.QPen(pen_colour, 1.5)
        pen.setCosmetic(True)
        self.ghost.setPen(pen)
        self.ghost.setBrush(brush)
        self.ghost.setPath(path)
        self.ghost.setVisible(True)

    # -- colours -----------------------------------------------------------------------------------
    def _level_colour(self, level: int):
        palette = self.document.palette
        return palette[min(max(level, 0), len(palette) - 1)]

    def _sync_colours(self, *args) -> None:
        """The editor previews the spot in the colours it will have: the document's palette at
        the current level (redrawn only when those change)."""
        if self.main_window.history is None or not self.document.levels.size:
            return
        key = (self.document.palette.tobytes(), self.main_window.current_level)
        if key != self._colours:
            self._colours = key
            self.editor.set_palette(self.document.palette, self.main_window.current_level)
