"""Image ▸ Double the levels… (thesis §4.5): learn from a photo how each grey level splits in two
given its 8 neighbours, then turn the G-level texture into a 2G-level one — one Action.

The photo defaults to the one the current DPJ was acquired from (and its quantiser), so the step
reads "acquire, synthesise with few levels, double". The table is a DPJ kept in the document's
store and saved with it. Learning it takes milliseconds on a small photo but seconds on a
12-megapixel one, so it runs in a worker, the latest setting winning (as the acquisition
dialog's), each photo and quantiser learnt once: a new seed only draws the preview again.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shiboken6
from PySide6 import QtCore, QtWidgets

from texeditor.markov import doubling
from texeditor.errors import TexeditorError
from texeditor.markov.levels import load_image
from texeditor.texture.actions import DoubleLevels

from . import resources
from .acquire_dialog import IMAGE_FILTER, QUANTISERS
from .dpj_editor.preview import LatestWins
from .images import pixmap
from .params_form import SeedEdit
from .widgets import select_path

PREVIEW = 200


class DoublingDialog(QtWidgets.QDialog):
    def __init__(self, window):
        super().__init__(window)
        self.main_window = window
        self.setWindowTitle("Double the grey levels")
        self.table = None
        self.doubling = False  # Double pressed: the levels are being doubled in the worker
        self.learnt = {}       # (path, quantiser, G) → (photo at 2G levels as RGB, table)
        self.worker = LatestWins(self)
        self.worker.done.connect(self._shown)
        self.worker.failed.connect(lambda exc: self._say(f"Cannot learn from this photo: {exc}"))
        self.finished.connect(lambda _result: self.worker.stop())
        self.paths: list[Path] = list(resources.sample_images())
        self.photo = QtWidgets.QComboBox()
        for path in self.paths:
            self.photo.addItem(path.stem, str(path))
        self.browse = QtWidgets.QPushButton("Browse…")
        self.method = QtWidgets.QComboBox()
        for text, key in QUANTISERS:
            self.method.addItem(text, key)
        self.seed = SeedEdit(1)
        self.photo_view = self._view("The photo at 2G levels: each level of the G-level "
                                     "quantisation cut in two at its mean grey")
        self.before_view = self._view("The texture now, at G levels (its top-left corner)")
        self.result_view = self._view("The texture doubled (its top-left corner)")
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)
        buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        self.apply_button = buttons.addButton("Double",
                                              QtWidgets.QDialogButtonBox.ButtonRole.AcceptRole)
        self.apply_button.setDefault(True)
        buttons.accepted.connect(self.apply)
        buttons.rejected.connect(self.reject)

        layout = QtWidgets.QVBoxLayout(self)
        form = QtWidgets.QFormLayout()
        row = QtWidgets.QHBoxLayout()
        row.addWidget(self.photo, 1)
        row.addWidget(self.browse)
        form.addRow("Photo", row)
        form.addRow("Quantiser", self.method)
        form.addRow("Seed", self.seed)
        layout.addLayout(form)
        views = QtWidgets.QGridLayout()
        for k, (text, view) in enumerate((("Photo at 2G levels", self.photo_view),
                                          ("Texture now, G levels", self.before_view),
                                          ("Texture doubled, 2G levels", self.result_view))):
            views.addWidget(QtWidgets.QLabel(text), 0, k)
            views.addWidget(view, 1, k)
        layout.addLayout(views)
        layout.addWidget(self.info)
        layout.addWidget(buttons)

        self._defaults()
        self.photo.currentIndexChanged.connect(self.recompute)
        self.method.currentIndexChanged.connect(self.recompute)
        self.seed.changed.connect(self.recompute)
        self.browse.clicked.connect(self.choose_file)
        self.recompute()

    @staticmethod
    def _view(tip: str) -> QtWidgets.QLabel:
        label = QtWidgets.QLabel()
        label.setFixedSize(PREVIEW, PREVIEW)
        label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        label.setFrameShape(QtWidgets.QFrame.Shape.StyledPanel)
        label.setToolTip(tip)
        return label

    def _defaults(self) -> None:
        """The photo and quantiser the current DPJ was acquired with, when known."""
        dpj = self.main_window.document.dpj
        meta = dpj.meta if dpj is not None else {}
        image = str(meta.get("image") or meta.get("source") or meta.get("name") or "")
        for k, path in enumerate(self.paths):
            if path.name == image or path.stem in image.split():
                self.photo.setCurrentIndex(k)
        method = meta.get("quantiser") or meta.get("quantizer")
        if method is not None and self.method.findData(method) >= 0:
            self.method.setCurrentIndex(self.method.findData(method))

    def choose_file(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Photo to learn from", "",
                                                        IMAGE_FILTER)
        if path:
            self.set_photo(path)

    def set_photo(self, path) -> None:
        select_path(self.photo, path)

    def recompute(self) -> None:
        """Learn the table from the photo and preview the doubled texture, in the worker;
        until it answers, Double is disabled."""
        self.table = None
        self.apply_button.setEnabled(False)
        doc = self.main_window.document
        path = self.photo.currentData()
        if path is None:
            self._say("choose a photo with Browse…")
            return
        self.info.setText("Learning from the photo…")
        key = (path, self.method.currentData(), doc.num_levels)
        crop, seed = doc.levels[:PREVIEW, :PREVIEW].copy(), self.seed.value()
        self.worker.request(lambda _progress, _cancel: self._learn(key, crop, seed))

    def _learn(self, key, crop, seed):
        """The worker's part: the photo's table (learnt once a photo, quantiser and G) and the
        preview doubled with it."""
        if key not in self.learnt:
            path, method, g = key
            try:
                image = load_image(path)
                refined = doubling.refine(image, g, method)
                table = doubling.learn(image, g, method, name=Path(path).stem)
            except TexeditorError as exc:
                return key, str(exc), crop, None
            self.learnt[key] = (np.asarray(refined.palette)[refined.children], table)
        return key, None, crop, doubling.double_levels(crop, self.learnt[key][1], seed)

    def wait(self, timeout_ms: int = 30_000) -> bool:
        """Block until the current settings' preview is shown (tests and scripts only)."""
        return self.worker.wait(timeout_ms)

    def _say(self, message: str) -> None:
        self.info.setText(f"<span style='color:#b00020'>{message}</span>")
        QtCore.QTimer.singleShot(0, self, self._make_room)

    def _shown(self, outcome) -> None:
        key, error, crop, result = outcome
        if error is not None:
            self._say(error)
            return
        picture, table = self.learnt[key]
        doc, g = self.main_window.document, key[2]
        self.photo_view.setPixmap(pixmap(picture, PREVIEW))
        self.before_view.setPixmap(pixmap(np.asarray(doc.palette)[crop], PREVIEW))
        self.result_view.setPixmap(pixmap(np.asarray(table.palette)[result.levels], PREVIEW))
        eight, four, own, none = result.contexts
        self.info.setText(
            f"G = {g} → {2 * g} levels: every level b becomes 2b or 2b + 1, drawn with the "
            f"photo's law given the 8 neighbours ({len(table):,} configurations learnt). "
            f"In the preview: {eight:,} points decided by 8 neighbours, {four:,} by 4, "
            f"{own + none:,} by their level alone. Works best on fine grains (§4.5).")
        self.table = table
        self.apply_button.setEnabled(True)
        QtCore.QTimer.singleShot(0, self, self._make_room)    # once the label has its lines

    def _make_room(self) -> None:
        """Grow to show the report whole: it arrives after the dialog is laid out, and a
        word-wrapped label's new lines would otherwise be drawn over the previews."""
        if shiboken6.isValid(self):
            self.layout().activate()
            self.resize(self.size().expandedTo(self.sizeHint()))

    def apply(self) -> None:
        """Double: the texture's levels are doubled in the worker (a second for a 2048²
        texture; status bar, Esc), then the step is applied and the dialog closes."""
        window = self.main_window
        if self.table is None or window.busy_note():
            return
        doc = window.document           # nothing edits it meanwhile: this dialog is modal
        action = DoubleLevels(doc.store_dpj(self.table), self.seed.value())
        self.apply_button.setEnabled(False)
        self.doubling = True

        def ended(levels=None) -> None:
            if not shiboken6.isValid(self) or not self.doubling:
                return                   # Cancel closed the dialog meanwhile: nothing applied
            self.doubling = False
            if levels is not None and window.submit(action, prepared=levels):
                self.accept()
            else:
                self.apply_button.setEnabled(self.table is not None)
        window.runner.run("Doubling the levels…",
                          lambda _progress, _cancel: action.doubled(doc),
                          ended, on_cancel=ended,
                          on_error=lambda exc: (window.show_error("Cannot double the levels", exc),
                                                ended()))

    def reject(self) -> None:
        """Cancel, also while the levels are being doubled: that work is stopped, no step."""
        if self.doubling:
            self.doubling = False
            self.main_window.runner.cancel()
        super().reject()


def open_doubling(window) -> DoublingDialog | None:
    if not window.document.levels.size:
        return None
    dialog = DoublingDialog(window)
    dialog.finished.connect(dialog.deleteLater)
    dialog.open()
    return dialog
