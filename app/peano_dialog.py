"""Image ▸ Peano sub-regions… (thesis §3.3.3a, Fig. 3.5–3.6): cut the canvas into cells, list
them along a Hilbert scan (or another fill order, §3.3.1), and give them levels with a dominance
expression.

The dialog shows the scan over the texture (the path and the cell numbers), the expression's tree
with each sub-region's level, and points at the offending character of a malformed expression.
Apply submits one PeanoLevels action; the dialog stays open to try another expression.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.paint import grains
from texeditor.paint import orders
from texeditor.paint import peano
from texeditor.errors import TexeditorError
from texeditor.paint.actions import PeanoLevels

from .canvas import colourize
from .widgets import spin_box

EXAMPLE = "6:7(2(1,2(2,3)),6:7(4,5,6:7(6,7),8))"
ORDER_NAMES = [("Peano (Hilbert)", "peano", "along the Hilbert scan"),
               ("Television (rows)", "tv", "row after row"),
               ("Spiral from the middle", "spiral", "in a spiral from the middle"),
               ("Polar about the middle", "polar", "by angle about the middle")]
MAX_DRAWN_CELLS = 16384
PATH_COLOUR = QtGui.QColor(255, 70, 70, 200)
NAMED_COLOUR = QtGui.QColor(255, 220, 60)
GRID_COLOUR = QtGui.QColor(255, 255, 255, 90)


class ScanView(QtWidgets.QWidget):
    """The texture with the cut, the path of the scan through the cells and their numbers; the
    cells the expression names are painted with the levels they will get."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setMinimumSize(360, 300)
        self.setSizePolicy(QtWidgets.QSizePolicy.Policy.Expanding,
                           QtWidgets.QSizePolicy.Policy.Expanding)
        self.image: QtGui.QImage | None = None
        self.grid_shape = (1, 1)
        self.cell, self.top, self.left = 8, 0, 0
        self.order = np.zeros((0, 2), int)
        self.total = 0
        self.assigned: dict[int, int] = {}
        self.palette_rgb = np.zeros((2, 3), np.uint8)

    def set_texture(self, levels: np.ndarray, palette) -> None:
        rgb = np.ascontiguousarray(colourize(levels, palette))
        h, w = levels.shape
        self.image = QtGui.QImage(rgb.data, w, h, 3 * w, QtGui.QImage.Format.Format_RGB888).copy()
        self.grid_shape = (h, w)
        self.palette_rgb = np.asarray(palette, np.uint8)

    def set_scan(self, cell, top, left, order, total, assigned) -> None:
        self.cell, self.top, self.left = cell, top, left
        self.order, self.total, self.assigned = order, total, assigned
        self.update()

    def _frame(self) -> tuple[float, float, float]:
        h, w = self.grid_shape
        scale = min((self.width() - 8) / w, (self.height() - 8) / h)
        return scale, (self.width() - w * scale) / 2, (self.height() - h * scale) / 2

    def paintEvent(self, ev):
        p = QtGui.QPainter(self)
        p.fillRect(self.rect(), QtGui.QColor(43, 43, 43))
        if self.image is None:
            return
        scale, x0, y0 = self._frame()
        h, w = self.grid_shape
        p.drawImage(QtCore.QRectF(x0, y0, w * scale, h * scale), self.image)
        if self.assigned:                                  # a veil: the named cells stand out
            p.fillRect(QtCore.QRectF(x0, y0, w * scale, h * scale), QtGui.QColor(0, 0, 0, 120))
        p.save()
        p.translate(x0, y0)
        p.scale(scale, scale)
        p.setClipRect(QtCore.QRectF(0, 0, w, h))
        s, t, l = self.cell, self.top, self.left
        for index, level in self.assigned.items():         # the named cells, in their levels
            if index <= len(self.order):
                r, c = self.order[index - 1]
                colour = QtGui.QColor(*(int(v) for v in self.palette_rgb[
                    min(level, len(self.palette_rgb) - 1)]))
                p.fillRect(QtCore.QRectF(l + c * s, t + r * s, s, s), colour)
        outline = QtGui.QPen(NAMED_COLOUR, 2)
        outline.setCosmetic(True)
        p.setPen(outline)
        for index in self.assigned:
            if index <= len(self.order):
                r, c = self.order[index - 1]
                p.drawRect(QtCore.QRectF(l + c * s, t + r * s, s, s))
        pen = QtGui.QPen(GRID_COLOUR, 0)
        p.setPen(pen)
        if len(self.order) and s * scale >= 4:
            rows, cols = self.order.max(axis=0) + 1
            for r in range(rows + 1):
                p.drawLine(QtCore.QLineF(l, t + r * s, l + cols * s, t + r * s))
            for c in range(cols + 1):
                p.drawLine(QtCore.QLineF(l + c * s, t, l + c * s, t + rows * s))
        if 1 < len(self.order) <= MAX_DRAWN_CELLS:
            path = QtGui.QPainterPath()
            centres = self.order[:, ::-1] * s + np.array([l, t]) + s / 2
            path.moveTo(*centres[0])
            for x, y in centres[1:]:
                path.lineTo(x, y)
            pen = QtGui.QPen(PATH_COLOUR, 2 if s * scale >= 6 else 1)
            pen.setCosmetic(True)
            p.setPen(pen)
            p.drawPath(path)
        p.restore()
        self._numbers(p, scale, x0, y0)
        p.end()

    def _numbers(self, p, scale, x0, y0) -> None:
        """Cell numbers where cells are big enough on screen (always for the named ones)."""
        side = self.cell * scale
        if side < 12 or not len(self.order):
            return
        font = p.font()
        font.setPixelSize(int(min(14, max(8, side * 0.4))))
        p.setFont(font)
        named = set(self.assigned)
        for k, (r, c) in enumerate(self.order[:4096], start=1):
            if side < 22 and k not in named:
                continue
            rect = QtCore.QRectF(x0 + (self.left + c * self.cell) * scale,
                                 y0 + (self.top + r * self.cell) * scale, side, side)
            font.setBold(k in named)
            p.setFont(font)
            p.setPen(QtGui.QColor(0, 0, 0, 200))
            p.drawText(rect.translated(1, 1), QtCore.Qt.AlignmentFlag.AlignCenter, str(k))
            p.setPen(QtGui.QColor(255, 255, 120) if k in named else QtGui.QColor(255, 255, 255))
            p.drawText(rect, QtCore.Qt.AlignmentFlag.AlignCenter, str(k))


