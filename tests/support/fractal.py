"""Shared material for the fractal tests: a small drawn canvas and one example of each fractal
Action (for the generic replay, bank and hostile tests)."""

from texeditor.fractal.actions import FractalRelief, IFSMotif
from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.recipe.history import History


def history() -> History:
    """A 40×32 G = 4 canvas with a band of level 1: something for a motif to cover."""
    h = History()
    h.apply(NewCanvas(40, 32, 4))
    h.apply(SetLevels(10, 0, 6, 40, 1))
    return h


EXAMPLES = [
    FractalRelief(48, 32, seed=3, roughness=0.7, levels=6),
    FractalRelief(16, 16, seed=1, roughness=0.0, levels=2),
    IFSMotif("tree", 16, 20, 30, level=3, seed=2, points=20_000),
    IFSMotif("fern", 30, 5, 24, level=2, seed=4, points=5_000, density=2),   # partly off
    IFSMotif("sierpinski", 16, 20, 16, level=1),
]
