"""The Plates dock: the colour plates under the texture (thesis §1.2.3–1.2.4) — add them, take
them from a blurred photo, remove them, show them or not.

It only gathers parameters and says what the user asked (signals); the main window builds the
Actions (app.plate_ops). Plates are painted with the ordinary tools once "Paint on the plates" is
ticked.
"""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

from .widgets import scrolled, spin_box

DEFAULT_PLATES = 4
DEFAULT_BLUR = 3.0         # % of the photo's width


class PlatesDock(QtWidgets.QDockWidget):
    """``add_requested(P)``, ``photo_requested(P, blur)`` (blur: a fraction of the photo's
    width), ``paste_requested(P, blur)`` (from the clipboard's picture),
    ``remove_requested()``; ``paint_box`` mirrors Tools ▸ Paint on the plates and ``show_box``
    View ▸ Show plates."""

    add_requested = QtCore.Signal(int)
    photo_requested = QtCore.Signal(int, float)
    paste_requested = QtCore.Signal(int, float)
    remove_requested = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__("Plates", parent)
        self.setObjectName("PlatesDock")
        body = QtWidgets.QWidget()
        form = QtWidgets.QFormLayout(body)
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)
        self.count = spin_box(2, 16, DEFAULT_PLATES, tip="Number of plates P (each a colour)")
        self.blur = spin_box(0.1, 100.0, DEFAULT_BLUR, decimals=1, suffix=" %",
                             tip="Blur of the photo before it is cut into plates, as a share of "
                                 "its width: more blur, larger plates")
        self.add_button = QtWidgets.QPushButton("Add plates")
        self.add_button.setToolTip("A plates layer of P colours, every point on plate 0: paint "
                                   "the others with the tools (Palette ▸ Paint on: Plates)")
        self.add_button.clicked.connect(lambda: self.add_requested.emit(self.count.value()))
        self.photo_button = QtWidgets.QPushButton("From a photo…")
        self.photo_button.setToolTip("Plates taken from a photo: blurred, stretched over the "
                                     "canvas and cut into P colour classes")
        self.photo_button.clicked.connect(
            lambda: self.photo_requested.emit(self.count.value(), self.blur.value() / 100))
        self.paste_button = QtWidgets.QPushButton("Paste")
        self.paste_button.setToolTip("Plates taken from the picture on the clipboard (a "
                                     "screenshot, a picture copied in a painting program or a "
                                     "browser, or an image file copied in a file manager), as "
                                     "from a photo")
        self.paste_button.clicked.connect(
            lambda: self.paste_requested.emit(self.count.value(), self.blur.value() / 100))
        self.remove_button = QtWidgets.QPushButton("Remove")
        self.remove_button.setToolTip("Take the plates away (undo brings them back)")
        self.remove_button.clicked.connect(self.remove_requested)
        self.paint_box = QtWidgets.QCheckBox("Paint on the plates")
        self.paint_box.setToolTip("The tools and the palette's swatches work on the plates "
                                  "instead of the texture's levels (Tools ▸ Paint on the plates, "
                                  "Shift+P)")
        self.show_box = QtWidgets.QCheckBox("Show plates")
        self.show_box.setChecked(True)
        self.show_box.setToolTip("Lay the texture on its plates on the canvas and in exports "
                                 "(View ▸ Show plates)")
        numbers = QtWidgets.QHBoxLayout()
        numbers.addWidget(self.count, 1)
        numbers.addWidget(QtWidgets.QLabel("Photo blur"))
        numbers.addWidget(self.blur, 1)
        form.addRow(self.info)
        form.addRow("Plates", numbers)
        for pair in ((self.add_button, self.remove_button),          # two rows: four buttons
                     (self.photo_button, self.paste_button)):        # do not fit the dock
            buttons = QtWidgets.QHBoxLayout()
            for button in pair:
                buttons.addWidget(button)
            form.addRow(buttons)
        checks = QtWidgets.QHBoxLayout()
        checks.addWidget(self.paint_box)
        checks.addWidget(self.show_box)
        form.addRow(checks)
        self.setWidget(scrolled(body))
        self.refresh(None)

    def refresh(self, colours) -> None:
        """Say whether the document has plates (``colours``: their P colours, or None)."""
        has = colours is not None
        self.info.setText(f"{len(colours)} plates under the texture's greys." if has else
                          "No plates: the palette's colours show.")     # one line: the dock
        self.info.setToolTip("The texture's greys are laid on the plates' colours "   # fits
                             "(I = plates + texture, thesis §1.2.3)" if has else    # 1280×800
                             "Add plates, take them from a photo or paste them")
        for widget in (self.remove_button, self.paint_box, self.show_box):
            widget.setEnabled(has)
