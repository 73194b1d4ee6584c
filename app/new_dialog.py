"""File ▸ New: the size and number of levels G of a blank canvas (a NewCanvas action)."""

from __future__ import annotations

from PySide6 import QtWidgets

from texeditor.recipe.actions import MAX_CANVAS_SIDE
from texeditor.markov.dpj import MAX_LEVELS


class NewDialog(QtWidgets.QDialog):
    def __init__(self, width: int = 256, height: int = 256, levels: int = 4, parent=None):
        super().__init__(parent)
        self.setWindowTitle("New texture")
        form = QtWidgets.QFormLayout(self)
        self.width_box, self.height_box = QtWidgets.QSpinBox(), QtWidgets.QSpinBox()
        for box, value in ((self.width_box, width), (self.height_box, height)):
            box.setRange(1, MAX_CANVAS_SIDE)
            box.setValue(value)
            box.setSuffix(" px")
        self.levels_box = QtWidgets.QSpinBox()
        self.levels_box.setRange(2, MAX_LEVELS)
        self.levels_box.setValue(levels)
        self.levels_box.setToolTip("Number of levels G; level 0 is the background")
        form.addRow("Width", self.width_box)
        form.addRow("Height", self.height_box)
        form.addRow("Levels G", self.levels_box)
        buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Ok
                                             | QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)

    def values(self) -> tuple[int, int, int]:
        return self.width_box.value(), self.height_box.value(), self.levels_box.value()
