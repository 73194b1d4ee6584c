"""The Dominance tree tool (Shift+G) (thesis §3.3.3a, Fig. 3.6): build a tree by placing its
vertices on screen, each carrying a grain, as the thesis asks of its light pen.

The first click places the root. Each later click hangs a new vertex under the *current parent*
(the root at first, ringed in yellow); a click near a vertex makes it the current parent instead,
and a drag from a vertex moves it. Every vertex takes the Grain tool's current grain (the Grain
stamps dock stays open to change it between clicks). Enter finishes the tree — one DominanceTree
action, undone by one Ctrl+Z — Backspace (or Ctrl+Z while building) takes back the last vertex,
Esc drops the tree; choosing another tool finishes it, so nothing placed is lost. The levels come
from the tree: a vertex is brighter than every vertex under it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.errors import TexeditorError
from texeditor.paint.actions import MIXES, DominanceTree
from texeditor.paint.grains import GrainType

from . import Tool
from .grain import GrainTool

PICK_PIXELS = 9             # a click this close to a vertex (on screen) picks it
EDGE = QtGui.QColor(40, 200, 255)
PARENT = QtGui.QColor(255, 220, 60)
GHOST_ALPHA = 170
STATUS_MS = 8000            # how long the status bar says a tree was kept, not drawn
Key = QtCore.Qt.Key


@dataclass(frozen=True)
class TreeSettings:
    low: int = 1                     # level of the vertices that dominate nothing
    high: int = -1                   # level of the root (-1: the top level)
    mix: str = "over"                # over: the tree covers what is there; brighter: max
    wrap: bool = False


class TreeOptions(QtWidgets.QWidget):
    """The grain each new vertex takes, the levels, the mix, and what to do next."""

    def __init__(self, tool: "TreeTool"):
        super().__init__()
        form = QtWidgets.QFormLayout(self)
        form.setContentsMargins(0, 0, 0, 0)
        self.grain = QtWidgets.QLabel()
        self.grain.setWordWrap(True)
        form.addRow("Grain", self.grain)
        levels = QtWidgets.QHBoxLayout()
        self.low = QtWidgets.QSpinBox()
        self.low.setRange(0, 15)
        self.low.setToolTip("Level of the vertices that dominate nothing (the leaves)")
        self.high = QtWidgets.QSpinBox()
        self.high.setRange(-1, 15)
        self.high.setSpecialValueText("top")
        self.high.setToolTip("Level of the root, the brightest (top: the palette's last level)")
        levels.addWidget(self.low)
        levels.addWidget(QtWidgets.QLabel("to"))
        levels.addWidget(self.high)
        form.addRow("Levels", levels)
        self.mix = QtWidgets.QComboBox()
        self.mix.addItem("Over", "over")
        self.mix.addItem("Brighter wins", "brighter")
        self.mix.setToolTip("Where the tree meets another tree or the texture: cover it, or "
                            "keep whichever level is brighter (dominance across trees)")
        assert [self.mix.itemData(k) for k in range(self.mix.count())] == list(MIXES)
        form.addRow("Mix", self.mix)
        self.wrap = QtWidgets.QCheckBox("Wrap around the edges")
        form.addRow(self.wrap)
        self.status = QtWidgets.QLabel()
        self.status.setWordWrap(True)
        self.status.setMinimumHeight(3 * self.status.fontMetrics().lineSpacing() + 4)
        form.addRow(self.status)
        buttons = QtWidgets.QHBoxLayout()
        self.finish_button = QtWidgets.QPushButton("Finish (Enter)")
        self.finish_button.clicked.connect(tool.finish)
        self.drop_button = QtWidgets.QPushButton("Drop (Esc)")
        self.drop_button.clicked.connect(tool.drop)
        buttons.addWidget(self.finish_button)
        buttons.addWidget(self.drop_button)
        form.addRow(buttons)
        for name in ("low", "high", "mix", "wrap"):
            tool.model.bind(name, getattr(self, name))


class KeyFilter(QtCore.QObject):
    """Keys on the canvas go to ``handler(key, modifiers, act)`` before the window's shortcuts
    (Esc, Ctrl+Z): it says whether it takes the key, and acts on it when ``act`` is True."""

    def __init__(self, handler):
        super().__init__()
        self.handler = handler

    def eventFilter(self, obj, ev):
        Type = QtCore.QEvent.Type
        if ev.type() not in (Type.ShortcutOverride, Type.KeyPress):
            return False
        if not self.handler(ev.key(), ev.modifiers(), ev.type() == Type.KeyPress):
            return False
        ev.accept()
        return True


class TreeTool(Tool):
    NAME = "Dominance tree"
    LABEL = "Tree"
    SHORTCUT = "Shift+G"
    TIP = ("Click to place vertices of a dominance tree, each with the current grain; click near "
           "a vertex to hang the next ones under it; Enter finishes")
    SETTINGS = TreeSettings
    PLACES_GRAINS = True            # picking a grain in the Grain stamps dock keeps this tool

    def __init__(self, window):
        super().__init__(window)
        self.opts: TreeOptions | None = None
        self.points: list[tuple[int, int]] = []
        self.parents: list[int] = []
        self.grains: list[GrainType] = []
        self.current_parent = -1          # where the next vertex hangs
        self.edges: QtWidgets.QGraphicsPathItem | None = None
        self.ring: QtWidgets.QGraphicsPathItem | None = None
        self.rubber: QtWidgets.QGraphicsPathItem | None = None     # where a click would go
        self._unsubscribe = None
        self.keys = KeyFilter(self.key)
        self.model.changed.connect(lambda _name: self.show_tree())

    @property
    def grain_tool(self) -> GrainTool:
        return next(t for t in self.main_window.tools if isinstance(t, GrainTool))

    # -- activation ---------------------------------------------------------------------------------
    def build_options(self):
        self.opts = TreeOptions(self)
        self.grain_tool.model.changed.connect(lambda _name: self.show_grain())
        return self.opts

    def activate(self) -> None:
        self.options()
        self.show_own_dock("grain_dock")
        canvas = self.main_window.canvas
        self.edges, self.ring, self.rubber = (QtWidgets.QGraphicsPathItem() for _ in range(3))
        solid, dashed = QtCore.Qt.PenStyle.SolidLine, QtCore.Qt.PenStyle.DashLine
        for item, colour, width, style in ((self.edges, EDGE, 1.5, solid),
                                           (self.ring, PARENT, 2.5, solid),
                                           (self.rubber, EDGE, 1.0, dashed)):
            pen = QtGui.QPen(colour, width)
            pen.setStyle(style)
            pen.setCosmetic(True)
            item.setPen(pen)
            item.setZValue(20)
            canvas.view.addItem(item)
        canvas.installEventFilter(self.keys)
        self._unsubscribe = self.main_window.history.subscribe(lambda _change: self.show_tree())
        self.show_grain()
        self.show_tree()

    def deactivate(self) -> None:
        self.finish(leaving=True)
        if self._unsubscribe is not None:
            self._unsubscribe()
            self._unsubscribe = None
        canvas = self.main_window.canvas
        canvas.removeEventFilter(self.keys)
        for item in (self.edges, self.ring, self.rubber):
            canvas.view.removeItem(item)
        self.edges = self.ring = self.rubber = None
        super().deactivate()

    def resize(self, bigger: bool) -> None:
        """[ and ]: the grain of the next vertices one point bigger or smaller."""
        self.grain_tool.resize(bigger)

    # -- building the tree --------------------------------------------------------------------------
    def vertex_near(self, cell) -> int | None:
        """The vertex within PICK_PIXELS of a cell on screen (the nearest), if any."""
        if not self.points:
            return None
        x, y = cell
        d = np.hypot(*(np.array(self.points) - (y, x)).T) * self.main_window.canvas.zoom()
        k = int(np.argmin(d))
        return k if d[k] <= PICK_PIXELS else None

    def click(self, cell, modifiers):
        near = self.vertex_near(cell)
        if near is not None:
            self.current_parent = near
        else:
            self.add(cell)
        self.show_tree()
        self.hover(cell)

    def hover(self, cell):
        """A dashed edge from the current parent to the pointer — or, near a vertex, a ring
        round it: what a click there would do."""
        if self.rubber is None:
            return
        path = QtGui.QPainterPath()
        near = None if cell is None else self.vertex_near(cell)
        radius = 6 / max(self.main_window.canvas.zoom(), 1e-6)
        if near is not None:
            r, c = self.points[near]
            path.addEllipse(QtCore.QPointF(c + 0.5, r + 0.5), radius, radius)
        elif cell is not None and 0 <= self.current_parent < len(self.points):
            r, c = self.points[self.current_parent]
            path.moveTo(c + 0.5, r + 0.5)
            path.lineTo(cell[0] + 0.5, cell[1] + 0.5)
        self.rubber.setPath(path)

    def add(self, cell) -> None:
        """A new vertex at ``cell`` (x, y), under the current parent, with the current grain."""
        self.points.append((cell[1], cell[0]))
        self.parents.append(self.current_parent)
        self.grains.append(self.grain_tool.grain)
        if self.current_parent < 0:
            self.current_parent = 0

    def drag(self, cell, modifiers):
        """From a vertex: move it; elsewhere: a vertex where the button is released."""
        moved = self.vertex_near(cell)
        last = cell
        try:
            while True:
                last = yield
                if moved is not None:
                    self.points[moved] = (last[1], last[0])
                    self.show_tree()
        except GeneratorExit:
            if moved is None:
                self.add(last)
            self.show_tree()
            raise

    def undo_vertex(self) -> None:
        """Take back the last vertex; the current parent stays, unless it was that vertex."""
        if not self.points:
            return
        self.points.pop()
        self.grains.pop()
        parent = self.parents.pop()
        if self.current_parent >= len(self.points):
            self.current_parent = parent
        self.show_tree()

    def drop(self) -> None:
        """Forget the tree being built (Esc)."""
        self.points, self.parents, self.grains, self.current_parent = [], [], [], -1
        self.show_tree()

    def action(self) -> DominanceTree:
        s = self.settings
        return DominanceTree.from_vertices(
            self.points, self.parents, self.grains, low=s.low, mix=s.mix,
            high=None if s.high < 0 else s.high,
            wrap=s.wrap or self.main_window.canvas.tiled)

    def finish(self, leaving: bool = False) -> bool:
        """Apply the tree as one step (Enter); a refused one stays on screen to be mended.
        ``leaving`` (another tool chosen): a tree that cannot be drawn is kept for when the
        tool comes back, said in the status bar — not a dialog at every change of tool."""
        if not self.points:
            return False
        try:
            action = self.action()
            if leaving:
                action.points_on(self.document.levels, self.document.num_levels)
        except TexeditorError as exc:
            if leaving:
                self.main_window.statusBar().showMessage(
                    f"The tree was kept, not drawn: {exc}", STATUS_MS)
            else:
                self.main_window.show_error("This tree cannot be drawn", exc)
            return False
        self.main_window.canvas.set_overlay(None)
        if not self.main_window.submit(action):
            return False
        self.drop()
        return True

    def key(self, key: int, modifiers, act: bool) -> bool:
        """Keys on the canvas while a tree is being built: Enter, Esc, Backspace or Delete, and
        Ctrl+Z (True: taken, the window's own shortcut does not run); done when ``act``."""
        if not self.points:
            return False
        mods = QtCore.Qt.KeyboardModifier
        undo = key == Key.Key_Z and modifiers & mods.ControlModifier \
            and not modifiers & mods.ShiftModifier
        slot = {Key.Key_Return: self.finish, Key.Key_Enter: self.finish, Key.Key_Escape: self.drop,
                Key.Key_Backspace: self.undo_vertex, Key.Key_Delete: self.undo_vertex}.get(
            key, self.undo_vertex if undo else None)
        if slot is not None and act:
            slot()
        return slot is not None

    # -- showing it ---------------------------------------------------------------------------------
    def show_grain(self) -> None:
        if self.opts is not None:
            grain = self.grain_tool.grain
            self.opts.grain.setText(f"<b>{grain.name}</b> · {grain.size} pt")
            self.opts.grain.setToolTip("The grain of the next vertex: choose another in the "
                                       "Grain stamps dock")

    def show_tree(self) -> None:
        """The grains as the tree will draw them, the edges, the current parent ringed, and a
        line saying where the next vertex goes (or why the tree cannot be drawn)."""
        if self.main_window.tool is not self or self.edges is None:
            return
        canvas = self.main_window.canvas
        problem = self._show_grains()
        edges, ring = QtGui.QPainterPath(), QtGui.QPainterPath()
        centre = [QtCore.QPointF(c + 0.5, r + 0.5) for r, c in self.points]
        radius = 4 / max(canvas.zoom(), 1e-6)
        for k, p in enumerate(self.parents):
            if p >= 0:
                edges.moveTo(centre[p])
                edges.lineTo(centre[k])
            edges.addEllipse(centre[k], radius, radius)
        if 0 <= self.current_parent < len(centre):
            ring.addEllipse(centre[self.current_parent], 2 * radius, 2 * radius)
        self.edges.setPath(edges)
        self.ring.setPath(ring)
        if not self.points:
            self.rubber.setPath(QtGui.QPainterPath())
        self.opts.status.setText(self._status(problem))
        self.opts.finish_button.setEnabled(bool(self.points))
        self.opts.drop_button.setEnabled(bool(self.points))

    def _show_grains(self) -> str:
        """Put the tree's grains, in their levels, on the canvas overlay; returns what is wrong
        ("" when the tree can be drawn)."""
        canvas = self.main_window.canvas
        if not self.points:
            canvas.set_overlay(None)
            return ""
        doc = self.document
        try:
            rows, cols, values = self.action().points_on(doc.levels, doc.num_levels)
        except TexeditorError as exc:
            canvas.set_overlay(None)
            return str(exc)
        if not len(rows):
            canvas.set_overlay(None)
            return ""
        t, l = rows.min(), cols.min()
        rgba = np.zeros((rows.max() - t + 1, cols.max() - l + 1, 4), np.uint8)
        pal = np.asarray(doc.palette, np.uint8)
        rgba[rows - t, cols - l, :3] = pal[np.minimum(values, len(pal) - 1)]
        rgba[rows - t, cols - l, 3] = GHOST_ALPHA
        canvas.set_overlay(rgba, (int(l), int(t)))
        return ""

    def _status(self, problem: str) -> str:
        if not self.points:
            return "Click to place the root of a tree."
        n = len(self.points)
        text = (f"{n} vert{'ices' if n > 1 else 'ex'}; the next hangs under vertex "
                f"{self.current_parent + 1} (ringed): click near a vertex to choose another. "
                "Backspace takes back the last one.")
        return text + (f"<br><span style='color:#b00020'>{problem}</span>" if problem else "")
