"""The shape every Models dialog shares: settings, a preview that is the step itself run on a
scratch document in the background, and OK, which applies exactly the step on show.

The preview runs in a worker (`LatestWins`: a change of setting drops the one under way and the
latest wins, its progress shown), so a 2048² model or a slow flow field never freezes the window;
OK is enabled only while the preview on show is the step the settings say, and adds one
undoable step.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor.errors import TexeditorError
from texeditor.markov.levels import has_colour, load_image, to_grey, to_rgb
from texeditor.recipe.exemplars import MAX_SIDE

from . import resources
from .acquire_dialog import IMAGE_FILTER
from .dpj_editor.preview import LatestWins
from .widgets import select_path

PREVIEW = 240                 # side of a preview, in pixels


def preview_view() -> QtWidgets.QLabel:
    label = QtWidgets.QLabel()
    label.setFixedSize(PREVIEW, PREVIEW)
    label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
    label.setFrameShape(QtWidgets.QFrame.Shape.StyledPanel)
    return label


def exemplar_from(image: np.ndarray) -> tuple[np.ndarray, str]:
    """A photo as an exemplar: uint8 grey or RGB (alpha laid on white), its middle 1024² at
    most (a crop, not a reduction: a micro-texture's grain keeps its scale); and a note."""
    colour = has_colour(image)
    h, w = np.shape(image)[:2]
    top, left = max((h - MAX_SIDE) // 2, 0), max((w - MAX_SIDE) // 2, 0)
    crop = np.asarray(image)[top:top + MAX_SIDE, left:left + MAX_SIDE]   # before converting:
    unit = to_rgb(crop) if colour else to_grey(crop)     # per pixel, and a 12-megapixel photo
    note = f" (its middle {crop.shape[1]}×{crop.shape[0]})" if crop.shape[:2] != (h, w) else ""
    return np.round(unit * 255).astype(np.uint8), note                    # took a second whole


def photo_box() -> tuple[QtWidgets.QComboBox, QtWidgets.QPushButton]:
    """The bundled photos in a box, and Browse… for any other."""
    box = QtWidgets.QComboBox()
    for path in resources.sample_images():
        box.addItem(path.stem, str(path))
    return box, QtWidgets.QPushButton("Browse…")


class StepDialog(QtWidgets.QDialog):
    """A model's dialog: subclasses build their settings and layout, then call ``finish``;
    ``request(action, scratch)`` previews a step, ``show_result`` draws it, ``before_apply``
    adds what the step needs to the document (an exemplar photo)."""

    def __init__(self, window, title: str):
        super().__init__(window)
        self.main_window = window
        self.setWindowTitle(title)
        self.preview_step = None                     # (action, prepared) the preview shows
        self.result_view = preview_view()
        self.busy = QtWidgets.QProgressBar()
        self.busy.setRange(0, 100)
        self.busy.setTextVisible(False)
        self.busy.setMaximumHeight(8)
        self.busy.hide()
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)
        self.info.setMinimumHeight(3 * self.info.fontMetrics().lineSpacing())   # never over the views
        self.buttons = QtWidgets.QDialogButtonBox(
            QtWidgets.QDialogButtonBox.StandardButton.Ok
            | QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        self.ok = self.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
        self.buttons.accepted.connect(self.apply)
        self.buttons.rejected.connect(self.reject)
        self.previews = LatestWins(self, delay_ms=120)
        self.previews.done.connect(self._shown)
        self.previews.failed.connect(self._failed)
        self.previews.progress.connect(lambda f: self.busy.setValue(round(100 * f)))
        self.finished.connect(lambda _result: self.previews.stop())     # closed either way

    def start(self, about: str) -> tuple[QtWidgets.QVBoxLayout, QtWidgets.QFormLayout]:
        """The dialog's layout begun: what the model does, then its settings' form (added
        by the caller once filled)."""
        layout = QtWidgets.QVBoxLayout(self)
        label = QtWidgets.QLabel(about)
        label.setWordWrap(True)
        layout.addWidget(label)
        return layout, QtWidgets.QFormLayout()

    def finish(self, layout: QtWidgets.QVBoxLayout) -> None:
        """The progress bar, the message and the buttons under the subclass's layout."""
        layout.addWidget(self.busy)
        layout.addWidget(self.info)
        layout.addWidget(self.buttons)
        self.setMinimumHeight(self.sizeHint().height())     # wrapped labels never squeezed

    # -- a photo box (dialogs that have one: self.photo, self.load_photo) -------------------------
    def choose_file(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Choose a photo", "", IMAGE_FILTER)
        if path:
            self.set_photo(path)

    def set_photo(self, path) -> None:
        select_path(self.photo, path)
        self.load_photo()

    def read_photo(self) -> None:
        """The chosen photo as the exemplar (``self.exemplar``, ``self.note``), or a
        TexeditorError saying why not."""
        path = self.photo.currentData()
        if path is None:
            raise TexeditorError("choose a photo with Browse…")
        self.exemplar, self.note = exemplar_from(load_image(path))

    # -- the preview ------------------------------------------------------------------------------
    def request(self, action, scratch) -> None:
        """Preview ``action`` on ``scratch`` (a document nothing else holds) in the worker."""
        self.busy.setValue(0)
        self.busy.show()
        self.previews.request(lambda progress, cancel: run_step(action, scratch, progress,
                                                                cancel))

    def _waiting(self) -> None:
        """The settings changed: the preview on show (or coming) is no longer OK's."""
        self.previews.drop()
        self.preview_step = None
        self.ok.setEnabled(False)

    def _shown(self, outcome) -> None:
        action, prepared, scratch = outcome
        self.busy.hide()
        self.show_result(action, scratch)
        self.preview_step = (action, prepared)
        self.ok.setEnabled(True)

    def show_result(self, action, scratch) -> None:
        raise NotImplementedError

    def _failed(self, exc) -> None:
        self.busy.hide()
        self.result_view.clear()
        self.info.setText(f"<span style='color:#b00020'>{exc}</span>")

    def wait(self, timeout_ms: int = 60_000) -> bool:
        """Until the preview of the latest settings is shown (tests and scripts only); at once
        when none is asked for."""
        if self.previews.job is None and self.previews.pending is None:
            return True
        return self.previews.wait(timeout_ms)

    def before_apply(self, action) -> None:
        """What the step needs in the document before it is applied (a subclass hook)."""

    def apply(self) -> None:
        if self.preview_step is None:
            return
        action, prepared = self.preview_step
        self.before_apply(action)
        if self.main_window.submit(action, prepared=prepared):
            self.accept()


def run_step(action, scratch, progress, cancel):
    """The worker's part: the step's slow preparation, then the step on the scratch document
    (which nothing else holds), so the GUI thread only shows it."""
    prepared = action.prepare(scratch, progress, cancel)
    with scratch.step():
        action.apply(scratch, prepared)
    return action, prepared, scratch
