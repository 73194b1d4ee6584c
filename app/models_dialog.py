"""Models ▸ Random-phase noise / Texton / Match histogram…: a model of a photo as one step.

The photo becomes an exemplar of the document (`recipe.exemplars`: kept by reference, saved in
the `.texture` and the bank), and the step names it, so it replays like any other. The preview
is the step itself run on a scratch document — a 256² random-phase noise takes milliseconds,
so it runs here on the GUI thread — and OK applies what the preview shows (undoable).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor.errors import TexeditorError
from texeditor.markov.levels import load_image, to_grey, to_rgb, has_colour
from texeditor.recipe.document import Document
from texeditor.recipe.exemplars import MAX_SIDE
from texeditor.spectral.actions import MatchHistogram, RandomPhaseNoise, Texton, MAX_MODEL_SIDE

from . import resources
from .acquire_dialog import IMAGE_FILTER
from .images import photo_rgb, pixmap
from .params_form import SeedEdit

PREVIEW = 240
TITLES = {"random_phase_noise": "Random-phase noise from a photo",
          "texton": "Texton of a photo", "match_histogram": "Match histogram to a photo"}
ABOUT = {
    "random_phase_noise": "The photo's Fourier modulus with random phases (Desolneux, Moisan, "
                          "Ronsin): a new sample of its micro-texture, of any size, tileable. "
                          "Best on fine, irregular textures (sand, gravel, plaster); objects and "
                          "edges are lost.",
    "texton": "The photo's Fourier modulus with zero phases: the elementary shape of its "
              "micro-texture (its size, direction, anisotropy), centred.",
    "match_histogram": "The texture's colours mapped so that the picture has the photo's grey or "
                       "colour distribution (φ = c_f⁻¹ ∘ c_g, per channel); the levels stay.",
}


def exemplar_from(image: np.ndarray) -> tuple[np.ndarray, str]:
    """A photo as an exemplar: uint8 grey or RGB (alpha laid on white), its middle 1024² at
    most (a crop, not a reduction: a micro-texture's grain keeps its scale); and a note."""
    colour = has_colour(image)
    unit = to_rgb(image) if colour else to_grey(image)
    h, w = unit.shape[:2]
    top, left = max((h - MAX_SIDE) // 2, 0), max((w - MAX_SIDE) // 2, 0)
    crop = unit[top:top + MAX_SIDE, left:left + MAX_SIDE]
    note = f" (its middle {crop.shape[1]}×{crop.shape[0]})" if crop.shape[:2] != (h, w) else ""
    return np.round(crop * 255).astype(np.uint8), note


class ModelDialog(QtWidgets.QDialog):
    """One model's settings, a live preview and OK, which applies the step."""

    def __init__(self, window, model: str):
        super().__init__(window)
        self.main_window, self.model = window, model
        self.setWindowTitle(TITLES[model])
        self.exemplar: np.ndarray | None = None
        self.result = None                     # (action, prepared) the preview shows
        self.photo = QtWidgets.QComboBox()
        for path in resources.sample_images():
            self.photo.addItem(path.stem, str(path))
        self.browse = QtWidgets.QPushButton("Browse…")
        h, w = window.document.shape
        self.width_box = self._spin(w or 256, "Points across")
        self.height_box = self._spin(h or 256, "Points down")
        self.seed = SeedEdit(1)
        self.levels = QtWidgets.QSpinBox()
        self.levels.setRange(2, 16)
        self.levels.setValue(window.document.num_levels if window.document.levels.size else 8)
        self.levels.setToolTip("Number of levels G the model's output is cut into (Lloyd on "
                               "greys, colour classes in CIELAB on colours)")
        self.photo_view, self.result_view = self._view(), self._view()
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)
        buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Ok
                                             | QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        self.ok = buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
        buttons.accepted.connect(self.apply)
        buttons.rejected.connect(self.reject)
        self._layout(buttons)
        self._timer = QtCore.QTimer(self, singleShot=True, interval=120)
        self._timer.timeout.connect(self.recompute)
        self.photo.currentIndexChanged.connect(self.load_photo)
        self.browse.clicked.connect(self.choose_file)
        for box in (self.width_box, self.height_box, self.levels):
            box.valueChanged.connect(self._timer.start)
        self.seed.changed.connect(self._timer.start)
        self.load_photo()

    @staticmethod
    def _spin(value: int, tip: str) -> QtWidgets.QSpinBox:
        box = QtWidgets.QSpinBox()
        box.setRange(1, MAX_MODEL_SIDE)
        box.setValue(min(max(value, 1), MAX_MODEL_SIDE))
        box.setToolTip(tip)
        return box

    @staticmethod
    def _view() -> QtWidgets.QLabel:
        label = QtWidgets.QLabel()
        label.setFixedSize(PREVIEW, PREVIEW)
        label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        label.setFrameShape(QtWidgets.QFrame.Shape.StyledPanel)
        return label

    def _layout(self, buttons) -> None:
        layout = QtWidgets.QVBoxLayout(self)
        about = QtWidgets.QLabel(ABOUT[self.model])
        about.setWordWrap(True)
        layout.addWidget(about)
        form = QtWidgets.QFormLayout()
        row = QtWidgets.QHBoxLayout()
        row.addWidget(self.photo, 1)
        row.addWidget(self.browse)
        form.addRow("Photo", row)
        if self.model == "random_phase_noise":
            size = QtWidgets.QHBoxLayout()
            size.addWidget(self.width_box)
            size.addWidget(QtWidgets.QLabel("×"))
            size.addWidget(self.height_box)
            size.addWidget(QtWidgets.QLabel("points"))
            size.addStretch(1)
            form.addRow("Size", size)
            form.addRow("Seed", self.seed)
        if self.model != "match_histogram":
            form.addRow("Levels G", self.levels)
        layout.addLayout(form)
        views = QtWidgets.QGridLayout()
        after = "Texture with the photo's histogram" if self.model == "match_histogram" \
            else "Result"
        for k, (text, view) in enumerate((("Photo", self.photo_view),
                                          (after, self.result_view))):
            views.addWidget(QtWidgets.QLabel(text), 0, k)
            views.addWidget(view, 1, k)
        layout.addLayout(views)
        layout.addWidget(self.info)
        layout.addWidget(buttons)

    def choose_file(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Choose a photo", "", IMAGE_FILTER)
        if path:
            self.set_photo(path)

    def set_photo(self, path) -> None:
        path = Path(path)
        index = self.photo.findData(str(path))
        if index < 0:
            self.photo.addItem(path.name, str(path))
            index = self.photo.count() - 1
        self.photo.setCurrentIndex(index)
        self.load_photo()

    def load_photo(self) -> None:
        self.exemplar, self.note, self.result = None, "", None
        self.ok.setEnabled(False)
        path = self.photo.currentData()
        try:
            if path is None:
                raise TexeditorError("choose a photo with Browse…")
            self.exemplar, self.note = exemplar_from(load_image(path))
        except TexeditorError as exc:
            self._failed(exc)
            return
        self.photo_view.setPixmap(pixmap(photo_rgb(self.exemplar), PREVIEW))
        self.recompute()

    def action(self, ref: str):
        if self.model == "random_phase_noise":
            return RandomPhaseNoise(ref, self.width_box.value(), self.height_box.value(),
                                    self.seed.value(), self.levels.value())
        if self.model == "texton":
            return Texton(ref, self.levels.value())
        return MatchHistogram(ref)

    def recompute(self) -> None:
        """Run the step on a scratch copy of the document (the exemplar added): the preview is
        exactly what OK applies."""
        self.result = None
        self.ok.setEnabled(False)
        if self.exemplar is None:
            return
        try:
            scratch = self.main_window.document.copy() if self.model == "match_histogram" \
                else Document()
            action = self.action(scratch.add_exemplar(self.exemplar))
            prepared = action.prepare(scratch)
            with scratch.step():
                action.apply(scratch, prepared)
        except TexeditorError as exc:
            self._failed(exc)
            return
        self.result_view.setPixmap(pixmap(np.asarray(scratch.palette)[scratch.levels], PREVIEW))
        h, w = self.exemplar.shape[:2]
        kind = "colour" if self.exemplar.ndim == 3 else "grey"
        self.info.setText(f"Photo {w}×{h}, {kind}{self.note}. Result {scratch.shape[1]}×"
                          f"{scratch.shape[0]}, G = {scratch.num_levels}. OK adds one step "
                          "(undo takes it back).")
        self.result = (action, prepared)
        self.ok.setEnabled(True)

    def _failed(self, exc) -> None:
        self.result_view.clear()
        self.info.setText(f"<span style='color:#b00020'>{exc}</span>")

    def apply(self) -> None:
        if self.result is None:
            return
        action, prepared = self.result
        self.main_window.history.add_exemplar(self.exemplar)
        if self.main_window.submit(action, prepared=prepared):
            self.accept()


def open_model(window, model: str) -> ModelDialog | None:
    """The dialog of one model (histogram matching needs a texture to recolour)."""
    if model == "match_histogram" and not window.document.levels.size:
        window.statusBar().showMessage("Match histogram: make or open a texture first.", 5000)
        return None
    dialog = ModelDialog(window, model)
    dialog.finished.connect(dialog.deleteLater)
    dialog.open()
    return dialog
