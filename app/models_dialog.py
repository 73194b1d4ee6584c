"""Models ▸ Random-phase noise / Texton / Match histogram / Heeger–Bergen…: a model of a photo
as one step.

The photo becomes an exemplar of the document (`recipe.exemplars`: kept by reference, saved in
the `.texture` and the bank), and the step names it, so it replays like any other. The preview
is the step itself run on a scratch document in the background (a 2048² colour model or a
Heeger–Bergen synthesis takes seconds), the latest change winning, with its progress shown; OK
applies what the preview shows (undoable).
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtWidgets

from texeditor.errors import TexeditorError
from texeditor.recipe.document import Document
from texeditor.pyramid.actions import HeegerBergen
from texeditor.pyramid.synthesis import ITERATIONS, MAX_ITERATIONS
from texeditor.spectral.actions import MatchHistogram, RandomPhaseNoise, Texton, MAX_MODEL_SIDE

from .images import photo_rgb, pixmap
from .params_form import SeedEdit
from .step_dialog import PREVIEW, StepDialog, photo_box, preview_view
from .widgets import row, spin_box
TITLES = {"random_phase_noise": "Random-phase noise from a photo",
          "texton": "Texton of a photo", "match_histogram": "Match histogram to a photo",
          "heeger_bergen": "Heeger–Bergen texture from a photo"}
SIZED = ("random_phase_noise", "heeger_bergen")          # models drawn at any size from a seed
ABOUT = {
    "random_phase_noise": "The photo's Fourier modulus with random phases (Desolneux, Moisan, "
                          "Ronsin): a new sample of its micro-texture, of any size, tileable. "
                          "Best on fine, irregular textures (sand, gravel, plaster); objects and "
                          "edges are lost.",
    "texton": "The photo's Fourier modulus with zero phases: the elementary shape of its "
              "micro-texture (its size, direction, anisotropy), centred.",
    "match_histogram": "The texture's colours mapped so that the picture has the photo's grey or "
                       "colour distribution (φ = c_f⁻¹ ∘ c_g, per channel); the levels stay.",
    "heeger_bergen": "Noise given the histograms of the photo's steerable-pyramid sub-bands and "
                     "of its greys (Heeger and Bergen): a new sample of a continuous-tone "
                     "texture, of any size, tileable. Best on stochastic textures (stone, "
                     "bark, clouds); regular patterns lose their order.",
}


class ModelDialog(StepDialog):
    """One model's settings, a live preview and OK, which applies the step."""

    def __init__(self, window, model: str):
        super().__init__(window, TITLES[model])
        self.model = model
        self.exemplar: np.ndarray | None = None
        self.photo, self.browse = photo_box()
        h, w = window.document.shape
        self.width_box = spin_box(16, MAX_MODEL_SIDE, w or 256, tip="Points across")
        self.height_box = spin_box(16, MAX_MODEL_SIDE, h or 256, tip="Points down")
        self.seed = SeedEdit(1)
        self.iterations = spin_box(0, MAX_ITERATIONS, ITERATIONS,
                                   tip="Rounds of histogram matching: about five suffice")
        self.levels = spin_box(2, 16, window.document.num_levels
                               if window.document.levels.size else 8,
                               tip="Number of levels G the model's output is cut into (Lloyd "
                                   "on greys, colour classes in CIELAB on colours)")
        self.photo_view = preview_view()
        self._layout()
        self.photo.currentIndexChanged.connect(self.load_photo)
        self.browse.clicked.connect(self.choose_file)
        for box in (self.width_box, self.height_box, self.levels, self.iterations):
            box.valueChanged.connect(self.recompute)
        self.seed.changed.connect(self.recompute)
        self.load_photo()

    def _layout(self) -> None:
        layout, form = self.start(ABOUT[self.model])
        form.addRow("Photo", row(self.photo, self.browse, stretch=False))
        if self.model in SIZED:
            form.addRow("Size", row(self.width_box, "×", self.height_box, "points"))
            form.addRow("Seed", self.seed)
        if self.model == "heeger_bergen":
            form.addRow("Iterations", row(self.iterations))
        if self.model != "match_histogram":
            form.addRow("Levels G", row(self.levels))
        layout.addLayout(form)
        views = QtWidgets.QGridLayout()
        after = "Texture with the photo's histogram" if self.model == "match_histogram" \
            else "Result"
        for k, (text, view) in enumerate((("Photo", self.photo_view),
                                          (after, self.result_view))):
            views.addWidget(QtWidgets.QLabel(text), 0, k)
            views.addWidget(view, 1, k)
        layout.addLayout(views)
        self.finish(layout)

    def load_photo(self) -> None:
        self.exemplar, self.note = None, ""
        self._waiting()
        try:
            self.read_photo()
        except TexeditorError as exc:
            self.photo_view.clear()
            self._failed(exc)
            return
        self.photo_view.setPixmap(pixmap(photo_rgb(self.exemplar), PREVIEW))
        self.recompute()

    def action(self, ref: str):
        if self.model == "random_phase_noise":
            return RandomPhaseNoise(ref, self.width_box.value(), self.height_box.value(),
                                    self.seed.value(), self.levels.value())
        if self.model == "heeger_bergen":
            return HeegerBergen(ref, self.width_box.value(), self.height_box.value(),
                                self.seed.value(), self.iterations.value(), self.levels.value())
        if self.model == "texton":
            return Texton(ref, self.levels.value())
        return MatchHistogram(ref)

    def recompute(self) -> None:
        """Run the step on a scratch copy of the document (the exemplar added) in the
        background: the preview is exactly what OK applies."""
        self._waiting()
        if self.exemplar is None:
            return
        scratch = self.main_window.document.copy() if self.model == "match_histogram" \
            else Document()
        try:
            action = self.action(scratch.add_exemplar(self.exemplar))
        except TexeditorError as exc:
            self._failed(exc)
            return
        self.request(action, scratch)

    def show_result(self, action, scratch) -> None:
        self.result_view.setPixmap(pixmap(np.asarray(scratch.palette)[scratch.levels], PREVIEW))
        h, w = self.exemplar.shape[:2]
        kind = "colour" if self.exemplar.ndim == 3 else "grey"
        self.info.setText(f"Photo {w}×{h}, {kind}{self.note}. Result {scratch.shape[1]}×"
                          f"{scratch.shape[0]}, G = {scratch.num_levels}. OK adds one step "
                          "(undo takes it back).")

    def before_apply(self, action) -> None:
        self.main_window.history.add_exemplar(self.exemplar)


def open_model(window, model: str):
    """The dialog of one model, deleted once closed; a model that works on the current texture
    (histogram matching recolours it, a motif is stamped on it) needs one first."""
    needs_texture = {"match_histogram": "Match histogram", "ifs_motif": "IFS motif"}
    if window.still_opening():               # the first texture, in the worker
        return None
    if model in needs_texture and not window.document.levels.size:
        window.statusBar().showMessage(f"{needs_texture[model]}: make or open a texture first.",
                                       5000)
        return None
    if model in ("fractal_relief", "ifs_motif"):            # no photo: their own dialog
        from .fractal_dialog import FractalDialog
        dialog = FractalDialog(window, model)
    elif model == "flow_texture":
        from .flow_dialog import FlowDialog
        dialog = FlowDialog(window)
    else:
        dialog = ModelDialog(window, model)
    dialog.finished.connect(dialog.deleteLater)
    dialog.open()
    return dialog
