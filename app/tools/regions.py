"""The region tools of thesis §3.4: Fill, Translate, Copy and Extract (the selection and what
can be done to it: recolour, delete, flip, scale, rotate, duplicate, global transforms).

Each click or drag becomes one Action of `texeditor.regions.actions`; the canvas overlay shows the
ghost of a moved region and the current selection, never the document itself.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor.regions import actions as ra
from texeditor.regions import extractext as regions
from texeditor.regions import transforms
from texeditor.errors import TexeditorError

from ..canvas import palette_lut
from ..widgets import spin_box
from . import Tool
from .handles import Change, TransformFrame

KINDS = [("Region", "region"), ("Region in region", "region_in_region"),
         ("Regions in region", "regions_in_region"), ("Neighbours", "neighbours"),
         ("Partial region", "partial")]
KIND_WORDS = {"region": "region", "region_in_region": "region in region",   # the status line's
              "regions_in_region": "regions in region", "neighbours": "neighbours",
              "partial": "partial region"}
SELECTION_TINT = (40, 200, 255)
GHOST_REST_MS = 150          # a handle drag's pointer still this long: the exact ghost


def mask_overlay(mask: np.ndarray, colour, alpha: int = 110):
    """An RGBA picture of a presence mask cut to its bounding box: the inside tinted, the
    frontier opaque (a still 'marching ants' line). Returns (rgba, (x, y)) or (None, None)."""
    found = transforms.bbox(mask)          # not np.nonzero: a drag redraws it at every move
    if found is None:
        return None, None
    r0, c0, r1, c1 = found
    box = np.pad(mask[r0:r1, c0:c1], 1)
    inner = box[1:-1, 1:-1]
    edge = inner & ~(box[:-2, 1:-1] & box[2:, 1:-1] & box[1:-1, :-2] & box[1:-1, 2:])
    rgba = np.zeros(inner.shape + (4,), np.uint8)
    rgba[inner, :3] = colour
    rgba[inner, 3] = alpha
    rgba[edge, 3] = 255
    return rgba, (int(c0), int(r0))


def ghost_overlay(carried: np.ndarray, palette):
    """A transformed selection — ``carried`` holds each moved point's level + 1, 0 elsewhere —
    in the colours it will have, a quarter tinted so that it shows over its own colour, its
    frontier in the selection's tint: what a handle drag would make, before it is made."""
    rgba, origin = mask_overlay(carried > 0, SELECTION_TINT, alpha=220)
    if rgba is None:
        return None, None
    (x, y), (h, w) = origin, rgba.shape[:2]
    inner = rgba[..., 3] == 220
    tinted = (0.75 * palette_lut(palette) + 0.25 * np.array(SELECTION_TINT)).astype(np.uint8)
    rgba[..., :3] = np.where(inner[..., None], tinted[carried[y:y + h, x:x + w] - 1],
                             rgba[..., :3])
    return rgba, origin


@dataclass(frozen=True)
class FillSettings:
    scope: str = "region"            # "region" (connected) or "global" (every point of the level)
    connectivity: int = 4


@dataclass(frozen=True)
class CopySettings(FillSettings):
    kind: str = "region"             # what a click extracts (KINDS)
    wrap: bool = False


@dataclass(frozen=True)
class TranslateSettings(CopySettings):
    fill: int = 0                    # the level left behind


@dataclass(frozen=True)
class ExtractSettings(CopySettings):
    angle: float = 90.0              # the selection panel's Rotate
    factor: float = 2.0              # its Scale
    dx: int = 16                     # its Duplicate: offset and copies along x and y
    dy: int = 0
    nx: int = 1
    ny: int = 1


def recipe(settings: FillSettings) -> dict:
    """The selection's recipe fields shared by the region Actions."""
    return {"scope": settings.scope, "connectivity": settings.connectivity}


