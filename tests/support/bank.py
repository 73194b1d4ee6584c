"""Shared material for the bank tests: small histories, and one history per Action type of the
engine (``one_of_each``, also the histories the release-0.1 files in tests/data were made of)."""

import numpy as np

from texeditor.markov import doubling
from texeditor.markov.levels import load_image
from texeditor.recipe.actions import (CropCanvas, NewCanvas, ResizeCanvas, SetLevels, SetPalette,
                                      Synthesize)
from texeditor.recipe.history import History
from texeditor.resources import ROOT as RESOURCES

from . import TINY_DPJS


def synthesised(seed: int = 1, size=(24, 16)) -> History:
    history = History()
    ref = history.add_dpj(TINY_DPJS[0])
    history.apply(Synthesize(ref, *size, seed))
    return history


def drawn(rects, size=(32, 32), levels: int = 2) -> History:
    """A hand-made texture: a blank canvas and filled rectangles (top, left, height, width, v)."""
    history = History()
    history.apply(NewCanvas(*size, levels))
    for rect in rects:
        history.apply(SetLevels(*rect))
    return history


def one_of_each() -> list:
    """(type, History) for every action type: the base actions, and one example of each other
    type applied to the document its own tests use (their EXAMPLES)."""
    from texeditor.spots.actions import PlaceSpot, ScatterSpots
    from texeditor.markov.multiscale import estimate_scales
    from texeditor.photo import PhotoModel, photo_tone
    from texeditor.recipe.actions import SynthesizeScales
    from texeditor.texture.actions import DoubleLevels

    from . import fractal, paint, plates, spectral, spots as spot, texture
    from .regions import EXAMPLES, T, history_of

    histories = []
    h = synthesised(3)
    second = h.add_dpj(TINY_DPJS[1])
    h.apply(Synthesize(second, 20, 18, 2))
    h.apply(SetPalette([(10, 20, 30), (200, 100, 0), (255, 255, 255)]))
    h.apply(ResizeCanvas(22, 25, 1))
    h.apply(CropCanvas(2, 3, 15, 12))
    histories.append(("base", h))
    for action in {type(a): a for a in EXAMPLES}.values():
        h = history_of(T)
        h.apply(action)
        histories.append((action.TYPE, h))
    for action in {type(a): a for a in paint.EXAMPLES}.values():
        h = History(paint.textured())
        h.apply(action)
        histories.append((action.TYPE, h))
    for action in {type(a): a for a in texture.EXAMPLES}.values():
        if action.TYPE != "double_levels":
            histories.append((action.TYPE, texture.history_of(texture.T, extra=[action])))
    h = texture.history_of(np.array([[0, 1, 2, 2], [1, 2, 0, 1], [2, 2, 1, 0]], np.uint8), 3)
    photo = load_image(RESOURCES / "images" / "gravel.png")[:80, :80]
    table = h.document.store_dpj(doubling.learn(photo, 3, "band", name="gravel"))
    h.apply(DoubleLevels(table, 5))             # a doubling table: a stored DPJ
    histories.append(("double_levels", h))
    h = History()
    model, levels = estimate_scales(photo, scales=2)
    refs = tuple(h.add_dpj(dpj) for dpj in model.dpjs)
    tone = PhotoModel(model, photo_tone(photo, levels[-1])).tone_pictures()
    photo_ref, levels_ref = (h.add_exemplar(p) for p in tone)
    h.apply(SynthesizeScales(refs, 30, 20, seed=4,     # a multi-scale synthesis, with its tone
                             tone_photo=photo_ref, tone_levels=levels_ref))
    h.apply(SetPalette([(0, 0, 0), (90, 90, 90), (170, 170, 170), (255, 255, 255)]))
    histories.append(("synthesize_scales", h))
    h = spot.canvas(base=1)
    h.apply(PlaceSpot(spot.DISC, 16, 16, level=2, contour=0.2, seed=5))
    h.apply(ScatterSpots(spot.DISC, 12, seed=7, scale=0.5, level=3))
    spot.delete(h, 2)                                   # the PlaceSpot, step 3
    histories.append(("spots", h))
    h = plates.history()
    for action in plates.EXAMPLES:                      # each plate step, the last removes them
        h.apply(action)
        histories.append((action.TYPE, History.from_log(h.applied, {})))
    for action in {type(a): a for a in spectral.EXAMPLES}.values():     # an exemplar photo each
        h = spectral.history()
        h.apply(action)
        histories.append((action.TYPE, h))
    for action in {type(a): a for a in fractal.EXAMPLES}.values():
        h = fractal.history()
        h.apply(action)
        histories.append((action.TYPE, h))
    return histories

