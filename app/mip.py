"""Mip levels of the canvas picture: the palette-mapped texture reduced by box averaging.

It sits between the level matrix and the canvas's image item (levels + palette -> reduced RGB):
below 100 % the canvas shows level k, whose pixel (i, j) is the mean colour of the cells
[i·2^k, (i+1)·2^k) × [j·2^k, (j+1)·2^k) (partial blocks at the right and bottom edges average
the cells they have), so a fine pattern seen from afar is its average colour, never the
nearest-neighbour moiré of sampling one cell in 2^k. No Qt here: pure arrays.
"""

from __future__ import annotations

import math

import numba
import numpy as np


def mip_level(zoom: float, shape: tuple[int, int]) -> int:
    """The mip level to show at ``zoom`` device pixels per cell: the largest k with 2^k ≤ 1/zoom
    (0 at 100 % and above), no coarser than a 1-pixel picture."""
    if zoom <= 0 or zoom >= 1 or not shape[0] or not shape[1]:
        return 0
    k = int(math.floor(math.log2(1.0 / zoom) + 1e-9))
    return max(0, min(k, math.ceil(math.log2(max(shape)))))


def box_average(levels: np.ndarray, lut: np.ndarray, k: int) -> np.ndarray:
    """(ceil(H/2^k), ceil(W/2^k), 3) uint8: the mean colour of each 2^k × 2^k block of
    ``lut[levels]`` (``lut`` a 256×3 uint8 table), rounded to the nearest integer."""
    return _averaged(_readonly(levels)[:, :, None], _readonly(lut[:, :3]), k)


_IDENTITY = np.repeat(np.arange(256, dtype=np.uint8)[:, None], 3, axis=1)
_IDENTITY.flags.writeable = False


def box_average_rgb(rgb: np.ndarray, k: int) -> np.ndarray:
    """The same mean colours for a picture that is already (H, W, 3) uint8 RGB (a texture shown
    with its photo's tone), in one pass over its pixels (a channel at a time through an
    identity table took a 2048² picture 45 ms, on the GUI thread at every edit)."""
    return _averaged(_readonly(rgb), _IDENTITY, k)


def _averaged(values: np.ndarray, lut: np.ndarray, k: int) -> np.ndarray:
    f = 1 << k
    h, w = values.shape[:2]
    return _box(values, lut, f, np.empty(((h + f - 1) // f, (w + f - 1) // f, 3), np.uint8))


def _readonly(a: np.ndarray) -> np.ndarray:
    """A C-contiguous uint8 read-only view: one compiled signature (numba types read-only arrays
    apart, and the document hands out read-only views) and one compilation."""
    a = np.ascontiguousarray(a, dtype=np.uint8).view()
    a.flags.writeable = False
    return a


@numba.njit(cache=True, nogil=True)
def _box(values, lut, f, out):   # pragma: no cover - compiled
    """Box means of ``lut[values]``: ``values`` (H, W, 1) levels through a 256×3 table, or
    (H, W, 3) colours, each channel through its column of an identity table."""
    h, w, depth = values.shape
    oh, ow = out.shape[0], out.shape[1]
    acc = np.zeros((ow, 3), np.uint32)
    for i in range(oh):
        acc[:] = 0
        r0 = i * f
        r1 = min(r0 + f, h)
        for r in range(r0, r1):
            for j in range(ow):
                a0 = a1 = a2 = 0
                for c in range(j * f, min(j * f + f, w)):
                    v0 = values[r, c, 0]
                    v1, v2 = (values[r, c, 1], values[r, c, 2]) if depth == 3 else (v0, v0)
                    a0 += lut[v0, 0]
                    a1 += lut[v1, 1]
                    a2 += lut[v2, 2]
                acc[j, 0] += a0
                acc[j, 1] += a1
                acc[j, 2] += a2
        for j in range(ow):
            n = (r1 - r0) * (min(j * f + f, w) - j * f)
            half = n // 2
            for k in range(3):
                out[i, j, k] = (acc[j, k] + half) // n
    return out
