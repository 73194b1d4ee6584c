"""Orientation fields (companion document 004): the direction a directional texture follows at
each point, from a photo's structure tensor or from strokes a user draws; the input of `lic`.

A field is an angle θ per point, modulo π (a direction, not a heading): the unit vector
(d_row, d_col) = (sin θ, cos θ), so θ = 0 runs along a row and θ = π/2 down a column. Fields
are averaged and resampled as doubled-angle vectors (cos 2θ, sin 2θ), which have no sign
ambiguity: θ and θ + π are the same vector, and the mean of 1° and 179° is 0°, not 90°.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from scipy import ndimage

from ..errors import InputError

DERIVATIVE_SIGMA = 1.0      # the gradient's own smoothing (points): pixel noise is not grain
FIELD_GRID = 128            # a drawn field is computed on at most this many nodes a side


def orientation_field(image, shape=None, *, sigma: float = 6.0, wrap: bool = False):
    """The flow direction of a photo (grey (h, w) or colour (h, w, 3)) and its coherence.

    The structure tensor J = G_σ * (∇I ∇Iᵀ) has its largest eigenvalue across the stripes
    (along the gradient); the flow is the eigenvector of the *smallest*, along the grain. Its
    doubled angle is that of −(J_cc − J_rr, 2 J_rc); the coherence (λ1 − λ2)/(λ1 + λ2) is 1 on
    perfect stripes and 0 where no direction dominates. ``shape`` (H, W) resamples both to
    an output size (the doubled-angle vectors, weighted by the tensor's strength, are
    interpolated, never the angles). ``wrap`` treats the photo as a torus (the field tiles).

    Returns (θ, coherence), float64 arrays of ``shape`` (the photo's by default), θ in [0, π).
    """
    grey = _grey(image)
    mode = "wrap" if wrap else "reflect"
    g_row = ndimage.gaussian_filter(grey, DERIVATIVE_SIGMA, order=(1, 0), mode=mode)
    g_col = ndimage.gaussian_filter(grey, DERIVATIVE_SIGMA, order=(0, 1), mode=mode)
    sigma = _check_sigma(sigma)
    j_rr, j_rc, j_cc = (ndimage.gaussian_filter(p, sigma, mode=mode)
                        for p in (g_row * g_row, g_row * g_col, g_col * g_col))
    vectors = np.stack([j_rr - j_cc, -2 * j_rc, j_rr + j_cc])     # (cos 2θ, sin 2θ)·(λ1−λ2), λ1+λ2
    if shape is not None:
        vectors = _resample(vectors, _check_shape(shape), wrap)
    return _angles(vectors[0], vectors[1], vectors[2])


def strokes_field(strokes, shape, *, wrap: bool = False):
    """The field of polylines drawn by a user: ``strokes`` a list of point lists (row, col) in
    the output's coordinates, ``shape`` (H, W) the output's size.

    Each segment lends its direction to every point, weighted by its length over the cubed
    distance to it, (d² + step²)^{3/2} with a grid step so the weight stays finite on the
    stroke: near a stroke the field follows it, between strokes it turns smoothly from one to
    the other (with 1/d², the far strokes together would outweigh the near one). A single
    straight stroke gives a constant field. ``wrap`` measures distances on the torus (the
    field tiles). Computed on a grid of at most FIELD_GRID nodes a side, then resampled.

    Returns (θ, coherence) like :func:`orientation_field`; the coherence is how much the
    strokes nearby agree.
    """
    height, width = _check_shape(shape)
    segments = _segments(strokes)
    if wrap:
        segments = _split(segments, min(height, width) / 4)
    step = max(1.0, max(height, width) / FIELD_GRID)
    grid = (max(1, round(height / step)), max(1, round(width / step)))
    c2, s2, total = _segment_vectors(segments, grid, height, width, step ** 2, wrap)
    vectors = _resample(np.stack([c2, s2, total]), (height, width), wrap)
    return _angles(vectors[0], vectors[1], vectors[2])


def field_vectors(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit flow vector (d_row, d_col) = (sin θ, cos θ) of each point, float64."""
    return np.sin(theta), np.cos(theta)


def _angles(c2, s2, total):
    """θ in [0, π) and coherence in [0, 1] from doubled-angle vectors and their total weight."""
    theta = np.mod(np.arctan2(s2, c2) / 2, np.pi)
    theta[theta >= np.pi] = 0.0            # -0.0 / 2 mod π can round to π
    with np.errstate(invalid="ignore", divide="ignore"):
        coherence = np.hypot(c2, s2) / total
    return theta, np.clip(np.nan_to_num(coherence, nan=0.0, posinf=0.0), 0.0, 1.0)


def _resample(vectors: np.ndarray, shape, wrap: bool) -> np.ndarray:
    """Each plane resized to ``shape`` (bilinear, pixel centres aligned as skimage's resize;
    smoothed first when it shrinks, which averages the vectors, so directions are too)."""
    if vectors.shape[1:] == tuple(shape):
        return vectors
    from skimage.transform import resize
    return np.stack([resize(v, shape, order=1, mode="wrap" if wrap else "edge")
                     for v in vectors])


def _segments(strokes) -> np.ndarray:
    """The segments of the polylines as an (n, 4) array (r0, c0, r1, c1), zero-length ones
    dropped; at least one with a length is needed for a direction."""
    if isinstance(strokes, np.ndarray) or not isinstance(strokes, (list, tuple)):
        raise InputError("strokes must be a list of polylines (lists of (row, col) points)")
    parts = []
    for stroke in strokes:
        points = np.asarray(stroke, dtype=np.float64)
        if points.ndim != 2 or points.shape[1] != 2 or not np.isfinite(points).all():
            raise InputError("each stroke must be a list of finite (row, col) points")
        if len(points) >= 2:
            parts.append(np.concatenate([points[:-1], points[1:]], axis=1))
    segments = np.concatenate(parts) if parts else np.zeros((0, 4))
    keep = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1]) > 0
    if not keep.any():
        raise InputError("draw at least one stroke (two distinct points) to give a direction")
    return np.ascontiguousarray(segments[keep])


