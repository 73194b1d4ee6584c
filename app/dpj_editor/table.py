"""The table of configurations: every non-zero entry of the DPJ being edited, with its thumbnail,
probability, share of the sum and role in the chain (unreachable entries are marked).

It sits between the editor's DPJ and the user: rows are read from the DPJ's arrays, and edits
(a new probability, deleted rows) go back as signals the editor turns into undoable DPJ edits.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.markov import chain, dpj_edit
from texeditor.markov.dpj import DPJ

from ..canvas import colourize
from ..images import qimage_from_rgb

CONFIG, PROB, SHARE, CHAIN = range(4)
HEADERS = ("Configuration", "Probability", "Share", "Chain")
CODE_ROLE = QtCore.Qt.ItemDataRole.UserRole + 1
THUMB_BOX = 36                  # pixels of the largest thumbnail side
MAX_THUMBS = 4096               # cached thumbnails (a screenful is a few dozen)
UNREACHABLE = QtGui.QColor("#c0392b")
DIGITS = "0123456789ABCDEF"
Order = QtCore.Qt.SortOrder
ROLE_TIPS = {
    chain.DEAD_END: "Dead end: it leads (to the right or below) to columns or rows no "
                    "configuration continues, mostly a pattern seen only at the photo's border",
    chain.TRANSIENT: "Transient: a row passes through it at most once, then never comes back",
    chain.MINOR_CLOSED: "A smaller closed class: a row that starts in it never leaves it, and a "
                        "row outside never enters it",
}


def config_text(config: np.ndarray) -> str:
    """A configuration as text, rows top to bottom separated by "/": "01/01"."""
    return "/".join("".join(DIGITS[x] for x in row) for row in config)


def thumb_cell(window: tuple[int, int]) -> int:
    return max(3, min(10, THUMB_BOX // max(window)))


class LevelFilter:
    """Which rows to show: by the levels a configuration contains, and by probability."""

    MODES = (("contains any of", "any"), ("contains all of", "all"), ("uses only", "only"))

    def __init__(self, levels=(), mode: str = "any", pmin: float | None = None,
                 pmax: float | None = None):
        self.levels, self.mode, self.pmin, self.pmax = tuple(levels), mode, pmin, pmax

    @property
    def active(self) -> bool:
        return bool(self.levels) or self.pmin is not None or self.pmax is not None

    def mask(self, dpj: DPJ, presence) -> np.ndarray:
        """A bool per entry; ``presence()`` gives the (entries, G) table only when needed."""
        keep = np.ones(len(dpj), bool)
        if self.levels:
            present = presence()
            chosen = np.zeros(dpj.levels, bool)
            chosen[[k for k in self.levels if k < dpj.levels]] = True
            if self.mode == "all":
                keep &= present[:, chosen].all(axis=1)
            elif self.mode == "only":
                keep &= ~present[:, ~chosen].any(axis=1)
            else:
                keep &= present[:, chosen].any(axis=1)
        if self.pmin is not None:
            keep &= dpj.probs >= self.pmin
        if self.pmax is not None:
            keep &= dpj.probs <= self.pmax
        return keep


class ConfigTableModel(QtCore.QAbstractTableModel):
    """The DPJ's entries as rows; ``rows`` holds the entry shown on each row (filtered, sorted).

    Sorting and filtering are numpy index arrays over the DPJ's own arrays, so ordering 200k
    entries costs milliseconds; the model is reset after each, and the view keeps its place.
    ``probabilityEdited(code, p)`` reports an in-place edit; the model never changes the DPJ.
    """

    probabilityEdited = QtCore.Signal(object, float)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.dpj = DPJ.empty((2, 2), 2)
        self.roles = np.zeros(0, np.int8)
        self.rows = np.zeros(0, np.int64)
        self.sort_key = (PROB, Order.DescendingOrder)
        self.filter = LevelFilter()
        self._presence = None
        self._thumbs: dict[int, QtGui.QPixmap] = {}

    # -- contents ----------------------------------------------------------------------------------
    def set_dpj(self, dpj: DPJ, roles: np.ndarray) -> None:
        if not np.array_equal(dpj.palette, self.dpj.palette) or dpj.window != self.dpj.window:
            self._thumbs.clear()
        self.beginResetModel()
        self.dpj, self.roles, self._presence = dpj, roles, None
        self.rows = self._ordered_rows()
        self.endResetModel()

    def set_roles(self, roles: np.ndarray) -> None:
        """The chain roles arrive later for a large DPJ (checked in the background)."""
        self.roles = roles
        if self.sort_key[0] == CHAIN:
            self.sort_by(*self.sort_key)
        elif len(self.rows):
            self.dataChanged.emit(self.index(0, 0), self.index(len(self.rows) - 1, CHAIN))

    def sort_by(self, column: int, order: Order) -> None:
        self.beginResetModel()
        self.sort_key = (column, order)
        self.rows = self._ordered_rows()
        self.endResetModel()

    def set_filter(self, level_filter: LevelFilter) -> None:
        self.beginResetModel()
        self.filter = level_filter
        self.rows = self._ordered_rows()
        self.endResetModel()

    def presence(self) -> np.ndarray:
        if self._presence is None:
            self._presence = dpj_edit.level_presence(self.dpj)
        return self._presence

    def _ordered_rows(self) -> np.ndarray:
        order = self._order()
        if not self.filter.active:
            return order
        return order[self.filter.mask(self.dpj, self.presence)[order]]

    def _order(self) -> np.ndarray:
        column, direction = self.sort_key
        n = len(self.dpj)
        descending = direction == Order.DescendingOrder
        if column == CONFIG:                # entries are stored by code already
            order = np.arange(n)
            return order[::-1].copy() if descending else order
        probs = self.dpj.probs
        if column == CHAIN:
            keys = (-probs if descending else probs, -self.roles if descending else self.roles)
            return np.lexsort(keys)
        return np.argsort(-probs if descending else probs, kind="stable")

    # -- Qt model ----------------------------------------------------------------------------------
    def rowCount(self, parent=QtCore.QModelIndex()) -> int:
        return 0 if parent.isValid() else len(self.rows)

    def columnCount(self, parent=QtCore.QModelIndex()) -> int:
        return 0 if parent.isValid() else len(HEADERS)

    def headerData(self, section, orientation, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if orientation == QtCore.Qt.Orientation.Horizontal:
            if role == QtCore.Qt.ItemDataRole.DisplayRole:
                return HEADERS[section]
            if role == QtCore.Qt.ItemDataRole.ToolTipRole:
                return ("The window's levels, rows top to bottom", "Double-click to edit",
                        "Share of the sum of all probabilities",
                        "Role in the horizontal chain: dead ends, transient entries and small "
                        "closed classes are unreachable in a long synthesis (Restrict removes "
                        "them)")[section]
        return None

    def flags(self, index):
        flags = super().flags(index)
        return flags | QtCore.Qt.ItemFlag.ItemIsEditable if index.column() == PROB else flags

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if not index.isValid():
            return None
        i, col = int(self.rows[index.row()]), index.column()
        R = QtCore.Qt.ItemDataRole
        if role == R.DisplayRole:
            return self._text(i, col)
        if role == R.EditRole and col == PROB:
            return float(self.dpj.probs[i])
        if role == R.DecorationRole and col == CONFIG:
            return self.thumbnail(i)
        if role == R.ForegroundRole and self.roles[i] != chain.MAIN:
            return UNREACHABLE
        if role == R.TextAlignmentRole and col in (PROB, SHARE):
            return int(QtCore.Qt.AlignmentFlag.AlignRight | QtCore.Qt.AlignmentFlag.AlignVCenter)
        if role == R.ToolTipRole and col == CHAIN and self.roles[i] != chain.MAIN:
            return ROLE_TIPS[int(self.roles[i])]
        if role == CODE_ROLE:
            return int(self.dpj.codes[i])
        return None

    def _text(self, i: int, col: int) -> str:
        p = float(self.dpj.probs[i])
        if col == CONFIG:
            return config_text(self.dpj.configs[i])
        if col == PROB:
            return f"{p:.6g}"
        if col == SHARE:
            total = self.dpj.total
            return f"{100 * p / total:.3g} %" if total > 0 else "–"
        role = int(self.roles[i])
        return "" if role == chain.MAIN else chain.ROLE_NAMES[role]

    def setData(self, index, value, role=QtCore.Qt.ItemDataRole.EditRole) -> bool:
        if role != QtCore.Qt.ItemDataRole.EditRole or index.column() != PROB:
            return False
        try:
            p = float(value)
        except (TypeError, ValueError):
            return False
        self.probabilityEdited.emit(int(self.dpj.codes[int(self.rows[index.row()])]), p)
        return True

    def thumbnail(self, i: int) -> QtGui.QPixmap:
        code = int(self.dpj.codes[i])
        pix = self._thumbs.get(code)
        if pix is None:
            if len(self._thumbs) >= MAX_THUMBS:
                self._thumbs.clear()
            pix = self._thumbs[code] = config_pixmap(self.dpj.configs[i], self.dpj.palette,
                                                     thumb_cell(self.dpj.window))
        return pix

    # -- rows ↔ entries ----------------------------------------------------------------------------
    def entries_of_rows(self, rows: np.ndarray) -> np.ndarray:
        return self.rows[rows]

    def row_of_code(self, code: int) -> int:
        i = int(np.searchsorted(self.dpj.codes, code))
        if i >= len(self.dpj) or self.dpj.codes[i] != code:
            return -1
        hits = np.flatnonzero(self.rows == i)
        return int(hits[0]) if len(hits) else -1

    def rows_of_codes(self, codes: np.ndarray) -> np.ndarray:
        """Rows (sorted) showing any of these codes."""
        wanted = np.isin(self.dpj.codes, codes)
        return np.flatnonzero(wanted[self.rows])


def config_pixmap(config: np.ndarray, palette, cell: int) -> QtGui.QPixmap:
    """A configuration drawn with its palette, ``cell`` pixels per point, with a thin frame."""
    rgb = colourize(config, palette)
    rgb = np.repeat(np.repeat(rgb, cell, axis=0), cell, axis=1)
    pix = QtGui.QPixmap.fromImage(qimage_from_rgb(rgb))
    p = QtGui.QPainter(pix)
    p.setPen(QtGui.QColor(128, 128, 128))
    p.drawRect(0, 0, pix.width() - 1, pix.height() - 1)
    p.end()
    return pix


class ConfigProxyModel(QtCore.QSortFilterProxyModel):
    """What the view talks to: header clicks call ``sort``, the filter bar ``set_filter``.

    Qt's own sorting asks Python for two values per comparison — 23 s for 200k rows, measured —
    and its filter calls Python once per row, so both are handed to the source model, which
    orders and filters with numpy; the proxy then maps rows one to one (in C++, milliseconds).
    """

    def sort(self, column: int, order=Order.AscendingOrder) -> None:
        if column >= 0:
            self.sourceModel().sort_by(column, order)

    def set_filter(self, level_filter: LevelFilter) -> None:
        self.sourceModel().set_filter(level_filter)


def number_validator(parent) -> QtGui.QValidator:
    """A non-negative decimal, plain or scientific ("0.25", "2.5e-3"); the range is the
    engine's to check, so a value above 1 is explained rather than silently refused."""
    pattern = QtCore.QRegularExpression(r"(\d+\.?\d*|\.\d+)([eE][-+]?\d{1,3})?")
    return QtGui.QRegularExpressionValidator(pattern, parent)


