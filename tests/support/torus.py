"""Reading a texture against its DPJ on the torus (the tileable and particle tests)."""

import numpy as np
import skimage as ski

from texeditor import estimate_dpj, quantize
from texeditor.markov import estimation


def off_the_dpj(levels, dpj, torus=True) -> float:
    """Share of the windows (read on the torus: across both seams and the corner too) that the
    DPJ does not have."""
    return float(np.mean(off_places(levels, dpj, torus)))


def off_places(levels, dpj, torus=False) -> np.ndarray:
    """Where (top-left corners) the windows the DPJ lacks lie (on the torus: across the seams
    too)."""
    return ~np.isin(window_codes(levels, dpj.window, dpj.levels, torus), dpj.codes)


def window_codes(levels, window, g, torus=True) -> np.ndarray:
    """The code of the window at each top-left corner (on the torus: across the seams too)."""
    u, v = window
    h, w = levels.shape if torus else (levels.shape[0] - v + 1, levels.shape[1] - u + 1)
    return estimation.window_codes(levels, window, g, wrap=torus).reshape(h, w)


def window_tv(a, b) -> float:
    """The total-variation distance between the histograms of two sets of window codes."""
    keys, inverse = np.unique(np.concatenate([a, b]), return_inverse=True)
    pa = np.bincount(inverse[:len(a)], minlength=len(keys)) / len(a)
    pb = np.bincount(inverse[len(a):], minlength=len(keys)) / len(b)
    return 0.5 * float(np.abs(pa - pb).sum())


def photo_dpj(name, window, levels=4):
    q = quantize(getattr(ski.data, name)(), levels, "lloyd")
    return estimate_dpj(q.levels, window, levels, wrap=True)
