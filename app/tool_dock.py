"""The Tools dock: a grid of tool buttons above the current tool's name, hint and options
(as in GIMP's toolbox and tool options)."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets


TOOL_COLUMNS = 4


class ToolOptionsDock(QtWidgets.QDockWidget):
    def __init__(self, parent=None):
        super().__init__("Tools", parent)
        self.setObjectName("ToolOptionsDock")
        body = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(body)
        self.box = QtWidgets.QGridLayout()
        self.box.setSpacing(2)
        self.buttons: dict[int, QtWidgets.QToolButton] = {}      # id(tool) → its button
        rule = QtWidgets.QFrame()
        rule.setFrameShape(QtWidgets.QFrame.Shape.HLine)
        rule.setFrameShadow(QtWidgets.QFrame.Shadow.Sunken)
        self.title = QtWidgets.QLabel()
        self.title.setStyleSheet("font-weight: bold")
        self.stack = QtWidgets.QStackedWidget()
        layout.addLayout(self.box)
        layout.addWidget(rule)
        layout.addWidget(self.title)
        layout.addWidget(self.stack)
        layout.addStretch(1)
        self.setWidget(body)
        self._pages: dict[int, int] = {}

    def set_tools(self, tools) -> None:
        """One button per tool (its checkable action), in rows of TOOL_COLUMNS."""
        for k, tool in enumerate(tools):
            button = QtWidgets.QToolButton()
            button.setDefaultAction(tool.qaction)
            button.setToolButtonStyle(QtCore.Qt.ToolButtonStyle.ToolButtonTextOnly)
            button.setAutoRaise(True)
            button.setSizePolicy(QtWidgets.QSizePolicy.Policy.Expanding,
                                 QtWidgets.QSizePolicy.Policy.Fixed)
            self.box.addWidget(button, k // TOOL_COLUMNS, k % TOOL_COLUMNS)
            self.buttons[id(tool)] = button

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
