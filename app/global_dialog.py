"""Image ▸ Global operators… (thesis §3.4.3): one map applied to the whole texture, or to the
Extract tool's selection when there is one — rotation, zoom, shear or a grid of copies — or the
random manipulation of every region, each by its own map drawn from a seed.

Each Apply submits one Action (Isometry, Similarity, Affinity, Identity or ScatterRegions); the
dialog stays open so a user can try a value, undo, and try another (or a new seed).
"""

from __future__ import annotations


from PySide6 import QtCore, QtWidgets

from texeditor.errors import TexeditorError
from texeditor.regions import actions as ra

from .params_form import SeedEdit
from .widgets import spin_box

OPERATORS = [
    ("Rotate (isometry)", "isometry"),
    ("Zoom (similarity)", "similarity"),
    ("Shear (affinity)", "affinity"),
    ("Grid of copies (identity)", "identity"),
    ("Scatter every region (random)", "scatter"),
]
ROTATIONS = [("None", "none"), ("Quarter turns", "quarter"), ("Any angle", "any")]
IN_WORKER = 2**18      # points from which a scatter is drawn in the worker (a 2048² texture's
                       # every region takes 4–5 s; a 512² one's a quarter of a second)
FIELDS = {"isometry": {"angle"}, "similarity": {"factor"}, "affinity": {"shear"},
          "identity": {"dx", "dy", "copies"},
          "scatter": {"radius", "rotation", "scale_min", "scale_max", "level", "fill", "seed"}}


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
        self.radius = spin_box(0, 4096, 8, decimals=1, suffix=" points",
                               tip="Each region moves at most this far, in any direction")
        self.rotation = QtWidgets.QComboBox()
        for text, key in ROTATIONS:
            self.rotation.addItem(text, key)
        self.rotation.setCurrentIndex(self.rotation.findData("quarter"))
        self.rotation.setToolTip("Each region turns about the centre of its box: not at all, by "
                                 "a multiple of 90° (exact), or by any angle")
        self.scale_min = spin_box(0.05, 16, 1, decimals=2, prefix="from ×",
                                  tip="The smallest zoom a region gets")
        self.scale_max = spin_box(0.05, 16, 1, decimals=2, prefix="to ×",
                                  tip="The largest zoom a region gets")
        self.level = spin_box(-1, 15, -1, tip="Without a selection: the regions of this level "
                              "only (every level but the background when none)")
        self.level.setSpecialValueText("every level but 0")
        self.fill = spin_box(0, 15, 0, tip="The level left where the regions were")
        self.seed = SeedEdit(1)
        self.rows = {}
        for key, label, widget in (("angle", "Angle", self.angle), ("factor", "Factor", self.factor),
                                   ("shear", "Shear", self.shear), ("dx", "Offset", self.dx),
                                   ("dy", "", self.dy), ("copies", "Copies", self.copies),
                                   ("radius", "Move within", self.radius),
                                   ("rotation", "Turn", self.rotation),
                                   ("scale_min", "Zoom", self.scale_min),
                                   ("scale_max", "", self.scale_max),
                                   ("level", "Regions of", self.level),
                                   ("fill", "Leave behind", self.fill),
                                   ("seed", "Seed", self.seed)):
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
        self.level.valueChanged.connect(self._show_target)
        self._show_fields()

    def _show_fields(self) -> None:
        key = self.operator.currentData()
        form = self.layout()
        for name, widget in self.rows.items():
            form.setRowVisible(widget, name in FIELDS[key])
        self.keep.setVisible(key not in ("identity", "scatter"))
        self._show_target()
        self.adjustSize()

    def showEvent(self, ev) -> None:
        super().showEvent(ev)
        self._show_target()

    def changeEvent(self, ev) -> None:
        """Coming back to the dialog after clicking a selection: say what Apply acts on now."""
        super().changeEvent(ev)
        if ev.type() == QtCore.QEvent.Type.ActivationChange and self.isActiveWindow():
            self._show_target()

    def _show_target(self) -> None:
        """Say what Apply acts on; a selection overrides the level of a scatter."""
        selected = bool(self._selection())
        self.level.setEnabled(not selected)
        scatter = self.operator.currentData() == "scatter"
        what = self._target_text()
        if scatter:
            what = f"every region of {what}" if selected or self.level.value() < 0 else \
                f"every region of level {self.level.value()}"
        self.target.setText(f"Applies to {what}.")

    def _selection(self) -> dict:
        """The Extract tool's selection recipe (while its point is on the canvas), or {} for
        the whole texture."""
        from .tools.regions import ExtractTool

        tool = next((t for t in self.main_window.tools if isinstance(t, ExtractTool)), None)
        selection = None if tool is None else tool.live_selection()
        return {} if selection is None else dict(selection)

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
        if key == "scatter":
            level = self.level.value()
            return ra.ScatterRegions(
                seed=self.seed.value(), radius=self.radius.value(),
                rotation=self.rotation.currentData(), scale_min=self.scale_min.value(),
                scale_max=self.scale_max.value(), fill=self.fill.value(),
                level=None if sel or level < 0 else level, **common)
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
        """Submit the operator; a scatter of a large texture (seconds) is drawn in the worker."""
        window = self.main_window
        try:
            action = self.action()
        except TexeditorError as exc:
            window.show_error("Cannot apply the operator", exc)
            return
        if isinstance(action, ra.ScatterRegions) and window.document.levels.size >= IN_WORKER:
            window.submit_computed(lambda doc: (action, action.scattered(doc)),
                                   "Scattering the regions…")
        else:
            window.submit(action)