class ProbabilityDelegate(QtWidgets.QStyledItemDelegate):
    """In-place edit of a probability: exact entry (decimal or scientific), 0..1."""

    def createEditor(self, parent, option, index):
        edit = QtWidgets.QLineEdit(parent)
        edit.setValidator(number_validator(edit))
        return edit

    def setEditorData(self, editor, index):
        editor.setText(repr(float(index.data(QtCore.Qt.ItemDataRole.EditRole))))
        editor.selectAll()

    def setModelData(self, editor, model, index):
        if editor.hasAcceptableInput():
            model.setData(index, float(editor.text()), QtCore.Qt.ItemDataRole.EditRole)


class PlainHeader(QtWidgets.QHeaderView):
    """A horizontal header that draws its sections without asking whether a whole column is
    selected: Qt's own asks the model for the flags of every row of the column, which with
    200k selected rows (Ctrl+A) blocks for seconds. A table of rows never needs that highlight."""

    def __init__(self, parent=None):
        super().__init__(QtCore.Qt.Orientation.Horizontal, parent)
        self.setHighlightSections(False)
        self.setSectionsClickable(True)

    def paintSection(self, painter, rect, logical) -> None:
        if not rect.isValid():
            return
        opt = QtWidgets.QStyleOptionHeader()
        self.initStyleOption(opt)
        opt.rect, opt.section = rect, logical
        opt.text = str(self.model().headerData(logical, self.orientation()) or "")
        opt.textAlignment = self.defaultAlignment()
        if self.isSortIndicatorShown() and self.sortIndicatorSection() == logical:
            opt.sortIndicator = (QtWidgets.QStyleOptionHeader.SortIndicator.SortDown
                                 if self.sortIndicatorOrder() == Order.AscendingOrder
                                 else QtWidgets.QStyleOptionHeader.SortIndicator.SortUp)
        visual, last = self.visualIndex(logical), self.count() - 1
        P = QtWidgets.QStyleOptionHeader.SectionPosition
        opt.position = (P.OnlyOneSection if last == 0 else P.Beginning if visual == 0
                        else P.End if visual == last else P.Middle)
        self.style().drawControl(QtWidgets.QStyle.ControlElement.CE_Header, opt, painter, self)


