"""The Models menu: texture models beyond the 1984 thesis (digest §11), one entry each.

``add_model_entries(window)`` makes the menu (objectName "ModelsMenu") and adds its entries;
a new model adds its own with one line there.
"""

from __future__ import annotations

from PySide6 import QtGui, QtWidgets


def add_model_entries(window) -> None:
    menu = QtWidgets.QMenu("&Models", window.menuBar())
    menu.setObjectName("ModelsMenu")
    window.menuBar().insertMenu(window.menu("ViewMenu").menuAction(), menu)   # after Image
    _entry(window, menu, "Random-phase &noise from a photo…", "random_phase_noise",
           "A new texture: a photo's Fourier modulus with random phases (micro-textures)")
    _entry(window, menu, "&Texton of a photo…", "texton",
           "A new texture: a photo's Fourier modulus with zero phases, its elementary shape")
    _entry(window, menu, "&Match histogram to a photo…", "match_histogram",
           "New colours giving the texture a photo's grey or colour distribution")


def _entry(window, menu, text: str, model: str, tip: str) -> QtGui.QAction:
    from .models_dialog import open_model
    action = QtGui.QAction(text, window)
    action.setObjectName(f"act_{model}")
    action.setStatusTip(tip)
    action.setToolTip(tip)
    action.triggered.connect(lambda _=False: open_model(window, model))
    menu.addAction(action)
    return action
