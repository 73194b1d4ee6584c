"""Shared material for the colour-plate tests: a small texture, a two-colour photo and one
example of every plate Action (each applied in turn to ``history``)."""

import numpy as np

from texeditor.paint.actions import Stroke
from texeditor.recipe.actions import NewCanvas, SetLevels, SetPalette
from texeditor.recipe.history import History
from texeditor.regions.actions import Fill
from texeditor.texture.plate_actions import AddPlates, OnPlates, PlatesFromPhoto, RemovePlates
from texeditor.texture.plates import grid_text, photo_grid

RED, BLUE, CREAM = (200, 40, 30), (30, 60, 190), (240, 230, 200)


def two_colour_photo(h=40, w=60) -> np.ndarray:
    """A photo red on its left half and blue on its right half."""
    photo = np.empty((h, w, 3), np.uint8)
    photo[:, : w // 2], photo[:, w // 2:] = RED, BLUE
    return photo


def history(w=12, h=8) -> History:
    """A G = 3 texture: level 1 in the top-left 3×4 block, level 2 in the bottom row."""
    history = History()
    history.apply(NewCanvas(w, h, 3))
    history.apply(SetLevels(0, 0, 3, 4, 1))
    history.apply(SetLevels(h - 1, 0, 1, w, 2))
    return history


EXAMPLES = [
    AddPlates((RED, BLUE, CREAM), fill=2),
    OnPlates.of(Stroke(points=((1, 1), (1, 8)), level=0, size=3, shape="square")),
    OnPlates.of(Fill(6, 10, 1)),
    OnPlates.of(SetPalette(((250, 0, 0), (0, 0, 250), (250, 250, 250)))),
    PlatesFromPhoto(grid_text(photo_grid(two_colour_photo(), 0.05, side=12)), plates=2,
                    name="halves"),
    RemovePlates(),
]
