"""The Brush (B) and Spray (A) tools (thesis §3.2.2): drag to paint with a brush of points.

A stroke is one Action on release (its points, brush and seed); while dragging, a StrokePainter
computes the dabs each pointer move brings and the StrokePreview draws just those points over the
texture, repainting only their dirty rectangle — never the whole 2048² image per move.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.paint import brushes
from texeditor.recipe.actions import replace_params
from texeditor.paint.brushes import Brush
from texeditor.errors import TexeditorError
from texeditor.paint.actions import Stroke

from ..params_form import new_seed
from . import Tool

PREVIEW_Z = 6            # over the overlay (5), under the pixel grid (10)
DIRTY_BLOCK = 64         # a stroke wrapping round an edge repaints the blocks it touched
TILE = 256               # the preview's tiles, made where the stroke goes
SHAPE_NAMES = [("Disc", "disc"), ("Square", "square"), ("Diamond", "diamond"),
               ("Line", "line")]


def palette_argb(palette) -> np.ndarray:
    """Opaque 0xAARRGGBB colours of the levels, for writing straight into a QImage."""
    pal = np.asarray(palette, np.uint32).reshape(-1, 3)
    lut = np.full(256, 0xFFFF00FF, np.uint32)
    lut[:len(pal)] = 0xFF000000 | (pal[:, 0] << 16) | (pal[:, 1] << 8) | pal[:, 2]
    return lut


class StrokePreview(QtWidgets.QGraphicsObject):
    """Points painted during a gesture, shown over the texture until the Action lands.

    Transparent ARGB tiles of 256×256 points (numpy arrays shared with QImages), made only where
    the stroke goes, so a stroke on a huge canvas costs the memory of what it covers. A move
    writes its new points and asks Qt to repaint only where they fell; ``clear`` drops the tiles.
    """

    def __init__(self, shape):
        super().__init__()
        self.canvas_shape = tuple(shape)
        self.tiles: dict[tuple[int, int], tuple[np.ndarray, QtGui.QImage]] = {}
        h, w = self.canvas_shape
        self.drawn: list[int] = [h, w, 0, 0]          # the box of what is drawn: t, l, b, r
        self.setFlag(QtWidgets.QGraphicsItem.GraphicsItemFlag.ItemUsesExtendedStyleOption)
        self.setZValue(PREVIEW_Z)

    def boundingRect(self) -> QtCore.QRectF:
        return QtCore.QRectF(0, 0, self.canvas_shape[1], self.canvas_shape[0])

    def _tile(self, key) -> np.ndarray:
        if key not in self.tiles:
            pixels = np.zeros((TILE, TILE), np.uint32)
            image = QtGui.QImage(pixels.data, TILE, TILE, 4 * TILE,
                                 QtGui.QImage.Format.Format_ARGB32_Premultiplied)
            self.tiles[key] = (pixels, image)
        return self.tiles[key][0]

    def paint(self, painter, option, widget=None):
        exposed = option.exposedRect.toAlignedRect().intersected(
            QtCore.QRect(0, 0, self.canvas_shape[1], self.canvas_shape[0]))
        for (ty, tx), (_pixels, image) in self.tiles.items():
            tile = QtCore.QRect(tx * TILE, ty * TILE, TILE, TILE)
            part = tile.intersected(exposed)
            if not part.isEmpty():
                painter.drawImage(QtCore.QRectF(part), image,
                                  QtCore.QRectF(part.translated(-tile.x(), -tile.y())))

    def draw(self, rows, cols, colours) -> None:
        """Show points (canvas rows, cols) in ARGB colours; repaint only where they fell: their
        box, or the 64×64 blocks they touched when they wrap round an edge."""
        if not len(rows):
            return
        keys = (rows // TILE) * (self.canvas_shape[1] // TILE + 1) + cols // TILE
        for key in np.unique(keys).tolist():
            here = keys == key
            pixels = self._tile(divmod(key, self.canvas_shape[1] // TILE + 1))
            pixels[rows[here] % TILE, cols[here] % TILE] = colours[here]
        t, l, b, r = rows.min(), cols.min(), rows.max() + 1, cols.max() + 1
        d = self.drawn
        d[:] = [min(d[0], t), min(d[1], l), max(d[2], b), max(d[3], r)]
        h, w = self.canvas_shape
        if 2 * (b - t) <= h and 2 * (r - l) <= w:
            self.update(QtCore.QRectF(l, t, r - l, b - t))
            return
        across = w // DIRTY_BLOCK + 1
        for block in np.unique((rows // DIRTY_BLOCK) * across + cols // DIRTY_BLOCK).tolist():
            by, bx = divmod(block, across)
            self.update(QtCore.QRectF(bx * DIRTY_BLOCK, by * DIRTY_BLOCK, DIRTY_BLOCK,
                                      DIRTY_BLOCK))

    def clear(self) -> None:
        t, l, b, r = self.drawn
        self.tiles.clear()
        if b > t:
            self.update(QtCore.QRectF(l, t, r - l, b - t))
        self.drawn[:] = [self.canvas_shape[0], self.canvas_shape[1], 0, 0]

    def snapshot(self) -> np.ndarray:
        """The preview as one (H, W) ARGB array (for checks on small canvases)."""
        h, w = self.canvas_shape
        out = np.zeros((h + TILE, w + TILE), np.uint32)
        for (ty, tx), (pixels, _image) in self.tiles.items():
            out[ty * TILE:(ty + 1) * TILE, tx * TILE:(tx + 1) * TILE] = pixels
        return out[:h, :w]


def preview_for(window) -> StrokePreview:
    """The canvas's stroke preview (one per window, remade when the canvas changes shape)."""
    canvas = window.canvas
    preview = canvas.stroke_preview
    shape = window.document.shape
    if preview is None or preview.canvas_shape != shape:
        if preview is not None:
            canvas.view.removeItem(preview)
        preview = StrokePreview(shape)
        canvas.view.addItem(preview)
        canvas.stroke_preview = preview
    return preview