class RegionOptions(QtWidgets.QWidget):
    """Scope, connectivity and (for moves and selections) the extraction kind and wrap-around:
    the widgets of a region tool's settings."""

    def __init__(self, model, *, kind=False, wrap=False, fill=False):
        super().__init__()
        form = QtWidgets.QFormLayout(self)
        form.setContentsMargins(0, 0, 0, 0)
        self.kind = QtWidgets.QComboBox()
        for text, value in KINDS:
            self.kind.addItem(text, value)
        self.kind.setToolTip("What the click extracts (thesis §3.4.2)")
        self.scope = QtWidgets.QComboBox()
        self.scope.addItem("Connected region", "region")
        self.scope.addItem("Every point of the level", "global")
        self.scope.setToolTip("Region: the connected region at the point; global: every point "
                              "of its level (EXTRACTEXT)")
        self.connectivity = QtWidgets.QComboBox()
        self.connectivity.addItem("4 (edges)", 4)
        self.connectivity.addItem("8 (edges and corners)", 8)
        self.wrap = QtWidgets.QCheckBox("Wrap around the edges")
        self.wrap.setToolTip("What leaves one side comes back on the other: tiles stay seamless")
        self.fill = QtWidgets.QSpinBox()
        self.fill.setRange(0, 15)
        self.fill.setToolTip("The level left behind where the region was (0 = background)")
        if kind:
            form.addRow("Extract", self.kind)
        form.addRow("Scope", self.scope)
        form.addRow("Connectivity", self.connectivity)
        if fill:
            form.addRow("Leave behind", self.fill)
        if wrap:
            form.addRow(self.wrap)
        for name in ("kind", "scope", "connectivity", "wrap", "fill"):
            model.bind(name, getattr(self, name))


class FillTool(Tool):
    NAME = "Fill"
    SHORTCUT = "F"
    TIP = "Click a region to fill it with the current level (REMPLIR)"
    SETTINGS = FillSettings

    def build_options(self):
        self.opts = RegionOptions(self.model)
        return self.opts

    def click(self, cell, modifiers):
        if self.inside(cell):
            x, y = cell
            self.main_window.submit(ra.Fill(y, x, self.main_window.current_level,
                                            **recipe(self.settings)))


class TranslateTool(Tool):
    """Drag from a region to where it goes; the ghost follows the pointer (TRANSLATER)."""

    NAME = "Translate"
    SHORTCUT = "M"
    TIP = "Drag a region to move it; what it leaves behind gets the chosen level"
    KEEP_SOURCE = False
    SETTINGS = TranslateSettings

    def build_options(self):
        self.opts = RegionOptions(self.model, kind=True, wrap=True, fill=not self.KEEP_SOURCE)
        return self.opts

    def drag(self, cell, modifiers):
        if not self.inside(cell):
            return
        x0, y0 = cell
        settings = self.settings
        selection = {**recipe(settings), "kind": settings.kind}
        try:
            mask = regions.select(self.document.levels, (y0, x0), **selection)
        except TexeditorError as exc:
            self.main_window.show_error("Nothing to move here", exc)
            return
        colour = self.document.palette[self.document.levels[y0, x0]]
        wrap = settings.wrap
        x, y = cell
        try:
            while True:
                x, y = yield
                ghost = regions.shift_mask(mask, (y - y0, x - x0), wrap=wrap)
                rgba, origin = mask_overlay(ghost, colour, alpha=170)
                self.main_window.canvas.set_overlay(rgba, origin or (0, 0))
        except GeneratorExit:
            self.main_window.canvas.set_overlay(None)
            if (x, y) != (x0, y0):
                self.main_window.submit(self.action(y0, x0, y, x, selection, wrap))
            raise

    def action(self, row, col, to_row, to_col, selection, wrap):
        return ra.Translate(row, col, to_row, to_col, fill=self.settings.fill, wrap=wrap,
                            **selection)


class CopyTool(TranslateTool):
    NAME = "Copy"
    SHORTCUT = "C"
    TIP = "Drag a region to copy it elsewhere (COPIER)"
    KEEP_SOURCE = True
    SETTINGS = CopySettings

    def action(self, row, col, to_row, to_col, selection, wrap):
        return ra.Copy(row, col, to_row, to_col, wrap=wrap, **selection)


