"""The Brushes dock (thesis §3.2.2, "several brushes grouped in a menu"): brush presets as
pictures of one dab, the user's own saved in the user data folder; and the few menu entries and
keys of the painting tools ([ and ], the Grain stamps menu, Peano sub-regions).

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
        self.setObjectName("BrushDock")
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
        self.reload()

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


# -- the painting tools' menu entries and keys -----------------------------------------------------

def install_paint_ui(window) -> None:
    """Add the Brushes and Grain stamps docks (shown while the Brush or Spray, or the Grain tool
    is current, or by View), [ and ] (tool size), the Grain stamps menu (the Grain tool's
    stamps; rendering every point as a grain is the Grain rendering dock's) and Image ▸ Peano
    sub-regions."""
    from .grain_editor import GrainDock
    window.brush_dock = BrushDock(window)
    window.grain_dock = GrainDock(_grain_tool(window), window)
    left = QtCore.Qt.DockWidgetArea.LeftDockWidgetArea
    window.addDockWidget(left, window.brush_dock)
    window.addDockWidget(left, window.grain_dock)
    bank = getattr(window, "bank_dock", None)
    if bank is not None:                                     # one column of docks, as tabs
        window.tabifyDockWidget(bank, window.brush_dock)
    window.tabifyDockWidget(window.brush_dock, window.grain_dock)
    for dock in (window.brush_dock, window.grain_dock):     # shown by their tools, on demand
        dock.hide()
    _grain_tool(window).reload()
    window.act_smaller = window._action("Smaller brush", lambda: _resize(window, False), "[",
                                        "Brush, spray or grain one step smaller")
    window.act_bigger = window._action("Bigger brush", lambda: _resize(window, True), "]",
                                       "Brush, spray or grain one step bigger")
    window.act_peano = window._action("&Peano sub-regions…", lambda: open_peano(window), None,
                                      "Cut the canvas into cells along a Hilbert scan and give "
                                      "them levels from a dominance expression (thesis §3.3.3a)")
    menus = {a.text().replace("&", ""): a.menu() for a in window.menuBar().actions()}
    if "Image" in menus:
        menus["Image"].addAction(window.act_peano)
    if "View" in menus:
        menus["View"].addActions([window.brush_dock.toggleViewAction(),
                                  window.grain_dock.toggleViewAction()])
    if "Tools" in menus:
        menus["Tools"].addSeparator()
        menus["Tools"].addActions([window.act_smaller, window.act_bigger])
    grains = window.menuBar().addMenu("Grain &stamps")
    grains.aboutToShow.connect(lambda: _fill_grain_menu(window, grains))
    _fill_grain_menu(window, grains)


def _resize(window, bigger: bool) -> None:
    resize = getattr(window.tool, "resize", None)
    if resize is not None:
        resize(bigger)


def _grain_tool(window):
    from .tools.grain import GrainTool
    return next(t for t in window.tools if isinstance(t, GrainTool))


def _fill_grain_menu(window, menu: QtWidgets.QMenu) -> None:
    """Several grain types at once from a menu: the library, then the editor."""
    tool = _grain_tool(window)
    menu.clear()
    group = QtGui.QActionGroup(menu)
    for grain in tool.grains:
        action = menu.addAction(grain.name)
        action.setCheckable(True)
        action.setChecked(grain.name == tool.grain.name)
        action.triggered.connect(lambda _=False, name=grain.name: tool.pick(name))
        group.addAction(action)
    menu.addSeparator()
    menu.addAction("Grain &editor…", tool.edit)


def open_peano(window):
    from .peano_dialog import PeanoDialog
    dialog = getattr(window, "_peano_dialog", None)
    if dialog is None:
        dialog = window._peano_dialog = PeanoDialog(window)
    dialog.refresh()
    dialog.show()
    dialog.raise_()
    return dialog