def unfold(cell, previous, shape, tiled: bool):
    """(row, col) of a pointer cell. In the tiled view cells come folded into the texture; the
    copy nearest the previous point keeps a stroke crossing a seam continuous."""
    x, y = cell
    if not tiled or previous is None:
        return y, x
    h, w = shape
    r0, c0 = previous
    dr, dc = y - r0, x - c0
    return r0 + dr - h * round(dr / h), c0 + dc - w * round(dc / w)


@dataclass(frozen=True)
class BrushSettings:
    """The Brush or Spray tool's settings: its brush (a preset's, changed in the options) and
    how strokes take levels and meet the edges."""

    preset: str = "Round 3"          # the preset the settings started from
    size: int = 3
    shape: str = "disc"
    angle: float = 0.0
    bitmap: object = None            # a drawn brush's points (from a preset)
    density: float = 0.25            # cloud settings (the Spray)
    concentration: float = 0.0
    spacing: float = 0.25
    random_levels: bool = False
    choices: str = "1, 2, 3"
    wrap: bool = False

    @classmethod
    def of(cls, brush: Brush, **other) -> "BrushSettings":
        return cls(brush.name, brush.size, brush.shape, brush.angle, brush.bitmap,
                   brush.density, brush.concentration, brush.spacing, **other)

    def brush(self, cloud: bool) -> Brush:
        return Brush(self.preset, self.size, self.shape, float(self.angle),
                     self.bitmap if self.shape == "bitmap" else None,
                     "cloud" if cloud else "solid", self.density, self.concentration,
                     self.spacing)

    def level_choices(self) -> str | None:
        return self.choices if self.random_levels else None


class BrushOptions(QtWidgets.QWidget):
    """The brush's settings in the Tool options dock, two to a row (cloud settings only for the
    Spray), so the dock stays short."""

    def __init__(self, model, cloud: bool):
        super().__init__()
        self.cloud = cloud
        grid = QtWidgets.QGridLayout(self)
        grid.setContentsMargins(0, 0, 0, 0)
        grid.setColumnStretch(1, 1)
        grid.setColumnStretch(3, 1)
        self.preset = QtWidgets.QLabel()
        self.preset.setToolTip("The preset these settings started from (Brushes dock)")
        grid.addWidget(self.preset, 0, 0, 1, 4)
        self.size_box = QtWidgets.QSpinBox()
        self.size_box.setRange(1, brushes.MAX_BRUSH_SIZE)
        self.size_box.setToolTip("Diameter in points ([ smaller, ] bigger)")
        self.shape_box = QtWidgets.QComboBox()
        for text, value in SHAPE_NAMES:
            self.shape_box.addItem(text, value)
        self.shape_box.addItem("Drawn", "bitmap")
        self.shape_box.setToolTip("Shape of the brush (a drawn one comes from a preset)")
        self._row(grid, 1, "Size", self.size_box, "Shape", self.shape_box)
        self.angle = QtWidgets.QSpinBox()
        self.angle.setRange(-180, 180)
        self.angle.setSuffix("°")
        self.angle.setToolTip("Turn of the brush, counter-clockwise (a calligraphic nib)")
        self.spacing = QtWidgets.QSpinBox()
        self.spacing.setRange(int(brushes.MIN_SPACING * 100), int(brushes.MAX_SPACING * 100))
        self.spacing.setSingleStep(5)
        self.spacing.setSuffix(" %")
        self.spacing.setToolTip("Distance between dabs along the stroke, in % of the size")
        self._row(grid, 2, "Angle", self.angle, "Spacing", self.spacing)
        self.density = QtWidgets.QSpinBox()
        self.density.setRange(1, 100)
        self.density.setSuffix(" %")
        self.density.setToolTip("Chance of each point of the brush in each dab")
        self.concentration = QtWidgets.QDoubleSpinBox()
        self.concentration.setRange(0, brushes.MAX_CONCENTRATION)
        self.concentration.setSingleStep(0.5)
        self.concentration.setDecimals(1)
        self.concentration.setToolTip("0: an even cloud; higher gathers the points toward the "
                                      "centre (same mean density)")
        if cloud:
            self._row(grid, 3, "Density", self.density, "Centre", self.concentration)
        self.random = QtWidgets.QCheckBox("Random levels")
        self.random.setToolTip("Each point takes a level drawn from this list (a level listed "
                               "twice is twice as likely); otherwise the palette's level")
        self.choices = QtWidgets.QLineEdit("1, 2, 3")
        self.choices.setPlaceholderText("1, 2, 3")
        grid.addWidget(self.random, 4, 0, 1, 2)
        grid.addWidget(self.choices, 4, 2, 1, 2)
        self.wrap = QtWidgets.QCheckBox("Wrap around the edges")
        self.wrap.setToolTip("A stroke leaving one edge continues on the opposite one "
                             "(seamless tiles; always on in the tiled view)")
        grid.addWidget(self.wrap, 5, 0, 1, 4)
        model.bind("preset", self.preset, put=lambda name: self.preset.setText(f"Preset: {name}"))
        for name, widget, scale in (("size", self.size_box, 1), ("shape", self.shape_box, 1),
                                    ("angle", self.angle, 1), ("density", self.density, 100),
                                    ("concentration", self.concentration, 1),
                                    ("spacing", self.spacing, 100),
                                    ("random_levels", self.random, 1),
                                    ("choices", self.choices, 1), ("wrap", self.wrap, 1)):
            model.bind(name, widget, scale=scale)

    @staticmethod
    def _row(grid, row, label1, widget1, label2, widget2) -> None:
        grid.addWidget(QtWidgets.QLabel(label1), row, 0)
        grid.addWidget(widget1, row, 1)
        grid.addWidget(QtWidgets.QLabel(label2), row, 2)
        grid.addWidget(widget2, row, 3)


