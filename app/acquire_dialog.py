"""File ▸ Acquire DPJ from image…: quantise a photo into G levels and count its u×v windows.

This is the automatic acquisition of thesis §5.2: the dialog shows the photo, its quantised levels
and the size of the estimated DPJ while the user tunes window, G, quantiser and wrap. With more
than one scale it acquires a photo model instead (photo.PhotoModel: a multi-scale DPJ, the
photo's tone) and shows the photo's levels at each scale, coarsest first. Reading,
quantising and counting take seconds on a large photo, so they run in a worker, the latest
setting winning: the dialog never freezes, and Acquire is enabled only for the current result.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.markov.dpj import DPJ, MAX_SIDE
from texeditor.errors import Cancelled, TexeditorError
from texeditor.markov.estimation import estimate_dpj
from texeditor.markov.levels import load_image, quantize
from texeditor.markov.multiscale import LEVELS as MODEL_LEVELS
from texeditor.markov.multiscale import WINDOW as MODEL_WINDOW
from texeditor.markov.multiscale import (MAX_SCALES, MultiScaleDPJ, default_scales, estimate_scales,
                                         has_phase, scales_phrase)
from texeditor.markov.scan import ROWS, SCAN_NAMES
from texeditor.photo import PhotoModel, photo_tone

from .canvas import colourize
from .dpj_editor.preview import LatestWins
from .images import PastedPicture, photo_rgb, qimage_from_rgb
from .widgets import row, scan_combo

PREVIEW = 240
IMAGE_FILTER = "Images (*.png *.jpg *.jpeg *.tif *.tiff *.bmp *.gif *.webp);;All files (*)"
QUANTISERS = (("Band (thesis: 90 % central band)", "band"), ("Lloyd–Max (least squares)", "lloyd"),
              ("Colour classes (CIELAB)", "lab"))
MODEL_QUANTISER = "lab"            # acquire_model's (colour classes; a grey photo: Lloyd–Max)
DEBOUNCE_MS = 150
SCALE_STRIP = 2 * PREVIEW + 6      # the scale previews share the width of the two big ones
SCALE_SIDE = 100                   # ... each at most this square (the dialog fits 800 pixels)
SMALLEST_PREVIEW = 120             # on a screen too short for the dialog, the two big previews
                                   # shrink down to this side, so its buttons stay on screen
PASTED = Path("Pasted picture")    # the name a picture from the clipboard goes by


@dataclass
class Acquired:
    """What the worker made of one request; ``error`` says why ``dpj`` (or ``image``) is None."""

    path: Path
    image: np.ndarray | None = None       # None: the file could not be read
    photo: QtGui.QImage | None = None     # the photo's preview, when it was read for this request
    quantization: object = None
    dpj: DPJ | None = None
    report: object = None
    levels: QtGui.QImage | None = None    # the quantised levels' preview
    model: PhotoModel | None = None       # several scales: the photo model (dpj: its finest)
    scale_levels: tuple = ()              # several scales: each one's levels, coarsest first
    scale_views: tuple = ()               # ... and their previews
    error: str = ""


def preview_image(rgb: np.ndarray) -> QtGui.QImage:
    """A PREVIEW-square QImage of an RGB array (a QImage, unlike a QPixmap, may be made in the
    worker); small images are enlarged without smoothing."""
    mode = (QtCore.Qt.TransformationMode.FastTransformation if max(rgb.shape[:2]) < PREVIEW
            else QtCore.Qt.TransformationMode.SmoothTransformation)
    return qimage_from_rgb(rgb).scaled(PREVIEW, PREVIEW,
                                       QtCore.Qt.AspectRatioMode.KeepAspectRatio, mode)


def chain_advice(report, wrap: bool) -> tuple[str, str, bool]:
    """What the DPJ's horizontal chain means for synthesis, in a user's words, with what to do;
    then the detail (for a tooltip) and whether it is a warning.

    The sampler draws a row left to right, each window continuing the columns the previous one
    ended with (its *state*). A *closed class* is a set of states it can go on drawing from for
    ever; a *transient* state is one it passes through and never sees again, and a *dead end*
    one no configuration continues — usually a column seen only at the photo's edges, pruned
    before the classes are counted (thesis §4.5, Massaloux). A *periodic* class makes every
    row cycle through the same few families of patterns."""
    states, closed, transient = report.states, report.closed_classes, report.transient_states
    detail = (f"Horizontal Markov chain of the DPJ: {states:,} states (column patterns of the "
              f"window), {closed} closed class(es) — sets of patterns the synthesis can keep "
              f"drawing from along a row — and {transient:,} transient state(s), which it passes "
              f"through at most once, mostly patterns seen only at the photo's edges; "
              f"{report.dead_ends:,} configuration(s) lead to a dead end (a pattern no "
              f"configuration continues, to the right or below). Main class: "
              + (f"period {report.period}" if report.period > 1 else "aperiodic")
              + ". The DPJ editor's Restrict (Massaloux, thesis §4.5) keeps the main closed "
              "class and drops the rest.")
    fewer = ("tick “Wrap around the edges”, " if not wrap else "") + \
        "choose fewer levels G or a smaller window"
    if states and closed == 0:
        return (f"Rows will hit dead ends: no run of column patterns can repeat, so the "
                f"synthesis will often repair (draw from a simpler context) and the result may "
                f"look patchy. To fix it, {fewer}.", detail, True)
    if closed > 1:
        return (f"The patterns fall into {closed} separate families: a row keeps the family it "
                f"starts in, so rows may look unlike each other. To join them, {fewer}, or use "
                "Restrict in the DPJ editor to keep the main one.", detail, True)
    if report.period > 1:
        return (f"Periodic: along a row the patterns cycle through {report.period} families, "
                "so the texture will show a regular beat. If the photo has none, "
                f"{fewer}.", detail, True)
    if transient and states and transient * 2 > states:
        return (f"{transient:,} of {states:,} column patterns occur only near the photo's "
                "edges: a row leaves them within a few points and never comes back. A larger "
                f"photo helps, or {fewer}.", detail, True)
    return ("Every row can be drawn to any length from this DPJ: ready to synthesise.", detail,
            False)


def scale_caption(k: int, scales: int) -> str:
    """A scale's reduction of the photo: "1/4", "1/2", "1/1" for 3 scales."""
    return f"1/{2 ** (scales - 1 - k)}"