class ConfigTable(QtWidgets.QWidget):
    """The filter bar, the table view and its buttons.

    Signals: ``entryActivated(config, p)`` when a row becomes current (the painter loads it),
    ``deleteRequested(codes)``, ``probabilityEdited(code, p)``.
    """

    entryActivated = QtCore.Signal(object, float)
    deleteRequested = QtCore.Signal(object)
    probabilityEdited = QtCore.Signal(object, float)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.model = ConfigTableModel(self)
        self.proxy = ConfigProxyModel(self)
        self.proxy.setSourceModel(self.model)
        # queued: the DPJ edit resets the model, which must not happen inside the delegate's commit
        self.model.probabilityEdited.connect(self.probabilityEdited,
                                             QtCore.Qt.ConnectionType.QueuedConnection)
        self._saved = (np.zeros(0, np.int64), None)
        self._restoring = False
        self.view = self._make_view()
        self.model.modelAboutToBeReset.connect(self._save_place)
        self.model.modelReset.connect(self._restore_place)
        self._level_buttons: list[QtWidgets.QToolButton] = []
        self.filter_timer = QtCore.QTimer(self, singleShot=True, interval=200)
        self.filter_timer.timeout.connect(self.apply_filter)

        self.levels_row = QtWidgets.QHBoxLayout()
        self.levels_row.setSpacing(2)
        self.mode = QtWidgets.QComboBox()
        for text, key in LevelFilter.MODES:
            self.mode.addItem(text, key)
        self.mode.currentIndexChanged.connect(self.filter_timer.start)
        self.pmin, self.pmax = self._bound("min"), self._bound("max")
        self.clear_filter_button = QtWidgets.QToolButton(text="Clear")
        self.clear_filter_button.setToolTip("Show every configuration")
        self.clear_filter_button.clicked.connect(self.clear_filter)
        self.count_label = QtWidgets.QLabel()
        self.delete_button = QtWidgets.QPushButton("Delete selected")
        self.delete_button.setToolTip("Remove the selected configurations (Delete)")
        self.delete_button.clicked.connect(self.delete_selected)
        self._layout()

    def _make_view(self) -> QtWidgets.QTableView:
        view = QtWidgets.QTableView()
        view.setHorizontalHeader(PlainHeader(view))
        view.setModel(self.proxy)
        view.setItemDelegateForColumn(PROB, ProbabilityDelegate(view))
        view.setSelectionBehavior(QtWidgets.QAbstractItemView.SelectionBehavior.SelectRows)
        view.setSelectionMode(QtWidgets.QAbstractItemView.SelectionMode.ExtendedSelection)
        view.setEditTriggers(QtWidgets.QAbstractItemView.EditTrigger.DoubleClicked
                             | QtWidgets.QAbstractItemView.EditTrigger.EditKeyPressed)
        view.verticalHeader().hide()
        view.verticalHeader().setSectionResizeMode(QtWidgets.QHeaderView.ResizeMode.Fixed)
        view.setIconSize(QtCore.QSize(THUMB_BOX, THUMB_BOX))
        view.setWordWrap(False)
        view.setAlternatingRowColors(True)
        header = view.horizontalHeader()
        header.setSectionResizeMode(QtWidgets.QHeaderView.ResizeMode.Interactive)
        header.setStretchLastSection(True)
        for col, width in ((CONFIG, 170), (PROB, 110), (SHARE, 80)):
            view.setColumnWidth(col, width)
        header.setSortIndicator(PROB, Order.DescendingOrder)
        view.setSortingEnabled(True)
        view.selectionModel().currentRowChanged.connect(self._current_changed)
        delete = QtGui.QShortcut(QtGui.QKeySequence(QtGui.QKeySequence.StandardKey.Delete), view)
        delete.setContext(QtCore.Qt.ShortcutContext.WidgetWithChildrenShortcut)
        delete.activated.connect(self.delete_selected)
        return view

    def _bound(self, placeholder: str) -> QtWidgets.QLineEdit:
        edit = QtWidgets.QLineEdit()
        edit.setPlaceholderText(placeholder)
        edit.setFixedWidth(self.fontMetrics().horizontalAdvance("0.000001") + 16)
        edit.setValidator(number_validator(edit))
        edit.textChanged.connect(self.filter_timer.start)
        return edit

    def _layout(self) -> None:
        bar = QtWidgets.QHBoxLayout()
        bar.addWidget(QtWidgets.QLabel("Show"))
        bar.addWidget(self.mode)
        bar.addLayout(self.levels_row)
        bar.addSpacing(12)
        bar.addWidget(QtWidgets.QLabel("p from"))
        bar.addWidget(self.pmin)
        bar.addWidget(QtWidgets.QLabel("to"))
        bar.addWidget(self.pmax)
        bar.addWidget(self.clear_filter_button)
        bar.addStretch(1)
        bottom = QtWidgets.QHBoxLayout()
        bottom.addWidget(self.count_label, 1)
        bottom.addWidget(self.delete_button)
        layout = QtWidgets.QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addLayout(bar)
        layout.addWidget(self.view, 1)
        layout.addLayout(bottom)

    # -- the DPJ -----------------------------------------------------------------------------------
    def set_dpj(self, dpj: DPJ, roles: np.ndarray) -> None:
        """Show a new DPJ, keeping the selected and current configurations where they still are."""
        self._sync_level_buttons(dpj)
        self.view.verticalHeader().setDefaultSectionSize(
            max(self.fontMetrics().height() + 6, thumb_cell(dpj.window) * dpj.window[1] + 6))
        self.model.set_dpj(dpj, roles)

    def _sync_level_buttons(self, dpj: DPJ) -> None:
        if (len(self._level_buttons) == dpj.levels
                and np.array_equal(dpj.palette, self.model.dpj.palette)):
            return
        checked = {k for k, b in enumerate(self._level_buttons) if b.isChecked()}
        for b in self._level_buttons:
            self.levels_row.removeWidget(b)
            b.deleteLater()
        self._level_buttons = []
        for k, rgb in enumerate(dpj.palette):
            b = QtWidgets.QToolButton(text=str(k))
            b.setCheckable(True)
            b.setChecked(k in checked)
            b.setToolTip(f"Filter on level {k}")
            r, g, bl = (int(c) for c in rgb)
            ink = "black" if 0.299 * r + 0.587 * g + 0.114 * bl > 140 else "white"
            b.setStyleSheet(f"QToolButton {{ background: rgb({r},{g},{bl}); color: {ink}; "
                            "border: 1px solid #888; min-width: 18px; }"
                            "QToolButton:checked { border: 3px solid palette(highlight); }")
            b.toggled.connect(self.filter_timer.start)
            self.levels_row.addWidget(b)
            self._level_buttons.append(b)

    # -- filter ------------------------------------------------------------------------------------
    def current_filter(self) -> LevelFilter:
        levels = [k for k, b in enumerate(self._level_buttons) if b.isChecked()]
        return LevelFilter(levels, self.mode.currentData(), _bound_value(self.pmin),
                           _bound_value(self.pmax))

    def apply_filter(self) -> None:
        self.filter_timer.stop()
        self.proxy.set_filter(self.current_filter())

    def clear_filter(self) -> None:
        for w in [*self._level_buttons, self.pmin, self.pmax]:
            w.blockSignals(True)
        for b in self._level_buttons:
            b.setChecked(False)
        self.pmin.clear()
        self.pmax.clear()
        for w in [*self._level_buttons, self.pmin, self.pmax]:
            w.blockSignals(False)
        self.apply_filter()

    def _show_count(self) -> None:
        n, shown = len(self.model.dpj), self.model.rowCount()
        text = f"{n:,} configurations" if shown == n else f"{shown:,} of {n:,} configurations shown"
        self.count_label.setText(text)

    # -- selection ---------------------------------------------------------------------------------
    def _save_place(self) -> None:
        """Before any reset (new DPJ, sort, filter): what was selected and current."""
        self._saved = (self.selected_codes(), self._current_code())

    def _restore_place(self) -> None:
        self._restore(*self._saved)
        self._show_count()

    def selected_rows(self) -> np.ndarray:
        """Rows of the selection, read from its ranges (a 200k-row selection is one range)."""
        mask = np.zeros(len(self.model.rows), bool)
        for r in self.view.selectionModel().selection():
            mask[r.top():r.bottom() + 1] = True
        return np.flatnonzero(mask)

    def selected_codes(self) -> np.ndarray:
        rows = self.selected_rows()
        return self.model.dpj.codes[self.model.entries_of_rows(rows)]

    def select_codes(self, codes) -> None:
        self._restore(np.asarray(codes, np.int64), None)

    def _current_code(self) -> int | None:
        index = self.view.currentIndex()
        return index.data(CODE_ROLE) if index.isValid() else None

    def _restore(self, codes: np.ndarray, current: int | None) -> None:
        sm = self.view.selectionModel()
        selection = QtCore.QItemSelection()
        rows = self.model.rows_of_codes(codes) if len(codes) else np.zeros(0, np.int64)
        if len(rows):
            breaks = np.flatnonzero(np.diff(rows) != 1)
            starts = np.concatenate([[rows[0]], rows[breaks + 1]])
            ends = np.concatenate([rows[breaks], [rows[-1]]])
            last = self.proxy.columnCount() - 1
            for a, b in zip(starts, ends):
                selection.select(self.proxy.index(int(a), 0), self.proxy.index(int(b), last))
        flags = QtCore.QItemSelectionModel.SelectionFlag
        row = self.model.row_of_code(current) if current is not None else -1
        self._restoring = True           # the painter keeps what is being painted
        try:
            if row >= 0:
                sm.setCurrentIndex(self.proxy.index(row, 0), flags.NoUpdate)
            sm.select(selection, flags.ClearAndSelect)
        finally:
            self._restoring = False

    def _current_changed(self, index, _previous) -> None:
        if not self._restoring and index.isValid() and index.row() < len(self.model.rows):
            i = int(self.model.rows[index.row()])
            self.entryActivated.emit(self.model.dpj.configs[i].copy(),
                                     float(self.model.dpj.probs[i]))

    def delete_selected(self) -> None:
        codes = self.selected_codes()
        if len(codes):
            self.deleteRequested.emit(codes)


def _bound_value(edit: QtWidgets.QLineEdit) -> float | None:
    text = edit.text().strip()
    if not text or not edit.hasAcceptableInput():
        return None
    return float(text)
