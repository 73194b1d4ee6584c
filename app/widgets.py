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
