"""The Grain stamps dock (thesis: "several grain types at once from a menu"): the grain library —
standard grains, then the user's — for the Grain tool, and the Grain stamps menu that lists it.

A click makes a grain the Grain tool's, a double click edits it in the grain editor; rendering
every point of the texture as a grain is the Grain rendering dock's (app.grain_rendering_dock).
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.paint.grains import GrainType

from .grain_editor import grain_icon

NAME_ROLE = QtCore.Qt.ItemDataRole.UserRole
MENU = "GrainStampsMenu"          # the objectName of the menu this dock fills


class GrainStampsDock(QtWidgets.QDockWidget):
    """The grain library as icons; the Grain tool (``tool``) keeps the current grain."""

    def __init__(self, window):
        from .tools.grain import GrainTool
        super().__init__("Grain stamps", window)
        self.setObjectName("GrainDock")          # the name saved layouts know
        self.main_window = window
        self.tool = tool = next(t for t in window.tools if isinstance(t, GrainTool))
        body = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(body)
        self.list = QtWidgets.QListWidget()
        self.list.setViewMode(QtWidgets.QListView.ViewMode.IconMode)
        self.list.setIconSize(QtCore.QSize(40, 40))
        self.list.setGridSize(QtCore.QSize(78, 76))
        self.list.setResizeMode(QtWidgets.QListView.ResizeMode.Adjust)
        self.list.setMovement(QtWidgets.QListView.Movement.Static)
        self.list.setWordWrap(True)
        self.list.setMinimumHeight(100)
        self.list.itemClicked.connect(lambda item: tool.pick(item.data(NAME_ROLE)))
        self.list.itemDoubleClicked.connect(lambda _item: tool.edit())
        layout.addWidget(self.list)
        row = QtWidgets.QHBoxLayout()
        self.edit_button = QtWidgets.QPushButton("Edit / draw…")
        self.edit_button.setToolTip("Open the grain editor on the selected grain")
        self.edit_button.clicked.connect(tool.edit)
        row.addWidget(self.edit_button)
        layout.addLayout(row)
        self.setWidget(body)
        tool.reload()                            # the user's grains (fills this dock once shown)
        self.refresh()

    def refresh(self) -> None:
        """List the tool's grains, its current one selected, in the document's colours."""
        window = self.main_window
        palette = None if window.history is None else window.document.palette
        self.fill(self.tool.grains, self.tool.grain.name, palette)

    def fill(self, grains: list[GrainType], current: str, palette=None) -> None:
        palette = np.array([[54, 54, 54], [100, 100, 100], [134, 134, 134], [168, 168, 168]]
                           if palette is None else palette, np.uint8)
        self.list.clear()
        for grain in grains:
            item = QtWidgets.QListWidgetItem(grain_icon(grain, palette, 1), grain.name)
            item.setData(NAME_ROLE, grain.name)
            item.setToolTip(grain.name)
            self.list.addItem(item)
            if grain.name == current:
                self.list.setCurrentItem(item)

    # -- the Grain stamps menu ---------------------------------------------------------------------
    def fill_menu(self, menu: QtWidgets.QMenu) -> None:
        """The library as checkable entries (the current grain checked), then the editor."""
        tool = self.tool
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
