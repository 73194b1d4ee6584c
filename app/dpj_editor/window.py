"""The DPJ editor window (thesis §5.2.2): enter a DPJ by hand with a probability palette, check it,
generate or reshape it, preview it live, and hand it to the main window.

The edited DPJ is not the document: it changes through a QUndoStack of DPJ edits here, and only
"Use this DPJ" makes it the main window's current DPJ (History.add_dpj), ready to synthesise.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shiboken6
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.markov import dpj_edit
from texeditor.markov.dpj import DPJ, MAX_LEVELS, MAX_SIDE, check_window, decode
from texeditor.markov.multiscale import scales_phrase
from texeditor.errors import TexeditorError
from texeditor.photo import load_model

from ..synthesis_worker import TaskRunner
from ..widgets import fit_to_screen, scrolled
from .charts import ChartsPanel
from .checks import ChecksPanel
from .generators import IN_BACKGROUND, GeneratorsPanel
from .painter import PainterPanel
from .preview import LatestWins, PreviewPanel
from .table import ConfigTable, config_text

DPJ_FILTER = "DPJ files (*.dpj);;All files (*)"
HAND_META = {"name": "hand-made", "source": "hand"}
BACKGROUND_CHECKS = 50_000      # entries above which the checks are computed off the GUI thread


def analyse(dpj: DPJ):
    """The numbers behind the checks: the DPJ's report and each entry's role in the chain."""
    return dpj.report(), dpj_edit.chain_roles(dpj)


def hand_made(window=(2, 2), levels: int = 3) -> DPJ:
    """The start of hand entry: the window and G chosen, every probability 0 (§5.2.2)."""
    return DPJ.empty(window, levels, meta=dict(HAND_META))


class DPJEdit(QtGui.QUndoCommand):
    """One edit of the DPJ: the DPJs before and after (immutable, so cheap to keep)."""

    def __init__(self, editor, before: DPJ, after: DPJ, text: str, merge_id: int = -1):
        super().__init__(text)
        self.editor, self.before, self.after, self.merge_id = editor, before, after, merge_id

    def id(self) -> int:
        return self.merge_id

    def mergeWith(self, other) -> bool:
        if self.merge_id < 0 or other.id() != self.merge_id:
            return False
        self.after = other.after
        self.setText(other.text())
        return True

    def redo(self) -> None:
        self.editor._show(self.after)

    def undo(self) -> None:
        self.editor._show(self.before)


class NewDPJDialog(QtWidgets.QDialog):
    """The window (u columns × v rows) and G come first; every probability starts at 0."""

    def __init__(self, window=(2, 2), levels: int = 3, parent=None):
        super().__init__(parent)
        self.setWindowTitle("New DPJ")
        self.u, self.v, self.levels = (self._spin(lo, hi, value) for lo, hi, value in
                                       ((1, MAX_SIDE, window[0]), (1, MAX_SIDE, window[1]),
                                        (2, MAX_LEVELS, levels)))
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)
        form = QtWidgets.QFormLayout(self)
        form.addRow("Window columns u", self.u)
        form.addRow("Window rows v", self.v)
        form.addRow("Levels G", self.levels)
        form.addRow(self.info)
        ok_cancel = (QtWidgets.QDialogButtonBox.StandardButton.Ok
                     | QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        self.buttons = QtWidgets.QDialogButtonBox(ok_cancel)
        self.buttons.accepted.connect(self.accept)
        self.buttons.rejected.connect(self.reject)
        form.addRow(self.buttons)
        self._explain()

    def _spin(self, lo, hi, value) -> QtWidgets.QSpinBox:
        box = QtWidgets.QSpinBox()
        box.setRange(lo, hi)
        box.setValue(value)
        box.valueChanged.connect(self._explain)
        return box

    def _explain(self) -> None:
        """Say how many configurations the window has; OK only for one a DPJ can index."""
        u, v, g = self.values()
        ok = self.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
        try:
            check_window((u, v), g)
        except TexeditorError as exc:
            self.info.setText(f"<span style='color:#b00020'>{exc}.</span>")
            ok.setEnabled(False)
            return
        ok.setEnabled(True)
        self.info.setText(f"{g}<sup>{u * v}</sup> = {g ** (u * v):,} possible configurations; "
                          "every probability starts at 0. A 2×2 window with 3 levels already "
                          "gives rich textures (§5.2.2).")

    def values(self) -> tuple[int, int, int]:
        return self.u.value(), self.v.value(), self.levels.value()


class DPJEditor(QtWidgets.QMainWindow):
    """Signals: ``used(dpj)`` for "Use this DPJ", ``synthesiseRequested(dpj)`` for a full
    synthesis in the main window."""

    used = QtCore.Signal(object)
    synthesiseRequested = QtCore.Signal(object)

    def __init__(self, parent=None, dpj: DPJ | None = None):
        super().__init__(parent)
        self.setWindowFlag(QtCore.Qt.WindowType.Window, True)
        self.setObjectName("DPJEditor")
        fit_to_screen(self, 1400, 900)      # a 1280×800 laptop gets the whole editor on screen
        self.headless = False
        self.path: Path | None = None
        self.dpj = dpj if dpj is not None else hand_made()
        self.undo_stack = QtGui.QUndoStack(self)
        self.runner = TaskRunner(self)

        self.table = ConfigTable()
        self.setCentralWidget(self.table)
        self.painter = PainterPanel()
        self.generators = GeneratorsPanel()
        self.checks = ChecksPanel()
        self.preview = PreviewPanel()
        self.charts = ChartsPanel()
        self.charts.setMinimumHeight(180)
        left, right = (QtCore.Qt.DockWidgetArea.LeftDockWidgetArea,
                       QtCore.Qt.DockWidgetArea.RightDockWidgetArea)
        self.docks = {}
        for title, widget, area, scroll in (
                ("Configuration painter", self.painter, left, False),
                ("Generators", self.generators, left, True),
                ("Checks", self.checks, right, True),         # scrolled: the column fits 800 px
                ("Live preview", self.preview, right, True),
                ("Charts", self.charts, right, False)):
            dock = QtWidgets.QDockWidget(title, self)
            dock.setObjectName(title.replace(" ", ""))
            dock.setWidget(scrolled(widget) if scroll else widget)
            dock.setFeatures(QtWidgets.QDockWidget.DockWidgetFeature.DockWidgetMovable
                             | QtWidgets.QDockWidget.DockWidgetFeature.DockWidgetFloatable)
            self.addDockWidget(area, dock)
            self.docks[title] = dock
        self.charts_tabbed = self.height() < 880
        if self.charts_tabbed:      # a short screen: the charts are a tab beside the preview
            self.tabifyDockWidget(self.docks["Live preview"], self.docks["Charts"])
            self.docks["Live preview"].raise_()
        side = max(self.painter.sizeHint().width(), self.generators.sizeHint().width()) + 24
        for title in ("Configuration painter", "Generators"):
            self.docks[title].setMinimumWidth(side)      # the generators never scroll sideways
        self._build_actions()
        self._build_status()
        self._connect()
        self._docks_sized = False
        self.report, self.unreachable = None, 0
        self.analysis = LatestWins(self, delay_ms=0)
        self.analysis.done.connect(lambda out: self._checked(*out))
        self.analysis.failed.connect(lambda exc: self.show_error("Cannot check this DPJ", exc,
                                                                 modal=False))
        self._show(self.dpj)
        self.undo_stack.setClean()

    # -- construction ------------------------------------------------------------------------------
    def _action(self, text, slot, shortcut=None, tip=None) -> QtGui.QAction:
        action = QtGui.QAction(text, self)
        if shortcut is not None:
            action.setShortcut(QtGui.QKeySequence(shortcut))
        if tip:
            action.setToolTip(tip)
            action.setStatusTip(tip)
        action.triggered.connect(slot)
        self.addAction(action)
        return action

    def _build_actions(self) -> None:
        K = QtGui.QKeySequence.StandardKey
        a = self._action
        self.act_new = a("&New DPJ…", self.new_dpj, K.New, "Choose the window and G; every "
                         "probability starts at 0")
        self.act_open = a("&Open…", lambda: self.open_file(), K.Open, "Open a .dpj file")
        self.act_save = a("&Save", self.save, K.Save, "Save the DPJ as a .dpj file")
        self.act_save_as = a("Save &As…", self.save_as, K.SaveAs)
        self.act_undo = a("&Undo", self.undo_stack.undo, "Ctrl+Z")
        self.act_redo = a("&Redo", self.undo_stack.redo, "Ctrl+Shift+Z")
        self.act_redo.setShortcuts([QtGui.QKeySequence("Ctrl+Shift+Z"),
                                    QtGui.QKeySequence("Ctrl+Y")])
        for act, can, text in ((self.act_undo, self.undo_stack.canUndoChanged,
                                self.undo_stack.undoTextChanged),
                               (self.act_redo, self.undo_stack.canRedoChanged,
                                self.undo_stack.redoTextChanged)):
            act.setEnabled(False)
            can.connect(act.setEnabled)
            text.connect(lambda t, act=act: act.setToolTip(f"{act.text().strip('&')}: {t}"))
        self.act_use = a("&Use this DPJ", self.use, "Ctrl+Return",
                         "Make it the main window's current DPJ")
        self.act_close = a("&Close", self.close, K.Close)
        menu = self.menuBar().addMenu("&File")
        menu.setObjectName("FileMenu")
        menu.addActions([self.act_new, self.act_open, self.act_save, self.act_save_as])
        menu.addSeparator()
        menu.addActions([self.act_use, self.act_close])
        menu = self.menuBar().addMenu("&Edit")
        menu.setObjectName("EditMenu")
        menu.addActions([self.act_undo, self.act_redo])
        menu = self.menuBar().addMenu("&View")
        menu.setObjectName("ViewMenu")
        for dock in self.docks.values():
            menu.addAction(dock.toggleViewAction())
        bar = self.addToolBar("DPJ")
        bar.setObjectName("DPJToolBar")
        bar.setToolButtonStyle(QtCore.Qt.ToolButtonStyle.ToolButtonTextOnly)
        bar.addActions([self.act_new, self.act_open, self.act_save])
        bar.addSeparator()
        bar.addActions([self.act_undo, self.act_redo])
        bar.addSeparator()
        bar.addAction(self.act_use)

    def _build_status(self) -> None:
        bar = self.statusBar()
        self.task_label = QtWidgets.QLabel()
        self.progress = QtWidgets.QProgressBar()
        self.progress.setRange(0, 0)
        self.progress.setFixedWidth(120)
        self.cancel_button = QtWidgets.QToolButton(text="Cancel")
        self.cancel_button.clicked.connect(self.runner.cancel)
        for w in (self.task_label, self.progress, self.cancel_button):
            bar.addPermanentWidget(w)
            w.hide()
        self.runner.started.connect(lambda label: self._busy(True, label))
        self.runner.finished.connect(lambda: self._busy(False, ""))

    def _busy(self, busy: bool, label: str) -> None:
        self.task_label.setText(label)
        for w in (self.task_label, self.progress, self.cancel_button):
            w.setVisible(busy)
        for b in (self.generators.generate_button, self.generators.merge_button):
            b.setEnabled(not busy)
        if busy:
            self.checks.stationarity.button.setEnabled(False)
            self.checks.chain.button.setEnabled(False)
        else:
            self._show_checks()

    def _connect(self) -> None:
        p = self.painter
        p.setRequested.connect(self._set_painted)
        p.removeRequested.connect(lambda config: self.apply(
            lambda d: dpj_edit.set_entry(d, config, 0.0), f"Remove {config_text(config)}"))
        t = self.table
        t.entryActivated.connect(p.load)
        t.deleteRequested.connect(self.delete)
        t.probabilityEdited.connect(self._set_code)
        c = self.checks
        c.normaliseRequested.connect(lambda: self.apply(dpj_edit.normalize, "Normalise"))
        c.stationaryRequested.connect(lambda: self.run_long(
            dpj_edit.make_stationary, "Make stationary", cancellable=True))
        c.restrictRequested.connect(lambda: self.run_long(dpj_edit.restrict, "Restrict"))
        g = self.generators
        g.edited.connect(self._generated)
        self.preview.seed.changed.connect(lambda: self.preview.request(self.dpj))
        self.preview.use_button.clicked.connect(self.use)
        self.preview.full_button.clicked.connect(self.synthesise_full)
        self.undo_stack.cleanChanged.connect(lambda _clean: self._update_title())

    def showEvent(self, ev) -> None:
        super().showEvent(ev)
        if not self._docks_sized:
            self._docks_sized = True
            QtCore.QTimer.singleShot(0, self, self._size_docks)     # once the layout has settled

    def _size_docks(self) -> None:
        """Painter, checks and preview at their natural height; generators and charts the rest."""
        right = ("Checks", "Live preview") if self.charts_tabbed else (
            "Checks", "Live preview", "Charts")
        for column in (("Configuration painter", "Generators"), right):
            docks = [self.docks[t] for t in column]
            natural = [d.widget().sizeHint().height() + d.height() - d.widget().height()
                       for d in docks[:-1]]
            rest = max(200, sum(d.height() for d in docks) - sum(natural))
            self.resizeDocks(docks, natural + [rest], QtCore.Qt.Orientation.Vertical)
        # the checks read on one line each; the table's columns need less than its share
        checks = self.docks["Checks"]
        want = min(self.checks.sizeHint().width() + 40, self.width() // 3)
        if checks.width() < want:
            self.resizeDocks([checks], [want], QtCore.Qt.Orientation.Horizontal)

    # -- edits -------------------------------------------------------------------------------------
    def edit(self, new: DPJ, text: str, merge_id: int = -1) -> None:
        """Make ``new`` the edited DPJ as one undoable step (merged with the previous one when
        they share a non-negative ``merge_id``: one slider drag, one step)."""
        if new is self.dpj or (new == self.dpj and new.meta == self.dpj.meta):
            return
        self.undo_stack.push(DPJEdit(self, self.dpj, new, text, merge_id))

    def apply(self, function, text: str, merge_id: int = -1) -> bool:
        """Apply ``function(dpj) -> dpj``; a refusal is explained and changes nothing."""
        try:
            new = function(self.dpj)
        except TexeditorError as exc:
            self.show_error(f"{text}: not possible", exc, modal=merge_id < 0)
            return False
        self.edit(new, text, merge_id)
        return True

    def run_long(self, function, text: str, cancellable: bool = False) -> None:
        """Apply ``function(dpj)`` in the background (large DPJs), with Cancel (passed on as
        ``cancel=`` when ``cancellable``; otherwise the result is dropped); the result is also
        dropped if the DPJ changed meanwhile."""
        if self.runner.busy:
            self.statusBar().showMessage("Busy: wait for the current work or cancel it.", 5000)
            return
        start = self.dpj

        def done(new):
            if self.dpj is not start:
                self.statusBar().showMessage(f"{text}: the DPJ changed meanwhile; run it again.",
                                             8000)
                return
            self.edit(new, text)

        def work(progress, cancel):
            return function(start, cancel=cancel) if cancellable else function(start)

        self.runner.run(f"{text}…", work, done,
                        on_cancel=lambda: self.statusBar().showMessage(f"{text} cancelled.", 5000),
                        on_error=lambda exc: self.show_error(f"{text}: not possible", exc))

    def start(self, dpj: DPJ, text: str, path: Path | None = None) -> None:
        """Replace the edited DPJ (a new one, a file, the main window's): undoable too."""
        self.path = path
        self.edit(dpj, text)
        self.undo_stack.setClean()
        self._update_title()

    def _set_painted(self, config, p: float) -> None:
        verb = "Remove" if p == 0 else "Set"
        self.apply(lambda d: dpj_edit.set_entry(d, config, p),
                   f"{verb} {config_text(config)}" + (f" to {p:.6g}" if p else ""))

    def _set_code(self, code: int, p: float) -> None:
        u, v = self.dpj.window
        config = decode([code], self.dpj.levels, v, u)[0]
        self._set_painted(config, p)

    def delete(self, codes) -> None:
        n = len(codes)
        self.apply(lambda d: dpj_edit.remove_entries(d, codes),
                   f"Delete {n:,} configuration{'s' if n != 1 else ''}")

    def _generated(self, function, text: str, gesture: int) -> None:
        if gesture == IN_BACKGROUND:
            self.run_long(function, text)
        else:
            self.apply(function, text, gesture)

    # -- showing a DPJ -----------------------------------------------------------------------------
    def _show(self, dpj: DPJ) -> None:
        """Every panel follows the DPJ (called by the undo commands). The checks of a large DPJ
        are computed in the background, so an edit never waits for them."""
        self.dpj = dpj
        background = len(dpj) > BACKGROUND_CHECKS
        checked = None if background else analyse(dpj)
        self.table.set_dpj(dpj, np.zeros(len(dpj), np.int8) if background else checked[1])
        self.painter.set_dpj(dpj)
        self.generators.set_dpj(dpj)
        self.charts.set_dpj(dpj)
        self.preview.request(dpj)
        if background:
            self.report = None
            self.checks.show_pending()
            self._enable_use(False)
            self.analysis.request(lambda progress, cancel: (dpj, *analyse(dpj)))
        else:
            self._checked(dpj, *checked)
        self._update_title()

    def _checked(self, dpj: DPJ, report, roles: np.ndarray) -> None:
        """Show the checks of ``dpj`` (dropped if the DPJ changed meanwhile)."""
        if dpj is not self.dpj:
            return
        if self.report is None:
            self.table.model.set_roles(roles)
        self.report, self.unreachable = report, int(np.count_nonzero(roles != dpj_edit.MAIN))
        self._show_checks()

    def _show_checks(self) -> None:
        if self.report is None:
            return
        self.checks.show_report(self.report, self.unreachable)
        self._enable_use(self.report.is_valid)

    def _enable_use(self, valid: bool) -> None:
        for w in (self.act_use, self.preview.use_button, self.preview.full_button):
            w.setEnabled(valid)

    def checked_report(self):
        """The report of the current DPJ, computed now if the background has not finished."""
        if self.report is None:
            self._checked(self.dpj, *analyse(self.dpj))
        return self.report

    def _update_title(self) -> None:
        if not shiboken6.isValid(self.undo_stack):
            return                  # the window is being destroyed (its stack goes first)
        u, v = self.dpj.window
        name = self.path.name if self.path is not None else self.dpj.meta.get("name", "DPJ")
        star = "" if self.undo_stack.isClean() else "*"
        self.setWindowTitle(f"{name}{star} ({u}×{v}, G = {self.dpj.levels}, {len(self.dpj):,} "
                            "configurations) — DPJ editor")

    # -- files and the main window -----------------------------------------------------------------
    def new_dpj(self) -> NewDPJDialog:
        """Ask for the window and G (window-modal, no nested event loop), then start afresh."""
        dialog = NewDPJDialog(self.dpj.window, self.dpj.levels, self)
        dialog.accepted.connect(lambda: self._new_from(dialog))
        dialog.finished.connect(dialog.deleteLater)
        self.new_dialog = dialog
        dialog.open()
        return dialog

    def _new_from(self, dialog: NewDPJDialog) -> None:
        u, v, g = dialog.values()
        try:
            dpj = hand_made((u, v), g)
        except TexeditorError as exc:
            self.show_error("Cannot make this DPJ", exc)
            return
        self.start(dpj, f"New DPJ {u}×{v}, G = {g}")
        self.painter.grid.set_config(np.zeros((v, u), np.uint8))

    def open_file(self, path=None) -> bool:
        if path is None:
            path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Open a DPJ", "", DPJ_FILTER)
            if not path:
                return False
        path = Path(path)
        try:
            dpj = load_model(path)
        except TexeditorError as exc:
            self.show_error(f"Cannot open {path.name}", exc)
            return False
        if not isinstance(dpj, DPJ):
            self.show_error(f"Cannot open {path.name}", f"{path.name} is a photo model of "
                            f"{scales_phrase(dpj.scales.scales)}: open it with the main "
                            "window's File ▸ Open DPJ or photo model…, which adds each "
                            "scale's DPJ to the texture; Edit DPJ then opens the current one "
                            "here.")
            return False
        dpj = DPJ(dpj.configs, dpj.probs, dpj.levels, palette=dpj.palette,
                  meta={"name": path.stem, **dpj.meta})
        self.start(dpj, f"Open {path.name}", path)
        return True

    def save(self) -> bool:
        return self.save_to(self.path) if self.path is not None else self.save_as()

    def save_as(self) -> bool:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, "Save the DPJ", "", DPJ_FILTER)
        if not path:
            return False
        path = Path(path)
        return self.save_to(path if path.suffix else path.with_suffix(".dpj"))

    def save_to(self, path) -> bool:
        """Write atomically (DPJ.save); a failure is a dialog and the DPJ stays as it is."""
        path = Path(path)
        try:
            self.dpj.save(path)
        except (TexeditorError, OSError) as exc:
            self.show_error(f"Cannot save {path.name}", exc)
            return False
        self.path = path
        self.undo_stack.setClean()
        self._update_title()
        self.statusBar().showMessage(f"Saved {path}", 5000)
        return True

    def use(self) -> bool:
        """Hand the DPJ to the main window (it becomes the current DPJ) when it is valid."""
        if not self.checked_report().is_valid:
            self.show_error("This DPJ cannot be used yet", "Probabilities in [0, 1] summing to 1 "
                            "are needed: see the checks (Normalise).")
            return False
        self.used.emit(self.named())
        return True

    def synthesise_full(self) -> None:
        if self.use():
            self.synthesiseRequested.emit(self.named())

    def named(self) -> DPJ:
        """The DPJ with a name for the main window's Synthesis dock."""
        if "name" in self.dpj.meta:
            return self.dpj
        name = self.path.stem if self.path is not None else HAND_META["name"]
        return DPJ(self.dpj.configs, self.dpj.probs, self.dpj.levels, palette=self.dpj.palette,
                   meta={**self.dpj.meta, "name": name})

    def show_error(self, title: str, exc, modal: bool = True) -> None:
        self.statusBar().showMessage(f"{title}: {exc}", 8000)
        if modal and not self.headless:
            QtWidgets.QMessageBox.critical(self, title, str(exc))

    def maybe_save(self) -> bool:
        """True when the edited DPJ may be dropped (saved, discarded, or unchanged): asked as the
        main window asks for its texture, with this editor in view. Headless never asks."""
        if self.undo_stack.isClean() or self.headless:
            return True
        self.show()
        self.raise_()
        name = self.path.name if self.path is not None else self.dpj.meta.get("name", "DPJ")
        buttons = QtWidgets.QMessageBox.StandardButton
        answer = QtWidgets.QMessageBox.question(
            self, "Unsaved DPJ", f"The DPJ “{name}” in the DPJ editor has changes that are not "
            "saved. Save them first?", buttons.Save | buttons.Discard | buttons.Cancel,
            buttons.Save)
        if answer == buttons.Save:
            return self.save()
        return answer == buttons.Discard

    def closeEvent(self, ev) -> None:
        self.preview.preview.timer.stop()    # the window is only hidden: it keeps its DPJ
        super().closeEvent(ev)

    def stop(self) -> None:
        """Stop the background work (before the window is destroyed)."""
        self.runner.cancel()
        self.analysis.stop()
        self.preview.preview.stop()


