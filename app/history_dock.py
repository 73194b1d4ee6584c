"""The history dock: the action log as a list (the texture's recipe), and an editor for a past step.

Clicking a step goes there (undo/redo many at once); "Apply & replay" replaces the selected step
with edited parameters and replays the later ones — non-destructive history (DESIGN.md);
"Optimise log…" shows what the log optimiser would drop, move and merge (thesis §5.4.2) and
replaces the log by its shorter one. The main window runs those replays in the worker.
"""

from __future__ import annotations

from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.recipe.actions import replace_params
from texeditor.recipe.logopt import optimize_with_notes
from texeditor.errors import TexeditorError

from .params_form import ParamsForm


class LogModel(QtCore.QAbstractListModel):
    """One row per action of a History; rows at or after ``index`` are the redo tail (greyed)."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.history = None

    def set_history(self, history) -> None:
        self.beginResetModel()
        self.history = history
        self.endResetModel()

    def refresh(self) -> None:
        self.beginResetModel()
        self.endResetModel()

    def rowCount(self, parent=QtCore.QModelIndex()) -> int:
        return 0 if self.history is None or parent.isValid() else len(self.history.actions)

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if self.history is None or not index.isValid():
            return None
        row = index.row()
        action = self.history.actions[row]
        applied = row < self.history.index
        moved = row in self.history.retargeted
        if role == QtCore.Qt.ItemDataRole.DisplayRole:
            return f"{'⚠ ' if moved else ''}{row + 1}. {action.label()}"
        if role == QtCore.Qt.ItemDataRole.ForegroundRole and not applied:
            return QtGui.QBrush(QtGui.QColor(140, 140, 140))
        if role == QtCore.Qt.ItemDataRole.FontRole:
            font = QtGui.QFont()
            font.setItalic(not applied)
            font.setBold(row == self.history.index - 1)
            return font
        if role == QtCore.Qt.ItemDataRole.SizeHintRole:     # as wide as the list (elided)
            bold = QtGui.QFont()
            bold.setBold(True)
            return QtCore.QSize(1, QtGui.QFontMetrics(bold).height() + 2)
        if role == QtCore.Qt.ItemDataRole.ToolTipRole:
            state = "current state" if row == self.history.index - 1 else (
                "applied" if applied else "undone: click to redo up to here")
            note = ("\nThe edit of an earlier step changed the region this step acts on: it now "
                    "fills or moves other points than before." if moved else "")
            return f"{action.label()} ({state}){note}"
        return None


MIN_ROWS = 8          # the list keeps this many steps in view however tall the step's form is


class OptimiseDialog(QtWidgets.QDialog):
    """What the log optimiser would do to the applied steps, note by note, before it is done:
    Optimise accepts (``optimised`` is the shorter log), Cancel leaves the log as it is."""

    def __init__(self, history, parent=None):
        super().__init__(parent)
        self.setWindowTitle("Optimise the log")
        applied = history.applied
        result = optimize_with_notes(applied, dict(history.document.dpjs))
        self.optimised = result.actions
        undone = len(history.actions) - history.index
        if result.notes:
            text = (f"The {len(applied)} steps become {len(result.actions)}, with the same "
                    f"texture (thesis §5.4.2: the log simplified and reorganised):")
            if undone:
                text += f" the {undone} undone step(s) after the current one go."
        else:
            text = "Nothing to do: the optimiser cannot make this log shorter."
        self.summary = QtWidgets.QLabel(text)
        self.summary.setWordWrap(True)
        self.notes = QtWidgets.QListWidget()
        self.notes.setWordWrap(True)
        self.notes.setSpacing(3)
        self.notes.setAlternatingRowColors(True)
        self.notes.setSelectionMode(QtWidgets.QAbstractItemView.SelectionMode.NoSelection)
        self.notes.setFocusPolicy(QtCore.Qt.FocusPolicy.NoFocus)
        self.notes.addItems([note[:1].upper() + note[1:] for note in result.notes])
        self.notes.setVisible(bool(result.notes))
        buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        self.optimise_button = buttons.addButton(
            "Optimise", QtWidgets.QDialogButtonBox.ButtonRole.AcceptRole)
        self.optimise_button.setEnabled(bool(result.notes))
        self.optimise_button.setToolTip("Replace the log by the shorter one (Ctrl+Z undoes it)")
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addWidget(self.summary)
        layout.addWidget(self.notes, 1)
        layout.addWidget(buttons)
        self.resize(560, 360 if result.notes else 120)


class HistoryDock(QtWidgets.QDockWidget):
    """Signals: ``stepClicked(steps)`` to go to the state after ``steps`` actions;
    ``editRequested(i, action)`` to replace step i (0-based) and replay;
    ``optimiseRequested(actions)`` to replace the applied steps by the optimised log."""

    stepClicked = QtCore.Signal(int)
    editRequested = QtCore.Signal(int, object)
    optimiseRequested = QtCore.Signal(object)
    TITLE_WIDTH = 280          # pixels of the selected step's title, at most

    def __init__(self, parent=None):
        super().__init__("History", parent)
        self.setObjectName("HistoryDock")
        self.history = None
        self.model = LogModel(self)
        self.view = QtWidgets.QListView()
        self.view.setModel(self.model)
        self.view.setEditTriggers(QtWidgets.QAbstractItemView.EditTrigger.NoEditTriggers)
        self.view.clicked.connect(self._clicked)
        self.view.setUniformItemSizes(True)
        self.view.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.view.setResizeMode(QtWidgets.QListView.ResizeMode.Adjust)   # a long step is
        #   elided to the list's width (its tooltip says it all), not scrolled sideways

        self.group = QtWidgets.QGroupBox("Selected step")
        box = QtWidgets.QVBoxLayout(self.group)
        self.form = ParamsForm()
        self.form.changed.connect(self._form_changed)
        # a step with many parameters scrolls down, never sideways, and never takes the list's rows
        self.form_area = QtWidgets.QScrollArea()
        self.form_area.setWidget(self.form)
        self.form_area.setWidgetResizable(True)
        self.form_area.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
        self.form_area.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.form_area.setMinimumHeight(60)
        box.addWidget(self.form_area, 1)
        self.apply_button = QtWidgets.QPushButton("Apply && replay")
        self.apply_button.setToolTip("Replace this step with the edited parameters and replay "
                                     "the steps after it")
        self.apply_button.clicked.connect(self._apply_edit)
        self.revert_button = QtWidgets.QPushButton("Revert")
        self.revert_button.clicked.connect(self._show_selected)
        self.view.setToolTip("Click a step to go back to it; edit its parameters below")

        self.optimise_button = QtWidgets.QPushButton("Optimise log…")
        self.optimise_button.setToolTip("Drop, move and merge steps for a shorter log with the "
                                        "same texture; shows what it would do first")
        self.optimise_button.clicked.connect(self.optimise)
        self.optimise_dialog: OptimiseDialog | None = None

        body = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(body)
        layout.setContentsMargins(4, 4, 4, 4)
        rows = self.view.fontMetrics().lineSpacing() + 2
        self.view.setMinimumHeight(MIN_ROWS * rows + 2 * self.view.frameWidth())
        splitter = QtWidgets.QSplitter(QtCore.Qt.Orientation.Vertical)   # the user sets the share
        splitter.setChildrenCollapsible(False)
        splitter.addWidget(self.view)
        splitter.addWidget(self.group)
        splitter.setStretchFactor(0, 1)     # the list keeps its rows; the form shows its fields
        splitter.setStretchFactor(1, 2)
        layout.addWidget(splitter)
        buttons = QtWidgets.QHBoxLayout()   # one row at the foot, as GIMP's and Krita's undo
        buttons.addWidget(self.optimise_button)     # history docks (a row of its own above the
        buttons.addStretch(1)                       # list left the docks short at 1280×800)
        buttons.addWidget(self.revert_button)
        buttons.addWidget(self.apply_button)
        layout.addLayout(buttons)
        self.setWidget(body)
        self.selected_step: int | None = None
        self._update_buttons()

    def set_history(self, history) -> None:
        self.history = history
        self.model.set_history(history)
        self.selected_step = None
        self.refresh()

    def refresh(self) -> None:
        """Re-read the log (after any change); keep the selected step's form if it still exists."""
        self.model.refresh()
        self.optimise_button.setEnabled(self.history is not None and self.history.index > 0)
        if self.history is None:
            return
        if self.selected_step is not None and self.selected_step >= len(self.history.actions):
            self.selected_step = None
        current = self.history.index - 1
        if current >= 0:
            self.view.setCurrentIndex(self.model.index(current))
            self.view.doItemsLayout()     # the scroll range must count the new rows first
            self.view.scrollTo(self.model.index(current))
        self._show_selected()

    def set_replaying(self, replaying: bool) -> None:
        """While an edit is replayed in the worker the log is about to change: its steps can be
        neither clicked nor edited (the status bar shows the progress and Cancel)."""
        self.view.setEnabled(not replaying)
        self.group.setEnabled(not replaying)
        self.optimise_button.setEnabled(not replaying and self.history is not None
                                        and self.history.index > 0)

    def optimise(self) -> OptimiseDialog | None:
        """Show what the optimiser would do (window-modal, no nested event loop); Optimise asks
        the main window to replace the log."""
        if self.history is None:
            return None
        dialog = OptimiseDialog(self.history, self)
        dialog.accepted.connect(lambda: self.optimiseRequested.emit(dialog.optimised))
        dialog.finished.connect(dialog.deleteLater)
        self.optimise_dialog = dialog
        dialog.open()
        return dialog

    def row_rect(self, step: int) -> QtCore.QRect:
        """Where step (0-based) is drawn in the list's viewport (for clicks in tests)."""
        return self.view.visualRect(self.model.index(step))

    def _clicked(self, index: QtCore.QModelIndex) -> None:
        self.selected_step = index.row()
        self._show_selected()
        self.stepClicked.emit(index.row() + 1)

    def _show_selected(self) -> None:
        step = self.selected_step
        if step is None and self.history is not None and self.history.index:
            step = self.history.index - 1
        if step is None or self.history is None:
            self.form.set_action(None)
            self._set_title("Selected step")
        else:
            self.form.set_action(self.history.actions[step], dict(self.history.document.dpjs))
            self._set_title(f"Step {step + 1}: {self.history.actions[step].label()}")
        self._shown_step = step
        self._update_buttons()

    def _set_title(self, title: str) -> None:
        """The form's title, elided past TITLE_WIDTH (a group box is as wide as its title: a long
        step's would widen the dock, and the canvas would shrink); in full as its tooltip."""
        shown = self.group.fontMetrics().elidedText(title, QtCore.Qt.TextElideMode.ElideRight,
                                                    self.TITLE_WIDTH)
        self.group.setTitle(shown)
        self.group.setToolTip(title if shown != title else "")

    def _form_changed(self) -> None:
        self._update_buttons()

    def _update_buttons(self) -> None:
        dirty = self.form.action is not None and bool(self.form.values())
        self.apply_button.setEnabled(dirty)
        self.revert_button.setEnabled(dirty)

    def _apply_edit(self) -> None:
        step = getattr(self, "_shown_step", None)
        if step is None or self.form.action is None:
            return
        try:
            new = replace_params(self.form.action, **self.form.values())
        except TexeditorError as exc:
            QtWidgets.QMessageBox.warning(self, "Cannot apply this edit", str(exc))
            return
        self.editRequested.emit(step, new)