def scale_name(name: str, k: int, scales: int) -> str:
    """The name of scale k's DPJ, as the DPJ lists show it: "brick scale 2/3"."""
    return f"{name} scale {k + 1}/{scales}"


def named_scales(ms: MultiScaleDPJ, meta: dict) -> MultiScaleDPJ:
    """The scales' DPJs with a name each (and the photo's ``meta``), so the document's DPJ lists
    tell them apart."""
    n = ms.scales
    return MultiScaleDPJ(tuple(
        DPJ(d.configs, d.probs, d.levels, palette=d.palette,
            meta={**d.meta, **meta, "name": scale_name(meta["name"], k, n)})
        for k, d in enumerate(ms.dpjs)))


def scale_palette(ms: MultiScaleDPJ, k: int) -> np.ndarray:
    """The colours of scale k's own levels (a conditional DPJ repeats them per parent)."""
    return ms.dpjs[k].palette[: ms.levels_at(k)]


def acquire_scales(out: Acquired, scales, window, levels: int, method: str, tone: bool,
                   meta: dict, cancel) -> Acquired:
    """A photo model of several scales, the photo's levels at each and their previews."""
    ms, lv = estimate_scales(out.image, scales=scales, levels=levels, window=window,
                             quantizer=method)
    if cancel():
        raise Cancelled("a newer setting was asked for")
    ms = named_scales(ms, meta)
    out.model = PhotoModel(ms, photo_tone(out.image, lv[-1]) if tone else None)
    out.dpj = ms.dpjs[-1]
    out.scale_levels = tuple(lv)
    out.scale_views = tuple(qimage_from_rgb(colourize(v, scale_palette(ms, k)))
                            for k, v in enumerate(lv))
    out.levels = preview_image(colourize(lv[-1], ms.palette))
    out.quantization = None
    return out


