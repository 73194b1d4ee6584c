"""The zone tools (thesis §3.3.3a, §3.3.1): Duplicate zone (D), Scramble frontier (Shift+D) and
Scan order (O).

The eye sees symmetries but not repetitions: draw a rectangle or a lasso, drag it elsewhere and a
copy lands there (one DuplicateZone action); the copy then becomes the zone, and where its frontier
shows, the Scramble tool adds grains at random in a band along it (one ScrambleFrontier action).
The Scan order tool lays the zone's levels — or the whole canvas's — along a polar, spiral or
Peano order about the clicked point (one LayAlongOrder action).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from PySide6 import QtWidgets

from texeditor.paint import orders, zones
from texeditor.errors import TexeditorError
from texeditor.paint.actions import DuplicateZone, LayAlongOrder, ScrambleFrontier

from ..params_form import new_seed
from . import Tool
from .regions import mask_overlay

ZONE_TINT = (255, 200, 40)
BAND_TINT = (255, 90, 40)
GHOST_ALPHA = 200
ORDER_NAMES = [("Spiral", "spiral"), ("Polar (by angle, then distance)", "polar"),
               ("Peano (Hilbert)", "peano"), ("Television (rows)", "tv")]
MAX_RAMP = 2**16            # the order is previewed as a ramp over zones up to this many points


class Zone:
    """A drawn zone: ``kind`` rectangle (two opposite corners) or lasso (vertices), (row, col)."""

    def __init__(self, kind: str, points):
        self.kind, self.points = kind, tuple(tuple(int(v) for v in p) for p in points)

    def mask(self, shape) -> np.ndarray:
        return zones.zone_mask(shape, self.kind, self.points)

    def moved(self, dr: int, dc: int) -> "Zone":
        return Zone(self.kind, [(r + dr, c + dc) for r, c in self.points])


@dataclass(frozen=True)
class ZoneSettings:
    kind: str = "rectangle"          # how a drag draws a new zone: "rectangle" or "lasso"
    wrap: bool = False


@dataclass(frozen=True)
class ScrambleSettings(ZoneSettings):
    band: int = 4                    # width of the band along the frontier, points
    density: float = 0.3             # chance of a grain at each point of the band
    grain: int = 2                   # side of the square grains added


@dataclass(frozen=True)
class OrderSettings(ZoneSettings):
    order: str = "spiral"            # the fill order the zone is laid along


class ZoneOptions(QtWidgets.QWidget):
    """Zone kind and wrap (the zone tools), the scramble settings, the fill order."""

    def __init__(self, model, scramble: bool, order: bool = False):
        super().__init__()
        form = QtWidgets.QFormLayout(self)
        form.setContentsMargins(0, 0, 0, 0)
        self.kind = QtWidgets.QComboBox()
        self.kind.addItem("Rectangle", "rectangle")
        self.kind.addItem("Lasso (freehand)", "lasso")
        self.kind.setToolTip("How a drag draws a new zone")
        form.addRow("Zone", self.kind)
        self.band = QtWidgets.QSpinBox()
        self.band.setRange(1, zones.MAX_BAND)
        self.band.setValue(4)
        self.band.setSuffix(" pt")
        self.band.setToolTip("Width of the band along the frontier (half inside, half outside)")
        self.density = QtWidgets.QSpinBox()
        self.density.setRange(1, 100)
        self.density.setValue(30)
        self.density.setSuffix(" %")
        self.density.setToolTip("Chance of a grain at each point of the band")
        self.grain = QtWidgets.QSpinBox()
        self.grain.setRange(1, 16)
        self.grain.setValue(2)
        self.grain.setSuffix(" pt")
        self.grain.setToolTip("Side of the square grains added")
        if scramble:
            form.addRow("Band", self.band)
            form.addRow("Density", self.density)
            form.addRow("Grain", self.grain)
        self.order = QtWidgets.QComboBox()
        for text, value in ORDER_NAMES:
            self.order.addItem(text, value)
        self.order.setToolTip("The order the levels, read row after row, are laid along "
                              "(thesis §3.3.1): a spiral makes rings, a polar order rays")
        self.wrap = QtWidgets.QCheckBox("Wrap around the edges")
        self.wrap.setToolTip("A copy leaving one edge comes back on the other (seamless tiles)")
        if order:
            form.addRow("Order", self.order)
        else:
            form.addRow(self.wrap)
        self.status = QtWidgets.QLabel()
        self.status.setWordWrap(True)
        self.status.setMinimumHeight(2 * self.status.fontMetrics().lineSpacing() + 4)
        form.addRow(self.status)
        for name, widget, scale in (("kind", self.kind, 1), ("wrap", self.wrap, 1),
                                    ("band", self.band, 1), ("density", self.density, 100),
                                    ("grain", self.grain, 1), ("order", self.order, 1)):
            model.bind(name, widget, scale=scale)


class ZoneTool(Tool):
    """Draw a zone, then drag it to duplicate it; the copy becomes the zone."""

    NAME = "Duplicate zone"
    SHORTCUT = "D"
    TIP = "Drag to draw a zone; drag from inside it to put a copy elsewhere"
    SCRAMBLE = False
    ORDER = False
    SETTINGS = ZoneSettings

    def __init__(self, window):
        super().__init__(window)
        self.opts: ZoneOptions | None = None

    # the zone is shared by both zone tools: duplicate, then scramble the copy's frontier
    @property
    def zone(self) -> Zone | None:
        return self.main_window.paint_zone

    @zone.setter
    def zone(self, zone: Zone | None) -> None:
        self.main_window.paint_zone = zone

    def build_options(self):
        self.opts = ZoneOptions(self.model, self.SCRAMBLE, self.ORDER)
        self.model.changed.connect(lambda name: name in ("", "wrap", "band") and self.show_zone())
        return self.opts

    def activate(self):
        self.options()
        self.show_zone()

    def zone_mask(self) -> np.ndarray | None:
        if self.zone is None:
            return None
        try:
            return self.zone.mask(self.document.shape)
        except TexeditorError:
            return None

    def show_zone(self) -> None:
        """The zone tinted on the canvas, and a line in the options saying what it is."""
        if self.main_window.tool is not self:
            return
        mask = self.zone_mask()
        rgba, origin = (None, None) if mask is None else mask_overlay(mask, ZONE_TINT, 70)
        self.main_window.canvas.set_overlay(rgba, origin or (0, 0))
        if mask is None or not mask.any():
            self.opts.status.setText("No zone: drag on the canvas to draw one.")
        else:
            self.opts.status.setText(f"Zone: {self.zone.kind}, {int(mask.sum())} points. "
                                     + self.next_step())

    def next_step(self) -> str:
        return "Drag from inside it to place a copy."

    def click(self, cell, modifiers):
        mask = self.zone_mask()
        if mask is None or not self.inside(cell) or not mask[cell[1], cell[0]]:
            self.zone = None
            self.show_zone()

    def drag(self, cell, modifiers):
        self.options()
        mask = self.zone_mask()
        x, y = cell
        if mask is not None and self.inside(cell) and mask[y, x]:
            yield from self._move(mask, cell)
        else:
            yield from self._draw(cell)

    def _draw(self, cell):
        """Draw a new zone: a rectangle from the press to the pointer, or a lasso path."""
        kind = self.settings.kind
        points = [(cell[1], cell[0])]
        try:
            while True:
                x, y = yield
                if kind == "rectangle":
                    points[1:] = [(y, x)]
                elif (y, x) != points[-1]:
                    points.append((y, x))
                if len(points) >= (2 if kind == "rectangle" else 3):
                    self.zone = Zone(kind, points)
                    self.show_zone()
        except GeneratorExit:
            self.show_zone()
            raise

    def _move(self, mask, cell):
        """Drag the zone: a ghost of its content follows; the copy lands on release."""
        x0, y0 = cell
        levels = self.document.levels
        t, l, b, r = _box(mask)
        rgba = np.zeros((b - t, r - l, 4), np.uint8)
        inner = mask[t:b, l:r]
        rgba[inner, :3] = np.asarray(self.document.palette, np.uint8)[levels[t:b, l:r][inner]]
        rgba[inner, 3] = GHOST_ALPHA
        x, y = cell
        try:
            while True:
                x, y = yield
                self.main_window.canvas.set_overlay(rgba, (l + x - x0, t + y - y0))
        except GeneratorExit:
            dr, dc = y - y0, x - x0
            if (dr, dc) != (0, 0):
                action = DuplicateZone(points=self.zone.points, offset_row=dr, offset_col=dc,
                                       zone=self.zone.kind, wrap=self.settings.wrap)
                if self.main_window.submit(action):
                    self.zone = self.zone.moved(dr, dc)
            self.show_zone()
            raise


def _box(mask) -> tuple[int, int, int, int]:
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    return int(rows[0]), int(cols[0]), int(rows[-1]) + 1, int(cols[-1]) + 1


class ScrambleTool(ZoneTool):
    """Scramble the frontier of the zone (the last copy, or a zone drawn here)."""

    NAME = "Scramble frontier"
    SHORTCUT = "Shift+D"
    TIP = "Click in the zone to scramble its frontier with random grains; drag to draw a zone"
    SCRAMBLE = True
    SETTINGS = ScrambleSettings

    def band(self) -> np.ndarray | None:
        mask = self.zone_mask()
        if mask is None or not mask.any():
            return None
        return zones.frontier_band(mask, self.settings.band, wrap=self.settings.wrap)

    def show_zone(self) -> None:
        """The band that will change, tinted over the texture."""
        if self.main_window.tool is not self:
            return
        super().show_zone()
        band = self.band()
        if band is not None and band.any():
            rgba, origin = mask_overlay(band, BAND_TINT, 90)
            self.main_window.canvas.set_overlay(rgba, origin)

    def next_step(self) -> str:
        return "Click inside it to scramble its frontier (the tinted band)."

    def click(self, cell, modifiers):
        mask = self.zone_mask()
        if mask is not None and self.inside(cell) and mask[cell[1], cell[0]]:
            self.scramble()
        else:
            super().click(cell, modifiers)

    def drag(self, cell, modifiers):
        self.options()
        yield from self._draw(cell)

    def scramble(self) -> None:
        if self.zone is None:
            return
        s = self.settings
        self.main_window.submit(ScrambleFrontier(
            points=self.zone.points, zone=self.zone.kind, band=s.band, density=s.density,
            grain_size=s.grain, wrap=s.wrap, seed=new_seed()))


class OrderTool(ZoneTool):
    """Lay the zone — or, with no zone, the whole canvas — along a fill order (§3.3.1)."""

    NAME = "Scan order"
    SHORTCUT = "O"
    TIP = ("Click to lay the zone (or, with none, the canvas) along a spiral, polar or Peano "
           "order about that point; drag to draw a zone")
    ORDER = True
    SETTINGS = OrderSettings

    def __init__(self, window):
        super().__init__(window)
        self._ramp = (None, None)      # (key, RGBA ramp) of the last order that has no centre

    def build_options(self):
        options = super().build_options()
        self.model.changed.connect(lambda name: name == "order" and self.show_zone())
        return options

    def next_step(self) -> str:
        return "Click inside it at the centre of the order (the ramp: first points dark)."

    def show_zone(self) -> None:
        super().show_zone()
        if self.main_window.tool is self and self.zone is None:
            self.opts.status.setText("No zone: a click lays the whole canvas along the order "
                                     "about that point. Drag to draw a zone.")

    def target(self, cell) -> np.ndarray | None:
        """The points a click at ``cell`` lays out: the zone it falls in, or the canvas when
        there is no zone (None: outside the zone, or off the canvas)."""
        if not self.inside(cell):
            return None
        mask = self.zone_mask()
        if self.zone is None:
            return np.ones(self.document.shape, bool)
        return mask if mask is not None and mask[cell[1], cell[0]] else None

    def hover(self, cell):
        """The order about the pointer as a ramp over the target, first points darkest."""
        mask = None if cell is None else self.target(cell)
        if mask is None or not mask.any() or mask.sum() > MAX_RAMP:
            self.show_zone()
            return
        order = self.settings.order
        t, l, b, r = _box(mask)
        key = (order, self.zone and self.zone.points, mask.shape)
        if order in ("tv", "peano") and self._ramp[0] == key:     # the same wherever the pointer
            rgba = self._ramp[1]
        else:
            try:
                cells = orders.fill_order(mask, order, (cell[1], cell[0])) - (t, l)
            except TexeditorError:
                self.show_zone()
                return
            rgba = np.zeros((b - t, r - l, 4), np.uint8)
            ramp = np.linspace(40, 255, len(cells)).astype(np.uint8)
            rgba[cells[:, 0], cells[:, 1]] = np.stack(
                [ramp, ramp, 255 - ramp // 2, np.full_like(ramp, 150)], axis=1)
            self._ramp = (key, rgba)
        self.main_window.canvas.set_overlay(rgba, (l, t))

    def click(self, cell, modifiers):
        if self.target(cell) is None:
            super().click(cell, modifiers)
            return
        zone = {} if self.zone is None else {"zone": self.zone.kind, "points": self.zone.points}
        self.main_window.submit(LayAlongOrder(self.settings.order, centre_row=cell[1],
                                              centre_col=cell[0], **zone))
        self.hover(cell)

    def drag(self, cell, modifiers):
        self.options()
        yield from self._draw(cell)