class ExtractTool(Tool):
    """Click to extract a selection; the panel then acts on it (thesis §3.4.2f, §3.4.3)."""

    NAME = "Extract"
    SHORTCUT = "E"
    TIP = ("Click to select what the chosen extraction finds; then drag its handles (move, "
           "scale, rotate) or use the panel")
    SETTINGS = ExtractSettings

    def __init__(self, window):
        super().__init__(window)
        self.selection: dict | None = None     # the recipe: row, col, kind, scope, connectivity
        self._mask: np.ndarray | None = None   # the selection's points, as last drawn
        self.frame: TransformFrame | None = None
        self._unsubscribe = None
        self._ghost = None                     # during a handle drag: (carried, its picture)
        self._latest: Change | None = None     # the drag's latest change
        self._placed = None                    # the overlay's own transform while Qt carries it
        self._resting = QtCore.QTimer(singleShot=True, interval=GHOST_REST_MS)
        self._resting.timeout.connect(self._exact_ghost)

    def build_options(self):
        box = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(box)
        layout.setContentsMargins(0, 0, 0, 0)
        self.opts = RegionOptions(self.model, kind=True, wrap=True)
        layout.addWidget(self.opts)
        self.status = QtWidgets.QLabel("No selection: click the canvas.")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        self.neighbours = NeighbourStepper(self)
        layout.addWidget(self.neighbours)
        self.panel = SelectionPanel(self)
        layout.addWidget(self.panel)
        self.panel.setEnabled(False)
        return box

    def activate(self):
        self.options()
        if self.frame is None:
            self.frame = self._build_frame()
        self._unsubscribe = self.main_window.history.subscribe(self.refresh)
        self.refresh()

    def deactivate(self):
        if self._unsubscribe is not None:
            self._unsubscribe()
            self._unsubscribe = None
        if self.frame is not None:
            self.frame.set_box(None)
        super().deactivate()

    def _build_frame(self) -> TransformFrame:
        """The transform handles, in the canvas for good; shown while a selection is."""
        factor = self.panel.factor
        frame = TransformFrame((factor.minimum(), factor.maximum()))
        frame.changing.connect(self.preview)
        frame.finished.connect(self.transform)
        frame.cancelled.connect(self.refresh)
        self.main_window.canvas.view.addItem(frame, ignoreBounds=True)
        return frame

    def click(self, cell, modifiers):
        self.options()
        if not self.inside(cell):
            self.clear()
            return
        x, y = cell
        self.selection = {"row": y, "col": x, "kind": self.settings.kind,
                          **recipe(self.settings), "neighbour": None}
        self.refresh()

    def clear(self) -> None:
        self.selection = None
        self.refresh()

    def live_selection(self) -> dict | None:
        """The selection, if its point is on the canvas as it is now (an undo or a model may
        have made the canvas smaller since it was clicked: then there is none to act on)."""
        s = self.selection
        h, w = self.document.shape
        return s if s is not None and 0 <= s["row"] < h and 0 <= s["col"] < w else None

    def mask(self) -> np.ndarray | None:
        s = self.live_selection()
        if s is None:
            return None
        return regions.select(self.document.levels, (s["row"], s["col"]), kind=s["kind"],
                              scope=s["scope"], connectivity=s["connectivity"],
                              neighbour=s["neighbour"])

    def neighbour_count(self) -> int:
        """How many neighbours the selection's region has (0 unless it selects neighbours)."""
        s = self.selection
        if s is None or s["kind"] != "neighbours" or self._mask is None:   # as last drawn
            return 0
        return int(regions.neighbour_labels(self.document.levels, (s["row"], s["col"]),
                                            scope=s["scope"],
                                            connectivity=s["connectivity"]).max())

    def step_neighbour(self, step: int) -> None:
        """Isolate the next (or previous) neighbour, as ISOLER finds them one by one: all of
        them, the 1st, the 2nd… the last, then all again. The selection's recipe records it."""
        n = self.neighbour_count()
        if not n:
            return
        current = self.selection["neighbour"] or 0
        k = (current + step) % (n + 1)
        self.selection = {**self.selection, "neighbour": k or None}
        self.refresh()

    def refresh(self, change=None) -> None:
        """Redraw the selection over the current document (after any change, undo included)."""
        self._forget_ghost()
        if self.main_window.tool is not self:
            return
        mask = self._mask = self.mask()
        rgba, origin = (None, None) if mask is None else mask_overlay(mask, SELECTION_TINT)
        self.main_window.canvas.set_overlay(rgba, origin or (0, 0))
        box = None if mask is None else transforms.bbox(mask)
        self.frame.set_box(None if box is None else
                           QtCore.QRectF(box[1], box[0], box[3] - box[1], box[2] - box[0]))
        count = 0 if mask is None else int(mask.sum())
        self.panel.setEnabled(count > 0)
        self.neighbours.show_count(self.neighbour_count())
        if self.selection is None:
            self.status.setText("No selection: click the canvas.")
        else:
            s = self.selection
            what = KIND_WORDS[s["kind"]] if s["neighbour"] is None else \
                f"neighbour {s['neighbour']}"
            self.status.setText(f"{count} points selected ({what} at "
                                f"x {s['col']}, y {s['row']}).")

    def build(self, action_type, **params):
        """A selection Action from the recipe (and the wrap option)."""
        fields = {f for f in action_type.__dataclass_fields__}
        recipe = {k: v for k, v in self.selection.items() if k in fields}
        if "wrap" in fields:
            params.setdefault("wrap", self.settings.wrap)
        return action_type(**recipe, **params)

    def submit(self, action_type, **params) -> None:
        """Apply a selection Action built from the recipe (and the wrap option)."""
        if self.selection is not None:
            self.main_window.submit(self.build(action_type, **params))

    # -- the transform handles --------------------------------------------------------------------
    def preview(self, change: Change) -> None:
        """Show where a handle drag takes the selection, over the untouched document: while the
        pointer moves, the selection's picture carried by Qt with the frame (instant at any
        size); once it rests, the engine's own result (wrap-around included)."""
        overlay = self.main_window.canvas.overlay
        if self._ghost is None:
            carried = np.where(self._mask, self.document.levels + 1, 0).astype(np.uint8)
            self._ghost = (carried, ghost_overlay(carried, self.document.palette))
        if self._placed is None:               # a new drag, or the engine's picture shown
            rgba, origin = self._ghost[1]
            self.main_window.canvas.set_overlay(rgba, origin or (0, 0))
            self._placed = overlay.transform()
        overlay.setTransform(self._placed * change.qtransform(self.frame.box.center()))
        self._latest = change
        self._resting.start()

    def _exact_ghost(self) -> None:
        """The pointer rests: the engine carries the selection (one call for the points and
        their levels: level + 1, 0 for the rest)."""
        if self._ghost is None or self._latest is None:
            return
        rgba, origin = ghost_overlay(self._carry(self._latest, self._ghost[0]),
                                     self.document.palette)
        self.main_window.canvas.set_overlay(rgba, origin or (0, 0))
        self._placed = None

    def _forget_ghost(self) -> None:
        self._resting.stop()
        self._ghost = self._latest = self._placed = None

    def transform(self, change: Change) -> None:
        """Commit a handle drag as one Action; the selection follows the points it moved and
        the panel shows the factor or angle used."""
        if change.is_identity or self.selection is None:
            self.refresh()                     # the selection as it was, no ghost
            return
        action, before = self._action(change), self.selection
        self.selection = self._followed(change)    # before the history redraws it
        if not self.main_window.submit(action):
            self.selection = before
            self.refresh()
            return
        field = {"scale": "factor", "rotate": "angle"}.get(change.mode)
        if field is not None:
            self.model.update(**{field: change.value})

    def _action(self, change: Change):
        """The Action a handle drag makes: the panel's own for a factor or an angle."""
        if change.mode == "move":
            dx, dy = change.value
            return self.build(ra.Translate, to_row=self.selection["row"] + dy,
                              to_col=self.selection["col"] + dx)
        if change.mode == "scale":
            return self.build(ra.ScaleSelection, factor=change.value)
        return self.build(ra.RotateSelection, angle=change.value)

    def _carry(self, change: Change, array: np.ndarray) -> np.ndarray:
        """``array`` after ``change`` of the selection, by the engine function its Action calls;
        on the mask itself it gives where the selected points land."""
        mask, wrap = self._mask, self.settings.wrap
        if change.mode == "move":
            dx, dy = change.value
            return regions.move(array, mask, (dy, dx), wrap=wrap)
        if change.mode == "scale":
            return regions.scale(array, mask, change.value, wrap=wrap)
        return regions.rotate(array, mask, change.value, wrap=wrap)

    def _followed(self, change: Change) -> dict | None:
        """The recipe of the transformed selection: its point, when it is one of the selected
        points, goes to the landed point nearest to where the map takes it (an anchor outside
        the selection, as for a region in a region, stays); None when nothing landed."""
        s = self.selection
        if not self._mask[s["row"], s["col"]]:
            return s
        landed = np.argwhere(self._carry(change, self._mask.view(np.uint8)))
        if not len(landed):
            return None
        p = change.qtransform(self.frame.box.center()).map(
            QtCore.QPointF(s["col"] + 0.5, s["row"] + 0.5))
        target = np.array([p.y() - 0.5, p.x() - 0.5])
        if self.settings.wrap:
            target %= self._mask.shape
        row, col = landed[np.argmin(((landed - target) ** 2).sum(axis=1))]
        return {**s, "row": int(row), "col": int(col)}


