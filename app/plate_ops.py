"""Colour plates in the main window: the Plates dock's requests as Actions, painting on the plates
with the ordinary tools, and the canvas and exports laid on the plates.

A mixin of MainWindow. While Tools ▸ Paint on the plates is on (and the document has plates), every level or palette step the window submits is wrapped in an ``OnPlates`` step, the
tools read the plates as their levels (``paint_document``) and the palette dock shows the plate
colours.
"""

from __future__ import annotations

import colorsys
from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor.markov.levels import load_image
from texeditor.texture.plate_actions import AddPlates, OnPlates, PlatesFromPhoto, RemovePlates
from texeditor.texture.plates import grid_text, laid_on_plates, levels_on_plates, photo_grid

from .acquire_dialog import IMAGE_FILTER, PASTED


def plate_colours(count: int) -> tuple:
    """``count`` soft colours evenly round the colour wheel, for a new plates layer."""
    return tuple(tuple(int(round(255 * c)) for c in colorsys.hsv_to_rgb(k / count, 0.45, 0.8))
                 for k in range(count))


class PlatesView:
    """A document seen by the tools while they paint on the plates: its plates as the levels,
    their colours as the palette; anything else is the document's."""

    def __init__(self, doc):
        self._doc = doc

    @property
    def levels(self):
        return self._doc.plates

    @property
    def palette(self):
        return self._doc.plate_colours

    @property
    def num_levels(self) -> int:
        return len(self._doc.plate_colours)

    def __getattr__(self, name):
        return getattr(self._doc, name)


class PlateOps:
    """Plates from the dock, painting target, pictures (needs history, palette_dock, plates_dock,
    act_plates, act_paint_plates, canvas, submit, tone_picture, clipboard_photo)."""

    # -- the dock's requests ------------------------------------------------------------------------
    def show_plates_dock(self) -> None:
        """Image ▸ Colour plates…: the Plates dock, in front of the Synthesis dock it shares."""
        self.plates_dock.show()
        self.plates_dock.raise_()
        QtCore.QTimer.singleShot(0, self, self._size_docks)      # its tab bar takes some height

    def add_plates(self, count: int) -> bool:
        return self.submit(AddPlates(plate_colours(count)))

    def remove_plates(self) -> bool:
        return self.submit(RemovePlates())

    def plates_from_photo(self, count: int, blur: float, path=None) -> bool:
        """Ask for a photo (unless ``path``); it is read, blurred, reduced and laid on the
        texture as plates in the worker (a large photo takes a second or two to decode, a
        2048² texture's plates 2.5 s), then the step is applied. False when nothing was
        started."""
        if self.busy_note():
            return False
        if path is None:
            path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Plates from a photo",
                                                            self._folder(), IMAGE_FILTER)
            if not path:
                return False
        path = Path(path)
        return self._plates_from(lambda: load_image(path), path.name, count, blur)

    def plates_from_clipboard(self, count: int, blur: float) -> bool:
        """The Plates dock's Paste: plates from the clipboard's picture, or from the image file
        copied in a file manager, as from a photo. False when nothing was started (nothing on
        the clipboard: the status bar says so)."""
        if self.busy_note():
            return False
        photo = self.clipboard_photo("Cannot take plates from this picture", "take plates from")
        if photo is None:
            return False
        if isinstance(photo, Path):
            return self.plates_from_photo(count, blur, photo)
        return self._plates_from(photo.photo, str(PASTED), count, blur)   # read in the worker

    def _plates_from(self, image, name: str, count: int, blur: float) -> bool:
        """Plates from the picture ``image()`` gives, read, blurred, reduced and laid on the
        texture in the worker (a large photo takes a second or two to decode, a 2048²
        texture's plates 2.5 s), then the step applied."""
        def read(doc) -> tuple:
            grid = grid_text(photo_grid(image(), blur))
            action = PlatesFromPhoto(grid, plates=count, name=name[:128])
            return action, action.prepare(doc)
        return self.submit_computed(read, f"Reading {name} for plates…",
                                    f"Cannot take plates from {name}")

    # -- painting on the plates ---------------------------------------------------------------------
    def painting_plates(self) -> bool:
        return self.act_paint_plates.isChecked() and self.document.plates is not None

    @property
    def paint_document(self):
        """What the tools paint: the document, or its plates (``PlatesView``)."""
        doc = self.document
        return PlatesView(doc) if self.painting_plates() else doc

    def paint_palette(self) -> np.ndarray:
        """The swatches the palette dock shows: the palette, or the plate colours."""
        return np.asarray(self.paint_document.palette)

    def on_target(self, action):
        """The step as the user means it: a level or palette step goes to the plates while
        painting them (a step that cannot is refused with the reason, by OnPlates)."""
        if self.painting_plates() and action.EFFECT in ("levels", "palette"):
            return OnPlates.of(action)
        return action

    def _paint_target_changed(self, _plates: bool = False) -> None:
        self.palette_dock.set_plates_mode(self.painting_plates())
        self.palette_dock.set_palette(self.paint_palette())

    def _refresh_plates(self) -> None:
        """The dock and the two toggles follow the document's plates (undo may take them)."""
        colours = self.document.plate_colours
        self.plates_dock.refresh(colours)
        for action in (self.act_plates, self.act_paint_plates):
            action.setEnabled(colours is not None)
        if colours is None:
            self.act_paint_plates.setChecked(False)
        self.palette_dock.set_plates_mode(self.painting_plates())

    # -- pictures ---------------------------------------------------------------------------------------
    def display_picture(self, palette=None, colours=None, wait: bool = True) -> np.ndarray | None:
        """The picture on show (and exported): the photo's tone or the palette's colours, laid
        on the plates when there are some and View ▸ Show plates is on; None when the palette's
        colours alone are shown (the canvas then draws levels through the palette).
        ``palette``/``colours``: a palette or plate colours previewed instead of the document's.
        ``wait`` False: a large tone may come later (see tone_picture)."""
        doc = self.document
        tone = self.tone_picture(wait)
        if doc.plates is None or not self.act_plates.isChecked() or not doc.levels.size:
            return tone
        colours = doc.plate_colours if colours is None else colours
        if tone is not None:
            return laid_on_plates(tone, doc.plates, colours)
        return levels_on_plates(doc.levels, doc.palette if palette is None else palette,
                                doc.plates, colours)

    def _preview_palette(self, palette) -> None:
        """A palette being dragged in the palette dock, shown on the canvas (not yet a step)."""
        doc = self.document
        if self.painting_plates():
            picture = self.display_picture(colours=palette)
        else:
            picture = self.display_picture(palette=palette)
        if picture is None:
            self.canvas.set_palette(palette)
        else:
            self.canvas.set_image(doc.levels, doc.palette, picture)

    def _plates_toggled(self, _on: bool = False) -> None:
        if self.history is not None:
            self._show_document(self.document, None)
