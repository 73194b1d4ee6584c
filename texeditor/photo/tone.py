"""Photographic tone: a level matrix shown with the photo's own greys and colours.

The document stays levels; this renders them. Each output point takes the pixel of a photo
point whose level context (the 3×3 levels around it) is the same, chosen in scan order among
a few candidates — those continuing the photo pixels of its left and upper neighbours (so tone
runs on smoothly across a level region) and a few drawn at random from the photo points with
that context (so no region is one long copy) — by the best match with the greys already
rendered around it. A context the photo never showed backs off to the 4 edge neighbours, then
to the point's own level. Seeded and exact: the same levels, tone and seed give the same image.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from ..errors import InputError
from ..markov.synthesis import uniform

RANDOM_CANDIDATES = 8      # drawn from the photo points sharing the context
FRESH_START = 1 / 64       # chance that a point considers only fresh candidates (no long copies)
COHERENCE = 0.5           # a continuing candidate's mismatch counts this much (Ashikhmin)
HALF = 2                   # the causal neighbourhood compared: rows above and left, ±HALF
# (row, column) offsets of the 3×3 level context, and of its 4-neighbour back-off
_NINE = tuple((di, dj) for di in (-1, 0, 1) for dj in (-1, 0, 1))
_FIVE = ((-1, 0), (0, -1), (0, 0), (0, 1), (1, 0))


class ToneIndex(NamedTuple):
    """The photo's points grouped by level context, three ways (3×3, 4 neighbours, own level)."""

    codes: tuple         # per back-off: every photo point's context code (row-major)
    keys: tuple          # per back-off: sorted unique context codes
    starts: tuple        # per back-off: first index of each code's points in ``points``, + end
    points: tuple        # per back-off: photo point indices sorted by context


def context_codes(levels: np.ndarray, num_levels: int) -> tuple:
    """The three context codes of every point (the border repeated outwards)."""
    lv = np.pad(np.asarray(levels, np.int64), 1, mode="edge")
    h, w = np.shape(levels)
    codes = []
    for cells in (_NINE, _FIVE, ((0, 0),)):
        code = np.zeros((h, w), np.int64)
        for di, dj in cells:
            code = code * num_levels + lv[1 + di:1 + di + h, 1 + dj:1 + dj + w]
        codes.append(code.ravel())
    return tuple(codes)


def tone_index(levels: np.ndarray, num_levels: int) -> ToneIndex:
    """Group the photo's points by their level contexts (sorted, for binary search)."""
    codes = context_codes(levels, num_levels)
    keys, starts, points = [], [], []
    for code in codes:
        order = np.argsort(code, kind="stable")
        unique, first = np.unique(code[order], return_index=True)
        keys.append(unique)
        starts.append(np.append(first, len(order)).astype(np.int64))
        points.append(order.astype(np.int64))
    return ToneIndex(codes, tuple(keys), tuple(starts), tuple(points))


def render(levels, num_levels: int, photo_levels, photo_grey, photo_pixels=None, *,
           seed: int = 0, index: ToneIndex | None = None):
    """Render ``levels`` (H, W) with the photo: returns (grey (H, W) uint8, pixels or None).

    ``photo_levels`` (h, w) are the photo's levels at the same G, ``photo_grey`` its greys (uint8)
    and ``photo_pixels`` its colours (h, w, 3) uint8, or None for a grey photo.
    """
    levels = np.ascontiguousarray(levels, dtype=np.uint8)
    if levels.ndim != 2 or levels.size == 0 or levels.max() >= num_levels:
        raise InputError(f"tone needs a non-empty matrix of levels 0..{num_levels - 1}")
    photo_grey = np.ascontiguousarray(photo_grey, dtype=np.uint8)
    index = index or tone_index(photo_levels, num_levels)
    state = np.random.SeedSequence([int(seed), 0x70E]).generate_state(1, np.uint64)
    source = np.empty(levels.shape, np.int64)
    grey = np.empty(levels.shape, np.uint8)
    _render(context_codes(levels, num_levels), index.codes, index.keys, index.starts,
            index.points, photo_grey, source, grey, state)
    pixels = None
    if photo_pixels is not None:
        flat = np.asarray(photo_pixels).reshape(-1, photo_pixels.shape[-1])
        pixels = flat[source.ravel()].reshape(*levels.shape, flat.shape[-1])
    return grey, pixels


@njit(cache=True, nogil=True)
def _bucket(keys, starts, key):
    """(first, end) of the photo points with context ``key``; (0, 0) if the photo has none."""
    a = np.searchsorted(keys, key)
    if a < len(keys) and keys[a] == key:
        return starts[a], starts[a + 1]
    return 0, 0


@njit(cache=True, nogil=True)
def _distance(grey, i, j, photo, pi, pj, best):
    """Squared grey differences over the rendered causal neighbourhood of (i, j), against the
    photo around (pi, pj); stops once past ``best``. Points off either picture are skipped."""
    w = grey.shape[1]
    pw = photo.shape[1]
    total = 0.0
    for di in range(-HALF, 1):
        for dj in range(-HALF, HALF + 1):
            if di == 0 and dj >= 0:
                break
            y, x, py, px = i + di, j + dj, pi + di, pj + dj
            if 0 <= y and 0 <= x < w and 0 <= py and 0 <= px < pw:
                d = float(grey[y, x]) - float(photo[py, px])
                total += d * d
        if total > best:
            return total
    return total


@njit(cache=True, nogil=True)
def _render(out_codes, photo_codes, keys, starts, points, photo, source, grey, state):
    """Scan order: coherent and fresh candidates of the right context, the best match wins."""
    h, w = grey.shape
    ph, pw = photo.shape
    cand = np.empty(4 + RANDOM_CANDIDATES, np.int64)
    for i in range(h):
        for j in range(w):
            n = i * w + j
            level, a, b = 0, 0, 0
            while level < 3:
                a, b = _bucket(keys[level], starts[level], out_codes[level][n])
                if a < b:
                    break
                level += 1
            count = 0
            if uniform(state) >= FRESH_START:       # continue the neighbours' photo pixels
                for di, dj in ((0, -1), (-1, 0), (-1, -1), (-1, 1)):
                    y, x = i + di, j + dj
                    if 0 <= y and 0 <= x < w:
                        py, px = source[y, x] // pw - di, source[y, x] % pw - dj
                        if 0 <= py < ph and 0 <= px < pw:
                            s = py * pw + px
                            if level == 3 or photo_codes[level][s] == out_codes[level][n]:
                                cand[count] = s
                                count += 1
            coherent = count
            for _ in range(RANDOM_CANDIDATES):     # fresh ones (anywhere: a level unseen)
                if level == 3:
                    cand[count] = min(np.int64(uniform(state) * ph * pw), ph * pw - 1)
                else:
                    cand[count] = points[level][min(a + np.int64(uniform(state) * (b - a)), b - 1)]
                count += 1
            best, chosen = np.inf, cand[0]
            for k in range(count):
                d = _distance(grey, i, j, photo, cand[k] // pw, cand[k] % pw, best)
                if k < coherent:
                    d *= COHERENCE
                if d < best:
                    best, chosen = d, cand[k]
            source[i, j] = chosen
            grey[i, j] = photo[chosen // pw, chosen % pw]
