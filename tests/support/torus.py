"""Reading a texture against its DPJ on the torus (the tileable and particle tests)."""

import numpy as np
import skimage as ski
from numpy.lib.stride_tricks import sliding_window_view

from texeditor import estimate_dpj, quantize
from texeditor.markov.dpj import encode


def off_the_dpj(levels, dpj, torus=True) -> float:
    """Share of the windows (read on the torus: across both seams and the corner too) that the
    DPJ does not have."""
    return float(np.mean(off_places(levels, dpj, torus)))


def off_places(levels, dpj, torus=False) -> np.ndarray:
    """Where (top-left corners) the windows the DPJ lacks lie (on the torus: across the seams
    too)."""
    u, v = dpj.window
    a = np.pad(levels, ((0, v - 1), (0, u - 1)), mode="wrap") if torus else levels
    windows = sliding_window_view(a, (v, u))
    codes = encode(np.ascontiguousarray(windows).reshape(-1, v, u), dpj.levels)
    return ~np.isin(codes, dpj.codes).reshape(windows.shape[:2])


def photo_dpj(name, window, levels=4):
    q = quantize(getattr(ski.data, name)(), levels, "lloyd")
    return estimate_dpj(q.levels, window, levels, wrap=True)
