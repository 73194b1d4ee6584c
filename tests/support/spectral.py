"""Shared material for the model tests: a small colour exemplar photo, a grey one, the History
that holds them and one example of every model Action."""

import numpy as np

from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.recipe.exemplars import exemplar_ref
from texeditor.recipe.history import History
from texeditor.flow.actions import FlowTexture
from texeditor.pyramid.actions import HeegerBergen
from texeditor.spectral.actions import MatchHistogram, RandomPhaseNoise, Texton


def colour_photo(h=24, w=32) -> np.ndarray:
    """Warm stripes with noise: a colour micro-texture."""
    rng = np.random.default_rng(11)
    stripes = 60 * np.sin(np.arange(w) * 2 * np.pi / 6)[None, :, None]
    base = np.array([150, 110, 70])[None, None, :] + stripes * np.array([1.0, 0.6, 0.2])
    return np.clip(base + rng.normal(0, 20, (h, w, 3)), 0, 255).astype(np.uint8)


def grey_photo(h=20, w=20) -> np.ndarray:
    return np.random.default_rng(12).integers(30, 220, (h, w)).astype(np.uint8)


COLOUR, GREY = exemplar_ref(colour_photo()), exemplar_ref(grey_photo())


def history() -> History:
    """A G = 3 drawn texture whose document holds both exemplars."""
    h = History()
    h.add_exemplar(colour_photo())
    h.add_exemplar(grey_photo())
    h.apply(NewCanvas(12, 8, 3))
    h.apply(SetLevels(0, 0, 3, 4, 1))
    h.apply(SetLevels(7, 0, 1, 12, 2))
    return h


EXAMPLES = [
    RandomPhaseNoise(COLOUR, 40, 30, seed=2, levels=5),
    RandomPhaseNoise(GREY, 16, 24, seed=9, levels=3),
    Texton(COLOUR, levels=4),
    Texton(GREY),
    MatchHistogram(COLOUR),
    MatchHistogram(GREY),
    HeegerBergen(COLOUR, 20, 16, seed=3, iterations=2, levels=4),
    HeegerBergen(GREY, 16, 16, seed=5, iterations=1, levels=3),
    FlowTexture("photo", COLOUR, width=24, height=20, seed=2, length=8, levels=4),
    FlowTexture("strokes", None, ((2, 2), (18, 30), (18, 30), (4, 40)), width=44, height=20,
                seed=3, length=6, tileable=True, levels=3),
]
