"""Image ▸ Composition… (thesis §5.4.1): incrust another texture into this one where a mask says
(point by point or by blocks, the thesis's pavés), mix the two, T3 = not[(a op1 T1) op2 (b op3
T2)] op4 c, or mix more textures in one expression — with a preview, one Action per Apply.

T1 is the current texture; T2 (and a mask texture) is picked as a synthesis of a DPJ of the
document, an opened `.texture` file, a bank entry (`bank_picker`), or this texture at an earlier
step: each becomes a *recipe* (the log that rebuilds it, see `texture_actions`). Sources are
rendered in the worker; the composition itself is instant and previewed on a copy of the
document, never on the document.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.texture import composition
from texeditor.errors import TexeditorError
from texeditor.recipe.actions import dpj_refs
from texeditor.texture.actions import MAX_SOURCES, Incrust, Mix, MixTextures
from texeditor.recipe.sources import check_recipe, recipe_of, synthesis_recipe

from .bank_picker import choose_bank_entry, load_bank_source
from .images import qimage_from_rgb
from .params_form import SeedEdit, dpj_summary

PREVIEW = 320
TINT = (40, 200, 255)             # the selection tint of the region tools
OP_NAMES = {"and": "and", "or": "or", "xor": "xor", "min": "min", "max": "max",
            "add": "add (clipped)", "multiply": "× (multiply)", "replace": "replace (over)"}
PRESETS = [("Custom", None),
           ("Average of T1 and T2", dict(a=0.5, op1="multiply", op2="add", b=0.5,
                                         op3="multiply", negate=False, op4="max", c=0.0)),
           ("T2 over T1 (T2's background clear)", dict(a=1.0, op1="multiply", op2="replace",
                                                       b=1.0, op3="multiply", negate=False,
                                                       op4="max", c=0.0)),
           ("Exclusive or", dict(a=1.0, op1="multiply", op2="xor", b=1.0, op3="multiply",
                                 negate=False, op4="max", c=0.0)),
           ("Darker of the two", dict(a=1.0, op1="multiply", op2="min", b=1.0, op3="multiply",
                                      negate=False, op4="max", c=0.0)),
           ("Negative of the brighter", dict(a=1.0, op1="multiply", op2="max", b=1.0,
                                             op3="multiply", negate=True, op4="max", c=0.0))]
MASKS = [("Levels of another texture", "texture"), ("Levels of this texture", "levels"),
         ("The Extract tool's selection", "selection"), ("Painted on the preview", "painted")]
EXPRESSIONS = [         # name, the expression over T1…Tn
    ("Average", lambda n: " add ".join(f"({w:g} multiply T{k})"
                                       for k, w in enumerate(_shares(n), start=1))),
    ("Brightest (max)", lambda n: " max ".join(f"T{k}" for k in range(1, n + 1))),
    ("Darkest (min)", lambda n: " min ".join(f"T{k}" for k in range(1, n + 1))),
    ("Each over the ones before", lambda n: " replace ".join(f"T{k}" for k in range(1, n + 1))),
    ("Exclusive or", lambda n: " xor ".join(f"T{k}" for k in range(1, n + 1))),
]


def _shares(n: int) -> list[float]:
    """n weights of two decimals summing to 1 (the first takes what rounding leaves)."""
    share = round(1 / n, 2)
    return [round(1 - share * (n - 1), 2)] + [share] * (n - 1)


class SourcePicker(QtWidgets.QWidget):
    """Which texture: a synthesis of a DPJ of the document, a .texture file, a bank entry, or
    this one at a step. ``recipe()`` gives (recipe text, the references of every DPJ it needs)."""

    changed = QtCore.Signal()

    def __init__(self, window, seed: int):
        super().__init__()
        self.main_window = window
        self.file_recipe: tuple[str, tuple] | None = None
        self.file_name = ""
        self.bank_source = None          # the chosen entry as a TextureSource
        form = QtWidgets.QFormLayout(self)
        form.setContentsMargins(0, 0, 0, 0)
        self.kind = QtWidgets.QComboBox()
        self.kind.addItem("Synthesis of a DPJ", "synth")
        self.kind.addItem("Texture file…", "file")
        self.kind.addItem("Bank entry…", "bank")
        self.kind.addItem("This texture at a step", "step")
        self.dpj = QtWidgets.QComboBox()
        self.dpj.setSizeAdjustPolicy(
            QtWidgets.QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.dpj.setMinimumContentsLength(18)
        self.seed = SeedEdit(seed)
        self.open_button = QtWidgets.QPushButton("Open a texture…")
        self.file_label = QtWidgets.QLabel("no file")
        self.bank_button = QtWidgets.QPushButton("Choose an entry…")
        self.bank_label = QtWidgets.QLabel("no entry")
        self.step = QtWidgets.QSpinBox()
        self.step.setToolTip("The texture after this many steps of the history")
        form.addRow("Source", self.kind)
        self.rows = {"synth": [self._row(form, "DPJ", self.dpj),
                               self._row(form, "Seed", self.seed)],
                     "file": [self._row(form, self.open_button, self.file_label)],
                     "bank": [self._row(form, self.bank_button, self.bank_label)],
                     "step": [self._row(form, "After step", self.step)]}
        self.kind.currentIndexChanged.connect(self._kind_changed)
        self.dpj.currentIndexChanged.connect(self.changed)
        self.seed.changed.connect(self.changed)
        self.step.valueChanged.connect(self.changed)
        self.open_button.clicked.connect(self.open_file)
        self.bank_button.clicked.connect(self.choose_entry)
        self.reload()
        self._kind_changed()

    @staticmethod
    def _row(form, label, widget):
        form.addRow(label, widget)
        return (form.labelForField(widget), widget)

    def _kind_changed(self) -> None:
        kind = self.kind.currentData()
        for key, rows in self.rows.items():
            for label, widget in rows:
                for w in (label, widget):
                    if w is not None:
                        w.setVisible(key == kind)
        self.changed.emit()

    def reload(self) -> None:
        """Follow the document: its DPJs and the number of steps."""
        history = self.main_window.history
        current = self.dpj.currentData()
        self.dpj.blockSignals(True)
        self.dpj.clear()
        doc = history.document
        for ref, dpj in doc.dpjs.items():
            if dpj.meta.get("source") != "doubling table":
                self.dpj.addItem(dpj_summary(dpj), ref)
        index = self.dpj.findData(current if current is not None else doc.dpj_ref)
        self.dpj.setCurrentIndex(max(0, index))
        self.dpj.blockSignals(False)
        self.step.setRange(1, max(1, history.index))
        if self.step.value() == 0 or self.step.value() > history.index:
            self.step.setValue(max(1, history.index))

    def open_file(self, path=None) -> None:
        from texeditor.recipe.texturefile import read_texture
        if path is None:
            path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Open a texture", "",
                                                            "Textures (*.texture)")
            if not path:
                return
        try:
            tex = read_texture(path)
            refs, text = tuple(dpj_refs(tex.actions)), recipe_of(tex.actions)
            check_recipe(text, refs, Path(path).name)     # its depth and number of DPJs
        except TexeditorError as exc:
            self.main_window.show_error("Cannot use this texture", exc)
            return
        for ref in refs:        # kept under the file's own reference, as a file's DPJ is
            self.main_window.document.dpjs.setdefault(ref, tex.dpjs[ref])
        self.file_recipe = (text, refs)
        self.file_name = Path(path).name
        self.file_label.setText(self.file_name)
        self.changed.emit()

    def choose_entry(self) -> QtWidgets.QDialog:
        """Pick a bank entry; the worker then replays it (checking the bank's hash) into a
        recipe. Returns the picker."""
        history = self.main_window.history

        def loaded(source):
            if history is self.main_window.history:
                self.bank_source = source
                self.bank_label.setText(source.name)
                self.changed.emit()

        return choose_bank_entry(self.main_window, lambda bank, entry_id: load_bank_source(
            self.main_window, bank, entry_id, loaded), parent=self)

    def recipe(self) -> tuple[str, tuple]:
        kind = self.kind.currentData()
        history = self.main_window.history
        if kind == "synth":
            ref = self.dpj.currentData()
            if ref is None:
                raise TexeditorError("the document holds no DPJ: acquire one, or pick a file")
            h, w = history.document.shape
            return synthesis_recipe(ref, w, h, self.seed.value()), (ref,)
        if kind == "file":
            if self.file_recipe is None:
                raise TexeditorError("open a .texture file first")
            return self.file_recipe
        if kind == "bank":
            if self.bank_source is None:
                raise TexeditorError("choose a bank entry first")
            self.bank_source.store(history.document)
            return self.bank_source.recipe, self.bank_source.refs
        actions = history.applied[:self.step.value()]
        return recipe_of(actions), tuple(dpj_refs(actions))

    def describe(self) -> str:
        kind = self.kind.currentData()
        if kind == "synth":
            return f"a synthesis (seed {self.seed.value()})"
        if kind == "file":
            return self.file_name or "a file"
        if kind == "bank":
            return f"bank entry “{self.bank_source.name}”" if self.bank_source else "a bank entry"
        return f"this texture at step {self.step.value()}"


class PaintablePreview(QtWidgets.QLabel):
    """The preview; in painting mode a drag marks membership points under a round brush."""

    painted = QtCore.Signal()

    def __init__(self):
        super().__init__()
        self.setFixedSize(PREVIEW, PREVIEW)
        self.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.setFrameShape(QtWidgets.QFrame.Shape.StyledPanel)
        self.painting = False
        self.radius = 3
        self.painted_mask: np.ndarray | None = None
        self._scale, self._origin = 1.0, (0, 0)

    def show_rgb(self, rgb: np.ndarray) -> None:
        h, w = rgb.shape[:2]
        scale = min(PREVIEW / w, PREVIEW / h)
        scale = float(int(scale)) if scale >= 1 else scale
        image = qimage_from_rgb(rgb).scaled(max(1, round(w * scale)), max(1, round(h * scale)),
                                            QtCore.Qt.AspectRatioMode.IgnoreAspectRatio,
                                            QtCore.Qt.TransformationMode.FastTransformation)
        self._scale = scale
        self._origin = ((PREVIEW - image.width()) // 2, (PREVIEW - image.height()) // 2)
        self.setPixmap(QtGui.QPixmap.fromImage(image))

    def cell_at(self, pos: QtCore.QPointF) -> tuple[int, int]:
        return (int((pos.y() - self._origin[1]) // self._scale),
                int((pos.x() - self._origin[0]) // self._scale))

    def paint_at(self, pos) -> None:
        if not self.painting or self.painted_mask is None:
            return
        r0, c0 = self.cell_at(pos)
        h, w = self.painted_mask.shape
        rr, cc = np.ogrid[:h, :w]
        self.painted_mask |= (rr - r0) ** 2 + (cc - c0) ** 2 <= self.radius ** 2
        self.painted.emit()

    def mousePressEvent(self, ev) -> None:
        self.paint_at(ev.position())

    def mouseMoveEvent(self, ev) -> None:
        if ev.buttons() & QtCore.Qt.MouseButton.LeftButton:
            self.paint_at(ev.position())


class CompositionDialog(QtWidgets.QDialog):
    def __init__(self, window):
        super().__init__(window)
        self.main_window = window
        self.setWindowTitle("Composition")
        self._pending = False
        outer = QtWidgets.QHBoxLayout(self)
        left = QtWidgets.QVBoxLayout()
        outer.addLayout(left, 1)

        self.tabs = QtWidgets.QTabWidget()
        self.tabs.addTab(self._incrust_page(), "Incrustation")
        self.tabs.addTab(self._mix_page(), "Mixing")
        self.tabs.addTab(self._expression_page(), "More textures")
        t2 = QtWidgets.QGroupBox("T2: the other texture")
        box = QtWidgets.QVBoxLayout(t2)
        self.source = SourcePicker(window, 2)
        box.addWidget(self.source)
        left.addWidget(t2)
        left.addWidget(self.tabs)
        left.addStretch(1)

        right = QtWidgets.QVBoxLayout()
        self.preview = PaintablePreview()
        self.preview.setToolTip("T3, the composed texture (the top-left corner, enlarged)")
        self.status = QtWidgets.QLabel()
        self.status.setWordWrap(True)
        self.status.setFixedWidth(PREVIEW)
        right.addWidget(QtWidgets.QLabel("Preview (T1 is the current texture)"))
        right.addWidget(self.preview)
        self.tint = QtWidgets.QCheckBox("Tint where T2 shows (incrustation)")
        self.tint.setChecked(True)
        self.tint.toggled.connect(self.schedule)
        right.addWidget(self.tint)
        right.addWidget(self.status)
        right.addStretch(1)
        buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Close)
        self.apply_button = buttons.addButton("Apply",
                                              QtWidgets.QDialogButtonBox.ButtonRole.ApplyRole)
        self.apply_button.setDefault(True)
        self.apply_button.clicked.connect(self.apply)
        buttons.rejected.connect(self.reject)
        right.addWidget(buttons)
        outer.addLayout(right)

        self.timer = QtCore.QTimer(self)
        self.timer.setSingleShot(True)
        self.timer.setInterval(150)
        self.timer.timeout.connect(self.update_preview)
        for signal in (self.source.changed, self.mask_source.changed, self.tabs.currentChanged,
                       self.preview.painted, self.block.valueChanged,
                       self.expression.textChanged):
            signal.connect(self.schedule)
        self._unsubscribe = window.history.subscribe(self._document_changed)
        self._history = window.history
        self.reset_painting()
        self.schedule()

    # -- pages -------------------------------------------------------------------------------------
    def _incrust_page(self) -> QtWidgets.QWidget:
        page = QtWidgets.QWidget()
        form = QtWidgets.QFormLayout(page)
        form.addRow(QtWidgets.QLabel("T3 = if mask then T2 else T1: T2 shows where the mask "
                                     "holds, the current texture elsewhere."))
        self.mask_kind = QtWidgets.QComboBox()
        for text, value in MASKS:
            self.mask_kind.addItem(text, value)
        self.mask_levels = QtWidgets.QLineEdit("1-15")
        self.mask_levels.setToolTip("The mask's levels where T2 shows, like 1,3-5 (0 is the "
                                    "background)")
        self.mask_source = SourcePicker(self.main_window, 3)
        self.mask_group = QtWidgets.QGroupBox("Mask texture")
        QtWidgets.QVBoxLayout(self.mask_group).addWidget(self.mask_source)
        self.radius = QtWidgets.QSpinBox()
        self.radius.setRange(0, 64)
        self.radius.setValue(3)
        self.radius.setSuffix(" points")
        self.clear_paint = QtWidgets.QPushButton("Clear the painting")
        paint_row = QtWidgets.QHBoxLayout()
        paint_row.addWidget(self.radius)
        paint_row.addWidget(self.clear_paint)
        self.paint_widget = QtWidgets.QWidget()
        self.paint_widget.setLayout(paint_row)
        self.block = QtWidgets.QSpinBox()
        self.block.setRange(1, 256)
        self.block.setSuffix(" points")
        self.block.setSpecialValueText("1 (point by point)")
        self.block.setToolTip("T2 shows by square blocks of this side (the thesis's pavés): "
                              "each point of a mask texture says what a block shows; another "
                              "mask shows T2 in a block where it holds on half of it")
        form.addRow("Mask", self.mask_kind)
        form.addRow("Levels", self.mask_levels)
        form.addRow("Blocks", self.block)
        form.addRow(self.mask_group)
        form.addRow("Brush radius", self.paint_widget)
        self.mask_kind.currentIndexChanged.connect(self._mask_kind_changed)
        self.mask_levels.textChanged.connect(self.schedule)
        self.radius.valueChanged.connect(lambda r: setattr(self.preview, "radius", r))
        self.clear_paint.clicked.connect(self.reset_painting)
        self._mask_form = form
        QtCore.QTimer.singleShot(0, self, self._mask_kind_changed)
        return page

    def _mix_page(self) -> QtWidgets.QWidget:
        page = QtWidgets.QWidget()
        form = QtWidgets.QFormLayout(page)
        form.addRow(QtWidgets.QLabel("T3 = not[(a op1 T1) op2 (b op3 T2)] op4 c, on the grey "
                                     "scale (0 background … 1 top level)."))
        self.preset = QtWidgets.QComboBox()
        for text, values in PRESETS:
            self.preset.addItem(text, values)
        self.weights = {k: self._weight(v) for k, v in (("a", 1.0), ("b", 1.0), ("c", 0.0))}
        self.ops = {k: self._op(v) for k, v in (("op1", "multiply"), ("op2", "max"),
                                                 ("op3", "multiply"), ("op4", "max"))}
        self.negate = QtWidgets.QCheckBox("not[…]: the complement of the bracket")
        form.addRow("Preset", self.preset)
        form.addRow("a op1 T1", self._pair(self.weights["a"], self.ops["op1"]))
        form.addRow("op2", self.ops["op2"])
        form.addRow("b op3 T2", self._pair(self.weights["b"], self.ops["op3"]))
        form.addRow(self.negate)
        form.addRow("op4 c", self._pair(self.ops["op4"], self.weights["c"]))
        self.preset.currentIndexChanged.connect(self._preset_chosen)
        for w in self.weights.values():
            w.valueChanged.connect(self._custom)
        for w in self.ops.values():
            w.currentIndexChanged.connect(self._custom)
        self.negate.toggled.connect(self._custom)
        return page

    def _expression_page(self) -> QtWidgets.QWidget:
        """T = an expression over T1 (this texture), T2 (above) and T3… picked here."""
        page = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(page)
        note = QtWidgets.QLabel("T = an expression over T1 (this texture), T2 (above) and the "
                                "textures below: and, or, xor, min, max, add, multiply, replace, "
                                "not, numbers 0…1; left to right, brackets group.")
        note.setWordWrap(True)
        layout.addWidget(note)
        self.extra_box = QtWidgets.QVBoxLayout()
        holder = QtWidgets.QWidget()
        holder.setLayout(self.extra_box)
        scroll = QtWidgets.QScrollArea()
        scroll.setWidgetResizable(True)
        scroll.setWidget(holder)
        scroll.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
        scroll.setMinimumHeight(230)                       # two pickers in view
        layout.addWidget(scroll, 1)
        row = QtWidgets.QHBoxLayout()
        self.add_texture = QtWidgets.QPushButton("Add a texture")
        self.remove_texture = QtWidgets.QPushButton("Remove the last")
        row.addWidget(self.add_texture)
        row.addWidget(self.remove_texture)
        layout.addLayout(row)
        form = QtWidgets.QFormLayout()
        self.expression_preset = QtWidgets.QComboBox()
        self.expression_preset.addItem("Custom", None)
        for text, make in EXPRESSIONS:
            self.expression_preset.addItem(text, make)
        self.expression = QtWidgets.QLineEdit()
        self.expression.setToolTip("The mixing formula over T1…Tn, e.g. (0.5 multiply T1) add "
                                   "(0.5 multiply T2) max T3")
        form.addRow("Preset", self.expression_preset)
        form.addRow("T =", self.expression)
        layout.addLayout(form)
        self.extra: list[SourcePicker] = []
        self.add_texture.clicked.connect(self.add_source)
        self.remove_texture.clicked.connect(self.remove_source)
        self.expression_preset.currentIndexChanged.connect(self._expression_chosen)
        self.expression.textEdited.connect(self._expression_typed)
        self._new_picker()
        self.expression_preset.setCurrentIndex(1)           # the average of T1, T2, T3
        return page

    def add_source(self) -> None:
        """One more texture T3, T4… (a picker of its own; at most T8)."""
        if len(self.extra) < MAX_SOURCES - 1:
            self._new_picker()
            self._textures_changed()

    def _new_picker(self) -> None:
        k = len(self.extra) + 3
        group = QtWidgets.QGroupBox(f"T{k}")
        picker = SourcePicker(self.main_window, k)
        QtWidgets.QVBoxLayout(group).addWidget(picker)
        self.extra_box.addWidget(group)
        self.extra.append(picker)
        picker.changed.connect(self.schedule)

    def remove_source(self) -> None:
        if len(self.extra) > 1:
            group = self.extra.pop().parentWidget()
            self.extra_box.removeWidget(group)
            group.deleteLater()
            self._textures_changed()

    def _textures_changed(self) -> None:
        self.add_texture.setEnabled(len(self.extra) < MAX_SOURCES - 1)
        self.remove_texture.setEnabled(len(self.extra) > 1)
        self._expression_chosen()
        self.schedule()

    def _expression_chosen(self) -> None:
        """A preset writes the expression for the textures there are now (the text's change
        schedules the preview)."""
        make = self.expression_preset.currentData()
        if make is not None:
            self.expression.setText(make(2 + len(self.extra)))

    def _expression_typed(self) -> None:
        self.expression_preset.blockSignals(True)
        self.expression_preset.setCurrentIndex(0)
        self.expression_preset.blockSignals(False)

    @staticmethod
    def _weight(value: float) -> QtWidgets.QDoubleSpinBox:
        box = QtWidgets.QDoubleSpinBox()
        box.setRange(0.0, 1.0)
        box.setSingleStep(0.05)
        box.setDecimals(3)
        box.setValue(value)
        box.setToolTip("A proportion of the grey scale: 0 the background, 1 the top level")
        return box

    @staticmethod
    def _op(value: str) -> QtWidgets.QComboBox:
        combo = QtWidgets.QComboBox()
        for op in composition.OPS:
            combo.addItem(OP_NAMES[op], op)
        combo.setCurrentIndex(combo.findData(value))
        return combo

    @staticmethod
    def _pair(*widgets) -> QtWidgets.QWidget:
        w = QtWidgets.QWidget()
        row = QtWidgets.QHBoxLayout(w)
        row.setContentsMargins(0, 0, 0, 0)
        for x in widgets:
            row.addWidget(x)
        return w

    def _preset_chosen(self) -> None:
        values = self.preset.currentData()
        if not values:
            return
        self._setting = True
        for k, w in self.weights.items():
            w.setValue(values[k])
        for k, w in self.ops.items():
            w.setCurrentIndex(w.findData(values[k]))
        self.negate.setChecked(values["negate"])
        self._setting = False
        self.schedule()

    def _custom(self) -> None:
        if not getattr(self, "_setting", False):
            self.preset.blockSignals(True)
            self.preset.setCurrentIndex(0)
            self.preset.blockSignals(False)
        self.schedule()

    def _mask_kind_changed(self) -> None:
        kind = self.mask_kind.currentData()
        form = self._mask_form
        for widget, shown in ((self.mask_levels, kind in ("texture", "levels")),
                              (self.mask_group, kind == "texture"),
                              (self.paint_widget, kind == "painted")):
            widget.setVisible(shown)
            label = form.labelForField(widget)
            if label is not None:
                label.setVisible(shown)
        self.preview.painting = kind == "painted" and self.tabs.currentIndex() == 0
        self.preview.setCursor(QtCore.Qt.CursorShape.CrossCursor if self.preview.painting
                               else QtCore.Qt.CursorShape.ArrowCursor)
        self.schedule()

    def reset_painting(self) -> None:
        self.preview.painted_mask = np.zeros(self.main_window.document.shape, bool)
        self.schedule()

    # -- the action --------------------------------------------------------------------------------
    def action(self):
        """The Incrust or Mix of the current settings (TexeditorError says what is missing)."""
        source, refs = self.source.recipe()
        if self.tabs.currentIndex() == 2:
            recipes = [(source, refs)] + [p.recipe() for p in self.extra]
            union = tuple(dict.fromkeys(r for _, refs in recipes for r in refs))
            return MixTextures(tuple(text for text, _ in recipes), union,
                               expression=self.expression.text())
        if self.tabs.currentIndex() == 1:
            values = {k: w.value() for k, w in self.weights.items()}
            values.update({k: w.currentData() for k, w in self.ops.items()})
            return Mix(source, refs, negate=self.negate.isChecked(), **values)
        kind, block = self.mask_kind.currentData(), self.block.value()
        if kind == "texture":
            mask_source, mask_refs = self.mask_source.recipe()
            return Incrust(source, refs, mask="texture", levels=self.mask_levels.text(),
                           mask_source=mask_source, mask_dpjs=mask_refs, block=block)
        if kind == "levels":
            return Incrust(source, refs, mask="levels", levels=self.mask_levels.text(),
                           block=block)
        mask = self._selection() if kind == "selection" else self.preview.painted_mask
        if mask is None or not mask.any():
            raise TexeditorError("the mask is empty: " + (
                "select with the Extract tool (E) first" if kind == "selection"
                else "paint on the preview"))
        points = tuple(map(tuple, np.argwhere(mask).tolist()))
        return Incrust(source, refs, mask="points", points=points, block=block)

    def _selection(self):
        from .tools.regions import ExtractTool
        tool = next((t for t in self.main_window.tools if isinstance(t, ExtractTool)), None)
        return None if tool is None else tool.mask()

    # -- preview and apply -------------------------------------------------------------------------
    def schedule(self) -> None:
        self.preview.painting = (self.mask_kind.currentData() == "painted"
                                 and self.tabs.currentIndex() == 0)
        self.timer.start()

    def hideEvent(self, ev) -> None:
        self.timer.stop()                 # no work is started for a closed dialog
        super().hideEvent(ev)

    def showEvent(self, ev) -> None:
        super().showEvent(ev)
        QtCore.QTimer.singleShot(0, self, self._document_changed)   # catch up with the document

    def _document_changed(self, change=None) -> None:
        if self.main_window.history is not self._history or not self.isVisible():
            return
        for picker in (self.source, self.mask_source, *self.extra):
            picker.reload()
        if self.preview.painted_mask is None or self.preview.painted_mask.shape != self.main_window.document.shape:
            self.reset_painting()
        self.schedule()

    def update_preview(self) -> None:
        """Render the sources in the worker if needed, then compose on a copy of the document."""
        try:
            action = self.action()
        except TexeditorError as exc:
            self.status.setText(str(exc))
            self.apply_button.setEnabled(False)
            self._show(self.main_window.document.levels)
            return
        runner = self.main_window.runner
        if not self.isVisible():
            return
        if runner.busy:
            self.timer.start()
            return
        dpjs = dict(self.main_window.document.dpjs)
        holder = _Store(dpjs)
        runner.run("Rendering the composition's sources…",
                   lambda progress, cancel: action.prepare(holder, progress, cancel),
                   lambda _=None: self._compose(action),
                   on_error=lambda exc: self.status.setText(f"Cannot render a source: {exc}"))

    def _compose(self, action) -> None:
        scratch = self.main_window.document.copy()
        try:
            scratch.apply(action)
        except TexeditorError as exc:
            self.status.setText(str(exc))
            self.apply_button.setEnabled(False)
            return
        changed = int((scratch.levels != self.main_window.document.levels).sum())
        inside = None
        if isinstance(action, Incrust) and self.tint.isChecked():
            inside = action.membership(self.main_window.document)
        self._show(scratch.levels, inside)
        self.status.setText(f"{action.label()}, T2 = {self.source.describe()}: "
                            f"{changed:,} points change.")
        self.apply_button.setEnabled(True)
        self._last = action

    def _show(self, levels, inside=None) -> None:
        """The levels in the document's colours; where T2 shows, tinted (and the painting)."""
        palette = np.asarray(self.main_window.document.palette)
        rgb = palette[levels[:PREVIEW, :PREVIEW]].copy()
        if self.preview.painting and self.preview.painted_mask is not None:
            inside = self.preview.painted_mask if inside is None else inside | self.preview.painted_mask
        if inside is not None:
            m = inside[:PREVIEW, :PREVIEW]
            rgb[m] = (rgb[m] * 0.7 + np.array(TINT) * 0.3).astype(np.uint8)
        self.preview.show_rgb(rgb)

    def apply(self) -> None:
        try:
            action = self.action()
        except TexeditorError as exc:
            self.main_window.show_error("Cannot compose", exc)
            return
        if self.main_window.runner.busy:
            return
        holder = _Store(dict(self.main_window.document.dpjs))
        self.main_window.runner.run("Rendering the composition's sources…",
                               lambda progress, cancel: action.prepare(holder, progress, cancel),
                               lambda _=None: self.main_window.submit(action),
                               on_error=lambda exc: self.main_window.show_error("Cannot compose", exc))


class _Store:
    """What a source's preparation reads from a document: its DPJs (a copy, for the worker)."""

    def __init__(self, dpjs):
        self.dpjs = dpjs


def open_composition(window, dialog: CompositionDialog | None = None) -> CompositionDialog:
    """Show the (non-modal) composition dialog for the current document: ``dialog`` (the one
    shown before, which the window keeps) or a new one if it was for another document."""
    if dialog is None or dialog._history is not window.history:
        if dialog is not None:
            dialog._unsubscribe()
            dialog.close()
            dialog.deleteLater()
        dialog = CompositionDialog(window)
    dialog.show()
    dialog.raise_()
    return dialog
