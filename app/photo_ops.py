"""Photo models in the main window: their scale DPJs in the document, multi-scale synthesis, and
the canvas drawn with the photo's tone.

A mixin of MainWindow. A photo model (photo.PhotoModel, from the acquire dialog or a `.dpj` of
format 2) puts its scale DPJs in the document's DPJ store, where SynthesizeScales steps refer to
them and a `.texture` keeps them; the model itself (its tone) stays with the window, which shows
any document whose levels it can draw with the photo's greys and colours instead of the palette.
"""

from __future__ import annotations

import hashlib
import threading
import time
from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor import warmup
from texeditor.errors import TexeditorError
from texeditor.markov.dpj import DPJ
from texeditor.photo import PhotoModel, document_model, load_model, step_wrap

from .acquire_dialog import named_scales
from .synthesis_dock import synthesis_step

DPJ_FILTER = "DPJ files and photo models (*.dpj);;All files (*)"


class ToneArrival(QtCore.QObject):
    """Carries a tone drawn on a background thread to the GUI thread (a queued signal)."""

    drawn = QtCore.Signal(object)


class PhotoOps:
    TONE_IN_BACKGROUND = 1 << 20      # points: a larger picture's tone is drawn off the GUI
                                      # thread (about 0.3 s and more), the edit shown at once

    """Attach a photo model, find the current DPJ's scales, render tone (needs history, canvas,
    act_tone, photo_model, synthesis_dock)."""

    # -- the model and its scales -------------------------------------------------------------------
    def attach_model(self, model: PhotoModel) -> None:
        """Add a photo model's scale DPJs to the document (coarsest first: the finest becomes
        the current DPJ) and keep the model for its tone."""
        self.photo_model = model
        self._tone_cache = None
        for dpj in model.scales.dpjs:
            self.history.add_dpj(dpj)
        self._show_document(self.history.document, None)

    def use_edited_scale(self, dpj: DPJ) -> int | None:
        """The DPJ editor's Use of a scale of the attached model, edited (the current DPJ was
        one of its scales, and this DPJ says it is scale k of as many, with the same window
        and levels): the model keeps it in place of scale k, with its tone, so Synthesise
        draws every scale and the tone from it (used as a DPJ alone, its composite levels were
        drawn as plain levels without the tone). Returns k, or None when it is not one."""
        model, k = self.photo_model, dpj.meta.get("scale")
        if model is None or self.history.document.dpj_ref not in self.scale_refs() \
                or isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < model.scales.scales:
            return None
        old = model.scales.dpjs[k]
        keys = ("scales", "parent_levels", "parents_under", "parent_phase")
        if (dpj.window, dpj.levels) != (old.window, old.levels) \
                or any(dpj.meta.get(key) != old.meta.get(key) for key in keys):
            return None
        dpjs = list(model.scales.dpjs)
        dpjs[k] = dpj
        try:
            scales = type(model.scales)(tuple(dpjs))
        except TexeditorError:
            return None
        self.photo_model = PhotoModel(scales, model.tone)
        self._tone_cache = None
        return k

    def scale_refs(self) -> tuple[str, ...]:
        """The scales (references, coarsest first) the current DPJ belongs to: the attached
        model's, or those of a multi-scale synthesis in the log (a reopened `.texture`); ()
        when the current DPJ is a plain one."""
        doc = self.history.document
        sets = []
        if self.photo_model is not None:
            sets.append(tuple(d.ref for d in self.photo_model.scales.dpjs))
        sets += [a.dpjs for a in reversed(self.history.actions) if a.TYPE == "synthesize_scales"]
        for refs in sets:
            if doc.dpj_ref in refs and all(r in doc.dpjs for r in refs):
                return tuple(refs)
        return ()

    def keep_model_for(self, history) -> None:
        """Another document is shown: the model stays attached only if the document holds its
        scales (a texture made from it), so other textures show with their own palette."""
        model = self.photo_model
        if model is not None and model.scales.dpjs[-1].ref not in history.document.dpjs:
            self.photo_model = None
            self._tone_cache = None

    # -- File ▸ Open DPJ ------------------------------------------------------------------------------
    def open_dpj(self, path=None) -> bool:
        """A `.dpj` file: a photo model (format 2) adds its scales and is attached; a single DPJ
        (format 1) becomes the current DPJ, as an acquired one does."""
        if path is None:
            path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Open a DPJ or photo model",
                                                            self._folder(), DPJ_FILTER)
            if not path:
                return False
        if self.edits_locked():
            return False
        path = Path(path)
        try:
            loaded = load_model(path)
        except (TexeditorError, OSError) as exc:
            self.show_error(f"Cannot open {path.name}", exc)
            return False
        if isinstance(loaded, PhotoModel):
            model = PhotoModel(named_scales(loaded.scales, {"name": path.stem}), loaded.tone)
            self.attach_model(model)
            tone = "with its tone" if model.tone is not None else "without tone"
            self.statusBar().showMessage(f"Opened the photo model {path.name}: {model.scales.scales} "
                                         f"scales, G = {model.levels}, {tone}.", 10000)
            return True
        dpj = loaded if "name" in loaded.meta else DPJ(
            loaded.configs, loaded.probs, loaded.levels, palette=loaded.palette,
            meta={**loaded.meta, "name": path.stem})
        self.history.add_dpj(dpj)
        u, v = dpj.window
        self.statusBar().showMessage(f"Opened {path.name}: a {u}×{v} DPJ with G = {dpj.levels}, "
                                     "now the current DPJ.", 10000)
        return True

    # -- tone -------------------------------------------------------------------------------------------
    def tone_model(self) -> PhotoModel | None:
        """The model whose tone shows the document: the one its synthesis step names (a
        reopened `.texture` or bank entry keeps it), else the attached one."""
        step = synthesis_step(self.history)      # refs are content hashes: an equal step
        cached = self._step_model                # names the same model
        if cached is None or cached[0] != step:
            try:
                model = document_model(self.history.document, step)
            except TexeditorError:
                model = None                   # a stored tone that does not fit: the palette
            cached = self._step_model = (step, model)
        return cached[1] or self.photo_model

    def tone_available(self) -> bool:
        """A model with tone is at hand and the document's levels are levels it knows."""
        model, doc = self.tone_model(), self.history.document
        return (model is not None and model.tone is not None and doc.levels.size > 0
                and doc.num_levels <= model.levels)

    def show_stored_tone(self, levels, tone) -> None:
        """A bank entry's stored tone picture (Bank.stored_tone) stands for the tone of
        ``levels`` until the tone's kernels draw it, the same pixels (a first start shows the
        built-in toned at once, not in the palette's greys for the seconds they compile)."""
        self._stored_tone = None if tone is None else (np.array(levels), tone)

    def tone_picture(self, wait: bool = True) -> np.ndarray | None:
        """The document's levels drawn with the photo's tone when tone is on and available
        (seeded by the synthesis that made the texture, so a picture is the same each time it is
        shown); None: the palette's colours are shown. ``wait`` False (the canvas after an
        edit): a large picture's tone is drawn on a background thread, and meanwhile the last
        tone is shown with the points that changed in their palette colours; so is any while
        the warm-up has not compiled the tone's kernels (a first start: not on this thread)."""
        if not (self.act_tone.isChecked() and self.tone_available()):
            return None
        doc, model = self.history.document, self.tone_model()
        step = synthesis_step(self.history)
        seed = int(step.seed) if step is not None else 0
        wrap = step_wrap(step)
        key = (seed, wrap, doc.shape,
               hashlib.blake2b(np.ascontiguousarray(doc.levels).data, digest_size=16).digest())
        cached = self._tone_cache                   # (model, key, its tone.Rendered)
        same_model = cached is not None and cached[0] is model
        if same_model and cached[1] == key:
            return cached[2].picture
        before = cached[2] if same_model else None  # the rows above the first edited one stay
        if not wait and (doc.levels.size >= self.TONE_IN_BACKGROUND or warmup.pending("tone")):
            self._draw_tone_later(model, key, doc.levels, seed, wrap, before)
            return self._tone_meanwhile(before, doc)
        start = time.perf_counter()
        drawn = model.rendering(doc.levels, seed=seed, wrap=wrap, before=before)
        self.tone_seconds = time.perf_counter() - start
        self._tone_cache = (model, key, drawn)
        return drawn.picture

    def _draw_tone_later(self, model, key, levels, seed, wrap, before) -> None:
        """Start drawing the tone on a thread, unless one is drawing: when it is done, the
        canvas asks again and the latest levels are drawn next (from the last rendering)."""
        if self._tone_drawing:
            return
        if self._tone_arrival is None:
            self._tone_arrival = ToneArrival(self)
            self._tone_arrival.drawn.connect(self._tone_drawn, QtCore.Qt.QueuedConnection)
        self._tone_drawing = True
        arrival, levels = self._tone_arrival, levels.copy()

        def draw():
            start = time.perf_counter()
            try:
                drawn = model.rendering(levels, seed=seed, wrap=wrap, before=before)
            except Exception as error:                 # shown on the GUI thread
                drawn = error
            try:
                arrival.drawn.emit((model, key, drawn, time.perf_counter() - start))
            except RuntimeError:                       # the window is gone
                pass
        threading.Thread(target=draw, name="tone", daemon=True).start()

    def _tone_drawn(self, payload) -> None:
        model, key, drawn, seconds = payload
        self._tone_drawing = False
        if isinstance(drawn, Exception):
            self.statusBar().showMessage(f"The photo's tone could not be drawn: {drawn}", 10_000)
            return
        self._tone_cache, self.tone_seconds = (model, key, drawn), seconds
        if self.history is not None and self.history.document.levels.size:
            self._show_document(self.history.document, None)     # the tone, or the next one

    def _tone_meanwhile(self, before, doc) -> np.ndarray | None:
        """The last tone with the points whose level changed since in their palette colours;
        before any, a bank entry's stored tone picture of these very levels (a first start,
        see show_stored_tone); else None, the palette."""
        if before is None or before.levels.shape != doc.shape:
            stored = self._stored_tone
            if stored is None or not np.array_equal(stored[0], doc.levels):
                return None
            picture = stored[1]
            return np.repeat(picture[..., None], 3, axis=2) if picture.ndim == 2 else picture
        picture = before.picture
        if picture.ndim == 2:
            picture = np.repeat(picture[..., None], 3, axis=2)
        else:
            picture = picture.copy()
        changed = before.levels != doc.levels
        picture[changed] = np.asarray(doc.palette)[doc.levels[changed], :3]
        return picture

    def tone_refs(self, refs) -> tuple[str | None, str | None]:
        """The tone a synthesis from all the scales ``refs`` names, so it travels with the
        texture: the attached model's, added to the document as two exemplars (photo, levels),
        else the one the log's latest step from these scales named (a reopened `.texture` or
        bank entry has no model attached, and a new seed keeps its tone). (None, None) when
        there is no such tone."""
        model = self.photo_model
        if model is not None and model.tone is not None \
                and tuple(refs) == tuple(d.ref for d in model.scales.dpjs):
            photo, levels = model.tone_pictures()
            return self.history.add_exemplar(photo), self.history.add_exemplar(levels)
        exemplars = self.history.document.exemplars
        for step in reversed(self.history.applied):
            if step.TYPE == "synthesize_scales" and tuple(step.dpjs) == tuple(refs) \
                    and step.tone_photo in exemplars and step.tone_levels in exemplars:
                return step.tone_photo, step.tone_levels
        return None, None

    def _tone_toggled(self, _on: bool = False) -> None:
        if self.history is not None:
            self._show_document(self.history.document, None)
