"""The synthesis dock: the current DPJ, the size and seed of the next texture, and its button.

Synthesis itself runs in a worker (synthesis_worker.py); this panel only gathers the parameters of
the Synthesize Action the main window will submit.
"""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

from texeditor.recipe.actions import MAX_CANVAS_SIDE

from .params_form import SeedEdit, dpj_summary
from .widgets import scrolled

DEFAULT_SIZE = 256
DEFAULT_SEED = 1984


def synthesis_step(history):
    """The Synthesize step that made the current texture (None when the last new canvas was not
    a synthesis, or there is none)."""
    for action in reversed(history.applied):
        if action.EFFECT == "reset":
            return action if action.TYPE == "synthesize" else None
    return None


class SynthesisDock(QtWidgets.QDockWidget):
    """``requested(width, height, seed)`` when the user asks for a synthesis."""

    requested = QtCore.Signal(int, int, int)

    def __init__(self, parent=None):
        super().__init__("Synthesis", parent)
        self.setObjectName("SynthesisDock")
        body = QtWidgets.QWidget()
        form = QtWidgets.QFormLayout(body)
        self.dpj_label = QtWidgets.QLabel()
        self.width_box = self._side()
        self.height_box = self._side()
        size_row = QtWidgets.QHBoxLayout()
        size_row.addWidget(self.width_box, 1)
        size_row.addWidget(QtWidgets.QLabel("×"))
        size_row.addWidget(self.height_box, 1)
        self.seed = SeedEdit(DEFAULT_SEED)
        self.button = QtWidgets.QPushButton("Synthesise")
        self.button.setToolTip("Draw a new texture from the current DPJ (Ctrl+R)")
        self.button.clicked.connect(self._request)
        form.addRow("DPJ", self.dpj_label)
        form.addRow("Size", size_row)
        form.addRow("Seed", self.seed)
        form.addRow(self.button)
        self.setWidget(scrolled(body))
        self.set_dpj(None)

    def _side(self) -> QtWidgets.QSpinBox:
        box = QtWidgets.QSpinBox()
        box.setRange(1, MAX_CANVAS_SIDE)
        box.setValue(DEFAULT_SIZE)
        box.setSuffix(" px")
        return box

    def set_dpj(self, dpj) -> None:
        self.has_dpj = dpj is not None
        if dpj is None:        # always two lines, so the dock keeps its height
            self.dpj_label.setText("none yet\nFile ▸ Acquire DPJ from image…")
        else:
            name, _, details = dpj_summary(dpj).partition(": ")
            self.dpj_label.setText(f"{name}\n{details}")
        self.dpj_label.setToolTip(dpj_summary(dpj) if dpj is not None else "")
        self.button.setEnabled(self.has_dpj and not getattr(self, "busy", False))

    def refresh(self, history) -> None:
        """Follow the document after any change (undo, redo, replay, open): its DPJ, and the
        size and seed of the synthesis that made the current texture. Those are shown when that
        step changes, so values typed for the next synthesis survive unrelated edits (a stroke)."""
        doc = history.document
        self.set_dpj(doc.dpj)
        step = synthesis_step(history)
        if step is not None and step != getattr(self, "_shown_step", None):
            self.show_step(step)
        self._shown_step = step

    def show_step(self, action) -> None:
        """Show a Synthesize step's size and seed."""
        self.width_box.setValue(action.width)
        self.height_box.setValue(action.height)
        self.seed.set_value(action.seed)

    def set_busy(self, busy: bool) -> None:
        self.busy = busy
        self.button.setEnabled(self.has_dpj and not busy)

    def values(self) -> tuple[int, int, int]:
        return self.width_box.value(), self.height_box.value(), self.seed.value()

    def _request(self) -> None:
        self.requested.emit(*self.values())
