"""2-D midpoint displacement (companion 003; digest §11): a fractal height field on a torus of
side 2^n by the diamond–square steps, then resampled to any size — a height source for the
relief preview.

Level k halves the grid's step; each new point is the mean of its four known neighbours (the
square's corners, then the diamond's tips, wrapping round the torus) plus a normal draw of
deviation σ0·2^(−k·H) (×2^(−H/2) at the diamond's tips, half a level further). Erratum of the
slides: their recursion per square recomputes the edges two squares share, with different
draws (cracks). Here every grid point is computed exactly once and then kept (`count=True`
counts the writes); the torus makes the field tileable.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..errors import InputError
from .ifs import checked_shape

MAX_SIDE = 4096


@njit(cache=True)
def _diamond_square(noise, h, sigma0, writes, count):
    n = noise.shape[0]
    g = np.zeros((n, n))
    g[0, 0] = sigma0 * noise[0, 0]
    if count:
        writes[0, 0] += 1
    step, k = n, 1
    while step > 1:
        half = step // 2
        s = sigma0 * 2.0 ** (-k * h)
        for i in range(0, n, step):                      # square step: the centres
            i2 = (i + step) % n
            for j in range(0, n, step):
                j2 = (j + step) % n
                mean = (g[i, j] + g[i, j2] + g[i2, j] + g[i2, j2]) / 4
                g[i + half, j + half] = mean + s * noise[i + half, j + half]
                if count:
                    writes[i + half, j + half] += 1
        s *= 2.0 ** (-h / 2)
        for i in range(0, n, half):                      # diamond step: the edge middles
            start = half if (i // half) % 2 == 0 else 0
            up, down = (i - half) % n, (i + half) % n
            for j in range(start, n, step):
                mean = (g[up, j] + g[down, j] + g[i, (j - half) % n] + g[i, (j + half) % n]) / 4
                g[i, j] = mean + s * noise[i, j]
                if count:
                    writes[i, j] += 1
        step, k = half, k + 1
    return g


def torus_side(shape) -> int:
    """The side 2^n of the torus a field of ``shape`` is drawn on: the smallest ≥ both sides."""
    return 1 << max(1, math.ceil(math.log2(max(shape))))


def midpoint_displacement(shape, roughness: float = 0.5, *, seed: int = 0, sigma0: float = 1.0,
                          count: bool = False):
    """A fractal height field (H, W) float64, tileable, from a seed.

    ``roughness`` H in [0, 1]: the deviation falls by 2^−H a level, so the variogram
    E[(g(x + d) − g(x))²] grows about as d^(2H) (H = 1 smooth hills, H = 0 rough). On a torus of
    side 2^n (`torus_side`); a square side 2^n is that torus itself, other sizes are its
    periodic linear resampling (still tileable). With ``count`` also the (2^n, 2^n) number of
    times each grid point was written (all ones: the erratum).
    """
    h, w = _shape(shape)
    if isinstance(roughness, bool) or not isinstance(roughness, (int, float, np.integer,
                                                                 np.floating)) \
            or not 0.0 <= float(roughness) <= 1.0:           # NaN fails too
        raise InputError(f"the roughness H must be a number within 0..1, got {roughness!r}")
    n = torus_side((h, w))
    noise = np.random.default_rng(int(seed)).standard_normal((n, n))
    writes = np.zeros((n, n) if count else (1, 1), np.int32)
    field = _diamond_square(noise, float(roughness), float(sigma0), writes, bool(count))
    out = _resample(_resample(field, h, 0), w, 1)
    return (out, writes) if count else out


def _resample(field: np.ndarray, size: int, axis: int) -> np.ndarray:
    """Periodic linear resampling of one axis to ``size`` points (the same array when equal)."""
    n = field.shape[axis]
    if size == n:
        return field
    at = np.arange(size) * (n / size)
    i0 = np.floor(at).astype(np.int64)
    f = at - i0
    a, b = np.take(field, i0, axis=axis), np.take(field, (i0 + 1) % n, axis=axis)
    f = f[:, None] if axis == 0 else f[None, :]
    return (1 - f) * a + f * b


def _shape(shape) -> tuple[int, int]:
    return checked_shape(shape, MAX_SIDE, "a midpoint-displacement field")