class PeanoDialog(QtWidgets.QDialog):
    def __init__(self, window):
        super().__init__(window)
        self.main_window = window
        self._shown = False
        self.setWindowTitle("Peano sub-regions")
        self.view = ScanView()
        self.tree = QtWidgets.QTreeWidget()
        self.tree.setHeaderLabels(["Dominance tree", "Level"])
        self.tree.setMinimumWidth(220)
        self.tree.header().setStretchLastSection(False)
        modes = QtWidgets.QHeaderView.ResizeMode
        self.tree.header().setSectionResizeMode(0, modes.Stretch)
        self.tree.header().setSectionResizeMode(1, modes.ResizeToContents)

        form = QtWidgets.QFormLayout()
        self.expression = QtWidgets.QLineEdit(EXAMPLE)
        mono = QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.SystemFont.FixedFont)
        self.expression.setFont(mono)
        self.expression.setToolTip("Numbers are cells in scan order (1 = first). X(…): X is "
                                   "brighter than all inside; a:b equal; groups nest")
        form.addRow("Expression", self.expression)
        self.error = QtWidgets.QLabel()           # the expression and a caret under the fault
        self.error.setFont(mono)
        self.error.setStyleSheet("color: #d04040")
        self.error.setSizePolicy(QtWidgets.QSizePolicy.Policy.Ignored,
                                 QtWidgets.QSizePolicy.Policy.Preferred)
        self.problem = QtWidgets.QLabel()         # what is wrong, in words
        self.problem.setWordWrap(True)
        self.problem.setStyleSheet("color: #d04040")
        errors = QtWidgets.QVBoxLayout()
        errors.setSpacing(0)
        errors.addWidget(self.error)
        errors.addWidget(self.problem)
        form.addRow("", errors)
        cut = QtWidgets.QHBoxLayout()
        self.cell = spin_box(1, 4096, 8, suffix=" pt", tip="Side of the cells (sub-regions)")
        self.left = spin_box(0, 16383, 0, prefix="x ", tip="First column of the cut")
        self.top = spin_box(0, 16383, 0, prefix="y ", tip="First row of the cut")
        for w in (self.cell, self.left, self.top):
            cut.addWidget(w)
        form.addRow("Cells, from", cut)
        count = QtWidgets.QHBoxLayout()
        self.across = spin_box(0, 16384, 0, tip="Cells across (0: to the right edge)")
        self.down = spin_box(0, 16384, 0, tip="Cells down (0: to the bottom edge)")
        self.across.setSpecialValueText("to the edge")
        self.down.setSpecialValueText("to the edge")
        count.addWidget(self.across)
        count.addWidget(QtWidgets.QLabel("×"))
        count.addWidget(self.down)
        form.addRow("Cells", count)
        self.order = QtWidgets.QComboBox()
        for text, value, _ in ORDER_NAMES:
            self.order.addItem(text, value)
        self.order.setToolTip("The order the cells are numbered in (thesis §3.3.1): the Peano "
                              "scan, or another fill order")
        assert sorted(v for _, v, _ in ORDER_NAMES) == sorted(orders.ORDERS)
        form.addRow("Numbered", self.order)
        levels = QtWidgets.QHBoxLayout()
        self.low = spin_box(0, 15, 1, tip="Level of the dimmest named cells")
        self.high = spin_box(0, 15, 3, tip="Level of the brightest")
        levels.addWidget(self.low)
        levels.addWidget(QtWidgets.QLabel("to"))
        levels.addWidget(self.high)
        form.addRow("Levels", levels)
        grain = QtWidgets.QHBoxLayout()
        self.grain = QtWidgets.QComboBox()
        self.grain.addItem("Fill the cell", "cell")
        for shape in grains.SHAPES[:-1]:
            self.grain.addItem(f"A {shape} grain", shape)
        self.grain_size = spin_box(0, 256, 0, suffix=" pt", tip="Grain diameter (0: the cell side)")
        self.grain_size.setSpecialValueText("cell side")
        grain.addWidget(self.grain, 1)
        grain.addWidget(self.grain_size)
        form.addRow("Each cell", grain)
        self.summary = QtWidgets.QLabel()
        self.summary.setWordWrap(True)

        buttons = QtWidgets.QDialogButtonBox()
        self.apply_button = buttons.addButton("Apply",
                                              QtWidgets.QDialogButtonBox.ButtonRole.ApplyRole)
        self.apply_button.setDefault(True)
        close = buttons.addButton(QtWidgets.QDialogButtonBox.StandardButton.Close)
        self.apply_button.clicked.connect(self.apply)
        close.clicked.connect(self.close)

        side = QtWidgets.QVBoxLayout()
        side.addLayout(form)
        side.addWidget(self.tree, 1)
        side.addWidget(self.summary)
        side.addWidget(buttons)
        layout = QtWidgets.QHBoxLayout(self)
        layout.addWidget(self.view, 3)
        layout.addLayout(side, 2)
        self.expression.textChanged.connect(self.update_scan)
        for w in (self.cell, self.left, self.top, self.across, self.down, self.low, self.high,
                  self.grain_size):
            w.valueChanged.connect(self.update_scan)
        self.grain.currentIndexChanged.connect(self.update_scan)
        self.order.currentIndexChanged.connect(self.update_scan)
        self.resize(940, 580)

    def refresh(self) -> None:
        """Follow the document: its texture, palette and top level."""
        doc = self.main_window.document
        top = doc.num_levels - 1
        first = self.high.maximum() != top or not self._shown
        self._shown = True
        self.high.setMaximum(top)
        self.low.setMaximum(top)
        if first:                              # the full range of the document's levels
            self.high.setValue(top)
        self.view.set_texture(doc.levels, doc.palette)
        self.update_scan()

    def action(self) -> PeanoLevels:
        return PeanoLevels(cell=self.cell.value(), expression=self.expression.text(),
                           low=self.low.value(), high=self.high.value(), top=self.top.value(),
                           left=self.left.value(), cells_down=self.down.value() or None,
                           cells_across=self.across.value() or None,
                           grain=self.grain.currentData(),
                           grain_size=self.grain_size.value() or None,
                           order=self.order.currentData())

    def update_scan(self) -> None:
        """Parse, assign, and show the scan and the tree (errors point at the character)."""
        doc = self.main_window.document
        self.error.clear()
        self.problem.clear()
        self.tree.clear()
        assigned, tree = {}, None
        try:
            action = self.action()
            tree = peano.parse_dominance(action.expression)
            assigned = action.levels_of(doc.num_levels)
        except peano.DominanceError as exc:
            self.error.setText(f"{exc.text}\n{' ' * exc.position}^")
            self.problem.setText(exc.problem[0].upper() + exc.problem[1:] + ".")
        except TexeditorError as exc:
            self.problem.setText(str(exc))
        try:
            down, across = peano.cell_grid(doc.shape, self.cell.value(), self.top.value(),
                                           self.left.value(), self.down.value() or None,
                                           self.across.value() or None)
        except TexeditorError as exc:
            self.problem.setText(str(exc))
            down = across = 0
        total = down * across
        order = self.order.currentData()
        drawn = orders.grid_order(down, across, order) if 0 < total <= MAX_DRAWN_CELLS else \
            orders.grid_order(down, across, order, limit=min(total, max(assigned, default=0)))
        missing = [i for i in assigned if i > total]
        if missing and not self.problem.text():
            self.problem.setText(f"Sub-region {max(missing)} does not exist: the cut has "
                                 f"{total} cells.")
        self.view.set_scan(self.cell.value(), self.top.value(), self.left.value(), drawn, total,
                           {i: v for i, v in assigned.items() if i <= total})
        if tree is not None:
            self._fill_tree(tree, assigned)
        self.apply_button.setEnabled(bool(assigned) and not self.problem.text())
        note = "" if total <= MAX_DRAWN_CELLS else " (too many to draw the path: larger cells " \
                                                   "show it)"
        scan = ORDER_NAMES[self.order.currentIndex()][2]
        self.summary.setText(f"{across}×{down} = {total} cells {scan}{note}; "
                             f"{len(assigned)} named, {len(set(assigned.values()))} levels.")

    def _fill_tree(self, tree: peano.Node, assigned: dict[int, int]) -> None:
        def add(node, parent):
            head = " : ".join(str(i) for i in node.head)
            level = assigned.get(node.head[0])
            item = QtWidgets.QTreeWidgetItem(parent, [head, "" if level is None else str(level)])
            if node.items:
                font = item.font(0)
                font.setBold(True)
                item.setFont(0, font)
            for child in node.items:
                add(child, item)
            return item
        add(tree, self.tree)
        self.tree.expandAll()

    def apply(self) -> None:
        try:
            action = self.action()
        except TexeditorError as exc:
            self.main_window.show_error("Cannot give these levels", exc)
            return
        if self.main_window.submit(action):
            self.view.set_texture(self.main_window.document.levels, self.main_window.document.palette)
            self.view.update()


def open_peano(window, dialog: PeanoDialog | None = None) -> PeanoDialog:
    """Show the (non-modal) Peano dialog: ``dialog``, the one the window keeps, or a new one."""
    if dialog is None:
        dialog = PeanoDialog(window)
    dialog.refresh()
    dialog.show()
    dialog.raise_()
    return dialog
