"""The Brushes dock (thesis §3.2.2, "several brushes grouped in a menu"): brush presets as
pictures of one dab, the user's own saved in the user data folder; and the painting tools' size
keys ([ and ]), which the dock offers to the window's Tools menu.

A preset is plain data (texeditor.paint.brushes.Brush); choosing one loads it into the Brush or Spray
tool, which turns strokes into Stroke actions.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.paint.brushes import Brush, BrushLibrary, StrokePainter
from texeditor.errors import TexeditorError

ICON = 44


def brush_icon(brush: Brush, colour=(230, 230, 230), side: int = ICON) -> QtGui.QIcon:
    """One dab of the brush (a sample cloud for a spray), enlarged to whole pixels per point."""
    n = brush.size + 2
    painter = StrokePainter(brush, (n, n), 1, seed=1)
    rows, cols, _ = painter.add((n // 2, n // 2))
    rgba = np.zeros((n, n, 4), np.uint8)
    rgba[rows, cols] = (*colour, 255)
    image = QtGui.QImage(np.ascontiguousarray(rgba).data, n, n, 4 * n,
                         QtGui.QImage.Format.Format_RGBA8888).copy()
    cell = max(1, min(3, (side - 4) // n))     # one scale for all: sizes compare
    scaled = image.scaled(n * cell, n * cell) if n * cell <= side else image.scaled(
        side - 4, side - 4, QtCore.Qt.AspectRatioMode.KeepAspectRatio,
        QtCore.Qt.TransformationMode.SmoothTransformation)
    pixmap = QtGui.QPixmap(side, side)
    pixmap.fill(QtGui.QColor(40, 40, 40))
    p = QtGui.QPainter(pixmap)
    p.drawImage((side - scaled.width()) // 2, (side - scaled.height()) // 2, scaled)
    p.end()
    return QtGui.QIcon(pixmap)


class BrushDock(QtWidgets.QDockWidget):
    """Presets: click one to paint with it (solid brushes in the Brush tool, clouds in the
    Spray); save the current tool's settings as a preset of your own."""

    def __init__(self, window):
        super().__init__("Brushes", window)
        self.setObjectName("BrushDock")          # the name saved layouts know
        self.main_window = window
        self.library = BrushLibrary()
        self.brushes: list[Brush] = []
        body = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(body)
        self.list = QtWidgets.QListWidget()
        self.list.setViewMode(QtWidgets.QListView.ViewMode.IconMode)
        self.list.setIconSize(QtCore.QSize(ICON, ICON))
        self.list.setGridSize(QtCore.QSize(78, 72))
        self.list.setResizeMode(QtWidgets.QListView.ResizeMode.Adjust)
        self.list.setMovement(QtWidgets.QListView.Movement.Static)
        self.list.setWordWrap(True)
        self.list.setMinimumHeight(160)
        self.list.itemClicked.connect(lambda item: self.choose(self.list.row(item)))
        layout.addWidget(self.list)
        row = QtWidgets.QHBoxLayout()
        self.save_button = QtWidgets.QPushButton("Save preset…")
        self.save_button.setToolTip("Keep the current Brush or Spray settings as a preset")
        self.save_button.clicked.connect(self.save_current)
        self.delete_button = QtWidgets.QPushButton("Delete")
        self.delete_button.setToolTip("Delete the selected preset (yours only)")
        self.delete_button.clicked.connect(self.delete_selected)
        row.addWidget(self.save_button)
        row.addWidget(self.delete_button)
        layout.addLayout(row)
        self.setWidget(body)
        self.act_smaller = self._action("Smaller brush", False, "[")
        self.act_bigger = self._action("Bigger brush", True, "]")
        self.reload()

    def _action(self, text: str, bigger: bool, key: str) -> QtGui.QAction:
        action = QtGui.QAction(text, self)
        action.setShortcut(QtGui.QKeySequence(key))
        tip = f"Brush, spray or grain one step {'bigger' if bigger else 'smaller'}"
        action.setStatusTip(tip)
        action.setToolTip(tip)
        action.triggered.connect(lambda: resize_tool(self.main_window, bigger))
        return action

    def menu_entries(self) -> list[tuple[str, QtGui.QAction | None]]:
        """(menu objectName, action or None for a separator) the window adds for this dock."""
        return [("ToolsMenu", None), ("ToolsMenu", self.act_smaller),
                ("ToolsMenu", self.act_bigger)]

    def reload(self) -> None:
        try:
            self.brushes = self.library.all()
        except TexeditorError as exc:
            self.brushes = self.library.standard()
            self.main_window.statusBar().showMessage(f"Your brush presets cannot be read: {exc}", 8000)
        self.list.clear()
        for brush in self.brushes:
            item = QtWidgets.QListWidgetItem(brush_icon(brush), brush.name)
            kind = "spray" if brush.distribution == "cloud" else "solid"
            item.setToolTip(f"{brush.name}: {brush.shape} {brush.size}, {kind}"
                            + (f", density {brush.density:.0%}" if kind == "spray" else ""))
            self.list.addItem(item)

    def tool_for(self, brush: Brush):
        from .tools.brush import BrushTool, SprayTool
        kind = SprayTool if brush.distribution == "cloud" else BrushTool
        return next(t for t in self.main_window.tools if type(t) is kind)

    def choose(self, row: int) -> None:
        """Paint with preset ``row``: its tool becomes current with its settings."""
        brush = self.brushes[row]
        tool = self.tool_for(brush)
        tool.set_brush(brush)
        self.main_window.set_tool(tool)
        self.main_window.statusBar().showMessage(f"{tool.NAME}: {brush.name}", 3000)

    def current_brush(self) -> Brush | None:
        from .tools.brush import BrushTool
        tool = self.main_window.tool
        return tool.brush if isinstance(tool, BrushTool) else None

    def save_current(self, name: str | None = None) -> None:
        brush = self.current_brush()
        if brush is None:
            QtWidgets.QMessageBox.information(self, "No brush", "Choose the Brush or Spray tool "
                                              "and set it up first.")
            return
        if name is None:
            name, ok = QtWidgets.QInputDialog.getText(self, "Save preset", "Name of the preset:",
                                                      text=f"My {brush.name}")
            if not ok:
                return
        try:
            self.library.save(brush.replace(name=name.strip()))
        except TexeditorError as exc:
            self.main_window.show_error("Cannot save this preset", exc)
            return
        self.reload()
        self.list.setCurrentRow(len(self.brushes) - 1)

    def delete_selected(self) -> None:
        row = self.list.currentRow()
        if row < 0:
            return
        try:
            self.library.remove(self.brushes[row].name)
        except TexeditorError as exc:
            self.main_window.show_error("Cannot delete this preset", exc)
            return
        self.reload()


def resize_tool(window, bigger: bool) -> None:
    """[ and ]: the current tool one step bigger or smaller, if it has a size."""
    resize = getattr(window.tool, "resize", None)
    if resize is not None:
        resize(bigger)
