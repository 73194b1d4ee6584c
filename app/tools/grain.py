"""The Grain tool (G) (thesis §3.3.3a): place grains of a chosen type by their centre of gravity.

A click places one grain centred at the pointer; a drag places it where the button is released;
Shift+drag places grains along the path at the chosen spacing, each moved at random by up to the
jitter. The grain type comes from the library (standard and user grains) shown in the options,
or from the grain editor. Every placement is one PlaceGrains action.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor.recipe.actions import replace_params
from texeditor.errors import TexeditorError
from texeditor.paint.grains import GrainLibrary, GrainType, standard_grains
from texeditor.paint.actions import PlaceGrains

from ..grain_editor import GrainEditor
from ..params_form import new_seed
from . import Tool
from .brush import palette_argb, preview_for, unfold

GHOST_ALPHA = 190
GHOST_EDGE = (40, 200, 255)
DEFAULT_GRAIN = "Circle 5"


@dataclass(frozen=True)
class GrainSettings:
    """The grain placed (chosen in the Grain stamps dock or menu) and the Shift+drag settings."""

    grain: GrainType | None = None
    spacing: int = 8                 # Shift+drag: one grain every so many points
    jitter: int = 2                  # each moved at random by up to this much
    wrap: bool = False


class GrainOptions(QtWidgets.QWidget):
    """The current grain (chosen in the Grain stamps dock or menu) and the Shift+drag settings."""

    def __init__(self, tool: "GrainTool"):
        super().__init__()
        grid = QtWidgets.QGridLayout(self)
        grid.setContentsMargins(0, 0, 0, 0)
        grid.setColumnStretch(1, 1)
        grid.setColumnStretch(3, 1)
        self.current = QtWidgets.QLabel()
        self.current.setWordWrap(True)
        self.edit_button = QtWidgets.QPushButton("Edit…")
        self.edit_button.setToolTip("Open the grain editor on this grain (draw your own there)")
        self.edit_button.clicked.connect(tool.edit)
        grid.addWidget(self.current, 0, 0, 1, 3)
        grid.addWidget(self.edit_button, 0, 3)
        self.spacing = QtWidgets.QSpinBox()
        self.spacing.setRange(1, 512)
        self.spacing.setValue(8)
        self.spacing.setSuffix(" pt")
        self.spacing.setToolTip("Shift+drag: one grain every so many points along the path")
        self.jitter = QtWidgets.QSpinBox()
        self.jitter.setRange(0, 256)
        self.jitter.setValue(2)
        self.jitter.setSuffix(" pt")
        self.jitter.setToolTip("Shift+drag: each grain moved at random by up to this much")
        grid.addWidget(QtWidgets.QLabel("Spacing"), 1, 0)
        grid.addWidget(self.spacing, 1, 1)
        grid.addWidget(QtWidgets.QLabel("Jitter"), 1, 2)
        grid.addWidget(self.jitter, 1, 3)
        self.wrap = QtWidgets.QCheckBox("Wrap around the edges")
        self.wrap.setToolTip("A grain over an edge continues on the opposite one")
        grid.addWidget(self.wrap, 2, 0, 1, 4)
        tool.model.bind("grain", self.current, put=self.show_grain)
        for name in ("spacing", "jitter", "wrap"):
            tool.model.bind(name, getattr(self, name))

    def show_grain(self, grain: GrainType) -> None:
        self.current.setText(f"<b>{grain.name}</b> · {grain.size} pt")
        self.current.setToolTip(describe(grain))


def describe(grain: GrainType) -> str:
    level = "the palette's level" if grain.level is None and not grain.own_levels else \
        "its own levels" if grain.level is None else f"level {grain.level}"
    angle = f", {grain.angle:g}°" if grain.angle else ""
    return f"{grain.name}: {grain.shape}, {grain.size} points{angle}, painted with {level}"


class GrainTool(Tool):
    NAME = "Grain"
    SHORTCUT = "G"
    TIP = "Click to place a grain by its centre of gravity; Shift+drag places grains along the path"
    SETTINGS = GrainSettings

    def __init__(self, window):
        super().__init__(window)
        self.library = GrainLibrary()
        self.grains: list[GrainType] = standard_grains()
        self.grain = next(g for g in self.grains if g.name == DEFAULT_GRAIN)
        self.opts: GrainOptions | None = None
        self.editor: GrainEditor | None = None

    @property
    def grain(self) -> GrainType:
        return self.settings.grain

    @grain.setter
    def grain(self, grain: GrainType) -> None:
        self.model.update(grain=grain)

    # -- the grain type ----------------------------------------------------------------------------
    def build_options(self):
        self.opts = GrainOptions(self)
        return self.opts

    def activate(self):
        self._show()
        self.show_own_dock("grain_dock")         # the library in view while placing grains

    def reload(self) -> None:
        """Read the library again (a damaged user file is reported; the standard grains stay)."""
        try:
            self.grains = self.library.all()
        except TexeditorError as exc:
            self.grains = self.library.standard()
            self.main_window.show_error("Your grain library cannot be read", exc)
        if self.grain.name not in [g.name for g in self.grains]:
            self.grains.append(self.grain)
        self._show()

    def _show(self) -> None:
        dock = getattr(self.main_window, "grain_dock", None)     # the Grain stamps dock
        if dock is not None:
            dock.refresh()

    def pick(self, name: str) -> None:
        """Choose a library grain by name (the Grain stamps dock and menu)."""
        self.use(next(g for g in self.grains if g.name == name))

    def use(self, grain: GrainType) -> None:
        """Make ``grain`` the current one and this tool the current tool (unless the current
        tool places this grain too: the Dominance tree keeps building)."""
        self.grain = grain
        names = [g.name for g in self.grains]
        if grain.name in names:
            self.grains[names.index(grain.name)] = grain
        else:
            self.grains.append(grain)
        self._show()
        current = self.main_window.tool
        if current is not self and not getattr(current, "PLACES_GRAINS", False):
            self.main_window.set_tool(self)
        self.main_window.statusBar().showMessage(describe(grain), 4000)

    def edit(self) -> GrainEditor | None:
        """Open the grain editor (one per tool, not modal) on the current grain (not before
        the window's first texture is there: the editor shows its palette)."""
        if self.main_window.still_opening():
            return None
        if self.editor is None:
            self.editor = GrainEditor(self.library, self.grain, self.document.palette,
                                      self.main_window.current_level, self.main_window)
            self.editor.chosen.connect(self.use)
            self.editor.libraryChanged.connect(self.reload)
        else:
            self.editor.palette_rgb = np.asarray(self.document.palette, np.uint8)
            self.editor.set_grain(self.grain)
        self.editor.show()
        self.editor.raise_()
        return self.editor

    def resize(self, bigger: bool) -> None:
        """[ and ]: the current grain one point bigger or smaller (drawn grains keep theirs);
        the library keeps its own size."""
        if self.grain.shape == "bitmap":
            return
        size = max(1, min(self.grain.size + (1 if bigger else -1), 256))
        self.grain = self.grain.replace(size=size)
        self._show()
        self.main_window.statusBar().showMessage(describe(self.grain), 2000)

    # -- gestures ----------------------------------------------------------------------------------
    def action(self, points, **options) -> PlaceGrains:
        wrap = self.settings.wrap or self.main_window.canvas.tiled
        return PlaceGrains.from_grain(self.grain, points, self.main_window.current_level,
                                      wrap=wrap, **options)

    def click(self, cell, modifiers):
        x, y = cell
        self.main_window.canvas.set_overlay(None)
        self.main_window.submit(self.action([(y, x)]))

    def hover(self, cell):
        """A ghost of the grain under the pointer: where a click puts it."""
        if cell is None:
            self.main_window.canvas.set_overlay(None)
            return
        self.ghost(cell)

    def ghost(self, cell) -> None:
        try:
            action = self.action([(cell[1], cell[0])])
            rows, cols, values = action.painter(self.document.shape).add(action.points[0])
        except TexeditorError:
            return
        if not len(rows):
            self.main_window.canvas.set_overlay(None)
            return
        t, l = rows.min(), cols.min()
        inside = np.zeros((rows.max() - t + 3, cols.max() - l + 3), bool)
        inside[rows - t + 1, cols - l + 1] = True
        edge = inside & ~(np.roll(inside, 1, 0) & np.roll(inside, -1, 0)
                          & np.roll(inside, 1, 1) & np.roll(inside, -1, 1))
        rgba = np.zeros(inside.shape + (4,), np.uint8)
        pal = np.asarray(self.document.palette, np.uint8)
        rgba[rows - t + 1, cols - l + 1, :3] = pal[np.minimum(values, len(pal) - 1)]
        rgba[inside, 3] = GHOST_ALPHA
        rgba[edge] = (*GHOST_EDGE, 255)          # an outline shows it on any texture
        self.main_window.canvas.set_overlay(rgba[1:-1, 1:-1], (int(l), int(t)))

    def drag(self, cell, modifiers):
        if modifiers & QtCore.Qt.KeyboardModifier.ShiftModifier:
            yield from self._along(cell)
            return
        last = cell
        try:
            while True:
                last = yield
                self.ghost(last)
        except GeneratorExit:
            self.main_window.canvas.set_overlay(None)
            self.main_window.submit(self.action([(last[1], last[0])]))
            raise

    def _along(self, cell):
        """Shift+drag: grains along the path, previewed as they fall."""
        self.main_window.canvas.set_overlay(None)
        shape, tiled = self.document.shape, self.main_window.canvas.tiled
        points = [unfold(cell, None, shape, False)]
        try:
            template = self.action(points, spacing=float(self.settings.spacing),
                                   jitter=float(self.settings.jitter), seed=new_seed())
        except TexeditorError as exc:
            self.main_window.show_error("Cannot place this grain", exc)
            return
        painter = template.painter(shape)
        colours = palette_argb(self.document.palette)
        preview = preview_for(self.main_window)
        rows, cols, values = painter.add(points[0])
        preview.draw(rows, cols, colours[values])
        try:
            while True:
                point = unfold((yield), points[-1], shape, tiled)
                if point != points[-1]:
                    points.append(point)
                    rows, cols, values = painter.add(point)
                    preview.draw(rows, cols, colours[values])
        except GeneratorExit:
            self.main_window.submit(replace_params(template, points=tuple(points)))
            preview.clear()
            raise
