"""The widgets of the bank browser: the lazy thumbnail model, its grid view and delegate, the
attribute range filters and the Save to bank dialog.

Used by app/bank_dock.py; they read names and thumbnails from the bank (texeditor.bank.store) and never
change it — the dock does.
"""

from __future__ import annotations

from collections import OrderedDict

from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.bank import attributes as attrs
from texeditor.bank.store import Bank
from texeditor.errors import TexeditorError

ICON = 80                         # thumbnail side on screen (they are stored at 128)
CELL = QtCore.QSize(ICON + 10, ICON + 26)
CACHE = 600                       # pixmaps kept (about 20 MB at most)
FILTERS = {                       # attribute: (low, high, step, decimals) of its range box
    "contrast": (0, 1, 0.05, 2), "granularity": (1, 1e6, 1, 1), "density": (0, 1, 0.05, 2),
    "directivity": (0, 1, 0.05, 2), "orientation": (0, 180, 5, 0), "regularity": (0, 1, 0.05, 2),
    "coarseness": (0, 1e4, 0.5, 1)}
IdRole = QtCore.Qt.ItemDataRole.UserRole


class BankModel(QtCore.QAbstractListModel):
    """The ids of the entries shown; names and thumbnails are read from the bank only when the
    view asks for a row, a batch at a time, so thousands of entries scroll smoothly."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.bank: Bank | None = None
        self.ids: list[int] = []
        self.rows: dict[int, int] = {}
        self.names: dict[int, tuple] = {}
        self.pixmaps: OrderedDict[int, QtGui.QPixmap] = OrderedDict()
        self.wanted: set[int] = set()
        self.placeholder = _placeholder()
        self._timer = QtCore.QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.timeout.connect(self.fetch)

    def set_ids(self, bank: Bank, ids: list) -> None:
        self.beginResetModel()
        self.bank, self.ids = bank, list(ids)
        self.rows = {entry_id: row for row, entry_id in enumerate(self.ids)}
        self.wanted.clear()
        self.endResetModel()

    def forget(self, ids=None) -> None:
        """Drop cached names and thumbnails (of ``ids``, or all) so they are read again."""
        for entry_id in (list(self.pixmaps) if ids is None else ids):
            self.pixmaps.pop(entry_id, None)
            self.names.pop(entry_id, None)
        if ids is None:
            self.names.clear()

    def rowCount(self, parent=QtCore.QModelIndex()) -> int:
        return 0 if parent.isValid() else len(self.ids)

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if not index.isValid():
            return None
        entry_id = self.ids[index.row()]
        if role == IdRole:
            return entry_id
        if role == QtCore.Qt.ItemDataRole.DisplayRole:
            return self._name(entry_id)[0]
        if role == QtCore.Qt.ItemDataRole.DecorationRole:
            pixmap = self.pixmaps.get(entry_id)
            if pixmap is None:
                self._want(entry_id)
                return self.placeholder
            self.pixmaps.move_to_end(entry_id)
            return pixmap
        if role == QtCore.Qt.ItemDataRole.ToolTipRole:
            name, tags = self._name(entry_id)
            return f"{name}\n{', '.join(tags)}" if tags else name
        return None

    def _name(self, entry_id: int) -> tuple:
        found = self.names.get(entry_id)
        if found is None:
            self._want(entry_id)
            return ("…", ())
        return found

    def _want(self, entry_id: int) -> None:
        self.wanted.add(entry_id)
        if not self._timer.isActive():
            self._timer.start(0)

    def fetch(self) -> None:
        """Read the rows the view asked for in one query each for names and thumbnails."""
        ids = [i for i in self.wanted if i in self.rows]
        self.wanted.clear()
        if not ids or self.bank is None:
            return
        try:
            self.names.update(self.bank.names([i for i in ids if i not in self.names]))
            thumbs = self.bank.thumbnails([i for i in ids if i not in self.pixmaps])
        except TexeditorError:
            return                   # the bank went away; the dock shows the error elsewhere
        for entry_id, png in thumbs.items():
            if png is not None:
                pixmap = QtGui.QPixmap()
                pixmap.loadFromData(png, "PNG")
                self.pixmaps[entry_id] = pixmap.scaled(
                    ICON, ICON, QtCore.Qt.AspectRatioMode.KeepAspectRatio,
                    QtCore.Qt.TransformationMode.SmoothTransformation)
        while len(self.pixmaps) > CACHE:
            self.pixmaps.popitem(last=False)
        rows = sorted(self.rows[i] for i in ids)
        self.dataChanged.emit(self.index(rows[0]), self.index(rows[-1]))


def _placeholder() -> QtGui.QPixmap:
    """A grey tile for thumbnails not read (or not computed) yet."""
    pixmap = QtGui.QPixmap(ICON, ICON)
    pixmap.fill(QtGui.QColor(70, 70, 70))
    painter = QtGui.QPainter(pixmap)
    painter.setPen(QtGui.QColor(150, 150, 150))
    painter.drawText(pixmap.rect(), QtCore.Qt.AlignmentFlag.AlignCenter, "…")
    painter.end()
    return pixmap


class ThumbnailDelegate(QtWidgets.QStyledItemDelegate):
    """A thumbnail and its name; the selection is a frame around the tile, never a tint of the
    texture's own colours (which is what the user is judging)."""

    def paint(self, painter, option, index) -> None:
        rect = option.rect.adjusted(3, 3, -3, -3)
        selected = bool(option.state & QtWidgets.QStyle.StateFlag.State_Selected)
        palette = option.palette
        painter.save()
        if selected:
            painter.setPen(QtCore.Qt.PenStyle.NoPen)
            painter.setBrush(palette.highlight())
            painter.drawRoundedRect(rect, 4, 4)
        pixmap = index.data(QtCore.Qt.ItemDataRole.DecorationRole)
        if pixmap is not None:
            left = rect.left() + (rect.width() - pixmap.width()) // 2
            painter.drawPixmap(left, rect.top() + 3, pixmap)
        text_rect = QtCore.QRect(rect.left() + 2, rect.top() + ICON + 5, rect.width() - 4,
                                 rect.bottom() - rect.top() - ICON - 5)
        text = option.fontMetrics.elidedText(index.data() or "", QtCore.Qt.TextElideMode.ElideRight,
                                             text_rect.width())
        painter.setPen(palette.highlightedText().color() if selected else palette.text().color())
        painter.drawText(text_rect, QtCore.Qt.AlignmentFlag.AlignHCenter
                         | QtCore.Qt.AlignmentFlag.AlignTop, text)
        painter.restore()

    def sizeHint(self, option, index) -> QtCore.QSize:
        return CELL


