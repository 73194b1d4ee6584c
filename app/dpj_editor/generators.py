"""Generators of a hand-made DPJ (thesis §5.2.2, digest §8, §11): from a seed, the weights of the
empty and all-maximum configurations, the grey scale's extremes, merging levels.

Each control produces a new DPJ through texeditor.markov.dpj_edit and hands it to the editor as an edit;
a slider drag is one gesture, so it becomes one undo step.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor.markov import dpj_edit

from ..palette_dock import grey_scale
from ..params_form import SeedEdit

WEIGHT_STEPS = 1000
ONE_STEP = -1          # an edit of its own (not part of a slider drag)
IN_BACKGROUND = -2     # an edit whose work may take seconds on a large DPJ: run it in the worker


class GeneratorsPanel(QtWidgets.QWidget):
    """``edited(function, text, gesture)``: apply ``function(dpj) -> dpj`` as one edit; edits
    sharing a non-negative ``gesture`` (one slider drag) merge into one undo step; ONE_STEP and
    IN_BACKGROUND are single steps, the second computed off the GUI thread."""

    edited = QtCore.Signal(object, str, int)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.dpj = None
        self._gesture = 0
        layout = QtWidgets.QVBoxLayout(self)
        layout.addWidget(self._seed_group())
        layout.addWidget(self._extremes_group())
        layout.addWidget(self._grey_group())
        layout.addWidget(self._merge_group())
        layout.addStretch(1)

    # -- from a seed -------------------------------------------------------------------------------
    def _seed_group(self) -> QtWidgets.QGroupBox:
        group = QtWidgets.QGroupBox("From a seed")
        form = QtWidgets.QFormLayout(group)
        self.seed = SeedEdit(1984)
        self.sparsity = QtWidgets.QSpinBox()
        self.sparsity.setRange(0, 99)
        self.sparsity.setSuffix(" %")
        self.sparsity.setToolTip("Share of configurations set to 0: more gives patterned textures")
        self.evenness = QtWidgets.QDoubleSpinBox()
        self.evenness.setRange(0.05, 100)
        self.evenness.setValue(1.0)
        self.evenness.setSingleStep(0.1)
        self.evenness.setToolTip("1: most configurations get a small value (granular); lower: a "
                                 "few take most of the probability (patterned)")
        self.generate_button = QtWidgets.QPushButton("Generate")
        self.generate_button.setToolTip("Draw every probability from the seed (replaces the DPJ)")
        self.generate_button.clicked.connect(self.generate)
        form.addRow("Seed", self.seed)
        form.addRow("Sparsity", self.sparsity)
        form.addRow("Evenness", self.evenness)
        form.addRow(self.generate_button)
        return group

    def generate(self) -> None:
        seed, sparsity, evenness = self.seed.value(), self.sparsity.value() / 100, \
            self.evenness.value()

        def draw(dpj):
            return dpj_edit.random_dpj(dpj.window, dpj.levels, seed, sparsity=sparsity,
                                       evenness=evenness, palette=dpj.palette,
                                       meta={"name": dpj.meta.get("name", "hand-made")})
        self.edited.emit(draw, f"Generate from seed {seed}", IN_BACKGROUND)

    # -- the empty and all-maximum configurations --------------------------------------------------
    def _extremes_group(self) -> QtWidgets.QGroupBox:
        group = QtWidgets.QGroupBox("Extreme configurations")
        form = QtWidgets.QFormLayout(group)
        self.empty = self._weight_slider("Probability of the empty configuration (every point "
                                         "level 0): high → airy, low → dense")
        self.full = self._weight_slider("Probability of the all-maximum configuration (every "
                                        "point level G−1)")
        self.empty_label, self.full_label = QtWidgets.QLabel(), QtWidgets.QLabel()
        form.addRow("Empty (all 0)", self._with_label(self.empty, self.empty_label))
        form.addRow("All maximum", self._with_label(self.full, self.full_label))
        return group

    def _weight_slider(self, tip: str) -> QtWidgets.QSlider:
        s = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        s.setRange(0, WEIGHT_STEPS)
        s.setToolTip(tip)
        s.sliderPressed.connect(self._new_gesture)
        s.valueChanged.connect(self._extremes_moved)
        return s

    def _with_label(self, widget, label) -> QtWidgets.QWidget:
        box = QtWidgets.QWidget()
        row = QtWidgets.QHBoxLayout(box)
        row.setContentsMargins(0, 0, 0, 0)
        label.setMinimumWidth(self.fontMetrics().horizontalAdvance("0.0000") + 4)
        A = QtCore.Qt.AlignmentFlag
        label.setAlignment(A.AlignRight | A.AlignVCenter)
        row.addWidget(widget, 1)
        row.addWidget(label)
        return box

    def _new_gesture(self) -> None:
        self._gesture += 1

    def _extremes_moved(self, _value) -> None:
        empty, full = self.empty.value() / WEIGHT_STEPS, self.full.value() / WEIGHT_STEPS
        self.empty_label.setText(f"{empty:.3f}")
        self.full_label.setText(f"{full:.3f}")
        dragging = self.empty.isSliderDown() or self.full.isSliderDown()
        self.edited.emit(lambda dpj: dpj_edit.set_extremes(dpj, empty=empty, full=full),
                         f"Empty {empty:.3f}, all-maximum {full:.3f}",
                         1_000_000 + self._gesture if dragging else ONE_STEP)

    def set_extremes(self, empty: float, full: float) -> None:
        """Set the sliders (tests, scripts) as a user would: one edit each."""
        self.empty.setValue(round(empty * WEIGHT_STEPS))
        self.full.setValue(round(full * WEIGHT_STEPS))

    # -- the grey scale (the DPJ's palette) --------------------------------------------------------
    def _grey_group(self) -> QtWidgets.QGroupBox:
        group = QtWidgets.QGroupBox("Grey scale of the levels")
        form = QtWidgets.QFormLayout(group)
        self.darkest = self._grey_slider(0, 255, 0, "Grey of level 0 (the background)")
        self.lightest = self._grey_slider(0, 255, 255, "Grey of the highest level: lower it so "
                                          "its grains do not stand out (§5.2.2)")
        self.contrast = self._grey_slider(-100, 100, 0, "Spread of the middle levels")
        form.addRow("Darkest", self.darkest)
        form.addRow("Lightest", self.lightest)
        form.addRow("Contrast", self.contrast)
        return group

    def _grey_slider(self, lo, hi, value, tip) -> QtWidgets.QSlider:
        s = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        s.setRange(lo, hi)
        s.setValue(value)
        s.setToolTip(tip)
        s.sliderPressed.connect(self._new_gesture)
        s.valueChanged.connect(self._grey_moved)
        return s

    def _grey_moved(self, _value) -> None:
        dark, light, contrast = self.darkest.value(), self.lightest.value(), self.contrast.value()
        dragging = any(s.isSliderDown() for s in (self.darkest, self.lightest, self.contrast))
        self.edited.emit(lambda dpj: dpj.with_palette(grey_scale(dpj.levels, dark, light,
                                                                 contrast)),
                         "Grey scale", 2_000_000 + self._gesture if dragging else ONE_STEP)

    # -- merging levels (R = QᵀPQ) -----------------------------------------------------------------
    def _merge_group(self) -> QtWidgets.QGroupBox:
        group = QtWidgets.QGroupBox("Merge or remap levels")
        layout = QtWidgets.QVBoxLayout(group)
        self.merge_grid = QtWidgets.QGridLayout()
        layout.addLayout(self.merge_grid)
        self.merge_boxes: list[QtWidgets.QSpinBox] = []
        buttons = QtWidgets.QHBoxLayout()
        self.pairs_button = QtWidgets.QPushButton("Pairs")
        self.pairs_button.setToolTip("Level k becomes k ÷ 2 (e.g. 8 levels to 4)")
        self.pairs_button.clicked.connect(self._pairs)
        self.merge_button = QtWidgets.QPushButton("Merge")
        self.merge_button.setToolTip("Recolour every configuration with this mapping and add the "
                                     "probabilities that meet: exact (R = QᵀPQ)")
        self.merge_button.clicked.connect(self.merge)
        buttons.addWidget(self.pairs_button)
        buttons.addStretch(1)
        buttons.addWidget(self.merge_button)
        layout.addLayout(buttons)
        return group

    def _rebuild_merge_boxes(self, levels: int) -> None:
        while self.merge_grid.count():
            self.merge_grid.takeAt(0).widget().deleteLater()
        self.merge_boxes = []
        for k in range(levels):
            box = QtWidgets.QSpinBox()
            box.setRange(0, levels - 1)
            box.setValue(k)
            box.setPrefix(f"{k} → ")
            box.setToolTip(f"The new level of level {k}")
            self.merge_grid.addWidget(box, k // 4, k % 4)
            self.merge_boxes.append(box)

    def mapping(self) -> list[int]:
        return [b.value() for b in self.merge_boxes]

    def set_mapping(self, mapping) -> None:
        for box, value in zip(self.merge_boxes, mapping):
            box.setValue(int(value))

    def _pairs(self) -> None:
        self.set_mapping([k // 2 for k in range(len(self.merge_boxes))])

    def merge(self) -> None:
        mapping = self.mapping()
        self.edited.emit(lambda dpj: dpj_edit.merge_levels(dpj, mapping),
                         f"Merge levels {' '.join(map(str, mapping))}", IN_BACKGROUND)

    # -- following the DPJ -------------------------------------------------------------------------
    def set_dpj(self, dpj) -> None:
        """Show the DPJ's own values on the sliders, without emitting edits."""
        old, self.dpj = self.dpj, dpj
        if old is None or old.levels != dpj.levels:
            self._rebuild_merge_boxes(dpj.levels)
        empty = dpj.prob(dpj_edit.empty_config(dpj))
        full = dpj.prob(dpj_edit.full_config(dpj))
        for slider, value, label in ((self.empty, empty, self.empty_label),
                                     (self.full, full, self.full_label)):
            if not slider.isSliderDown():
                slider.blockSignals(True)
                slider.setValue(round(value * WEIGHT_STEPS))
                slider.blockSignals(False)
            label.setText(f"{value:.3f}")
        grey = dpj.palette[:, 0]
        if np.all(dpj.palette == grey[:, None]) and not any(
                s.isSliderDown() for s in (self.darkest, self.lightest, self.contrast)):
            for slider, value in ((self.darkest, grey[0]), (self.lightest, grey[-1])):
                slider.blockSignals(True)
                slider.setValue(int(value))
                slider.blockSignals(False)