class NeighbourStepper(QtWidgets.QWidget):
    """With the neighbours selected: step through them one at a time (LIMITROPHES/ISOLER,
    thesis Fig. 3.16) — all of them, the 1st, the 2nd… — so that one can be acted on alone."""

    def __init__(self, tool: ExtractTool):
        super().__init__()
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        self.previous = QtWidgets.QPushButton("◀")
        self.previous.setToolTip("The previous neighbour (before the first: all of them)")
        self.next = QtWidgets.QPushButton("▶")
        self.next.setToolTip("The next neighbour, in the order ISOLER finds them (after the "
                             "last: all of them)")
        self.label = QtWidgets.QLabel()
        self.label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        for w in (self.previous, self.next):
            w.setFixedWidth(w.sizeHint().height() * 2)
        row.addWidget(self.previous)
        row.addWidget(self.label, 1)
        row.addWidget(self.next)
        self.previous.clicked.connect(lambda: tool.step_neighbour(-1))
        self.next.clicked.connect(lambda: tool.step_neighbour(1))
        self.tool = tool
        self.hide()

    def show_count(self, n: int) -> None:
        """Shown while the selection is of neighbours (``n`` of them)."""
        self.setVisible(n > 0)
        k = self.tool.selection["neighbour"] if n else None
        self.label.setText(f"All {n} neighbours" if k is None else f"Neighbour {k} of {n}")