def _split(segments: np.ndarray, longest: float) -> np.ndarray:
    """Each segment cut into equal pieces at most ``longest`` long: on the torus a short
    segment's nearest image is one of the nine around the canvas."""
    lengths = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
    pieces = np.maximum(np.ceil(lengths / longest), 1).astype(np.int64)
    index = np.repeat(np.arange(len(segments)), pieces)
    k = np.arange(len(index)) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    start, end = segments[index, :2], segments[index, 2:]
    f0, f1 = (k / pieces[index])[:, None], ((k + 1) / pieces[index])[:, None]
    return np.ascontiguousarray(np.concatenate([start + f0 * (end - start),
                                                start + f1 * (end - start)], axis=1))


@njit(cache=True)
def _segment_vectors(segments, grid, height, width, soft, wrap):
    """Σ w·(cos 2φ, sin 2φ) and Σ w over the segments at each grid node's output position,
    w = length / (d² + soft)^{3/2}, d the (torus) distance from the node to the segment."""
    gh, gw = grid
    c2 = np.zeros((gh, gw))
    s2 = np.zeros((gh, gw))
    total = np.zeros((gh, gw))
    n = segments.shape[0]
    shifts = 1 if wrap else 0
    for i in range(gh):
        r = (i + 0.5) * height / gh - 0.5
        for j in range(gw):
            c = (j + 0.5) * width / gw - 0.5
            for k in range(n):
                r0, c0, r1, c1 = segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
                dr, dc = r1 - r0, c1 - c0
                if wrap:      # its middle on the canvas: the images one turn away suffice
                    r0 -= np.floor((r0 + 0.5 * dr) / height) * height
                    c0 -= np.floor((c0 + 0.5 * dc) / width) * width
                length2 = dr * dr + dc * dc
                best = np.inf
                for a in range(-shifts, shifts + 1):
                    for b in range(-shifts, shifts + 1):
                        pr, pc = r - r0 - a * height, c - c0 - b * width
                        t = min(max((pr * dr + pc * dc) / length2, 0.0), 1.0)
                        er, ec = pr - t * dr, pc - t * dc
                        best = min(best, er * er + ec * ec)
                w = np.sqrt(length2) / (best + soft) ** 1.5
                # doubled angle of (dr, dc) = (sin φ, cos φ)·len: cos 2φ, sin 2φ
                c2[i, j] += w * (dc * dc - dr * dr) / length2
                s2[i, j] += w * 2 * dr * dc / length2
                total[i, j] += w
    return c2, s2, total


def _grey(image) -> np.ndarray:
    from ..markov.levels import to_grey
    image = np.asarray(image)
    if image.ndim not in (2, 3) or min(image.shape[:2]) < 2:
        raise InputError(f"a photo must be a (h, w) or (h, w, 3) picture, got shape {image.shape}")
    if np.issubdtype(image.dtype, np.floating) and not np.isfinite(image).all():
        raise InputError("the photo has values that are not finite numbers")
    return to_grey(image)


def _check_sigma(sigma) -> float:
    if isinstance(sigma, bool) or not isinstance(sigma, (int, float, np.number)) \
            or not np.isfinite(sigma) or not 0.5 <= sigma <= 256:
        raise InputError(f"the field's smoothing sigma must be 0.5..256 points, got {sigma!r}")
    return float(sigma)


def _check_shape(shape) -> tuple[int, int]:
    try:
        height, width = (int(s) for s in shape)
    except (TypeError, ValueError):
        raise InputError(f"an output shape is (height, width), got {shape!r}") from None
    if height < 1 or width < 1:
        raise InputError(f"an output shape must be positive, got {shape!r}")
    return height, width
