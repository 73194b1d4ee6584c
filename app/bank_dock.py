"""The bank browser dock: the texture bank as a grid of thumbnails, with search, attribute filters,
tags, "more like this", open, duplicate, delete (trash and undo), import and export.

It sits between the bank (texeditor.bank.store, SQLite) and the main window: opening an entry replays its
log in the window's TaskRunner and hands the History to ``set_history``; saving sends a snapshot
of the current document to the worker and stores the result. The bank opens on ``load()`` (the
application's start-up), never merely because the dock exists.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor import warmup
from texeditor.wording import counted
from texeditor.bank.store import Bank, make_record
from texeditor.errors import TexeditorError

from .bank_view import IdRole, RangeFilters, SaveToBankDialog, ThumbnailGrid

SEARCH_DELAY_MS = 150
WATCH_MS = 2000                   # how often the browser looks for changes made elsewhere
START_ENTRY = "Gravel with tone"  # the built-in the window opens on: shown in its photo's greys
ENGINE_NOTE_MS = 1500             # the "Preparing the synthesis engine" note after this long
TEXTURE_FILTER = "Textures (*.texture);;All files (*)"


class BankDock(QtWidgets.QDockWidget):
    """The texture bank browser. ``load()`` opens the bank; ``start()`` also opens an entry."""

    def __init__(self, window):
        super().__init__("Texture bank", window)
        self.setObjectName("BankDock")
        self.main = window                   # the MainWindow (QWidget.window() stays Qt's)
        self.bank: Bank | None = None
        self.opened: tuple | None = None     # (entry id, the History it was opened into)
        self.deleted: list[int] = []         # trashed by this dock, for "Undo delete"
        self.like: int | None = None
        self._search_timer = QtCore.QTimer(self)
        self._search_timer.setSingleShot(True)
        self._search_timer.setInterval(SEARCH_DELAY_MS)
        self._search_timer.timeout.connect(self.refresh)
        self._watch = QtCore.QTimer(self)        # another window or program changed the bank
        self._watch.setInterval(WATCH_MS)
        self._watch.timeout.connect(self._check_elsewhere)
        self._build()
        self._set_enabled(False)
        self._sized = False

    # -- construction -------------------------------------------------------------------------------
    def _build(self) -> None:
        body = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(body)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addLayout(self._build_search())
        self.filters = RangeFilters()
        self.filters.changed.connect(self._search_timer.start)
        self.filters.hide()
        layout.addWidget(self.filters)
        self.like_bar = self._build_like_bar()
        layout.addWidget(self.like_bar)
        self.view = self._build_view()
        layout.addWidget(self.view, 1)
        self.status = QtWidgets.QLabel()
        self.status.setWordWrap(True)
        self.status.setStyleSheet("color: palette(mid)")
        layout.addWidget(self.status)
        layout.addLayout(self._build_buttons())
        layout.addWidget(self._build_details())
        self.open_bank_button = QtWidgets.QPushButton("Open the texture bank")
        self.open_bank_button.clicked.connect(lambda: self.load())
        layout.addWidget(self.open_bank_button)
        self.setWidget(body)
        self.act_save = QtGui.QAction("Save to &bank…", self.main)
        self.act_save.setShortcut(QtGui.QKeySequence("Ctrl+B"))
        self.act_save.setStatusTip("Store the texture in the bank: its DPJ, its optimised log, "
                                   "a thumbnail, tags and attributes")
        self.act_save.triggered.connect(self.save_current)
        self.main.addAction(self.act_save)

    def _build_search(self) -> QtWidgets.QHBoxLayout:
        row = QtWidgets.QHBoxLayout()
        self.search = QtWidgets.QLineEdit()
        self.search.setPlaceholderText("Search names, descriptions, tags (tag:x)")
        self.search.setClearButtonEnabled(True)
        self.search.textChanged.connect(self._search_timer.start)
        self.search.returnPressed.connect(self.refresh)
        self.filter_button = QtWidgets.QToolButton()
        self.filter_button.setText("Filters")
        self.filter_button.setCheckable(True)
        self.filter_button.setToolTip("Attribute ranges: contrast, grain size, density, …")
        self.filter_button.toggled.connect(self._show_filters)
        self.menu_button = QtWidgets.QToolButton()
        self.menu_button.setText("⋯")
        self.menu_button.setPopupMode(QtWidgets.QToolButton.ToolButtonPopupMode.InstantPopup)
        self.menu_button.setMenu(self._build_menu())
        row.addWidget(self.search, 1)
        row.addWidget(self.filter_button)
        row.addWidget(self.menu_button)
        return row

    def _build_menu(self) -> QtWidgets.QMenu:
        menu = QtWidgets.QMenu(self)
        self.act_import = menu.addAction("Import .texture…", self.import_file)
        self.act_export = menu.addAction("Export .texture…", self.export_selected)
        menu.addSeparator()
        self.act_trash = menu.addAction("Show the trash")
        self.act_trash.setCheckable(True)
        self.act_trash.toggled.connect(self._show_trash)
        self.act_empty = menu.addAction("Empty the trash…", self.empty_trash)
        menu.addSeparator()
        self.act_verify = menu.addAction("Verify the bank…", self.verify)
        return menu

    def _build_like_bar(self) -> QtWidgets.QWidget:
        bar = QtWidgets.QWidget()
        row = QtWidgets.QHBoxLayout(bar)
        row.setContentsMargins(0, 0, 0, 0)
        self.like_label = QtWidgets.QLabel()
        clear = QtWidgets.QToolButton()
        clear.setText("✕")
        clear.setToolTip("Back to the whole bank")
        clear.clicked.connect(lambda: self.set_like(None))
        row.addWidget(self.like_label, 1)
        row.addWidget(clear)
        bar.hide()
        return bar

    def _build_view(self) -> QtWidgets.QListView:
        view = ThumbnailGrid()
        self.model = view.model()
        view.doubleClicked.connect(lambda index: self.open_entry(index.data(IdRole)))
        view.selectionModel().currentChanged.connect(self._selected)
        for key, slot in ((QtCore.Qt.Key.Key_Return, self.open_selected),
                          (QtCore.Qt.Key.Key_Delete, self.delete_selected)):
            shortcut = QtGui.QShortcut(QtGui.QKeySequence(key), view)
            shortcut.setContext(QtCore.Qt.ShortcutContext.WidgetShortcut)
            shortcut.activated.connect(slot)
        return view

    def _build_buttons(self) -> QtWidgets.QHBoxLayout:
        row = QtWidgets.QHBoxLayout()

        def button(text, tip, slot):
            b = QtWidgets.QToolButton()
            b.setText(text)
            b.setToolTip(tip)
            b.clicked.connect(slot)
            row.addWidget(b)
            return b

        self.open_button = button("Open", "Replay the entry into the canvas (Enter, double-click)",
                                  self.open_selected)
        self.like_button = button("Like", "More like this: the entries nearest to this one in "
                                  "contrast, grain, density, orientation, regularity, coarseness",
                                  lambda: self.set_like(self.selected()))
        self.duplicate_button = button("Copy", "Duplicate the entry, to re-tag or rename it",
                                       self.duplicate_selected)
        self.delete_button = button("Delete", "Move the entry to the trash (Del)",
                                    self.delete_selected)
        self.undo_button = button("Undelete", "Bring back the entry deleted last",
                                  self.undo_delete)
        self.restore_button = button("Restore", "Take the entry out of the trash",
                                     self.restore_selected)
        self.restore_button.hide()
        row.addStretch(1)
        return row

    def _build_details(self) -> QtWidgets.QWidget:
        """Name, tags, description and attributes of the selected entry, under a header that
        folds them away when the grid needs the room."""
        panel = QtWidgets.QWidget()
        outer = QtWidgets.QVBoxLayout(panel)
        outer.setContentsMargins(0, 0, 0, 0)
        outer.setSpacing(2)
        self.details_toggle = QtWidgets.QToolButton()
        self.details_toggle.setText("Selected entry")
        self.details_toggle.setCheckable(True)
        self.details_toggle.setChecked(True)
        self.details_toggle.setAutoRaise(True)
        self.details_toggle.setToolButtonStyle(QtCore.Qt.ToolButtonStyle.ToolButtonTextBesideIcon)
        self.details_toggle.setArrowType(QtCore.Qt.ArrowType.DownArrow)
        box = QtWidgets.QFrame()
        box.setFrameShape(QtWidgets.QFrame.Shape.StyledPanel)
        form = QtWidgets.QFormLayout(box)
        form.setContentsMargins(6, 4, 6, 4)
        self.name_edit = QtWidgets.QLineEdit()
        self.tags_edit = QtWidgets.QLineEdit()
        self.tags_edit.setPlaceholderText("tags, separated by commas")
        self.description_edit = QtWidgets.QPlainTextEdit()
        self.description_edit.setFixedHeight(46)
        self.info = QtWidgets.QLabel()
        self.apply_button = QtWidgets.QPushButton("Apply")
        self.apply_button.setToolTip("Store the new name, tags and description")
        self.apply_button.clicked.connect(self.apply_details)
        for w in (self.name_edit, self.tags_edit):
            w.textEdited.connect(lambda _t: self.apply_button.setEnabled(True))
            w.returnPressed.connect(self.apply_details)
        self.description_edit.textChanged.connect(lambda: self.apply_button.setEnabled(True))
        form.addRow("Name:", self.name_edit)
        form.addRow("Tags:", self.tags_edit)
        form.addRow("About:", self.description_edit)
        form.addRow(self.info)
        form.addRow(self.apply_button)
        area = _FitArea()                      # on a small screen the details scroll
        area.setWidget(box)
        area.setWidgetResizable(True)
        area.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
        area.setMinimumHeight(40)
        area.setSizePolicy(QtWidgets.QSizePolicy.Policy.Preferred,
                           QtWidgets.QSizePolicy.Policy.Maximum)   # never taller than needed
        self.details_toggle.toggled.connect(area.setVisible)
        self.details_toggle.toggled.connect(lambda on: self.details_toggle.setArrowType(
            QtCore.Qt.ArrowType.DownArrow if on else QtCore.Qt.ArrowType.RightArrow))
        outer.addWidget(self.details_toggle)
        outer.addWidget(area)
        self.details_area = area
        panel.setSizePolicy(QtWidgets.QSizePolicy.Policy.Preferred,
                            QtWidgets.QSizePolicy.Policy.Maximum)
        self.details = box
        return panel

    def showEvent(self, ev) -> None:
        super().showEvent(ev)
        if not self._sized:
            self._sized = True          # after the window has sized its own docks
            QtCore.QTimer.singleShot(0, self, lambda: QtCore.QTimer.singleShot(
                0, self, self._take_height))

    def _take_height(self) -> None:
        """The tool options above keep their natural height; the browser takes the rest."""
        if not self.isFloating():
            self.main.tool_dock.fit_height()

    # -- the bank -----------------------------------------------------------------------------------
    def load(self, path=None, *, prepare: bool = True) -> bool:
        """Open the bank (``path``, or $TEXEDITOR_BANK, or the user data folder) and list it;
        entries still pending get their thumbnails in the background (with ``prepare``)."""
        if self.bank is not None:
            self.bank.close()
            self.bank = None
        try:
            self.bank = Bank(path)
        except TexeditorError as exc:
            self._set_enabled(False)
            self.status.setText(f"The texture bank cannot be opened: {exc}")
            self.open_bank_button.setText("Try again to open the bank")
            return False
        self._set_enabled(True)
        self.bank.changed_elsewhere()
        self._watch.start()
        self.refresh()
        if prepare and self.bank.pending() and not self.main.runner.busy:
            self._prepare(None)
        return True

    def start(self) -> bool:
        """At start-up: open the bank and put a built-in entry on the canvas, then prepare the
        entries a first run installs. The numba kernels compile meanwhile in a background
        thread (a first start: tens of seconds), and the entry shows at once from its stored
        picture (``Bank.open_stored``). False when there is no bank or it is empty."""
        self._warm_up()
        if not self.load(prepare=False) or self.main.runner.busy:
            return False
        ids = [e.id for e in self.bank.search(START_ENTRY) if e.name == START_ENTRY] \
            or self.bank.find()
        if not ids:
            return False
        self._prepare(ids[0])
        return True

    def _warm_up(self) -> None:
        """Compile the kernels in the background; a note in the status bar while it lasts
        (shown after ENGINE_NOTE_MS: a warm numba cache only loads them, in about a second)."""
        from .mip import box_average           # the canvas's kernel (below 100 %), compiled first
        warmup.start(first=[lambda: box_average(np.zeros((2, 2), np.uint8),
                                                np.zeros((256, 3), np.uint8), 1)])
        self._to_confirm: int | None = None      # an entry shown from its stored picture
        self.engine_note = QtWidgets.QLabel("Preparing the synthesis engine… (first start only)")
        self.engine_note.setToolTip("The synthesis kernels are compiled once, for this computer "
                                    "(tens of seconds). Meanwhile the bank's stored pictures are "
                                    "shown, and a synthesis or an edit that needs the kernels "
                                    "waits for them with the busy bar.")
        self.main.statusBar().insertPermanentWidget(0, self.engine_note)
        self.engine_note.hide()
        self._engine_timer = QtCore.QTimer(self)
        self._engine_timer.setInterval(100)
        self._engine_timer.timeout.connect(self._engine_tick)
        self._engine_since = QtCore.QElapsedTimer()
        self._engine_since.start()
        self._engine_timer.start()

    def _engine_tick(self) -> None:
        if not warmup.ready():
            if self._engine_since.elapsed() >= ENGINE_NOTE_MS:
                self.engine_note.show()
            return
        if self.engine_note.isVisible():
            self.engine_note.hide()
            problem = warmup.error()
            self.main.statusBar().showMessage(
                f"The synthesis engine is ready (prepared in {warmup.seconds() or 0:.0f} s)."
                if problem is None else f"The synthesis kernels could not be prepared ahead "
                f"({problem}); they compile when first used.", 8000)
        if self._to_confirm is None or self.bank is None:
            self._engine_timer.stop()
        elif not self.main.runner.busy:
            self._engine_timer.stop()
            self._confirm(self._to_confirm)

    def _confirm(self, entry_id: int) -> None:
        """Now that the kernels are ready: synthesise the entry shown from its stored picture
        and compare (the picture matched its recorded hash; this checks the recipe too)."""
        self._to_confirm = None
        bank, name = self.bank, self.bank.get(entry_id).name

        def done(same: bool) -> None:
            if not same:
                self.main.show_error(f"“{name}” is not what its recipe synthesises", RuntimeError(
                    f"the stored picture of “{name}” matches its recorded SHA-256, but its log "
                    "synthesises another texture: the bank entry is damaged (⋯ ▸ Verify the "
                    "bank… lists it). Steps replayed from now on use the log's own result."))

        self.main.runner.run(f"Checking “{name}” against its recipe…",
                             lambda progress, cancel: bank.confirm_stored(entry_id, cancel=cancel),
                             done, on_error=lambda exc: self.main.show_error(
                                 f"“{name}” cannot be checked against its recipe", exc))

    def _prepare(self, open_id: int | None) -> None:
        """In the worker: open an entry — from its stored picture when it has one (no kernels
        needed), else by replay — then prepare the pending entries (``_prepare_pending``)."""
        if open_id is None:
            self._prepare_pending()
            return
        bank, name = self.bank, self.bank.get(open_id).name

        def work(progress, cancel):
            history = bank.open_stored(open_id)
            if history is not None:
                return history, True
            return bank.open(open_id, progress=progress, cancel=cancel), False

        def done(result):
            history, stored = result
            self._show_opened(open_id, history, stored=stored)
            if stored:                        # checked by synthesis once the kernels are ready
                self._to_confirm = open_id
                self._engine_timer.start()
            self._prepare_pending()

        def failed(exc):
            self.main.show_error(f"Cannot open “{name}”", exc)
            self._prepare_pending()

        self.main.runner.run(f"Opening “{name}” from the bank…", work, done, on_error=failed)

    def _prepare_pending(self) -> None:
        """In the worker: thumbnails and attributes of the pending entries (the built-ins from
        their stored pictures; others are replayed, which waits for the kernels)."""
        bank = self.bank
        if bank is None or not bank.pending() or self.main.runner.busy:
            return

        def done(failed):
            self.model.forget()
            self.refresh()
            if failed:
                self.status.setText(f"{len(failed)} entries do not replay to their recorded "
                                    "texture (⋯ ▸ Verify the bank… lists them).")

        self.main.runner.run("Preparing the texture bank's thumbnails and attributes…",
                             lambda progress, cancel: bank.prepare_pending(progress=progress,
                                                                           cancel=cancel),
                             done, on_error=lambda exc: self.main.show_error(
                                 "The texture bank cannot be prepared", exc))

    def _set_enabled(self, on: bool) -> None:
        for w in (self.search, self.filter_button, self.menu_button, self.view, self.details,
                  self.open_button, self.like_button, self.duplicate_button, self.delete_button,
                  self.undo_button, self.restore_button):
            w.setEnabled(on)
        self.act_save.setEnabled(True)        # saving opens the bank if needed
        self.open_bank_button.setVisible(not on)
        if on:
            self._update_buttons()

    def _check_elsewhere(self) -> None:
        if self.bank is None or not self.isVisible():
            return
        try:
            changed = self.bank.changed_elsewhere()
        except TexeditorError:
            return
        if changed:
            self.model.forget()
            self.refresh()

    # -- listing ------------------------------------------------------------------------------------
    def refresh(self) -> None:
        """Run the search (text, filters, likeness, trash) and show its entries."""
        if self.bank is None:
            return
        keep = self.selected()
        trash = self.act_trash.isChecked()
        try:
            ids = self.bank.find(self.search.text(), ranges=self.filters.ranges(), like=self.like,
                                 trash=trash)
        except TexeditorError as exc:
            self.status.setText(str(exc))
            return
        self.model.set_ids(self.bank, ids)
        self._describe_listing(len(ids), trash)
        if keep in self.model.rows:
            self.select(keep)
        else:
            self._selected(QtCore.QModelIndex())

    def _describe_listing(self, n: int, trash: bool) -> None:
        where = "in the trash" if trash else "in the bank"
        total = self.bank.count(trash=trash)
        text = f"{n} of {total} entries {where}" if n != total else f"{n} entries {where}"
        if not self.bank.fts and self.search.text().strip():
            text += " — " + self.bank.search_mode
        self.status.setText(text)
        self.search.setToolTip(f"Search: {self.bank.search_mode}. Words match the starts of "
                               "words; tag:x or #x keeps the entries tagged x.")

    def select(self, entry_id: int) -> None:
        row = self.model.rows.get(entry_id)
        if row is not None:
            index = self.model.index(row)
            self.view.setCurrentIndex(index)
            self.view.scrollTo(index)

    def selected(self) -> int | None:
        index = self.view.currentIndex()
        return index.data(IdRole) if index.isValid() else None

    def _selected(self, index, _previous=None) -> None:
        entry = None
        if index.isValid() and self.bank is not None:
            try:
                entry = self.bank.get(index.data(IdRole))
            except TexeditorError:
                entry = None
        self._show_details(entry)
        self._update_buttons()

    def _show_details(self, entry) -> None:
        self.details.setEnabled(entry is not None)
        self.name_edit.setText(entry.name if entry else "")
        self.tags_edit.setText(", ".join(entry.tags) if entry else "")
        self.description_edit.blockSignals(True)
        self.description_edit.setPlainText(entry.description if entry else "")
        self.description_edit.blockSignals(False)
        self.info.setText(_summary(entry) if entry else "No entry selected.")
        self.apply_button.setEnabled(False)
        self.details_area.updateGeometry()     # a scroll area does not pass size changes up

    def _update_buttons(self) -> None:
        chosen = self.selected() is not None
        trash = self.act_trash.isChecked()
        for b in (self.open_button, self.like_button, self.duplicate_button):
            b.setEnabled(chosen)
        self.delete_button.setEnabled(chosen and not trash)
        self.delete_button.setVisible(not trash)
        self.restore_button.setVisible(trash)
        self.restore_button.setEnabled(chosen and trash)
        self.undo_button.setEnabled(bool(self.deleted))
        self.act_export.setEnabled(chosen)

    def _show_filters(self, on: bool) -> None:
        self.filters.setVisible(on)
        self.refresh()

    def _show_trash(self, on: bool) -> None:
        self.setWindowTitle("Texture bank — trash" if on else "Texture bank")
        self.refresh()

    def set_like(self, entry_id: int | None) -> None:
        """Order the bank by likeness to an entry ("more like this"); None: back to normal."""
        if entry_id is not None:
            entry = self.bank.get(entry_id)
            if entry.pending:
                self.status.setText(f"“{entry.name}” has no attributes yet.")
                return
            self.like_label.setText(f"Most like “{entry.name}” first")
        self.like = entry_id
        self.like_bar.setVisible(entry_id is not None)
        self.refresh()
        if entry_id is not None and self.model.ids:
            self.select(self.model.ids[0])

    # -- opening and saving ---------------------------------------------------------------------------
    def open_selected(self) -> None:
        if self.selected() is not None:
            self.open_entry(self.selected())

    def open_entry(self, entry_id: int) -> None:
        """Replay an entry in the worker (its hash checked), then show it on the canvas."""
        win = self.main
        if self.bank is None:
            return
        if win.runner.busy:
            win.statusBar().showMessage("Wait for the current work to end (or cancel it), "
                                        "then open the entry.", 5000)
            return
        if not win.maybe_save():
            return
        bank, name = self.bank, self.bank.get(entry_id).name
        win.runner.run(f"Opening “{name}” from the bank…",
                       lambda progress, cancel: bank.open(entry_id, progress=progress,
                                                          cancel=cancel),
                       lambda history: self._show_opened(entry_id, history),
                       on_cancel=lambda: win.statusBar().showMessage("Opening cancelled.", 5000),
                       on_error=lambda exc: win.show_error(f"Cannot open “{name}”", exc))

    def _show_opened(self, entry_id: int, history, *, stored: bool = False) -> None:
        entry = self.bank.get(entry_id)
        if stored:                            # shown toned before the tone's kernels compile
            self.main.show_stored_tone(history.document.levels, self.bank.stored_tone(entry))
        self.main.set_history(history, name=f"“{entry.name}” from the bank")
        self.opened = (entry_id, history)
        self.select(entry_id)
        n = len(history.actions)
        how = ("shown from its stored picture" if stored
               else f"{counted(n, 'step')} replayed")
        self.main.statusBar().showMessage(
            f"Opened “{entry.name}” from the bank: {how}, SHA-256 verified.", 8000)

    def save_current(self) -> SaveToBankDialog | None:
        """File ▸ Save to bank…: ask for name, tags, description (window-modal), then save."""
        if self.bank is None and not self.load(prepare=False):
            self.main.show_error("No texture bank", RuntimeError(self.status.text()))
            return None
        history = self.main.history
        if history is None or not history.document.levels.size:
            return None
        parent = self._parent_entry()
        entry = self.bank.get(parent) if parent is not None else None
        dialog = SaveToBankDialog(entry.name if entry else "", entry.tags if entry else (),
                                  entry.description if entry else "",
                                  entry.name if entry else None, self.main)
        dialog.accepted.connect(lambda: self._save(
            history, dialog.name.text(), dialog.tags.text(), dialog.description.toPlainText(),
            parent if dialog.version.isChecked() else None))
        dialog.finished.connect(dialog.deleteLater)
        self.save_dialog = dialog
        dialog.open()
        return dialog

    def _parent_entry(self) -> int | None:
        """The entry the current document was opened from, if it is still that document."""
        if self.opened is None or self.opened[1] is not self.main.history:
            return None
        try:
            return self.bank.get(self.opened[0]).id
        except TexeditorError:
            return None                      # deleted for good meanwhile

    def _save(self, history, name, tags, description, parent) -> None:
        win = self.main
        if win.runner.busy:
            win.statusBar().showMessage("Wait for the current work to end, then save.", 5000)
            return
        snapshot = history.document.copy()   # the worker reads a copy; editing may go on
        bank = self.bank

        def done(record):
            try:
                entry_id = bank.insert(record, parent=parent)
            except TexeditorError as exc:
                win.show_error("Cannot save to the bank", exc)
                return
            if history is win.history:
                self.opened = (entry_id, history)
            self.act_trash.setChecked(False)
            self.refresh()
            self.select(entry_id)
            steps = len(record.actions)
            win.statusBar().showMessage(f"Saved “{record.name}” to the bank "
                                        f"({counted(steps, 'step')} after optimising "
                                        f"{len(snapshot.actions)}).", 8000)
            if bank.pending():                 # a bank opened for this save: its built-ins
                self._prepare(None)

        win.runner.run("Saving to the bank…",
                       lambda progress, cancel: make_record(
                           snapshot, name, tags=tags, description=description,
                           progress=progress, cancel=cancel),
                       done, on_error=lambda exc: win.show_error("Cannot save to the bank", exc))

    # -- editing entries ------------------------------------------------------------------------------
    def apply_details(self) -> None:
        entry_id = self.selected()
        if entry_id is None:
            return
        if self._guard("Cannot change the entry", lambda: self.bank.update(
                entry_id, name=self.name_edit.text(), tags=self.tags_edit.text(),
                description=self.description_edit.toPlainText())):
            self.model.forget([entry_id])
            self.refresh()
            self.select(entry_id)

    def duplicate_selected(self) -> None:
        entry_id = self.selected()
        if entry_id is not None:
            new = self._guard("Cannot duplicate", lambda: self.bank.duplicate(entry_id))
            if new:
                self.refresh()
                self.select(new)

    def delete_selected(self) -> None:
        """Move the selected entry to the trash; "Undo delete" (or the trash) brings it back."""
        entry_id = self.selected()
        if entry_id is None or self.act_trash.isChecked():
            return
        row = self.model.rows[entry_id]
        name = self.bank.get(entry_id).name
        if self._guard("Cannot delete", lambda: self.bank.trash(entry_id)) is not None:
            self.deleted.append(entry_id)
            self.refresh()
            if self.model.ids:
                self.select(self.model.ids[min(row, len(self.model.ids) - 1)])
            self.main.statusBar().showMessage(f"Moved “{name}” to the trash (Undo delete "
                                                "brings it back).", 8000)
            self._update_buttons()

    def undo_delete(self) -> None:
        while self.deleted:
            entry_id = self.deleted.pop()
            if self._guard("Cannot restore", lambda: self.bank.restore(entry_id)) is not None:
                self.refresh()
                self.select(entry_id)
                break
        self._update_buttons()

    def restore_selected(self) -> None:
        entry_id = self.selected()
        if entry_id is not None and self._guard("Cannot restore",
                                                lambda: self.bank.restore(entry_id)) is not None:
            if entry_id in self.deleted:
                self.deleted.remove(entry_id)
            self.refresh()

    def empty_trash(self) -> None:
        n = self.bank.count(trash=True)
        if not n:
            return
        answer = QtWidgets.QMessageBox.question(
            self, "Empty the trash", f"Delete the {n} entries in the trash for good?")
        if answer == QtWidgets.QMessageBox.StandardButton.Yes:
            self._guard("Cannot empty the trash", self.bank.purge)
            self.deleted.clear()
            self.refresh()

    def _guard(self, title: str, fn):
        """Run a bank change; an error is a dialog and the bank stays as it was."""
        try:
            result = fn()
        except TexeditorError as exc:
            self.main.show_error(title, exc)
            return None
        return True if result is None else result

    # -- files and checks -----------------------------------------------------------------------------
    def import_file(self, path=None) -> None:
        if path is None:
            path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Import a texture into the bank",
                                                            str(Path.home()), TEXTURE_FILTER)
            if not path:
                return
        win, bank, path = self.main, self.bank, Path(path)
        if win.runner.busy:
            return

        def done(entry_id):
            self.refresh()
            self.select(entry_id)
            win.statusBar().showMessage(f"Imported {path.name} into the bank.", 8000)

        win.runner.run(f"Importing {path.name}…",
                       lambda progress, cancel: bank.import_texture(path, progress=progress,
                                                                    cancel=cancel),
                       done, on_error=lambda exc: win.show_error(f"Cannot import {path.name}",
                                                                 exc))

    def export_selected(self, path=None) -> None:
        entry_id = self.selected()
        if entry_id is None or self.main.runner.busy:
            return
        name = self.bank.get(entry_id).name
        if path is None:
            start = str(Path.home() / f"{name}.texture")
            path, _ = QtWidgets.QFileDialog.getSaveFileName(self, "Export the entry", start,
                                                            TEXTURE_FILTER)
            if not path:
                return
        win, bank, path = self.main, self.bank, Path(path)
        win.runner.run(f"Exporting “{name}”…",
                       lambda progress, cancel: bank.export_texture(entry_id, path,
                                                                    progress=progress,
                                                                    cancel=cancel),
                       lambda _r: win.statusBar().showMessage(f"Exported “{name}” to {path}.",
                                                              8000),
                       on_error=lambda exc: win.show_error("Cannot export", exc))

    def verify(self) -> None:
        """Replay every entry in the worker and report the ones that do not match."""
        win, bank = self.main, self.bank
        if win.runner.busy:
            return

        def done(checks):
            bad = [c for c in checks if not c.ok]
            self.verify_report = bad
            text = (f"All {len(checks) - 1} entries replay to their recorded SHA-256; the "
                    "database is sound." if not bad else
                    f"{len(bad)} of {len(checks) - 1} entries do not replay to their recorded "
                    "texture:\n\n" + "\n".join(c.message for c in bad[:12]))
            if win.headless:
                win.statusBar().showMessage(text.splitlines()[0], 8000)
            elif bad:
                QtWidgets.QMessageBox.warning(win, "Verify the bank", text)
            else:
                QtWidgets.QMessageBox.information(win, "Verify the bank", text)

        win.runner.run("Verifying the bank…",
                       lambda progress, cancel: bank.verify(progress=progress, cancel=cancel),
                       done, on_error=lambda exc: win.show_error("Cannot verify the bank", exc))


class _FitArea(QtWidgets.QScrollArea):
    """A scroll area that asks for its content's full height (Qt's asks for less)."""

    def sizeHint(self) -> QtCore.QSize:
        return self.widget().sizeHint() + QtCore.QSize(0, 2)


def _summary(entry) -> str:
    """Size, steps and attributes of an entry, in short lines."""
    kind = " · built-in" if entry.builtin else ""
    steps = counted(entry.actions, "step")
    head = f"{entry.width}×{entry.height}, G = {entry.levels}, {steps}{kind}"
    a = entry.attributes
    if a is None:
        return head + "\nAttributes not computed yet."
    direction = (f"oriented {a.orientation:.0f}° ({a.directivity:.2f})" if a.directivity >= 0.2
                 else f"isotropic ({a.directivity:.2f})")
    regular = f"period {a.period:.0f} ({a.regularity:.2f})" if a.period else \
        f"irregular ({a.regularity:.2f})"
    lines = [head, f"contrast {a.contrast:.2f} · density {a.density:.2f}",
             f"regions of {a.granularity:.0f} points · coarseness {a.coarseness:.1f}",
             f"{direction} · {regular}"]
    g = entry.grain.get("render_grains")
    if g:
        across = g.get("compression_x")
        squeeze = f"{g.get('compression', 0):g}" + (
            "" if across is None else f" down, {across:g} across")
        lines.append(f"grains: {g.get('shape')} {g.get('size')} px, explosion "
                     f"{g.get('explosion_x', 1):g}×{g.get('explosion_y', 1):g}, compression "
                     f"{squeeze}")
    return "\n".join(lines)