def acquire(path: Path, image, window, levels: int, method: str, wrap: bool, cancel,
            scales: int | None = 1, tone: bool = True, scan: str = ROWS,
            stationary: bool = False, show: bool = False) -> Acquired:
    """Read the photo (unless ``image`` is given: an array, or a PastedPicture read here;
    ``show``: make its preview all the same), quantise it and count its windows: all the slow
    part of the dialog, for the worker. Stops between stages when ``cancel()``.
    ``scales``: 1 for one DPJ, more for a photo model (``tone``: with the photo's tone), None
    for as many as the photo's size suggests (markov.multiscale.default_scales). One DPJ is
    counted in the ``scan`` asked for, and made ``stationary`` if asked (§5.2.2)."""
    pasted = isinstance(image, PastedPicture)
    out = Acquired(path, None if pasted else image)
    try:
        if pasted:
            out.image = image.photo()
        elif image is None:
            out.image = load_image(path)
        if image is None or show:
            out.photo = preview_image(photo_rgb(out.image))
    except TexeditorError as exc:
        out.error = str(exc)
        return out
    if cancel():
        raise Cancelled("a newer setting was asked for")
    meta = {"name": path.stem, "image": path.name, "quantiser": method}
    if scales is None:
        scales = default_scales(np.shape(out.image))
    try:
        if scales > 1:
            return acquire_scales(out, scales, window, levels, method, tone, meta, cancel)
        out.quantization = q = quantize(out.image, levels, method)
        if cancel():
            raise Cancelled("a newer setting was asked for")
        out.dpj = estimate_dpj(q.levels, window, levels, wrap=wrap, scan=scan,
                               stationary=stationary, palette=q.palette, meta=meta, cancel=cancel)
        out.report = out.dpj.report()
    except Cancelled:
        raise
    except TexeditorError as exc:
        out.dpj, out.error = None, str(exc)
        return out
    out.levels = preview_image(colourize(q.levels, q.palette))
    return out


def pasted_photo(mime: QtCore.QMimeData | None):
    """What a clipboard (or a drop) offers to acquire from: a picture (images.PastedPicture,
    read into an array in the worker), else the first local file it names as a Path, else
    None. A picture that cannot be used raises ImageError."""
    if mime is None:
        return None
    if mime.hasImage():
        image = QtGui.QImage(mime.imageData())
        if not image.isNull():
            return PastedPicture(image)
    for url in mime.urls() if mime.hasUrls() else ():
        if url.isLocalFile():
            return Path(url.toLocalFile())
    return None


def acquisition_notes(dpj) -> list[str]:
    """How a DPJ was acquired beyond window and G: its scan (when not rows), stationarity."""
    notes = []
    if dpj.meta.get("scan", ROWS) != ROWS:
        notes.append("scanned by " + SCAN_NAMES[dpj.meta["scan"]].lower())
    if dpj.meta.get("stationary"):
        notes.append("made stationary")
    return notes