class SelectionPanel(QtWidgets.QGroupBox):
    """What can be done to the selection: each button is one Action."""

    def __init__(self, tool: ExtractTool):
        super().__init__("Selection")
        self.tool = tool
        grid = QtWidgets.QGridLayout(self)
        row = 0

        def button(text, tip, slot, col=0, span=1):
            b = QtWidgets.QPushButton(text)
            b.setToolTip(tip)
            b.clicked.connect(slot)
            grid.addWidget(b, row, col, 1, span)
            return b

        self.recolour = button("Recolour", "Give the selection the current level",
                               self.do_recolour)
        self.delete = button("Delete", "Set the selection to the background (level 0)",
                             self.do_delete, 1)
        row += 1
        self.flip_h = button("Flip ↔", "Mirror left–right about its centre",
                             lambda: tool.submit(ra.FlipSelection, axis="horizontal"))
        self.flip_v = button("Flip ↕", "Mirror top–bottom about its centre",
                             lambda: tool.submit(ra.FlipSelection, axis="vertical"), 1)
        row += 1
        self.angle = spin_box(-360, 360, 90, decimals=1, suffix="°")
        grid.addWidget(self.angle, row, 0)
        self.rotate = button("Rotate", "Turn the selection about its centre (counter-clockwise)",
                             lambda: tool.submit(ra.RotateSelection, angle=tool.settings.angle), 1)
        row += 1
        self.factor = spin_box(0.05, 16, 2.0, decimals=2, suffix="×")
        grid.addWidget(self.factor, row, 0)
        self.scale_button = button("Scale", "Zoom the selection about its centre",
                            lambda: tool.submit(ra.ScaleSelection, factor=tool.settings.factor),
                            1)
        row += 1
        grid.addWidget(QtWidgets.QLabel("Duplicate"), row, 0, 1, 2)
        row += 1
        self.dx = spin_box(-4096, 4096, 16, prefix="x ")
        self.dy = spin_box(-4096, 4096, 0, prefix="y ")
        grid.addWidget(self.dx, row, 0)
        grid.addWidget(self.dy, row, 1)
        row += 1
        self.nx = spin_box(1, 64, 1, prefix="× ")
        self.nx.setToolTip("Copies along x, side by side (a grid: identity, thesis §3.4.3)")
        self.ny = spin_box(1, 64, 1, prefix="× ")
        self.ny.setToolTip("Copies along y")
        grid.addWidget(self.nx, row, 0)
        grid.addWidget(self.ny, row, 1)
        row += 1
        self.duplicate = button("Duplicate", "Copy the selection by the offset, on a grid of "
                                "copies", self.do_duplicate, 0, 2)
        for name in ("angle", "factor", "dx", "dy", "nx", "ny"):
            tool.model.bind(name, getattr(self, name))

    def do_recolour(self):
        self.tool.submit(ra.ChangeLevel, value=self.tool.main_window.current_level)

    def do_delete(self):
        self.tool.submit(ra.DeleteSelection)
        self.tool.clear()

    def do_duplicate(self):
        s = self.tool.settings
        self.tool.submit(ra.Identity, offset_row=s.dy, offset_col=s.dx, repeat_rows=s.ny,
                         repeat_cols=s.nx)


