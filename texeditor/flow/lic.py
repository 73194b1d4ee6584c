"""Line integral convolution (Cabral and Leedom 1993; companion document 004): seeded white
noise smoothed along the streamlines of an orientation field (`field`), so the picture has the
field's grain — wood, hair, brushed metal, grass — and the noise's randomness across it.

Each point's value is a Hann-weighted mean of the noise along its streamline, traced both ways
over a length L (points) by midpoint (RK2) steps of STEP points; the cost is points × L/STEP,
in numba, by bands of rows so a worker can report progress and cancel.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
from numba import njit

from ..errors import Cancelled, InputError

STEP = 1.0             # points per integration step (midpoint rule)
MAX_LENGTH = 256       # the longest streamline (points): its cost is that many half-steps a point
BAND_POINTS = 2**17    # points per numba call between progress reports


def line_integral_convolution(theta: np.ndarray, length: float, *, seed: int, wrap: bool = False,
        progress: Callable[[float], None] | None = None,
        cancel: Callable[[], bool] | None = None) -> np.ndarray:
    """The LIC of seeded uniform white noise along the field θ (H, W) (`field` convention:
    direction (sin θ, cos θ) in (row, col)), over a streamline ``length`` points long,
    float64 of θ's shape. ``wrap``: noise and streamlines on the torus, so the picture tiles
    when the field does; otherwise a streamline stops at the border. Its values are means of
    noise, so their spread shrinks as L grows: normalise before use (`contrast`)."""
    theta = _check_theta(theta)
    noise = np.random.default_rng(seed).random(theta.shape)
    return smooth_along(noise, theta, length, wrap=wrap, progress=progress, cancel=cancel)


def smooth_along(picture: np.ndarray, theta: np.ndarray, length: float, *, wrap: bool = False,
                 progress: Callable[[float], None] | None = None,
                 cancel: Callable[[], bool] | None = None) -> np.ndarray:
    """Any picture (H, W) smoothed along the field θ of its shape: the convolution of
    :func:`line_integral_convolution`, whose picture is white noise."""
    theta = _check_theta(theta)
    noise = np.asarray(picture, dtype=np.float64)
    if noise.shape != theta.shape or not np.isfinite(noise).all():
        raise InputError("the picture smoothed must be finite and of the field's shape")
    length = check_length(length)
    d_row, d_col = np.sin(theta), np.cos(theta)
    out = np.empty(theta.shape)
    height, width = theta.shape
    rows = max(1, BAND_POINTS // width)
    steps = max(1, int(round(length / 2 / STEP)))
    weights = 0.5 * (1 + np.cos(np.pi * np.arange(steps + 1) / (steps + 1)))   # Hann, centre 1
    for top in range(0, height, rows):
        if cancel is not None and cancel():
            raise Cancelled("flow texture cancelled")
        _lic_rows(noise, d_row, d_col, weights, top, min(top + rows, height), wrap, out)
        if progress is not None:
            progress(min(top + rows, height) / height)
    return out


def contrast(picture: np.ndarray, reference=None) -> np.ndarray:
    """A LIC picture with a usable spread of greys, float64 in [0, 1]: the reference photo's
    grey histogram when one is given (φ = c_f⁻¹ ∘ c_g: the value of rank i becomes the
    photo's quantile at rank i, `pyramid.match_quantiles`), else standardised to mean 1/2 and
    standard deviation 1/6, clipped."""
    if reference is not None:
        from ..markov.levels import to_grey
        from ..pyramid.synthesis import match_quantiles, quantiles
        target = quantiles(np.sort(to_grey(reference), axis=None), picture.size)
        return match_quantiles(picture, target)
    spread = picture.std()
    centred = picture - picture.mean()
    scaled = centred / (6 * spread) if spread > 0 else centred
    return np.clip(0.5 + scaled, 0.0, 1.0)


def check_length(length) -> float:
    if isinstance(length, bool) or not isinstance(length, (int, float, np.number)) \
            or not np.isfinite(length) or not 1 <= length <= MAX_LENGTH:
        raise InputError(f"the streamline length L must be 1..{MAX_LENGTH} points, got {length!r}")
    return float(length)


def _check_theta(theta) -> np.ndarray:
    theta = np.asarray(theta, dtype=np.float64)
    if theta.ndim != 2 or theta.size == 0 or not np.isfinite(theta).all():
        raise InputError("a field is a non-empty (H, W) array of finite angles")
    return theta


@njit(cache=True)
def _lic_rows(noise, d_row, d_col, weights, top, bottom, wrap, out):
    """Rows top..bottom-1 of the LIC, written in one loop nest (helpers cost a third more).

    From each point, both ways: a midpoint step of STEP along the field (nearest point's
    direction, turned to agree with the heading of the step before: the field has no sign),
    then the noise there (bilinear), weighted. A planar streamline stops at the border."""
    height, width = noise.shape
    for r in range(top, bottom):
        for c in range(width):
            acc = weights[0] * noise[r, c]
            total = weights[0]
            for way in range(2):
                pr, pc = float(r), float(c)
                vr, vc = d_row[r, c], d_col[r, c]
                if way:
                    vr, vc = -vr, -vc
                for k in range(1, weights.shape[0]):
                    i, j = _nearest(pr, pc, height, width, wrap)
                    ar, ac = d_row[i, j], d_col[i, j]
                    if ar * vr + ac * vc < 0:
                        ar, ac = -ar, -ac
                    mr, mc = pr + 0.5 * STEP * ar, pc + 0.5 * STEP * ac
                    if not wrap and not (-0.5 <= mr < height - 0.5 and -0.5 <= mc < width - 0.5):
                        break
                    i, j = _nearest(mr, mc, height, width, wrap)
                    br, bc = d_row[i, j], d_col[i, j]
                    if br * ar + bc * ac < 0:
                        br, bc = -br, -bc
                    nr, nc = pr + STEP * br, pc + STEP * bc
                    if wrap:
                        nr, nc = _wrap_float(nr, height), _wrap_float(nc, width)
                    elif not (-0.5 <= nr < height - 0.5 and -0.5 <= nc < width - 0.5):
                        break
                    pr, pc, vr, vc = nr, nc, br, bc
                    acc += weights[k] * _sample(noise, pr, pc, wrap)
                    total += weights[k]
            out[r, c] = acc / total


@njit(cache=True, inline="always")
def _nearest(pr, pc, height, width, wrap):
    """The point nearest (pr, pc): on the torus, or the border's for a midpoint just off it."""
    i, j = int(pr + 1.5) - 1, int(pc + 1.5) - 1      # rounding, for pr, pc > -1.5
    if wrap:
        return _wrap_index(i, height), _wrap_index(j, width)
    return min(max(i, 0), height - 1), min(max(j, 0), width - 1)


@njit(cache=True, inline="always")
def _sample(noise, pr, pc, wrap):
    """The noise at (pr, pc), bilinear (on the torus, or with the border repeated)."""
    height, width = noise.shape
    r0, c0 = int(pr + 1.0) - 1, int(pc + 1.0) - 1       # floor, for pr, pc > -1
    fr, fc = pr - r0, pc - c0
    if wrap:
        ra, rb = _wrap_index(r0, height), _wrap_index(r0 + 1, height)
        ca, cb = _wrap_index(c0, width), _wrap_index(c0 + 1, width)
    else:
        ra, rb = min(max(r0, 0), height - 1), min(max(r0 + 1, 0), height - 1)
        ca, cb = min(max(c0, 0), width - 1), min(max(c0 + 1, 0), width - 1)
    top = noise[ra, ca] * (1 - fc) + noise[ra, cb] * fc
    low = noise[rb, ca] * (1 - fc) + noise[rb, cb] * fc
    return top * (1 - fr) + low * fr


@njit(cache=True, inline="always")
def _wrap_index(i, n):
    """i on the torus of n, for i within one turn of it (what a step of a point reaches)."""
    if i < 0:
        return i + n
    if i >= n:
        return i - n
    return i


@njit(cache=True, inline="always")
def _wrap_float(x, n):
    if x < 0:
        x += n
    elif x >= n:
        x -= n
    return x if x < n else 0.0      # -1e-17 + n rounds to n
