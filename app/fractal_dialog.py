"""Models ▸ Fractal relief… / IFS motif…: the fractal models of the companion documents as one
step each (digest §11: midpoint displacement, 003; IFS, 002).

The preview is the step itself run on a scratch document in the background (`LatestWins`), the
latest setting winning; OK applies exactly what the preview shows (undoable). The relief shows
its levels and the relief preview's shading (texeditor.relief) side by side; the motif shows
the texture with the motif stamped on it.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor.errors import TexeditorError
from texeditor.fractal.actions import MAX_MOTIF_SIDE, FractalRelief, IFSMotif
from texeditor.fractal.ifs import BUILTINS
from texeditor.recipe.document import Document
from texeditor.relief.previews import plane_preview
from texeditor.spectral.actions import MAX_MODEL_SIDE

from .images import pixmap
from .params_form import SeedEdit
from .step_dialog import PREVIEW, StepDialog, preview_view
from .widgets import row, spin_box
TITLES = {"fractal_relief": "Fractal relief", "ifs_motif": "IFS motif"}
ABOUT = {
    "fractal_relief": "Heights by 2-D midpoint displacement (companion 003): each point of a "
                      "grid computed once, its deviation falling by 2^−H a level; cut into G "
                      "levels whose greys rise with the height, so the Relief dock shades it "
                      "as terrain. Tileable.",
    "ifs_motif": "An IFS attractor drawn by the chaos game (companion 002): the digest's tree, "
                 "Barnsley's fern or Sierpinski's triangle, stamped in one level on the "
                 "texture (undo takes it back).",
}
MOTIF_NAMES = {"tree": "Tree (the digest's IFS)", "fern": "Barnsley fern",
               "sierpinski": "Sierpinski triangle"}


class FractalDialog(StepDialog):
    """One fractal model's settings, a live preview and OK, which applies the step."""

    def __init__(self, window, model: str):
        super().__init__(window, TITLES[model])
        self.model = model
        doc = window.document
        h, w = doc.shape
        self.width_box = spin_box(1, MAX_MODEL_SIDE, w or 256, tip="Points across")
        self.height_box = spin_box(1, MAX_MODEL_SIDE, h or 256, tip="Points down")
        self.seed = SeedEdit(1)
        self.roughness = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        self.roughness.setRange(0, 100)
        self.roughness.setValue(50)
        self.roughness.setToolTip("H: 1 smooth hills, 0 rough ground")
        self.roughness_label = QtWidgets.QLabel()
        self.levels = spin_box(2, 16, doc.num_levels if doc.levels.size else 8,
                               tip="Number of levels G the heights are cut into")
        self.motif = QtWidgets.QComboBox()
        for name in BUILTINS:
            self.motif.addItem(MOTIF_NAMES.get(name, name), name)
        side = max(min(h, w) // 2, 8)
        self.size_box = spin_box(1, MAX_MOTIF_SIDE, side, tip="Side of the motif's square")
        self.row_box = spin_box(-MAX_MOTIF_SIDE, 65536, h // 2, tip="Row of the motif's centre")
        self.col_box = spin_box(-MAX_MOTIF_SIDE, 65536, w // 2, tip="Column of its centre")
        self.points = spin_box(1000, 1 << 24, 200_000, tip="Chaos-game points: more, denser")
        self.density = spin_box(1, 1000, 1, tip="Hits a point needs to be painted")
        self.level = spin_box(0, max(doc.num_levels - 1, 0), max(doc.num_levels - 1, 0),
                              tip="The level the motif is painted in")
        self.shaded_view = preview_view()
        self._layout()
        for box in (self.width_box, self.height_box, self.levels, self.size_box, self.row_box,
                    self.col_box, self.points, self.density, self.level):
            box.valueChanged.connect(self.recompute)
        self.roughness.valueChanged.connect(self.recompute)
        self.motif.currentIndexChanged.connect(self.recompute)
        self.seed.changed.connect(self.recompute)
        self.recompute()

    def _layout(self) -> None:
        layout, form = self.start(ABOUT[self.model])
        if self.model == "fractal_relief":
            form.addRow("Size", row(self.width_box, "×", self.height_box, "points"))
            form.addRow("Roughness H", row(self.roughness, self.roughness_label, stretch=False))
            form.addRow("Levels G", row(self.levels))
        else:
            form.addRow("Motif", row(self.motif))
            form.addRow("Square", row(self.size_box, "points, centre row", self.row_box,
                                      "column", self.col_box))
            form.addRow("Points", row(self.points, "painted from", self.density, "hits"))
            form.addRow("Level", row(self.level))
        form.addRow("Seed", self.seed)
        layout.addLayout(form)
        views = QtWidgets.QGridLayout()
        shown = (("Levels", self.result_view), ("Relief", self.shaded_view)) \
            if self.model == "fractal_relief" else (("Texture with the motif", self.result_view),)
        for k, (text, view) in enumerate(shown):
            views.addWidget(QtWidgets.QLabel(text), 0, k)
            views.addWidget(view, 1, k)
        layout.addLayout(views)
        self.finish(layout)

    def action(self):
        if self.model == "fractal_relief":
            return FractalRelief(self.width_box.value(), self.height_box.value(),
                                 self.seed.value(), self.roughness.value() / 100,
                                 self.levels.value())
        return IFSMotif(self.motif.currentData(), self.row_box.value(), self.col_box.value(),
                        self.size_box.value(), self.level.value(), self.seed.value(),
                        self.points.value(), self.density.value())

    def recompute(self) -> None:
        """Run the step on a scratch document in the background: the preview is OK's step."""
        self.roughness_label.setText(f"{self.roughness.value() / 100:.2f}")
        self._waiting()
        scratch = Document() if self.model == "fractal_relief" \
            else self.main_window.document.copy()
        try:
            action = self.action()
        except TexeditorError as exc:
            self._failed(exc)
            return
        self.request(action, scratch)

    def show_result(self, action, scratch) -> None:
        picture = np.asarray(scratch.palette)[scratch.levels]
        self.result_view.setPixmap(pixmap(picture, PREVIEW))
        if self.model == "fractal_relief":
            self.shaded_view.setPixmap(pixmap(plane_preview(scratch.levels, scratch.palette,
                                                            size=PREVIEW), PREVIEW))
        self.info.setText(f"Result {scratch.shape[1]}×{scratch.shape[0]}, G = "
                          f"{scratch.num_levels}. OK adds one step (undo takes it back).")
