"""An edit form for one Action's parameters, built from the engine's ParamSpecs.

The history dock shows it for the selected step; its values become ``replace_params(action, ...)``
so editing a past step is an ordinary, validated Action (non-destructive history).
"""

from __future__ import annotations

import secrets

from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.recipe.actions import param_specs
from texeditor.wording import counted

INT32 = 2**31 - 1
LONG_TEXT = 80             # a text parameter longer than this is structured data, shown as its size
LABELS = {"dpj": "DPJ", "dpjs": "DPJs", "levels": "Levels G",
          "more_drafts": "More drafts on small scales",
          "coarse_redraws": "Redraws at a coarsest dead end",
          "given_redraws": "Redraws at a finer dead end",
          "coarse_row_redraws": "Coarsest redraws a row, per point",
          "free_moves": "Shares: moves free of the parents",
          "forced_moves": "Shares: forced moves at last",
          "lean_drafts": "Drafts: only past the parents' error"}
NEW_SEED_MAX = 2**31 - 1   # fresh seeds stay readable; any seed up to 2**63-1 can be typed


def new_seed() -> int:
    return secrets.randbelow(NEW_SEED_MAX)


def dpj_summary(dpj) -> str:
    u, v = dpj.window
    source = dpj.meta.get("name") or dpj.meta.get("source") or "DPJ"
    parents = dpj.meta.get("parent_levels")
    if isinstance(parents, int) and parents > 1 and dpj.levels % parents == 0:
        # a photo model's finer scale: its levels given the coarser scale's (composite levels)
        given = (f"{parents // 2} and the row's phase" if dpj.meta.get("parent_phase") is True
                 else str(parents))
        g = f"{dpj.levels // parents} given {given} ({dpj.levels} composite levels)"
    else:
        g = str(dpj.levels)
    return f"{source}: {u}×{v}, G = {g}, {len(dpj):,} configurations"


class SeedEdit(QtWidgets.QWidget):
    """A seed (0..2**63-1) with a button that draws a new one."""

    changed = QtCore.Signal()

    def __init__(self, value: int = 0, parent=None):
        super().__init__(parent)
        row = QtWidgets.QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        self.edit = QtWidgets.QLineEdit(str(value))
        self.edit.setValidator(QtGui.QRegularExpressionValidator(
            QtCore.QRegularExpression(r"\d{1,19}"), self.edit))
        self.edit.textChanged.connect(self.changed)
        self.button = QtWidgets.QToolButton()
        self.button.setText("New seed")
        self.button.setToolTip("Draw a new random seed: same seed, same texture")
        self.button.clicked.connect(lambda: self.set_value(new_seed()))
        row.addWidget(self.edit, 1)
        row.addWidget(self.button)

    def value(self) -> int:
        return int(self.edit.text() or 0)

    def set_value(self, value: int) -> None:
        self.edit.setText(str(int(value)))


