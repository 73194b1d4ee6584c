"""Reading a texture against its DPJ on the torus (the tileable and particle tests)."""

import numpy as np
import skimage as ski
from numpy.lib.stride_tricks import sliding_window_view

from texeditor import estimate_dpj, quantize
from texeditor.markov.dpj import encode


def off_the_dpj(levels, dpj, torus=True) -> float:
    """Share of the windows (read on the torus: across both seams and the corner too) that the
    DPJ does not have."""
    u, v = dpj.window
    a = np.pad(levels, ((0, v - 1), (0, u - 1)), mode="wrap") if torus else levels
    codes = encode(np.ascontiguousarray(sliding_window_view(a, (v, u)).reshape(-1, v, u)),
                   dpj.levels)
    return float(np.mean(~np.isin(codes, dpj.codes)))


def photo_dpj(name, window, levels=4):
    q = quantize(getattr(ski.data, name)(), levels, "lloyd")
    return estimate_dpj(q.levels, window, levels, wrap=True)
