"""Small shared widget helpers."""

from __future__ import annotations

from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.markov.scan import SCAN_NAMES

# a window manager's frame and title bar, which Qt learns only once the window is shown
DECORATIONS = QtCore.QSize(16, 40)


def available_area(window: QtWidgets.QWidget) -> QtCore.QRect:
    """The usable part of the screen the window (or its parent) is on, less the window's frame."""
    parent = window.parentWidget()
    screen = (parent.screen() if parent is not None else None) or window.screen() \
        or QtGui.QGuiApplication.primaryScreen()
    area = screen.availableGeometry()
    return area.adjusted(0, 0, -DECORATIONS.width(), -DECORATIONS.height())


def fit_to_screen(window: QtWidgets.QWidget, width: int, height: int) -> QtCore.QSize:
    """Resize a top-level window to width×height, or to less on a smaller screen (a 1280×800
    laptop): never beyond the available screen area, so no button is out of reach."""
    area = available_area(window)
    size = QtCore.QSize(min(width, area.width()), min(height, area.height()))
    window.resize(size)
    return size


def scrolled(body: QtWidgets.QWidget) -> QtWidgets.QScrollArea:
    """A frameless scroll area around a dock's body, so docks shrink on small screens."""
    area = QtWidgets.QScrollArea()
    area.setWidget(body)
    area.setWidgetResizable(True)
    area.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
    return area


def tight_vertically(layout: QtWidgets.QLayout, margin: int = 4) -> None:
    """Small top and bottom margins for a dock's body: at 1280×800 the Synthesis and Palette
    docks show every control beside a History list of eight rows only so."""
    m = layout.contentsMargins()
    layout.setContentsMargins(m.left(), margin, m.right(), margin)


def spin_box(lo, hi, value, *, decimals: int = 0, suffix: str = "", prefix: str = "",
             tip: str = "") -> QtWidgets.QAbstractSpinBox:
    """An integer spin box, or a decimal one when ``decimals`` > 0, set up in one call."""
    box = QtWidgets.QDoubleSpinBox() if decimals else QtWidgets.QSpinBox()
    if decimals:
        box.setDecimals(decimals)
    box.setRange(lo, hi)
    box.setValue(value)
    box.setSuffix(suffix)
    box.setPrefix(prefix)
    box.setToolTip(tip)
    return box


def scan_combo(tip: str) -> QtWidgets.QComboBox:
    """The four scan directions (texeditor.markov.scan) by name; an item's data is its key."""
    box = QtWidgets.QComboBox()
    for key, name in SCAN_NAMES.items():
        box.addItem(name, key)
    box.setToolTip(tip)
    return box


def select_path(combo: QtWidgets.QComboBox, path) -> None:
    """Select the item of ``path`` in a combo of files (its data the path), added if new."""
    path = Path(path)
    index = combo.findData(str(path))
    if index < 0:
        combo.addItem(path.name, str(path))
        index = combo.count() - 1
    combo.setCurrentIndex(index)


def row(*items, stretch: bool = True) -> QtWidgets.QHBoxLayout:
    """A form row of widgets and words ("columns ×"), left-aligned; without ``stretch`` the
    first widget takes the room instead (a file combo before its Browse button)."""
    layout = QtWidgets.QHBoxLayout()
    for k, item in enumerate(items):
        widget = QtWidgets.QLabel(item) if isinstance(item, str) else item
        layout.addWidget(widget, 0 if stretch or k else 1)
    if stretch:
        layout.addStretch(1)
    return layout
