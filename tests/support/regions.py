"""Shared material for the region operator tests: grids written as the thesis draws them, its
test bench T, and one example of every region Action with the document they apply to."""

import textwrap

import numpy as np
from hypothesis import strategies as st

from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.recipe.history import History
from texeditor.regions.actions import (Affinity, ChangeLevel, Copy, DeleteSelection, Fill,
                                      FlipSelection, Identity, Isometry, RotateSelection,
                                      ScaleSelection, ScatterRegions, Similarity, Translate)


def grid(text: str) -> np.ndarray:
    rows = [line.split() for line in textwrap.dedent(text).strip().splitlines()]
    return np.array([[0 if c == "." else int(c) for c in row] for row in rows], np.uint8)


def marks(text: str) -> np.ndarray:
    rows = [line.split() for line in textwrap.dedent(text).strip().splitlines()]
    return np.array([[c == "#" for c in row] for row in rows], bool)


def show(array: np.ndarray) -> str:
    """A mask as '#'/'.' or a level matrix as digits/'.', one line per row (readable diffs)."""
    array = np.atleast_2d(array)
    if array.dtype == bool:
        return "\n".join(" ".join("#" if v else "." for v in row) for row in array)
    return "\n".join(" ".join(str(v) if v else "." for v in row) for row in array)


def same(array, text) -> bool:
    expected = marks(text) if array.dtype == bool else grid(text)
    return show(array) == show(expected)


# The thesis-sized test bench: a 1-ring holding a ring of background around a 3 (nested regions),
# 2s and 3s touching the right and bottom edges and a corner.
T = grid("""
    . . . . . . . .
    . 1 1 1 1 1 . 2
    . 1 . . . 1 . 2
    . 1 . 3 . 1 . .
    . 1 . . . 1 . .
    . 1 1 1 1 1 . 3
    . . . . . . . 3
    2 2 . . . . 3 3
""")


@st.composite
def grids(draw, max_side=10, max_level=3):
    h, w = draw(st.integers(1, max_side)), draw(st.integers(1, max_side))
    cells = draw(st.lists(st.integers(0, max_level), min_size=h * w, max_size=h * w))
    return np.array(cells, np.uint8).reshape(h, w)



EXAMPLES = [
    Fill(3, 2, 2), Fill(0, 0, 3, scope="global", connectivity=8),
    Translate(1, 7, 0, 6), Translate(1, 1, -2, 9, fill=1, kind="regions_in_region", wrap=True),
    Copy(3, 3, 6, 4), Copy(7, 7, 0, 0, scope="global", connectivity=8, wrap=True),
    ChangeLevel(1, 1, 3, kind="neighbours", neighbour=2),
    ChangeLevel(1, 1, 2, kind="neighbours"), DeleteSelection(3, 3, kind="partial"),
    ScaleSelection(1, 1, 1.5), ScaleSelection(3, 3, 2, factor_cols=0.5, fill=1, wrap=True),
    RotateSelection(1, 7, 30), RotateSelection(1, 1, 90, kind="region_in_region"),
    FlipSelection(7, 0, "vertical"), FlipSelection(1, 1, kind="regions_in_region"),
    Identity(2, 3), Identity(0, 4, 2, 3, 3, 4, wrap=True, row=1, col=1),
    Isometry(90, 3.5, 3.5), Isometry(30, 2, 2, row=1, col=1, keep_source=True, fill=3),
    Similarity(1.5, 2, 2, row=1, col=1, kind="neighbours", neighbour=3),
    Similarity(0.5, -0.5, -0.5, wrap=True), Similarity(2, 3, 3, angle=45, row=3, col=3),
    Affinity(1, 0, 1, 1), Affinity(1, 0.5, 0, 1, 1, 1, 2, -3, row=1, col=1, fill=1),
    ScatterRegions(2, radius=1, row=1, col=1, kind="neighbours", neighbour=2),
    ScatterRegions(1, rotation="quarter", level=3, fill=1),
    ScatterRegions(5, radius=2, rotation="any", scale_min=0.5, scale_max=1.5, wrap=True),
]


def history_of(levels, g: int = 4) -> History:
    """A History whose document holds ``levels`` (a NewCanvas and one SetLevels per point)."""
    h, w = levels.shape
    history = History()
    history.apply(NewCanvas(w, h, g))
    for (r, c), v in np.ndenumerate(levels):
        if v:
            history.apply(SetLevels(r, c, 1, 1, int(v)))
    return history