class BrushTool(Tool):
    """Drag to paint a stroke of the current level; a click paints one dab."""

    NAME = "Brush"
    SHORTCUT = "B"
    TIP = "Drag to paint with the current level; [ and ] change the size"
    CLOUD = False
    DEFAULT = Brush("Round 3", 3, "disc")
    SETTINGS = BrushSettings

    def __init__(self, window):
        super().__init__(window)
        self.opts: BrushOptions | None = None
        self.settings = BrushSettings.of(self.DEFAULT)

    def build_options(self):
        self.opts = BrushOptions(self.model, self.CLOUD)
        return self.opts

    def activate(self):
        self.show_own_dock("brush_dock")         # the presets in view while painting

    @property
    def brush(self) -> Brush:
        return self.settings.brush(self.CLOUD)

    def set_brush(self, brush: Brush) -> None:
        """Take a preset's settings (from the brush dock)."""
        s = self.settings
        self.settings = BrushSettings.of(brush, random_levels=s.random_levels,
                                         choices=s.choices, wrap=s.wrap)

    def resize(self, bigger: bool) -> None:
        """[ and ]: about 10 % smaller or bigger, at least one point."""
        size = self.settings.size
        step = max(1, round(size * 0.1))
        size = max(1, min(size + step if bigger else size - step, brushes.MAX_BRUSH_SIZE))
        self.model.update(size=size)
        self.main_window.statusBar().showMessage(f"{self.NAME} size {self.settings.size}", 2000)

    def stroke(self, points, seed: int) -> Stroke:
        s = self.settings
        return Stroke.from_brush(self.brush, points, self.main_window.current_level,
                                 level_choices=s.level_choices(), seed=seed,
                                 wrap=s.wrap or self.main_window.canvas.tiled)

    def click(self, cell, modifiers):
        x, y = cell
        self.main_window.submit(self.stroke([(y, x)], new_seed()))

    def drag(self, cell, modifiers):
        try:
            template = self.stroke([unfold(cell, None, self.document.shape, False)], new_seed())
        except TexeditorError as exc:
            self.main_window.show_error("Cannot paint with this brush", exc)
            return
        shape, tiled = self.document.shape, self.main_window.canvas.tiled
        painter = template.painter(shape)
        colours = palette_argb(self.document.palette)
        preview = preview_for(self.main_window)
        points = [template.points[0]]
        self._show(preview, painter.add(points[0]), colours)
        try:
            while True:
                point = unfold((yield), points[-1], shape, tiled)
                if point != points[-1]:
                    points.append(point)
                    self._show(preview, painter.add(point), colours)
        except GeneratorExit:
            self.main_window.submit(replace_params(template, points=tuple(points)))
            preview.clear()
            raise

    @staticmethod
    def _show(preview, painted, colours) -> None:
        rows, cols, values = painted
        preview.draw(rows, cols, colours[values])


class SprayTool(BrushTool):
    """The brush as a cloud of points (the thesis's own brush: strokes become point clouds)."""

    NAME = "Spray"
    SHORTCUT = "A"
    TIP = "Drag to spray a cloud of points of the current level; [ and ] change the size"
    CLOUD = True
    DEFAULT = Brush("Spray 16", 16, "disc", distribution="cloud", density=0.3)
