"""The Tools dock: a grid of tool buttons above the current tool's name, hint and options
(as in GIMP's toolbox and tool options)."""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets


TOOL_COLUMNS = 4
MIN_BELOW = 220          # pixels the dock under the tool options keeps (a row of thumbnails)


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
        self.body = body
        area = QtWidgets.QScrollArea()    # a tall tool's options scroll: the window keeps its size
        area.setWidget(body)
        area.setWidgetResizable(True)
        area.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
        area.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.setWidget(area)
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
        self.stack.updateGeometry()
        QtCore.QTimer.singleShot(0, self, self.fit_height)

    def fit_height(self) -> None:
        """Take the current tool's natural height from the dock below (the bank, brushes…),
        leaving it at least MIN_BELOW pixels; beyond that the options scroll."""
        main = self.parent()
        if not isinstance(main, QtWidgets.QMainWindow) or self.isFloating() or not self.isVisible():
            return
        area = main.dockWidgetArea(self)
        below = [d for d in main.findChildren(QtWidgets.QDockWidget) if d is not self
                 and d.isVisible() and not d.visibleRegion().isEmpty()    # not a hidden tab
                 and not d.isFloating() and main.dockWidgetArea(d) == area]
        if not below:
            return
        natural = self.body.sizeHint().height() + self.height() - self.widget().height() + 2
        total = self.height() + below[0].height()
        mine = max(120, min(natural, total - MIN_BELOW))
        main.resizeDocks([self, below[0]], [mine, total - mine],
                         QtCore.Qt.Orientation.Vertical)