def open_editor(window, *, new: bool = False) -> DPJEditor:
    """File ▸ New DPJ… / Edit DPJ… of the main window: the one editor window, shown."""
    editor = getattr(window, "dpj_editor", None)
    if editor is None:
        editor = DPJEditor(window)
        editor.headless = window.headless
        editor.used.connect(lambda dpj: use_in_main_window(window, dpj, editor))
        editor.synthesiseRequested.connect(lambda _dpj: window.synthesise_from_dock())
        window.dpj_editor = editor
    editor.show()
    editor.raise_()
    editor.activateWindow()
    current = window.document.dpj if window.history is not None else None
    if new:
        editor.new_dpj()
    elif current is not None and current is not editor.dpj:
        editor.start(current, "Edit the current DPJ")
    return editor


def confirm_close(window) -> bool:
    """Before the main window closes: every DPJ editor of it with unsaved changes asks Save /
    Discard / Cancel (open or only hidden, its DPJ would be lost); False keeps everything open."""
    return all(editor.maybe_save() for editor in window.findChildren(DPJEditor))


def use_in_main_window(window, dpj: DPJ, editor: DPJEditor | None = None) -> None:
    if window.edits_locked():               # the editor keeps its DPJ: "Use" again later
        if editor is not None:
            editor.statusBar().showMessage("The main window is replaying its history: use this "
                                           "DPJ again when it has finished.", 8000)
        return
    k = window.use_edited_scale(dpj)
    window.history.add_dpj(dpj)
    u, v = dpj.window
    if k is not None:
        window.statusBar().showMessage(f"The edited scale {k + 1} of the photo model is now in "
                                       "its place: Synthesise draws every scale, and the tone, "
                                       "with it.", 10000)
        return
    window.statusBar().showMessage(f"The hand-made {u}×{v} DPJ with G = {dpj.levels} is now the "
                                   f"current DPJ: {len(dpj):,} configurations.", 10000)
