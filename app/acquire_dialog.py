"""File ▸ Acquire DPJ from image…: quantise a photo into G levels and count its u×v windows.

This is the automatic acquisition of thesis §5.2: the dialog shows the photo, its quantised levels
and the size of the estimated DPJ while the user tunes window, G, quantiser and wrap.
"""

from __future__ import annotations

from pathlib import Path

from PySide6 import QtCore, QtWidgets

from texeditor.dpj import MAX_SIDE
from texeditor.errors import TexeditorError
from texeditor.estimation import estimate_dpj
from texeditor.levels import load_image, quantize

from .canvas import colourize
from .images import photo_rgb, pixmap

PREVIEW = 240
IMAGE_FILTER = "Images (*.png *.jpg *.jpeg *.tif *.tiff *.bmp *.gif *.webp);;All files (*)"
QUANTISERS = (("Band (thesis: 90 % central band)", "band"), ("Lloyd–Max (least squares)", "lloyd"))


class AcquireDialog(QtWidgets.QDialog):
    """Build it, set a photo, adjust the widgets, accept: ``dpj`` is then the acquired DPJ."""

    def __init__(self, samples: list[Path] = (), parent=None):
        super().__init__(parent)
        self.setWindowTitle("Acquire a DPJ from an image")
        self.image = None
        self.path: Path | None = None
        self.dpj = None
        self.quantization = None

        self.source = QtWidgets.QComboBox()
        self.source.setMinimumContentsLength(24)
        for path in samples:
            self.source.addItem(path.stem.replace("_", " "), str(path))
        self.source.activated.connect(lambda _i: self.set_image_path(self.source.currentData()))
        self.browse = QtWidgets.QPushButton("Browse…")
        self.browse.clicked.connect(self.choose_file)

        self.u = self._spin(1, MAX_SIDE, 3, "Window width u (columns)")
        self.v = self._spin(1, MAX_SIDE, 3, "Window height v (rows)")
        self.levels = self._spin(2, 16, 4, "Number of levels G (3..8 is usually enough)")
        self.method = QtWidgets.QComboBox()
        for text, key in QUANTISERS:
            self.method.addItem(text, key)
        self.method.currentIndexChanged.connect(self._schedule)
        self.wrap = QtWidgets.QCheckBox("Wrap around the edges (the photo is periodic)")
        self.wrap.toggled.connect(self._schedule)
        self.synthesise_now = QtWidgets.QCheckBox("Synthesise a texture from it now")
        self.synthesise_now.setChecked(True)

        self.photo_view = self._preview_label("photo")
        self.levels_view = self._preview_label("quantised")
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)
        self.info.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)

        self.buttons = QtWidgets.QDialogButtonBox(
            QtWidgets.QDialogButtonBox.StandardButton.Ok
            | QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        self.ok_button = self.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
        self.ok_button.setText("Acquire")
        self.buttons.accepted.connect(self.accept)
        self.buttons.rejected.connect(self.reject)
        self._layout()

        self._timer = QtCore.QTimer(self, singleShot=True, interval=150)
        self._timer.timeout.connect(self.recompute)
        if samples:
            self.set_image_path(samples[0])
        else:
            self._show_error("Choose a photo with Browse…")

    # -- layout -------------------------------------------------------------------------------------
    def _spin(self, lo, hi, value, tip) -> QtWidgets.QSpinBox:
        s = QtWidgets.QSpinBox()
        s.setRange(lo, hi)
        s.setValue(value)
        s.setToolTip(tip)
        s.valueChanged.connect(self._schedule)
        return s

    def _preview_label(self, name) -> QtWidgets.QLabel:
        label = QtWidgets.QLabel()
        label.setObjectName(name)
        label.setFixedSize(PREVIEW, PREVIEW)
        label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        label.setStyleSheet("background: #2b2b2b; color: #bbbbbb;")
        return label

    def _layout(self) -> None:
        source_row = QtWidgets.QHBoxLayout()
        source_row.addWidget(self.source, 1)
        source_row.addWidget(self.browse)
        window_row = QtWidgets.QHBoxLayout()
        window_row.addWidget(self.u)
        window_row.addWidget(QtWidgets.QLabel("columns ×"))
        window_row.addWidget(self.v)
        window_row.addWidget(QtWidgets.QLabel("rows"))
        window_row.addStretch(1)
        form = QtWidgets.QFormLayout()
        form.addRow("Photo", source_row)
        form.addRow("Window", window_row)
        form.addRow("Levels G", self.levels)
        form.addRow("Quantiser", self.method)
        form.addRow("", self.wrap)

        previews = QtWidgets.QGridLayout()
        previews.addWidget(self.photo_view, 0, 0)
        previews.addWidget(self.levels_view, 0, 1)
        previews.addWidget(QtWidgets.QLabel("Photo"), 1, 0, QtCore.Qt.AlignmentFlag.AlignHCenter)
        previews.addWidget(QtWidgets.QLabel("Quantised to G levels"), 1, 1,
                           QtCore.Qt.AlignmentFlag.AlignHCenter)

        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(form)
        layout.addLayout(previews)
        layout.addWidget(self.info)
        layout.addWidget(self.synthesise_now)
        layout.addWidget(self.buttons)

    # -- inputs ---------------------------------------------------------------------------------------
    def choose_file(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Choose a photo", "", IMAGE_FILTER)
        if path:
            self.set_image_path(path)

    def set_image_path(self, path) -> None:
        """Read a photo (errors are shown in the dialog, which stays open) and estimate."""
        path = Path(path)
        try:
            image = load_image(path)
        except TexeditorError as exc:
            self.image, self.dpj = None, None
            self.photo_view.clear()
            self.levels_view.clear()
            self.photo_view.setText("cannot read this file")
            self._show_error(str(exc))
            return
        self.image, self.path = image, path
        if self.source.findData(str(path)) < 0:
            self.source.addItem(path.name, str(path))
        self.source.setCurrentIndex(self.source.findData(str(path)))
        self.photo_view.setPixmap(pixmap(photo_rgb(image), PREVIEW))
        self.recompute()

    def _schedule(self, *_args) -> None:
        self._timer.start()

    # -- the estimate ---------------------------------------------------------------------------------
    def recompute(self) -> None:
        """Quantise and estimate now (fast: a 512² photo takes a few tens of milliseconds)."""
        self._timer.stop()
        if self.image is None:
            return
        window, levels = (self.u.value(), self.v.value()), self.levels.value()
        method, wrap = self.method.currentData(), self.wrap.isChecked()
        try:
            q = quantize(self.image, levels, method)
            meta = {"name": self.path.stem, "image": self.path.name, "quantiser": method}
            dpj = estimate_dpj(q.levels, window, levels, wrap=wrap, palette=q.palette, meta=meta)
        except TexeditorError as exc:
            self.dpj = None
            self._show_error(str(exc))
            return
        self.quantization, self.dpj = q, dpj
        self.levels_view.setPixmap(pixmap(colourize(q.levels, q.palette), PREVIEW))
        self._show_report()

    def _show_report(self) -> None:
        dpj, (u, v), g = self.dpj, self.dpj.window, self.dpj.levels
        report = self.dpj.report()
        h, w = self.quantization.levels.shape
        self.info.setStyleSheet("")
        self.info.setText(
            f"<b>{len(dpj):,} non-zero configurations</b> of {u}×{v} windows with G = {g} "
            f"(from a {w}×{h} photo).<br>Horizontal chain: {report.states:,} states, "
            f"{report.closed_classes} closed class(es), {report.transient_states} transient.")
        self.ok_button.setEnabled(True)

    def _show_error(self, message: str) -> None:
        self.info.setStyleSheet("color: #d04040;")
        self.info.setText(message)
        self.ok_button.setEnabled(False)

    def accept(self) -> None:
        self.recompute()     # a change still waiting on the timer must not be lost
        if self.dpj is not None:
            super().accept()
