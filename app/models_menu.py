"""The Models menu: texture models beyond the 1984 thesis (digest §11), one entry each.

``add_model_entries(window)`` fills the window's menu "ModelsMenu" (declared in MENUS);
a new model adds its own with one line there.
"""

from __future__ import annotations

from PySide6 import QtGui


def add_model_entries(window) -> None:
    menu = window.menu("ModelsMenu")
    _entry(window, menu, "Random-phase &noise from a photo…", "random_phase_noise",
           "A new texture: a photo's Fourier modulus with random phases (micro-textures)")
    _entry(window, menu, "&Texton of a photo…", "texton",
           "A new texture: a photo's Fourier modulus with zero phases, its elementary shape")
    _entry(window, menu, "&Match histogram to a photo…", "match_histogram",
           "New colours giving the texture a photo's grey or colour distribution")
    _entry(window, menu, "&Heeger–Bergen texture from a photo…", "heeger_bergen",
           "A new texture: noise given a photo's pyramid sub-band histograms (stone, bark)")
    _entry(window, menu, "&Flow texture…", "flow_texture",
           "A new texture: noise smoothed along a photo's grain or strokes you draw (wood, hair)")
    _entry(window, menu, "&Fractal relief…", "fractal_relief",
           "A new texture: midpoint-displacement heights in G levels, for the relief preview")
    _entry(window, menu, "&IFS motif…", "ifs_motif",
           "Stamp a fractal motif (tree, fern, Sierpinski triangle) in one level")


def _entry(window, menu, text: str, model: str, tip: str) -> QtGui.QAction:
    from .models_dialog import open_model
    action = QtGui.QAction(text, window)
    action.setObjectName(f"act_{model}")
    action.setStatusTip(tip)
    action.setToolTip(tip)
    action.triggered.connect(lambda _=False: open_model(window, model))
    menu.addAction(action)
    return action