class ThumbnailGrid(QtWidgets.QListView):
    """The bank's entries as tiles in icon mode (uniform sizes, so thousands lay out at once),
    whose columns share the width evenly (no ragged gap on the right)."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setModel(BankModel(self))
        self.setItemDelegate(ThumbnailDelegate(self))
        self.setViewMode(QtWidgets.QListView.ViewMode.IconMode)
        self.setResizeMode(QtWidgets.QListView.ResizeMode.Adjust)
        self.setMovement(QtWidgets.QListView.Movement.Static)
        self.setUniformItemSizes(True)
        self.setIconSize(QtCore.QSize(ICON, ICON))
        self.setGridSize(CELL)
        self.setEditTriggers(QtWidgets.QAbstractItemView.EditTrigger.NoEditTriggers)
        self.setSelectionMode(QtWidgets.QAbstractItemView.SelectionMode.SingleSelection)
        self.setVerticalScrollMode(QtWidgets.QAbstractItemView.ScrollMode.ScrollPerPixel)
        self.verticalScrollBar().setSingleStep(CELL.height() // 3)
        self.setMinimumHeight(CELL.height() + 8)

    def sizeHint(self) -> QtCore.QSize:
        """Two rows: the grid asks for little and takes what is left (the details come first)."""
        return QtCore.QSize(3 * CELL.width() + 20, 2 * CELL.height() + 8)

    def layout_width(self) -> int:
        """The width Qt lays the tiles out in: the viewport's without scroll bars, less a
        vertical scroll bar's (QListView keeps room for it whether shown or not). Columns
        counted from the viewport's own width disagreed with Qt's: the last row fell below the
        fold and the scroll bar came and went until it stayed hidden ("3 results", 2 shown)."""
        extent = self.style().pixelMetric(QtWidgets.QStyle.PixelMetric.PM_ScrollBarExtent,
                                          None, self.verticalScrollBar())
        return self.maximumViewportSize().width() - extent - 1    # a tile wraps past right()

    def resizeEvent(self, ev) -> None:
        super().resizeEvent(ev)
        width = self.layout_width()
        columns = max(1, width // CELL.width())
        size = QtCore.QSize(max(CELL.width(), width // columns), CELL.height())
        if size != self.gridSize():
            self.setGridSize(size)


class RangeFilters(QtWidgets.QWidget):
    """One row per attribute: a check box to use it, and the low and high bounds."""

    changed = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        grid = QtWidgets.QGridLayout(self)
        grid.setContentsMargins(0, 0, 0, 0)
        grid.setVerticalSpacing(2)
        self.rows = {}
        for row, (name, (lo, hi, step, decimals)) in enumerate(FILTERS.items()):
            use = QtWidgets.QCheckBox(name)
            use.setToolTip(attrs.DESCRIPTIONS[name])
            boxes = []
            for value in (lo, hi):
                box = QtWidgets.QDoubleSpinBox()
                box.setRange(lo, hi)
                box.setSingleStep(step)
                box.setDecimals(decimals)
                box.setValue(value if name != "granularity" or value == lo else 1000)
                box.setEnabled(False)
                box.valueChanged.connect(self.changed)
                boxes.append(box)
            use.toggled.connect(lambda on, b=boxes: [x.setEnabled(on) for x in b])
            use.toggled.connect(self.changed)
            grid.addWidget(use, row, 0)
            grid.addWidget(boxes[0], row, 1)
            grid.addWidget(QtWidgets.QLabel("–"), row, 2)
            grid.addWidget(boxes[1], row, 3)
            self.rows[name] = (use, *boxes)

    def ranges(self) -> dict:
        return {name: (lo.value(), hi.value()) for name, (use, lo, hi) in self.rows.items()
                if use.isChecked()}

    def set_range(self, name: str, lo: float, hi: float) -> None:
        use, low, high = self.rows[name]
        low.setValue(lo)
        high.setValue(hi)
        use.setChecked(True)


class SaveToBankDialog(QtWidgets.QDialog):
    """Name, tags and description of a texture going into the bank; optionally a new version of
    the entry it was opened from."""

    def __init__(self, name: str, tags, description: str, parent_name: str | None, parent=None):
        super().__init__(parent)
        self.setWindowTitle("Save to bank")
        form = QtWidgets.QFormLayout(self)
        self.name = QtWidgets.QLineEdit(name)
        self.name.setPlaceholderText("a name to find it by")
        self.tags = QtWidgets.QLineEdit(", ".join(tags))
        self.tags.setPlaceholderText("keys, separated by commas: gravel, fine, warm")
        self.description = QtWidgets.QPlainTextEdit(description)
        self.description.setPlaceholderText("what it is, how it was made (searchable)")
        self.description.setFixedHeight(72)
        self.version = QtWidgets.QCheckBox(f"A new version of “{parent_name}”")
        self.version.setToolTip("Keep the link to the entry this texture was opened from; "
                                "both stay in the bank")
        self.version.setChecked(parent_name is not None)
        self.version.setVisible(parent_name is not None)
        form.addRow("&Name:", self.name)
        form.addRow("&Tags:", self.tags)
        form.addRow("&Description:", self.description)
        form.addRow(self.version)
        buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Save
                                             | QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        self.ok_button = buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Save)
        self.name.textChanged.connect(lambda t: self.ok_button.setEnabled(bool(t.strip())))
        self.ok_button.setEnabled(bool(name.strip()))
        form.addRow(buttons)
        self.resize(420, self.sizeHint().height())
