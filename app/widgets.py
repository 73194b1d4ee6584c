"""Small shared widget helpers."""

from __future__ import annotations

from PySide6 import QtWidgets


def scrolled(body: QtWidgets.QWidget) -> QtWidgets.QScrollArea:
    """A frameless scroll area around a dock's body, so docks shrink on small screens."""
    area = QtWidgets.QScrollArea()
    area.setWidget(body)
    area.setWidgetResizable(True)
    area.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
    return area


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
