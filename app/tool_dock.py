"""The tool options dock: the current tool's name, hint and options panel (as in GIMP)."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets


class ToolOptionsDock(QtWidgets.QDockWidget):
    def __init__(self, parent=None):
        super().__init__("Tool options", parent)
        self.setObjectName("ToolOptionsDock")
        body = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(body)
        self.title = QtWidgets.QLabel()
        self.title.setStyleSheet("font-weight: bold")
        self.stack = QtWidgets.QStackedWidget()
        layout.addWidget(self.title)
        layout.addWidget(self.stack)
        layout.addStretch(1)
        self.setWidget(body)
        self._pages: dict[int, int] = {}

    def show_tool(self, tool) -> None:
        key = id(tool)
        if key not in self._pages:
            self._pages[key] = self.stack.addWidget(tool.options())
        self.stack.setCurrentIndex(self._pages[key])
        shortcut = f"  ({tool.SHORTCUT})" if tool.SHORTCUT else ""
        self.title.setText(tool.NAME + shortcut)
        self.stack.setFixedHeight(self.stack.currentWidget().sizeHint().height())
        self.stack.currentWidget().setToolTip(tool.TIP)
        self.title.setToolTip(tool.TIP)
        self.setMinimumHeight(0)
        self.stack.updateGeometry()
        QtCore.QTimer.singleShot(0, self.stack.updateGeometry)
