"""Choose a bank entry: a small window-modal dialog with the bank browser's search field and
thumbnail grid (the model, view and delegate of `bank_view`), OK and Cancel.

The composition dialog and the Spot tool use it to name a bank entry as a texture source; then
`load_bank_source` turns the entry into a recipe in the worker (replayed, its SHA-256 checked).
It reads the bank the browser dock has open (opening it if needed) and never changes it.
"""

from __future__ import annotations

from typing import Callable

from PySide6 import QtCore, QtWidgets

from texeditor.bank.store import Bank
from texeditor.errors import TexeditorError
from texeditor.recipe.sources import TextureSource, bank_source

from .bank_view import IdRole, ThumbnailGrid

SEARCH_DELAY_MS = 150
RETRY_MS = 100                    # how often a source waits for the worker to be free
EMPTY = ("The texture bank is empty: File ▸ Save to bank… (Ctrl+B) stores the current texture "
         "in it.")


def window_bank(window) -> tuple[Bank | None, str]:
    """The bank the browser dock has open, opened now if it is not; else (None, why not)."""
    dock = getattr(window, "bank_dock", None)
    if dock is None:
        return None, "this window has no texture bank"
    if dock.bank is None and not dock.load(prepare=False):
        return None, dock.status.text()
    return dock.bank, ""


class BankPicker(QtWidgets.QDialog):
    """Search the bank and pick one entry. ``bank`` None shows ``problem`` and picks nothing;
    ``entry_id()`` is the chosen entry (None until one is selected)."""

    def __init__(self, bank: Bank | None, problem: str = "", note: str = "", parent=None):
        super().__init__(parent)
        self.setWindowTitle("Choose a bank entry")
        self.bank = bank
        layout = QtWidgets.QVBoxLayout(self)
        if note:
            layout.addWidget(_wrapped(note))
        self.search = QtWidgets.QLineEdit()
        self.search.setPlaceholderText("Search names, descriptions, tags (tag:x)")
        self.search.setClearButtonEnabled(True)
        self.grid = ThumbnailGrid()
        self.grid.setMinimumSize(4 * 100, 3 * 110)
        self.status = _wrapped("")
        self.info = _wrapped("")
        buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Ok
                                             | QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        self.ok_button = buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
        self.ok_button.setEnabled(False)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        for w in (self.search, self.grid, self.status, self.info, buttons):
            layout.addWidget(w)
        self._timer = QtCore.QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.setInterval(SEARCH_DELAY_MS)
        self._timer.timeout.connect(self.refresh)
        self.search.textChanged.connect(self._timer.start)
        self.grid.selectionModel().currentChanged.connect(self._selected)
        self.grid.doubleClicked.connect(lambda _index: self.accept())
        if bank is None:
            self.search.setEnabled(False)
            self.grid.setEnabled(False)
            self.status.setText(f"The texture bank cannot be used: {problem}")
        else:
            self.refresh()

    def refresh(self) -> None:
        """List the entries that match the search (all of them when it is empty)."""
        text = self.search.text()
        try:
            ids = self.bank.find(text)
        except TexeditorError as exc:
            self.status.setText(str(exc))
            return
        self.grid.model().set_ids(self.bank, ids)
        self._selected(QtCore.QModelIndex())
        if ids:
            self.grid.setCurrentIndex(self.grid.model().index(0))
        if not ids and not text.strip():
            self.status.setText(EMPTY)
        elif not ids:
            self.status.setText(f"No entry matches “{text.strip()}”.")
        else:
            self.status.setText(f"{len(ids)} entr{'ies' if len(ids) != 1 else 'y'}")

    def entry_id(self) -> int | None:
        index = self.grid.currentIndex()
        return index.data(IdRole) if index.isValid() else None

    def _selected(self, index, _previous=None) -> None:
        entry = None
        if index.isValid():
            try:
                entry = self.bank.get(index.data(IdRole))
            except TexeditorError as exc:
                self.status.setText(str(exc))
        self.ok_button.setEnabled(entry is not None)
        self.info.setText("" if entry is None else
                          f"“{entry.name}”: {entry.width}×{entry.height}, G = {entry.levels}")


def _wrapped(text: str) -> QtWidgets.QLabel:
    label = QtWidgets.QLabel(text)
    label.setWordWrap(True)
    return label


def choose_bank_entry(window, on_chosen: Callable[[Bank, int], None], *, note: str = "",
                      parent=None) -> BankPicker:
    """Open the picker (window-modal) on the window's bank; ``on_chosen(bank, entry id)`` runs
    after OK. Returns the dialog, which deletes itself when closed."""
    bank, problem = window_bank(window)
    dialog = BankPicker(bank, problem, note, parent or window)
    dialog.accepted.connect(lambda: on_chosen(bank, dialog.entry_id()))
    dialog.finished.connect(dialog.deleteLater)
    dialog.open()
    return dialog


def load_bank_source(window, bank: Bank, entry_id: int,
                     on_loaded: Callable[[TextureSource], None],
                     on_failed: Callable[[], None] | None = None) -> None:
    """Turn an entry into a texture source in the worker (replayed, its hash checked), then
    ``on_loaded(source)`` on the GUI thread; waits its turn while other work runs. When the
    entry cannot be used (gone, damaged, too deep a recipe) or its reading is cancelled,
    ``on_failed()`` runs instead (before the message is shown), so the caller can undo its
    choice."""
    runner = window.runner
    if runner.busy:
        QtCore.QTimer.singleShot(RETRY_MS, window, lambda: load_bank_source(   # not once the
            window, bank, entry_id, on_loaded, on_failed))                       # window is gone
        return
    failed = on_failed or (lambda: None)
    try:
        name = bank.get(entry_id).name
    except TexeditorError as exc:             # deleted, or the bank went away, meanwhile
        failed()
        window.show_error("Cannot use this bank entry", exc)
        return

    def cancelled():
        failed()
        window.statusBar().showMessage(f"Reading “{name}” cancelled.", 5000)

    def error(exc):
        failed()
        window.show_error(f"Cannot use “{name}”", exc)

    runner.run(f"Reading “{name}” from the bank…",
               lambda progress, cancel: bank_source(bank, entry_id, progress, cancel),
               on_loaded, on_cancel=cancelled, on_error=error)
