"""Image ▸ Global operators… (thesis §3.4.3): one map applied to the whole texture, or to the
Extract tool's selection when there is one — rotation, zoom, shear or a grid of copies.

Each Apply submits one Action (Isometry, Similarity, Affinity or Identity); the dialog stays open
so a user can try a value, undo, and try another.
"""

from __future__ import annotations


from PySide6 import QtWidgets

from texeditor.regions import actions as ra

from .widgets import spin_box

OPERATORS = [
    ("Rotate (isometry)", "isometry"),
    ("Zoom (similarity)", "similarity"),
    ("Shear (affinity)", "affinity"),
    ("Grid of copies (identity)", "identity"),
]


class GlobalOperatorsDialog(QtWidgets.QDialog):
    def __init__(self, window):
        super().__init__(window)
        self.main_window = window
        self.setWindowTitle("Global operators")
        form = QtWidgets.QFormLayout(self)
        self.operator = QtWidgets.QComboBox()
        for text, key in OPERATORS:
            self.operator.addItem(text, key)
        form.addRow("Operator", self.operator)
        self.angle = spin_box(-360, 360, 45, decimals=1, suffix="°",
                              tip="Counter-clockwise turn about the centre")
        self.factor = spin_box(0.05, 16, 0.5, decimals=3, suffix="×",
                               tip="Below 1: finer and denser; above 1: coarser")
        self.shear = spin_box(-4, 4, 0.5, decimals=3, tip="Columns move by this times the row: "
                              "squares become parallelograms")
        self.dx = spin_box(-4096, 4096, 32, prefix="x ", tip="Columns across to the first copy")
        self.dy = spin_box(-4096, 4096, 0, prefix="y ", tip="Rows down to the first copy")
        self.copies = spin_box(1, 64, 2, prefix="× ", tip="Copies along each axis")
        self.rows = {}
        for key, label, widget in (("angle", "Angle", self.angle), ("factor", "Factor", self.factor),
                                   ("shear", "Shear", self.shear), ("dx", "Offset", self.dx),
                                   ("dy", "", self.dy), ("copies", "Copies", self.copies)):
            form.addRow(label, widget)
            self.rows[key] = widget
        self.wrap = QtWidgets.QCheckBox("Wrap around the edges (tiles stay seamless)")
        self.wrap.setChecked(True)
        self.keep = QtWidgets.QCheckBox("Keep the source (transform a copy)")
        form.addRow(self.wrap)
        form.addRow(self.keep)
        self.target = QtWidgets.QLabel()
        self.target.setWordWrap(True)
        form.addRow(self.target)
        buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Close)
        self.apply_button = buttons.addButton("Apply",
                                              QtWidgets.QDialogButtonBox.ButtonRole.ApplyRole)
        self.apply_button.clicked.connect(self.apply)
        self.apply_button.setDefault(True)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)
        self.operator.currentIndexChanged.connect(self._show_fields)
        self._show_fields()

    def _show_fields(self) -> None:
        used = {"isometry": {"angle"}, "similarity": {"factor"},
                "affinity": {"shear"}, "identity": {"dx", "dy", "copies"}}[self.operator.currentData()]
        form = self.layout()
        for key, widget in self.rows.items():
            form.setRowVisible(widget, key in used)
        self.keep.setVisible(self.operator.currentData() != "identity")
        self.target.setText(f"Applies to {self._target_text()}.")
        self.adjustSize()

    def showEvent(self, ev) -> None:
        super().showEvent(ev)
        self.target.setText(f"Applies to {self._target_text()}.")

    def _selection(self) -> dict:
        """The Extract tool's selection recipe, or {} for the whole texture."""
        from .tools.regions import ExtractTool

        tool = next((t for t in self.main_window.tools if isinstance(t, ExtractTool)), None)
        if tool is None or tool.selection is None:
            return {}
        return dict(tool.selection)

    def _target_text(self) -> str:
        sel = self._selection()
        return "the whole texture" if not sel else \
            f"the selection at x {sel['col']}, y {sel['row']}"

    def action(self):
        """The Action the current fields describe."""
        key = self.operator.currentData()
        sel = self._selection()
        h, w = self.main_window.document.shape
        centre = {"centre_row": (h - 1) / 2, "centre_col": (w - 1) / 2}
        common = {"wrap": self.wrap.isChecked(), **sel}
        if key == "identity":
            n = self.copies.value()
            return ra.Identity(offset_row=self.dy.value(), offset_col=self.dx.value(),
                               repeat_rows=n if self.dy.value() else 1,
                               repeat_cols=n if self.dx.value() else 1, **common)
        common["keep_source"] = self.keep.isChecked()
        if key == "isometry":
            return ra.Isometry(angle=self.angle.value(), **centre, **common)
        if key == "similarity":
            return ra.Similarity(factor=self.factor.value(), **centre, **common)
        return ra.Affinity(m00=1.0, m01=0.0, m10=self.shear.value(), m11=1.0, **centre, **common)

    def apply(self) -> None:
        self.main_window.submit(self.action())
