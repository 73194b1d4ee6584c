"""Photo or strokes → directional texture in one call: the orientation field (`field`), the
line integral convolution of seeded noise along it (`lic`), the photo's greys (`contrast`).
The `FlowTexture` step calls this, then cuts the picture into levels like the other models."""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..errors import InputError
from .field import orientation_field, strokes_field
from .lic import contrast, line_integral_convolution

LENGTH = 20.0           # default streamline length (points): a grain some twenty points long
SIGMA = 6.0             # default smoothing of a photo's field (photo points)


def flow_texture(shape, *, photo=None, strokes=None, seed: int, length: float = LENGTH,
                 sigma: float = SIGMA, wrap: bool = False,
                 progress: Callable[[float], None] | None = None,
                 cancel: Callable[[], bool] | None = None) -> np.ndarray:
    """A grey (H, W) directional texture, float64 in [0, 1]: seeded noise smoothed along a
    field over ``length`` points. The field is that of ``strokes`` (polylines of (row, col)
    points in the output's coordinates) when given, else the orientation field of ``photo``
    (smoothed over ``sigma`` photo points, stretched to ``shape``). With a photo the greys
    follow its histogram, else they are standardised. ``wrap``: the texture tiles (when the
    field does: strokes on the torus do; a photo's field is computed on the torus, so its
    seam is smoothed, not hidden)."""
    if strokes is not None:
        theta, _ = strokes_field(strokes, shape, wrap=wrap)
    elif photo is not None:
        theta, _ = orientation_field(photo, shape, sigma=sigma, wrap=wrap)
    else:
        raise InputError("a flow texture needs a photo or strokes for its field")
    picture = line_integral_convolution(theta, length, seed=seed, wrap=wrap,
                                        progress=progress, cancel=cancel)
    return contrast(picture, photo)