class AcquireDialog(QtWidgets.QDialog):
    """Build it, set a photo, adjust the widgets, accept: ``dpj`` is then the acquired DPJ;
    with several scales ``model`` is the photo model and ``dpj`` its finest scale's DPJ.
    ``photo``: the photo to start on (a path, a pasted picture or an array), else the first
    sample."""

    def __init__(self, samples: list[Path] = (), parent=None, photo=None):
        super().__init__(parent)
        self.setWindowTitle("Acquire a DPJ from an image")
        self.image = None                 # the photo at ``path``, once read
        self.path: Path | None = None
        self.dpj = None                   # the result of the current settings, once ready
        self.model = None                 # ... a PhotoModel, when it has several scales
        self.scale_levels = ()            # ... and the photo's levels at each scale
        self.quantization = None
        self.worker = LatestWins(self, delay_ms=DEBOUNCE_MS)
        self.worker.done.connect(self._computed)
        self.worker.failed.connect(lambda exc: self._show_error(f"Cannot estimate: {exc!r}"))
        self.finished.connect(lambda _result: self.worker.stop())

        self.source = QtWidgets.QComboBox()
        self.source.setMinimumContentsLength(24)
        for path in samples:
            self.source.addItem(path.stem.replace("_", " "), str(path))
        self.source.activated.connect(self._source_chosen)
        self.pasted = None                # the last picture pasted into the dialog
        self._show_pasted = False         # ... whose preview the worker is to make
        self.browse = QtWidgets.QPushButton("Browse…")
        self.browse.clicked.connect(self.choose_file)
        self.paste = QtWidgets.QPushButton("Paste")
        self.paste.setToolTip("Acquire from the picture on the clipboard (Ctrl+V), or from the "
                              "image file copied in a file manager")
        self.paste.clicked.connect(self.paste_photo)
        paste_key = QtGui.QShortcut(QtGui.QKeySequence.StandardKey.Paste, self)
        paste_key.activated.connect(self.paste_photo)

        # first defaults: a photo model as `texeditor resynth` acquires it (the texture an artist
        # expects from a photo); "auto" unticked and 1 scale give the thesis's single DPJ
        self.u = self._spin(1, MAX_SIDE, MODEL_WINDOW[0], "Window width u (columns)")
        self.v = self._spin(1, MAX_SIDE, MODEL_WINDOW[1], "Window height v (rows)")
        self.levels = self._spin(2, 16, MODEL_LEVELS, "Number of levels G (3..8 is usually "
                                 "enough)")
        self.method = QtWidgets.QComboBox()
        for text, key in QUANTISERS:
            self.method.addItem(text, key)
        self.method.setCurrentIndex(self.method.findData(MODEL_QUANTISER))
        self.method.currentIndexChanged.connect(self._schedule)
        self.wrap = QtWidgets.QCheckBox("Wrap around the edges (the photo is periodic)")
        self.wrap.toggled.connect(self._schedule)
        self.scan = scan_combo("The order the window sweeps the photo (thesis §5.2.1b): the "
                               "synthesis draws along the same lines, so choose the one that "
                               "runs along the texture's direction (columns for vertical "
                               "stripes). The DPJ remembers it and the Synthesis dock proposes it.")
        self.scan.currentIndexChanged.connect(self._schedule)
        self.stationary = QtWidgets.QCheckBox("Make stationary")
        self.stationary.setToolTip("Balance the DPJ so that its left and right (and top and "
                                   "bottom) sub-windows are equally likely, the thesis's "
                                   "stationarity condition (§5.2.2), keeping its configurations; "
                                   "a wrapped count already is. Takes long on large DPJs.")
        self.stationary.toggled.connect(self._schedule)
        self.scales = self._spin(1, MAX_SCALES, 1, "Scales: 1 acquires one DPJ; more acquire a "
                                 "photo model, the photo reduced by 2, 4… with a DPJ per scale "
                                 "(each finer one given the coarser levels under it), so the "
                                 "texture keeps structure larger than the window")
        self.auto_scales = QtWidgets.QCheckBox("auto")
        self.auto_scales.setToolTip("As many scales as bring the photo's shorter side to about "
                                    "64 points at the coarsest")
        self.auto_scales.setChecked(True)
        self.scales.setEnabled(False)
        self.auto_scales.toggled.connect(self._auto_toggled)
        self.tone = QtWidgets.QCheckBox("Photographic tone")
        self.tone.setToolTip("Keep the photo's greys and colours with the model: its textures "
                             "are shown with them instead of the palette")
        self.tone.setChecked(True)
        self.tone.toggled.connect(self._schedule)
        self.synthesise_now = QtWidgets.QCheckBox("Synthesise a texture from it now")
        self.synthesise_now.setChecked(True)

        self.photo_view = self._preview_label("photo")
        self.levels_view = self._preview_label("quantised")
        self.levels_caption = QtWidgets.QLabel("Quantised to G levels")
        self.scale_strip = QtWidgets.QWidget()           # the scales' previews, coarsest first
        self.scale_strip.setObjectName("scales")
        self.scale_strip_layout = QtWidgets.QGridLayout(self.scale_strip)
        self.scale_strip_layout.setContentsMargins(0, 0, 0, 0)
        self.scale_strip.hide()
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)
        self.info.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
        self.busy = QtWidgets.QProgressBar()        # indeterminate while the worker computes
        self.busy.setRange(0, 0)
        self.busy.setTextVisible(False)
        self.busy.setMaximumHeight(8)
        self.busy.hide()

        self.buttons = QtWidgets.QDialogButtonBox(
            QtWidgets.QDialogButtonBox.StandardButton.Ok
            | QtWidgets.QDialogButtonBox.StandardButton.Cancel)
        self.ok_button = self.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
        self.ok_button.setText("Acquire")
        self.buttons.accepted.connect(self.accept)
        self.buttons.rejected.connect(self.reject)
        self._layout()
        self._restore_settings()
        self._follow_scales()

        if isinstance(photo, (np.ndarray, PastedPicture)):
            self.set_image(photo)
        elif photo is not None or samples:
            self.set_image_path(photo if photo is not None else samples[0])
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
        form = QtWidgets.QFormLayout()
        form.addRow("Photo", row(self.source, self.browse, self.paste, stretch=False))
        form.addRow("Window", row(self.u, "columns ×", self.v, "rows"))
        form.addRow("Levels G", self.levels)
        form.addRow("Quantiser", self.method)
        form.addRow("", self.wrap)
        form.addRow("Scan", row(self.scan, self.stationary))
        form.addRow("Scales", row(self.scales, self.auto_scales))
        form.addRow("", self.tone)

        previews = QtWidgets.QGridLayout()
        previews.addWidget(self.photo_view, 0, 0)
        previews.addWidget(self.levels_view, 0, 1)
        previews.addWidget(QtWidgets.QLabel("Photo"), 1, 0, QtCore.Qt.AlignmentFlag.AlignHCenter)
        previews.addWidget(self.levels_caption, 1, 1, QtCore.Qt.AlignmentFlag.AlignHCenter)
        previews.addWidget(self.scale_strip, 2, 0, 1, 2)

        layout = QtWidgets.QVBoxLayout(self)
        layout.addLayout(form)
        layout.addLayout(previews)
        layout.addWidget(self.info)
        layout.addWidget(self.busy)
        layout.addWidget(self.synthesise_now)
        layout.addWidget(self.buttons)

    # -- inputs ---------------------------------------------------------------------------------------
    def choose_file(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Choose a photo", "", IMAGE_FILTER)
        if path:
            self.set_image_path(path)

    def set_image_path(self, path) -> None:
        """Read a photo and estimate, in the worker (errors are shown in the dialog, which stays
        open)."""
        self.path, self.image = Path(path), None
        self.recompute()

    def set_image(self, image) -> None:
        """Acquire from a picture already in memory (pasted: an array, or a PastedPicture the
        worker reads): listed as "Pasted picture" among the photos, so choosing another and
        coming back finds it again."""
        self.pasted = image
        self.path, self.image = PASTED, image
        self._show_pasted = True          # its preview is made in the worker (a large one takes
        self._show_preview(self.photo_view, None)     # a second)
        if self.source.findData(str(PASTED)) < 0:
            self.source.addItem(str(PASTED), str(PASTED))
        self.source.setCurrentIndex(self.source.findData(str(PASTED)))
        self.recompute()

    def paste_photo(self) -> bool:
        """Paste: the clipboard's picture (or the image file copied in a file manager) becomes
        the photo; with nothing usable there the dialog says so and keeps its photo."""
        try:
            source = pasted_photo(QtWidgets.QApplication.clipboard().mimeData())
        except TexeditorError as exc:
            return self._paste_refused(str(exc))
        if source is None:
            return self._paste_refused("The clipboard holds no picture: copy one in another "
                                       "program (or an image file in a file manager), then "
                                       "paste.")
        if isinstance(source, Path):
            self.set_image_path(source)
        else:
            self.set_image(source)
        return True

    def _paste_refused(self, message: str) -> bool:
        """Say why, in the dialog; the photo on show and its result stay acquirable."""
        self.info.setStyleSheet("color: #d04040;")
        self.info.setText(message)
        QtWidgets.QApplication.beep()
        return False

    def _source_chosen(self, _index: int) -> None:
        data = self.source.currentData()
        if data == str(PASTED) and self.pasted is not None:
            self.set_image(self.pasted)
        else:
            self.set_image_path(data)

    def _schedule(self, *_args) -> None:
        self._follow_scales()
        self.recompute()

    def _auto_toggled(self, on: bool) -> None:
        self.scales.setEnabled(not on)
        self._schedule()

    def _follow_scales(self) -> None:
        """Only what the current number of scales uses is enabled: the scales wrap around the
        photo's edges always and are drawn in rows, and tone belongs to a photo model."""
        several = self.auto_scales.isChecked() or self.scales.value() > 1
        for one_dpj in (self.wrap, self.scan, self.stationary):
            one_dpj.setEnabled(not several)
        self.tone.setEnabled(several)

    def requested_scales(self) -> int | None:
        """The number of scales asked for (None: auto)."""
        return None if self.auto_scales.isChecked() else self.scales.value()

    # -- the estimate ---------------------------------------------------------------------------------
    def recompute(self) -> None:
        """Ask the worker for the current settings (after a short pause, so that typing a value
        asks once); until it answers, the previous result cannot be acquired."""
        if self.path is None:
            return
        path, image = self.path, self.image
        window, levels = (self.u.value(), self.v.value()), self.levels.value()
        method, wrap = self.method.currentData(), self.wrap.isChecked()
        scales, tone = self.requested_scales(), self.tone.isChecked()
        scan, stationary = self.scan.currentData(), self.stationary.isChecked()
        show = self._show_pasted
        self.dpj, self.model = None, None
        self.ok_button.setEnabled(False)
        self.busy.show()
        self.worker.request(lambda _progress, cancel: acquire(
            path, image, window, levels, method, wrap, cancel, scales, tone, scan, stationary,
            show))

    def wait(self, timeout_ms: int = 30_000) -> bool:
        """Block until the current settings' result is shown (tests and scripts only)."""
        return self.worker.wait(timeout_ms)

    def _computed(self, out: Acquired) -> None:
        """Show the result of the latest request (older ones never arrive here)."""
        self.busy.hide()
        if out.image is None:
            self._unreadable(out.error)
            return
        if out.photo is not None:
            self.image, self._show_pasted = out.image, False
            if out.path == PASTED:
                self.pasted = out.image           # read once
            self._show_preview(self.photo_view, out.photo)
            if self.source.findData(str(out.path)) < 0:
                self.source.addItem(out.path.name, str(out.path))
            self.source.setCurrentIndex(self.source.findData(str(out.path)))
        if out.dpj is None:
            self._show_scales(())
            self._show_error(out.error)
            return
        self.quantization, self.dpj, self.model = out.quantization, out.dpj, out.model
        self.scale_levels = out.scale_levels
        self._show_preview(self.levels_view, out.levels)
        self._show_scales(out.scale_views)
        if out.model is not None:
            self._show_model(out.model)
        else:
            self._show_report(out.report)
        QtCore.QTimer.singleShot(0, self, self._make_room)   # once new widgets have their sizes

    def _make_room(self) -> None:
        """Grow to show the scales' strip and the wrapped report whole (the layout's minimum
        does not count a word-wrapped label's lines, and the previews would overlap), then stay
        on the screen: moved up, and on a screen too short, the big previews made smaller —
        grown down past a 1280×800 screen's bottom, Acquire and Cancel could not be reached."""
        self.layout().activate()
        self.resize(self.size().expandedTo(self.sizeHint()))
        screen = self.screen()
        if screen is None:
            return
        room = screen.availableGeometry()
        over = self.frameGeometry().height() - room.height()
        if over > 0 and self.photo_view.width() > SMALLEST_PREVIEW:
            side = max(SMALLEST_PREVIEW, self.photo_view.width() - over)
            for view in (self.photo_view, self.levels_view):
                view.setFixedSize(side, side)
                self._show_preview(view, view.property("image"))
            self.layout().activate()
            self.resize(self.width(), self.sizeHint().height())
        frame = self.frameGeometry()
        left = max(room.left(), min(frame.left(), room.right() + 1 - frame.width()))
        top = max(room.top(), min(frame.top(), room.bottom() + 1 - frame.height()))
        if (left, top) != (frame.left(), frame.top()):
            self.move(self.x() + left - frame.left(), self.y() + top - frame.top())

    @staticmethod
    def _show_preview(view: QtWidgets.QLabel, image) -> None:
        """A big preview: its PREVIEW-square image, smaller when the preview is (_make_room)."""
        view.setProperty("image", image)
        if image is None:
            view.clear()
            return
        if view.width() < PREVIEW:
            image = image.scaled(view.width(), view.height(),
                                 QtCore.Qt.AspectRatioMode.KeepAspectRatio,
                                 QtCore.Qt.TransformationMode.SmoothTransformation)
        view.setPixmap(QtGui.QPixmap.fromImage(image))

    def _show_scales(self, views) -> None:
        """Each scale's levels, small and side by side, captioned with its reduction; the
        coarse ones enlarged without smoothing, so their blocks show what they hold."""
        grid = self.scale_strip_layout
        while grid.count():
            grid.takeAt(0).widget().deleteLater()
        self.scale_strip.setVisible(bool(views))
        self.levels_caption.setText("Finest scale, G levels" if views else "Quantised to G levels")
        if not views:
            return
        n = len(views)
        side = min(SCALE_SIDE, (SCALE_STRIP - 6 * (n - 1)) // n)
        for k, view in enumerate(views):
            label = QtWidgets.QLabel()
            label.setObjectName(f"scale{k}")
            label.setFixedSize(side, side)
            label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
            label.setStyleSheet("background: #2b2b2b;")
            label.setPixmap(QtGui.QPixmap.fromImage(view.scaled(
                side, side, QtCore.Qt.AspectRatioMode.KeepAspectRatio,
                QtCore.Qt.TransformationMode.FastTransformation)))
            caption = QtWidgets.QLabel(scale_caption(k, n))
            caption.setObjectName(f"scale{k}caption")
            grid.addWidget(label, 0, k, QtCore.Qt.AlignmentFlag.AlignHCenter)
            grid.addWidget(caption, 1, k, QtCore.Qt.AlignmentFlag.AlignHCenter)

    def _show_model(self, model: PhotoModel) -> None:
        ms = model.scales
        if self.auto_scales.isChecked():
            self.scales.blockSignals(True)        # the number auto chose, without asking again
            self.scales.setValue(ms.scales)
            self.scales.blockSignals(False)
        h, w = self.scale_levels[-1].shape
        parts = []
        for k, dpj in enumerate(ms.dpjs):
            u, v = dpj.window
            given = f" given {ms.levels_at(k - 1)}" if k else ""
            given += " and the row's phase" if has_phase(dpj) else ""
            parts.append(f"{scale_caption(k, ms.scales)}: {u}×{v}, G = {ms.levels_at(k)}{given}, "
                         f"{len(dpj):,} configurations")
        tone = ("shown with the photo's own " + ("colours" if model.tone.colour is not None
                                                  else "greys")
                if model.tone is not None else "shown with the palette (no tone)")
        self.info.setStyleSheet("")
        self.info.setText(f"<b>A photo model of {scales_phrase(ms.scales)}</b> from a {w}×{h} "
                          f"photo — {'; '.join(parts)}.<br>"
                          f"<span style='color: #308030'>Each finer scale is drawn given the "
                          f"coarser one under it; textures are {tone}.</span>")
        self.info.setToolTip("The coarsest scale is an ordinary DPJ; each finer one is a "
                             "conditional DPJ over composite levels parent · G + level.")
        self.ok_button.setEnabled(True)

    def _unreadable(self, message: str) -> None:
        self.path, self.image, self.dpj, self.model = None, None, None, None
        self._show_scales(())
        self._show_preview(self.photo_view, None)
        self._show_preview(self.levels_view, None)
        self.photo_view.setText("cannot read this file")
        self._show_error(message)

    def _show_report(self, report) -> None:
        dpj, (u, v), g = self.dpj, self.dpj.window, self.dpj.levels
        h, w = self.quantization.levels.shape
        self.info.setStyleSheet("")
        advice, detail, warn = chain_advice(report, self.wrap.isChecked())
        colour = "#c07000" if warn else "#308030"
        how = "".join(f", {note}" for note in acquisition_notes(dpj))
        self.info.setText(
            f"<b>{len(dpj):,} non-zero configurations</b> of {u}×{v} windows with G = {g} "
            f"(from a {w}×{h} photo{how}).<br><span style='color: {colour}'>{advice}</span>")
        self.info.setToolTip(detail)
        self.ok_button.setEnabled(True)

    def _show_error(self, message: str) -> None:
        self.busy.hide()
        self.info.setStyleSheet("color: #d04040;")
        self.info.setText(message)
        self.ok_button.setEnabled(False)

    def accept(self) -> None:
        """Only the current settings' result may be acquired (Acquire is disabled until then).
        The settings are kept for the next time the dialog opens."""
        if self.dpj is not None:
            self._keep_settings()
            super().accept()

    # -- the settings kept from one acquisition to the next -----------------------------------------
    def _kept(self):
        """(key, widget) of every setting the dialog keeps."""
        return (("u", self.u), ("v", self.v), ("levels", self.levels), ("scales", self.scales),
                ("quantiser", self.method), ("scan", self.scan), ("wrap", self.wrap),
                ("stationary", self.stationary), ("auto", self.auto_scales),
                ("tone", self.tone), ("synthesise", self.synthesise_now))

    def _keep_settings(self) -> None:
        from .files import settings
        store = settings()
        for key, widget in self._kept():
            value = (widget.value() if isinstance(widget, QtWidgets.QSpinBox)
                     else widget.currentData() if isinstance(widget, QtWidgets.QComboBox)
                     else widget.isChecked())
            store.setValue(f"acquire/{key}", value)

    def _restore_settings(self) -> None:
        """The settings of the last acquisition; one missing, of the wrong kind or out of range
        (a settings file edited by hand) keeps its default."""
        from .files import settings
        store = settings()
        for key, widget in self._kept():
            raw = store.value(f"acquire/{key}")
            if raw is None:
                continue
            if isinstance(widget, QtWidgets.QSpinBox):
                try:
                    value = int(str(raw))
                except ValueError:
                    continue
                if widget.minimum() <= value <= widget.maximum():
                    widget.setValue(value)
            elif isinstance(widget, QtWidgets.QComboBox):
                if widget.findData(str(raw)) >= 0:
                    widget.setCurrentIndex(widget.findData(str(raw)))
            elif str(raw).lower() in ("true", "false"):
                widget.setChecked(str(raw).lower() == "true")
        self.scales.setEnabled(not self.auto_scales.isChecked())