class ParamsForm(QtWidgets.QWidget):
    """Rows for the parameters of one action; ``changed`` fires on every edit."""

    changed = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        self.form = QtWidgets.QFormLayout(self)
        self.form.setFieldGrowthPolicy(QtWidgets.QFormLayout.FieldGrowthPolicy.AllNonFixedFieldsGrow)
        # in a narrow dock a long row puts its field under its name instead of scrolling sideways
        self.form.setRowWrapPolicy(QtWidgets.QFormLayout.RowWrapPolicy.WrapLongRows)
        self.action = None
        self.editors: dict[str, tuple[str, QtWidgets.QWidget]] = {}

    def set_action(self, action, dpjs: dict | None = None) -> None:
        while self.form.rowCount():
            self.form.removeRow(0)
        self.editors.clear()
        self.action = action
        if action is None:
            return
        for spec in param_specs(action):
            editor = self._editor(spec, dpjs or {})
            editor.setToolTip(spec.doc)
            if isinstance(editor, QtWidgets.QLabel):
                editor.setWordWrap(True)        # a description wraps: the form never scrolls sideways
            self.form.addRow(LABELS.get(spec.name, spec.name.replace("_", " ").capitalize()), editor)

    def _editor(self, spec, dpjs) -> QtWidgets.QWidget:
        kind, value = spec.kind, spec.value
        if value is None:      # an optional parameter left to its automatic value
            w = QtWidgets.QLabel(self._describe(kind, value))
            w.setEnabled(False)
            return w
        if kind == "int":
            w = QtWidgets.QSpinBox()
            w.setRange(int(max(spec.minimum if spec.minimum is not None else -INT32, -INT32)),
                       int(min(spec.maximum if spec.maximum is not None else INT32, INT32)))
            w.setValue(int(value))
            w.valueChanged.connect(self.changed)
            self.editors[spec.name] = (kind, w)
        elif kind == "seed":
            w = SeedEdit(value)
            w.changed.connect(self.changed)
            self.editors[spec.name] = (kind, w)
        elif kind == "float":
            w = QtWidgets.QDoubleSpinBox()
            w.setDecimals(4)
            w.setRange(spec.minimum if spec.minimum is not None else -1e9,
                       spec.maximum if spec.maximum is not None else 1e9)
            w.setValue(float(value))
            w.valueChanged.connect(self.changed)
            self.editors[spec.name] = (kind, w)
        elif kind == "bool":
            w = QtWidgets.QCheckBox()
            w.setChecked(bool(value))
            w.toggled.connect(self.changed)
            self.editors[spec.name] = (kind, w)
        elif kind == "str" and self._is_document(spec):
            w = QtWidgets.QLabel(f"{len(value):,} characters (set by its tool)")
            w.setEnabled(False)
        elif kind == "str":
            w = QtWidgets.QLineEdit(value or "")
            w.textChanged.connect(self.changed)
            self.editors[spec.name] = (kind, w)
        elif kind == "refs":
            w = QtWidgets.QLabel(self._describe_refs(value, dpjs))
            w.setWordWrap(True)
            w.setEnabled(False)
        elif kind == "ref" and dpjs:
            w = QtWidgets.QComboBox()
            w.setSizeAdjustPolicy(
                QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
            w.setMinimumContentsLength(12)
            for ref, dpj in dpjs.items():
                w.addItem(dpj_summary(dpj), ref)
            w.setCurrentIndex(max(0, w.findData(value)))
            w.currentIndexChanged.connect(self.changed)
            self.editors[spec.name] = (kind, w)
        else:
            w = QtWidgets.QLabel(self._describe(kind, value))
            w.setEnabled(False)
        return w

    @staticmethod
    def _is_document(spec) -> bool:
        """A long structured text (an envelope, a recipe): not something to edit as one line."""
        return (spec.maximum or 0) > LONG_TEXT and len(spec.value) > LONG_TEXT

    @staticmethod
    def _describe_refs(refs, dpjs) -> str:
        """Read-only: the DPJs a recipe needs follow from the recipe, set with it by its tool."""
        if not refs:
            return "none"
        names = [dpj_summary(dpjs[r]) if r in dpjs else r for r in refs]
        return f"{len(refs)} DPJ{'s' if len(refs) > 1 else ''}: " + "; ".join(names)

    @staticmethod
    def _describe(kind, value) -> str:
        if value is None:
            return "default"
        if kind == "palette":
            return f"{counted(len(value), 'colour')} (edit them in the Palette dock)"
        if kind == "points":
            return counted(len(value), "point")
        if kind == "texts":
            return f"{counted(len(value), 'texture recipe')} (set by its tool)"
        return str(value)

    def values(self) -> dict:
        """The edited parameters that differ from the action's own."""
        out = {}
        for name, (kind, w) in self.editors.items():
            if kind in ("int", "seed", "float"):
                value = w.value()
            elif kind == "bool":
                value = w.isChecked()
            elif kind == "ref":
                value = w.currentData()
            else:
                value = w.text()
            if value != getattr(self.action, name):
                out[name] = value
        return out

    def editor(self, name: str) -> QtWidgets.QWidget:
        return self.editors[name][1]
