"""Fill orders (thesis §3.3.1, Fig. 3.4): the order in which the points of a region are produced.

A texture is computed point after point and shown in television order, row after row from the
top, left to right. A frame memory allows any other order fixed in advance — polar, spiral, or a
Peano (Hilbert) scan — and a sequence laid along such an order gives textures with special spots,
such as the knots of wood. :func:`fill_order` lists a region's points in one of these orders;
:func:`lay_along` takes the region's levels in television order (the order they were produced)
and lays them along another; `PeanoLevels` numbers its sub-regions along any of them.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .peano import MAX_CELLS, scan_order

ORDERS = ("tv", "polar", "spiral", "peano")

__all__ = ["ORDERS", "fill_order", "grid_order", "lay_along"]


def fill_order(mask, order: str = "tv", centre=None) -> np.ndarray:
    """The (row, col) of the region's points, as an (n, 2) int array, in the fill ``order``:

    - ``tv``: row after row from the top, each left to right (the television scan);
    - ``polar``: about ``centre``, by angle — counter-clockwise on screen from the ray going
      right — then by distance from the centre (the centre itself first);
    - ``spiral``: a square spiral out of ``centre``: one step right, then turning clockwise on
      screen (down, left, up, right…), ring after ring;
    - ``peano``: along the Hilbert curve of the region's bounding box (`peano.scan_order`).

    ``centre`` (row, col) defaults to the middle cell of the region's bounding box.

    >>> fill_order(np.ones((3, 3), bool), "spiral").tolist()
    [[1, 1], [1, 2], [2, 2], [2, 1], [2, 0], [1, 0], [0, 0], [0, 1], [0, 2]]
    """
    mask = np.asarray(mask, dtype=bool)
    if mask.ndim != 2:
        raise InputError("a fill order runs over a 2-D region")
    if order not in ORDERS:
        raise InputError(f"the fill order must be one of {', '.join(ORDERS)}, got {order!r}")
    rows, cols = np.nonzero(mask)                       # television order
    if not len(rows) or order == "tv":
        return np.stack([rows, cols], axis=1).astype(np.int64)
    top, left, bottom, right = (int(v) for v in (rows.min(), cols.min(), rows.max(), cols.max()))
    if order == "peano":
        return _peano(mask, top, left, bottom, right)
    if centre is None:
        centre = ((top + bottom) // 2, (left + right) // 2)
    dr, dc = rows - int(centre[0]), cols - int(centre[1])
    key = _polar_key(dr, dc) if order == "polar" else _spiral_key(dr, dc)
    sort = np.lexsort(key[::-1])
    return np.stack([rows[sort], cols[sort]], axis=1).astype(np.int64)


def _polar_key(dr, dc):
    """(angle, squared distance): the angle of the reduced direction, so points on one ray get
    the very same float, and distinct rays (at least 1/16384² rad apart) never do."""
    g = np.maximum(np.gcd(dr, dc), 1)
    angle = np.mod(np.arctan2(-dr // g, dc // g), 2 * np.pi)       # row 0 is on top: up is -dr
    angle[(dr == 0) & (dc == 0)] = -1.0                             # the centre comes first
    return angle, dr.astype(np.int64) ** 2 + dc.astype(np.int64) ** 2


def _spiral_key(dr, dc):
    """(ring, place along it): ring k is the square at Chebyshev distance k; the walk enters it
    one step right of the previous ring's last cell, goes down the right side, left along the
    bottom, up the left side and right along the top."""
    k = np.maximum(np.abs(dr), np.abs(dc)).astype(np.int64)
    place = np.select([(dc == k) & (dr > -k),                     # right side, going down
                       (dr == k) & (dc < k),                      # bottom, going left
                       (dc == -k) & (dr < k)],                    # left side, going up
                      [dr + k - 1, 3 * k - 1 - dc, 5 * k - 1 - dr],
                      7 * k - 1 + dc)                             # top, going right
    return k, place


def _peano(mask, top, left, bottom, right) -> np.ndarray:
    h, w = bottom - top + 1, right - left + 1
    if h * w > MAX_CELLS:
        raise InputError(f"a Peano order over a {w}×{h} box has more than {MAX_CELLS} points: "
                         "choose a smaller zone")
    cells = scan_order(h, w) + np.array([top, left])
    return cells[mask[cells[:, 0], cells[:, 1]]]


def grid_order(rows: int, cols: int, order: str = "peano", limit: int | None = None):
    """The cells of a rows × cols grid in a fill order (the first ``limit`` only): the numbering
    of Peano sub-regions. Polar and spiral orders turn about the grid's middle cell."""
    if order == "peano":
        return scan_order(rows, cols, limit)
    if rows * cols > MAX_CELLS:
        raise InputError(f"{cols}×{rows} cells are too many for a scan (at most {MAX_CELLS}): "
                         f"choose larger cells")
    cells = fill_order(np.ones((rows, cols), bool), order)
    return cells if limit is None else cells[:limit]


def lay_along(levels, mask, order: str, centre=None) -> np.ndarray:
    """The region's levels, read in television order (as a texture is produced), laid back
    along ``order``: the k-th level produced goes to the k-th point of the fill order. Other
    points keep theirs; in television order nothing changes.

    >>> lay_along(np.arange(9, dtype=np.uint8).reshape(3, 3), np.ones((3, 3), bool), "spiral")
    array([[6, 7, 8],
           [5, 0, 1],
           [4, 3, 2]], dtype=uint8)
    """
    levels = np.asarray(levels)
    mask = np.asarray(mask, dtype=bool)
    if mask.shape != levels.shape:
        raise InputError(f"the region is {mask.shape[1]}×{mask.shape[0]}, the texture "
                         f"{levels.shape[1]}×{levels.shape[0]}")
    cells = fill_order(mask, order, centre)
    out = levels.copy()
    out[cells[:, 0], cells[:, 1]] = levels[mask]
    return out
