"""Projected-IFS curves (companion 002, Guérin, after Zair): fractal Bézier curves for rough spot
outlines. A curve is its control polygon P times barycentric subdivision matrices,
S_{n+1} = S_n 𝕋 (de Casteljau's construction when 𝕋 is Bézier's).

Each cubic piece (4 control points) is split into halves by P·T0 and P·T1. With roughness 0 the
T_i are de Casteljau's, so the points are the Bézier curve's at s = k/2^depth exactly. With
roughness r each split uses T_i + r·A·D, D drawn from the seed with zero column sums (still
barycentric) and zero where the junction conditions of 002 §2.1 fix the matrices: T0 e0 = e0 and
T1 e3 = e3 (the piece keeps its end points), T0 e3 = T1 e0 (the halves meet). A displacement is
a zero-sum mix of the current polygon's points, so it shrinks with the polygon: the same
roughness at every scale (Blanc-Talon's perturbed subdivision). A closed outline's pieces share
their end points, so it stays closed.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

#: de Casteljau's halves of a cubic, acting on the right of the (points × 4) polygon.
BEZIER_T0 = np.array([[1, 1 / 2, 1 / 4, 1 / 8], [0, 1 / 2, 1 / 2, 3 / 8],
                      [0, 0, 1 / 4, 3 / 8], [0, 0, 0, 1 / 8]])
BEZIER_T1 = np.array([[1 / 8, 0, 0, 0], [3 / 8, 1 / 4, 0, 0],
                      [3 / 8, 1 / 2, 1 / 2, 0], [1 / 8, 1 / 4, 1 / 2, 1]])
AMPLITUDE = 0.8                 # roughness 1: the largest share of the bulge added
#: The bulge b(P) = (p1 + p2 − p0 − p3)/2 as weights: a zero-sum column (barycentric kept).
BULGE = np.array([-0.5, 0.5, 0.5, -0.5])
MAX_DEPTH = 12
MAX_OUTLINE_POINTS = 1 << 17


def check_roughness(roughness) -> float:
    if isinstance(roughness, bool) or not isinstance(roughness, (int, float, np.integer,
                                                                 np.floating)) \
            or not 0.0 <= float(roughness) <= 1.0:                    # NaN fails too
        raise InputError(f"the roughness must be a number within 0..1, got {roughness!r}")
    return float(roughness)


def subdivide(pieces: np.ndarray, roughness: float, rng: np.random.Generator | None) -> np.ndarray:
    """One level: (M, 4, 2) cubic pieces → (2M, 4, 2), each piece's halves in order."""
    t0 = np.broadcast_to(BEZIER_T0, (len(pieces), 4, 4))
    t1 = np.broadcast_to(BEZIER_T1, (len(pieces), 4, 4))
    if roughness > 0:
        eps = rng.uniform(-1.0, 1.0, (len(pieces), 3)) * (roughness * AMPLITUDE)
        t0, t1 = t0.copy(), t1.copy()
        t0[:, :, 1:3] += eps[:, 0, None, None] * BULGE[None, :, None]   # left inner points
        t0[:, :, 3] += eps[:, 1:2] * BULGE[None, :]           # the halves' shared point
        t1[:, :, 0] += eps[:, 1:2] * BULGE[None, :]
        t1[:, :, 1:3] += eps[:, 2, None, None] * BULGE[None, :, None]   # right inner points
    # new[m, j] = Σ_i T[m, i, j] · P[m, i]
    left = np.einsum("mij,mic->mjc", t0, pieces)
    right = np.einsum("mij,mic->mjc", t1, pieces)
    left[:, 0], right[:, 3] = pieces[:, 0], pieces[:, 3]     # the ends, exactly
    right[:, 0] = left[:, 3]                                  # the halves meet, exactly
    return np.stack([left, right], axis=1).reshape(-1, 4, 2)


def fractal_curve(pieces, depth: int, roughness: float = 0.0, seed: int = 0) -> np.ndarray:
    """The points of the pieces' projected-IFS curve at s = k/2^depth, k < 2^depth, piece after
    piece ((M·2^depth, 2)); a closed outline's last point (its first) is not repeated.

    ``pieces`` (M, 4, 2): cubic control polygons, each ending where the next begins. The draws
    of level k come from the seed before those of level k + 1, so a deeper curve refines a
    shallower one: its every other point is the shallower curve's.
    """
    pieces = np.asarray(pieces, np.float64).reshape(-1, 4, 2)
    roughness = check_roughness(roughness)
    if not 0 <= depth <= MAX_DEPTH or len(pieces) << depth > MAX_OUTLINE_POINTS:
        raise InputError(f"a fractal curve has at most {MAX_OUTLINE_POINTS} points "
                         f"({len(pieces)} pieces at depth {depth})")
    rng = np.random.default_rng(int(seed)) if roughness > 0 else None
    for _ in range(depth):
        pieces = subdivide(pieces, roughness, rng)
    return pieces[:, 0].copy()


def catmull_rom_pieces(pts: np.ndarray) -> np.ndarray:
    """The closed Catmull–Rom curve through the points as cubic Bézier pieces (M, 4, 2): the
    smooth outline a fractal curve roughens (its roughness-0 curve)."""
    prev, nxt, nxt2 = (np.roll(pts, k, axis=0) for k in (1, -1, -2))
    return np.stack([pts, pts + (nxt - prev) / 6, nxt - (nxt2 - pts) / 6, nxt], axis=1)


def fractal_outline(pts: np.ndarray, step: float, roughness: float, seed: int) -> np.ndarray:
    """The closed fractal Bézier outline through the points, sampled about ``step`` apart (the
    depth is the smallest that brings the longest piece's polygon under ``step``)."""
    pieces = catmull_rom_pieces(np.asarray(pts, np.float64))
    longest = float(np.linalg.norm(np.diff(pieces, axis=1), axis=2).sum(axis=1).max())
    depth = int(np.clip(np.ceil(np.log2(max(longest / step, 1.0))), 1, MAX_DEPTH))
    while depth > 1 and len(pieces) << depth > MAX_OUTLINE_POINTS:
        depth -= 1
    return fractal_curve(pieces, depth, roughness, seed)
