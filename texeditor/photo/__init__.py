"""Photographic synthesis: a multi-scale DPJ (markov.multiscale) drawn, then shown with the
photo's own greys and colours (``tone``) — photo → texture in one call.

``resynthesize(photo, (H, W), seed=S)`` acquires a :class:`PhotoModel` and draws from it; the
model can be saved as a `.dpj` (format 2) and drawn again, bit-exact from its seed.
"""

from __future__ import annotations

import numpy as np

from . import tone
from ..markov.multiscale import COARSE_WINDOW, WINDOW, default_scales, scales_that_fit
from ..markov.synthesis import check_seed, check_size
from .model import (PhotoModel, Resynthesis, Tone, acquire_model, as_photo, document_model,
                    document_tone, load_model, model_from_bytes, photo_tone, step_wrap)


def resynthesize(photo, shape, *, seed: int = 0, tone: bool = True, tileable: bool = False,
                 progress=None, cancel=None, **acquire) -> Resynthesis:
    """A (H, W) texture like ``photo``: ``.image`` (uint8 grey or RGB) and ``.levels``;
    ``tileable``: both repeat without a seam.

    ``acquire`` overrides the model's defaults (scales, levels, window, coarse_levels,
    coarse_window, quantizer), chosen for quality; without ``scales``, the photo's number of
    scales, or fewer when the texture is too small to hold them (auto_scales). ``photo``: an
    array, or an image file's path (read by load_image)."""
    check_seed(seed), check_size(shape)          # before the photo's model is made
    photo = as_photo(photo)
    if acquire.get("scales") is None:
        acquire["scales"] = auto_scales(photo, shape, **acquire)
    model = acquire_model(photo, tone=tone, **acquire)
    return model.synthesize(shape, seed=seed, tone=tone, tileable=tileable, progress=progress,
                            cancel=cancel)


def auto_scales(photo, shape, *, window=WINDOW, coarse_window=COARSE_WINDOW, **_) -> int:
    """The scales "auto" gives a (H, W) texture of ``photo``: about COARSEST_SIDE points a side
    at the photo's coarsest, as long as the texture holds every scale's window."""
    scales = default_scales(np.shape(photo))
    try:
        return scales_that_fit(shape, scales, window, coarse_window)
    except (TypeError, ValueError):     # not a window: acquire_model says what is wrong
        return scales


__all__ = ["tone", "PhotoModel", "Resynthesis", "Tone", "acquire_model", "auto_scales",
           "document_model", "document_tone", "load_model", "model_from_bytes", "photo_tone",
           "resynthesize", "step_wrap"]
