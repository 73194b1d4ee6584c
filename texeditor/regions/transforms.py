"""Global operators (thesis §3.4.3): identity, isometry, similarity and affinity of a level matrix.

One affine map carries a selection (a presence mask from `regions`) or resamples the whole texture,
by nearest neighbour so that levels stay levels; ``wrap`` treats the canvas as one tile of a
periodic plane, so a tileable texture stays tileable under a map that keeps the tiling.

Conventions: points are (row, col), row 0 on top; a map is ``f(p) = M (p - centre) + centre +
offset`` with M a 2×2 matrix acting on (row, col) column vectors; each destination point q takes
the value at ``round(f⁻¹(q))`` (rounding half up, the same on every machine).
"""

from __future__ import annotations

import math
import operator

import numpy as np

from ..errors import InputError

MAX_LEVEL = 255
MAX_WARP_POINTS = 2**26       # destination points a carried selection may span (wrap, big zooms)
BAND_POINTS = 2**19           # resampling, carrying a selection: bands of this many points

Point = tuple[float, float]


# -- input checks shared with `regions` -----------------------------------------------------------

def as_levels(levels, name: str = "levels") -> np.ndarray:
    """The level matrix as a 2-D uint8 array (no copy when it already is one; never written)."""
    array = np.asarray(levels)
    if array.ndim != 2:
        raise InputError(f"{name} must be a 2-D matrix of levels, got {array.ndim} dimensions")
    if array.dtype == np.uint8:
        return array
    if array.dtype.kind not in "iub":
        raise InputError(f"{name} must hold integer levels, got {array.dtype}")
    if array.size and (int(array.min()) < 0 or int(array.max()) > MAX_LEVEL):
        raise InputError(f"{name} must hold levels 0..{MAX_LEVEL}")
    return array.astype(np.uint8)


def as_mask(mask, shape: tuple[int, int], name: str = "mask") -> np.ndarray:
    """A presence mask: a bool array of the canvas shape (no copy when it already is one)."""
    array = np.asarray(mask)
    if array.shape != tuple(shape):
        raise InputError(f"{name} has shape {array.shape}, the canvas is {tuple(shape)}")
    if array.dtype != bool:
        if array.dtype.kind not in "iub":
            raise InputError(f"{name} must be a presence matrix of 0/1 or booleans")
        array = array != 0
    return array


def as_point(point, name: str = "point") -> tuple[int, int]:
    """(row, col) as two Python ints (anywhere in the plane)."""
    try:
        r, c = point
        return operator.index(r), operator.index(c)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be two integers (row, col), got {point!r}") from None


def check_point(point, shape: tuple[int, int], name: str = "point") -> tuple[int, int]:
    """(row, col) as ints, which must name a point of the canvas."""
    r, c = as_point(point, name)
    h, w = shape
    if not (0 <= r < h and 0 <= c < w):
        raise InputError(f"{name} ({r}, {c}) is outside the {w}×{h} canvas "
                         f"(rows 0..{h - 1}, columns 0..{w - 1})")
    return r, c


def as_level(value, name: str = "value") -> int:
    try:
        value = operator.index(value)
    except TypeError:
        raise InputError(f"{name} must be an integer level, got {value!r}") from None
    if not 0 <= value <= MAX_LEVEL:
        raise InputError(f"{name} = {value} is not a level 0..{MAX_LEVEL}")
    return value


def _as_vector(value, name: str) -> Point:
    try:
        a, b = (float(x) for x in value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be two numbers (row, col), got {value!r}") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise InputError(f"{name} must be finite, got {value!r}")
    return a, b


# -- boxes ----------------------------------------------------------------------------------------

def bbox(mask: np.ndarray) -> tuple[int, int, int, int] | None:
    """(top, left, bottom, right) of the True points, bottom/right exclusive; None when empty."""
    rows = np.flatnonzero(mask.any(axis=1))
    if not len(rows):
        return None
    cols = np.flatnonzero(mask.any(axis=0))
    return int(rows[0]), int(cols[0]), int(rows[-1]) + 1, int(cols[-1]) + 1


def selection_centre(mask) -> Point:
    """The centre of a selection's bounding box (the pivot of the local manipulations).

    >>> selection_centre(np.array([[0, 1, 1], [0, 1, 0]], bool))
    (0.5, 1.5)
    """
    mask = np.asarray(mask, dtype=bool)
    box = bbox(mask)
    if box is None:
        raise InputError("the selection is empty: it has no centre")
    t, l, b, r = box
    return (t + b - 1) / 2, (l + r - 1) / 2


# -- translations by slicing (exact and fast: the identity operator, moves, copies) ---------------

def _pieces(start: int, stop: int, shift: int, size: int, wrap: bool):
    """Source intervals [a, b) of [start, stop) and their destinations after ``+shift``."""
    lo, hi = start + shift, stop + shift
    if not wrap:
        a, b = max(lo, 0), min(hi, size)
        return [(a - shift, b - shift, a)] if a < b else []
    out = []
    while lo < hi:                         # at most two pieces: the span is at most ``size`` long
        base = lo % size
        n = min(hi - lo, size - base)
        out.append((lo - shift, lo - shift + n, base))
        lo += n
    return out


def paste(out: np.ndarray, source: np.ndarray, mask: np.ndarray, offset, *, wrap: bool = False,
          box=None) -> None:
    """Write ``source`` at the points of ``mask`` moved by the integer ``offset``, into ``out``.

    Points leaving the canvas are dropped (or come back on the other side with ``wrap``). In place:
    the one helper here that writes; the public operators call it on their own copy.
    """
    box = bbox(mask) if box is None else box
    if box is None:
        return
    (dr, dc), (h, w) = offset, out.shape
    t, l, b, r = box
    if wrap and (b - t > h or r - l > w):
        raise InputError("a selection larger than the canvas cannot wrap")
    for r0, r1, d0 in _pieces(t, b, dr, h, wrap):
        for c0, c1, e0 in _pieces(l, r, dc, w, wrap):
            m = mask[r0:r1, c0:c1]
            out[d0:d0 + r1 - r0, e0:e0 + c1 - c0][m] = source[r0:r1, c0:c1][m]


# -- affine maps ----------------------------------------------------------------------------------

def rotation_matrix(angle: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """The (row, col) matrix turning the picture ``angle`` degrees counter-clockwise on screen.

    Multiples of 90° are exact integers; other entries are rounded to 12 decimals so that the same
    angle gives the same matrix on every machine.

    >>> rotation_matrix(90)
    ((0, -1), (1, 0))
    """
    angle = float(angle)
    if not math.isfinite(angle):
        raise InputError(f"the angle must be a finite number of degrees, got {angle}")
    quarter = angle / 90.0
    if quarter == round(quarter):
        cos, sin = ((1, 0), (0, 1), (-1, 0), (0, -1))[int(round(quarter)) % 4]
    else:
        t = math.radians(angle % 360.0)
        cos, sin = round(math.cos(t), 12) + 0.0, round(math.sin(t), 12) + 0.0
    return ((cos, -sin), (sin, cos))


def linear_map(matrix):
    """The matrix as four floats and its inverse (closed form: the same bits everywhere)."""
    try:
        (a, b), (c, d) = ((float(x) for x in row) for row in matrix)
    except (TypeError, ValueError):
        raise InputError(f"the map must be a 2×2 matrix ((a, b), (c, d)), got {matrix!r}") from None
    if not all(math.isfinite(x) for x in (a, b, c, d)):
        raise InputError("the map's matrix must have finite entries")
    det = a * d - b * c
    if abs(det) < 1e-9:
        raise InputError("the map is singular (its determinant is 0): it would squash the "
                         "texture onto a line")
    return (a, b, c, d), (d / det, -b / det, -c / det, a / det)


def _forward(m, centre, offset, rows, cols):
    a, b, c, d = m
    y, x = np.asarray(rows, float) - centre[0], np.asarray(cols, float) - centre[1]
    return a * y + b * x + centre[0] + offset[0], c * y + d * x + centre[1] + offset[1]


def _sources(inv, centre, offset, rows: np.ndarray, cols: np.ndarray):
    """Nearest source (row, col) of every destination of the grid rows × cols (2-D int arrays)."""
    a, b, c, d = inv
    y = rows.astype(float) - (centre[0] + offset[0])
    x = cols.astype(float) - (centre[1] + offset[1])
    sr = np.floor((a * y + (centre[0] + 0.5))[:, None] + (b * x)[None, :]).astype(np.intp)
    sc = np.floor((c * y + (centre[1] + 0.5))[:, None] + (d * x)[None, :]).astype(np.intp)
    return sr, sc


def _integer_offset(offset) -> tuple[int, int] | None:
    r, c = offset
    return (int(r), int(c)) if r == int(r) and c == int(c) else None


def _carry(mask, m, inv, centre, offset, wrap, *, label=None, box=None):
    """Where each point of a selection lands: destination (rows, cols) and source (rows, cols),
    a band of BAND_POINTS destination points at a time (an iterator of such four arrays).

    Every destination point of the image of the selection's box takes its nearest source; it is
    kept when that source is selected. With ``wrap`` destinations are folded onto the canvas and,
    where folds overlap, the last in scan order wins: within a band its last one is kept, and
    the bands come in scan order, so writing them in turn leaves the last of all (as the whole
    box at once did; its index arrays took 2.5 GB for a box of 2^26 points). ``mask`` may be a
    label matrix: the selection is then its points of ``label``, whose box is ``box``. A box too
    large is refused here, before anything is written.
    """
    h, w = mask.shape
    t, l, b, r = bbox(mask) if box is None else box
    ys, xs = _forward(m, centre, offset, [t - 0.5, t - 0.5, b - 0.5, b - 0.5],
                      [l - 0.5, r - 0.5, l - 0.5, r - 0.5])
    r0, r1 = math.floor(ys.min()) - 1, math.ceil(ys.max()) + 2
    c0, c1 = math.floor(xs.min()) - 1, math.ceil(xs.max()) + 2
    if not wrap:
        r0, r1, c0, c1 = max(r0, 0), min(r1, h), max(c0, 0), min(c1, w)
    if r1 <= r0 or c1 <= c0:
        return iter(())
    if (r1 - r0) * (c1 - c0) > MAX_WARP_POINTS:
        raise InputError(f"the transformed selection would span {(r1 - r0)}×{(c1 - c0)} points; "
                         "use a smaller factor")
    folds = wrap and (r1 - r0 > h or c1 - c0 > w)       # folds may overlap
    return _carried(mask, inv, centre, offset, wrap, folds, label, (r0, r1, c0, c1))


def _carried(mask, inv, centre, offset, wrap, folds, label, box):
    h, w = mask.shape
    r0, r1, c0, c1 = box
    rows = max(1, BAND_POINTS // (c1 - c0))
    cols = min(c1 - c0, BAND_POINTS)            # a row longer than a band is cut too
    for top in range(r0, r1, rows):
        qr = np.arange(top, min(top + rows, r1))
        for left in range(c0, c1, cols):
            sr, sc = _sources(inv, centre, offset, qr, np.arange(left, min(left + cols, c1)))
            ok = (sr >= 0) & (sr < h) & (sc >= 0) & (sc < w)
            ok[ok] = mask[sr[ok], sc[ok]] if label is None else mask[sr[ok], sc[ok]] == label
            dr, dc = np.nonzero(ok)
            sr, sc = sr[dr, dc], sc[dr, dc]
            dr, dc = dr + top, dc + left
            if wrap:
                dr, dc = dr % h, dc % w
                if folds:                           # keep the last in scan order
                    flat = (dr * w + dc)[::-1]
                    _, first = np.unique(flat, return_index=True)
                    keep = np.sort(len(flat) - 1 - first)
                    dr, dc, sr, sc = dr[keep], dc[keep], sr[keep], sc[keep]
            yield dr, dc, sr, sc


def _checked(levels, mask, centre, offset, fill):
    levels = as_levels(levels)
    mask = None if mask is None else as_mask(mask, levels.shape)
    return (levels, mask, _as_vector(centre, "centre"), _as_vector(offset, "offset"),
            as_level(fill, "fill"))


def warp(levels, matrix, *, centre: Point = (0.0, 0.0), offset: Point = (0.0, 0.0), mask=None,
         wrap: bool = False, fill: int = 0, keep_source: bool = False) -> np.ndarray:
    """Apply the affine map ``p ↦ matrix·(p − centre) + centre + offset``; a new matrix.

    Without ``mask`` the whole texture is resampled: each point takes the level found at its
    preimage; a preimage off the canvas reads ``fill`` (or the point's own level with
    ``keep_source``), or wraps around with ``wrap``. With ``mask`` only the selection is carried:
    its points are set to ``fill`` (unless ``keep_source``: a duplicate) and its levels are written
    where the map takes them, dropped off the canvas or folded back onto it with ``wrap``.

    >>> grid = np.array([[1, 2, 0],
    ...                  [3, 4, 0],
    ...                  [0, 0, 0]], np.uint8)
    >>> warp(grid, ((0, 1), (1, 0)))                  # transpose: mirror across the diagonal
    array([[1, 3, 0],
           [2, 4, 0],
           [0, 0, 0]], dtype=uint8)
    >>> warp(grid, ((1, 0), (0, 1)), offset=(1, 1), mask=grid == 4)   # move one point
    array([[1, 2, 0],
           [3, 0, 0],
           [0, 0, 4]], dtype=uint8)
    """
    levels, mask, centre, offset, fill = _checked(levels, mask, centre, offset, fill)
    m, inv = linear_map(matrix)
    shift = _integer_offset(offset) if m == (1.0, 0.0, 0.0, 1.0) else None
    if mask is not None:
        out = levels.copy()
        box = bbox(mask)
        if box is None:
            return out
        if not keep_source:
            t, l, b, r = box
            out[t:b, l:r][mask[t:b, l:r]] = fill
        if shift is not None:
            paste(out, levels, mask, shift, wrap=wrap, box=box)
        else:
            for dr, dc, sr, sc in _carry(mask, m, inv, centre, offset, wrap):
                out[dr, dc] = levels[sr, sc]
        return out
    if shift is not None and wrap:
        return np.roll(levels, shift, axis=(0, 1))
    return _resample(levels, inv, centre, offset, wrap, fill, keep_source)


def _resample(levels, inv, centre, offset, wrap, fill, keep_source) -> np.ndarray:
    h, w = levels.shape
    out = np.empty_like(levels)
    cols = np.arange(w)
    step = max(1, BAND_POINTS // max(w, 1))
    for top in range(0, h, step):
        rows = np.arange(top, min(top + step, h))
        sr, sc = _sources(inv, centre, offset, rows, cols)
        if wrap:
            out[rows[0]:rows[-1] + 1] = levels[sr % h, sc % w]
            continue
        inside = (sr >= 0) & (sr < h) & (sc >= 0) & (sc < w)
        got = levels[np.clip(sr, 0, h - 1), np.clip(sc, 0, w - 1)]
        base = levels[rows[0]:rows[-1] + 1] if keep_source else fill
        out[rows[0]:rows[-1] + 1] = np.where(inside, got, base)
    return out


def carry_region(out: np.ndarray, levels: np.ndarray, labels: np.ndarray, label: int, box,
                 matrix, *, centre: Point, offset: Point = (0.0, 0.0),
                 wrap: bool = False) -> None:
    """Write the region ``labels == label`` of ``levels`` (its box ``box``) where the map takes
    it, into ``out``: in place, as `paste` — the operators that move many regions, each by its
    own map, call it on their own copy. Only the region's box is read, whatever the canvas.

    >>> labels = np.array([[1, 1, 0], [0, 2, 0], [0, 0, 0]])
    >>> out = np.zeros((3, 3), np.uint8)
    >>> carry_region(out, labels.astype(np.uint8) * 5, labels, 2, (1, 1, 2, 2), ((1, 0), (0, 1)),
    ...              centre=(1, 1), offset=(1, 1))
    >>> out
    array([[ 0,  0,  0],
           [ 0,  0,  0],
           [ 0,  0, 10]], dtype=uint8)
    """
    m, inv = linear_map(matrix)
    for dr, dc, sr, sc in _carry(labels, m, inv, _as_vector(centre, "centre"),
                                 _as_vector(offset, "offset"), wrap, label=label, box=box):
        out[dr, dc] = levels[sr, sc]


def transform_mask(mask, matrix, *, centre: Point = (0.0, 0.0), offset: Point = (0.0, 0.0),
                   wrap: bool = False) -> np.ndarray:
    """Where a selection lands under the map (the presence mask after ``warp(..., mask=mask)``).

    >>> transform_mask(np.eye(3, dtype=bool), ((1, 0), (0, -1)), centre=(1, 1)).astype(int)
    array([[0, 0, 1],
           [0, 1, 0],
           [1, 0, 0]])
    """
    mask = np.asarray(mask)
    if mask.ndim != 2:
        raise InputError("a presence mask must be 2-D")
    mask = as_mask(mask, mask.shape)
    centre, offset = _as_vector(centre, "centre"), _as_vector(offset, "offset")
    m, inv = linear_map(matrix)
    out = np.zeros(mask.shape, bool)
    if not mask.any():
        return out
    shift = _integer_offset(offset) if m == (1.0, 0.0, 0.0, 1.0) else None
    if shift is not None:
        paste(out, mask, mask, shift, wrap=wrap)
    else:
        for dr, dc, _, _ in _carry(mask, m, inv, centre, offset, wrap):
            out[dr, dc] = True
    return out


# -- the four global operators --------------------------------------------------------------------

def identity(levels, offset, *, mask=None, repeat: tuple[int, int] = (1, 1),
             step: tuple[int, int] | None = None, wrap: bool = False) -> np.ndarray:
    """IDENTITE: duplicate the selection (or the whole texture) to ``offset``, optionally on a grid.

    Copies are placed at ``offset + (i·step_rows, j·step_cols)`` for ``i < repeat[0]``,
    ``j < repeat[1]`` (``step`` defaults to the size of the selection's box, so the copies tile);
    every copy reads the texture as it was before the operator, later copies (scan order) lie over
    earlier ones, and what no copy covers is untouched. With ``wrap`` a copy leaving the canvas
    comes back on the other side: the whole texture duplicated with ``wrap`` is a cyclic shift.

    >>> grid = np.array([[1, 2, 0, 0, 0, 0],
    ...                  [3, 0, 0, 0, 0, 0]], np.uint8)
    >>> identity(grid, (0, 2), mask=grid > 0, repeat=(1, 2))
    array([[1, 2, 1, 2, 1, 2],
           [3, 0, 3, 0, 3, 0]], dtype=uint8)
    """
    levels = as_levels(levels)
    h, w = levels.shape
    mask = np.ones(levels.shape, bool) if mask is None else as_mask(mask, levels.shape)
    dr, dc = as_point(offset, "offset")
    nr, nc = as_point(repeat, "repeat")
    if nr < 1 or nc < 1:
        raise InputError(f"repeat must be at least (1, 1), got ({nr}, {nc})")
    box = bbox(mask)
    out = levels.copy()
    if box is None:
        return out
    sr, sc = (box[2] - box[0], box[3] - box[1]) if step is None else as_point(step, "step")
    if nr * nc > 1 and not wrap:           # copies wholly off the canvas cost nothing: skip them
        irange = [i for i in range(nr) if -h < dr + i * sr + box[0] < h]
        jrange = [j for j in range(nc) if -w < dc + j * sc + box[1] < w]
    else:
        irange, jrange = range(nr), range(nc)
    if len(irange) * len(jrange) > 65536:
        raise InputError("at most 65536 copies fit a canvas: use fewer repeats or a larger step")
    for i in irange:
        for j in jrange:
            paste(out, levels, mask, (dr + i * sr, dc + j * sc), wrap=wrap, box=box)
    return out


def isometry(levels, angle: float, centre: Point, *, mask=None, wrap: bool = False, fill: int = 0,
             keep_source: bool = False) -> np.ndarray:
    """ISOMETRIE: turn the texture (or a selection) ``angle`` degrees counter-clockwise about
    ``centre`` — it changes the texture's orientation. See :func:`warp` for the options.

    >>> grid = np.array([[0, 1, 0],
    ...                  [0, 2, 3],
    ...                  [0, 0, 0]], np.uint8)
    >>> isometry(grid, 90, (1, 1))
    array([[0, 3, 0],
           [1, 2, 0],
           [0, 0, 0]], dtype=uint8)
    """
    return warp(levels, rotation_matrix(angle), centre=centre, mask=mask, wrap=wrap, fill=fill,
                keep_source=keep_source)


def similarity(levels, factor: float, centre: Point, *, angle: float = 0.0, mask=None,
               wrap: bool = False, fill: int = 0, keep_source: bool = False) -> np.ndarray:
    """SIMILITUDE: zoom by ``factor`` about ``centre`` (a homothety), turned by ``angle`` degrees.

    A factor below 1 packs more grains per unit area (a finer texture); with ``wrap`` and
    factor 1/k the texture is repeated k×k times and stays tileable.

    >>> grid = np.array([[1, 2, 0, 0],
    ...                  [3, 4, 0, 0],
    ...                  [0, 0, 0, 0],
    ...                  [0, 0, 0, 0]], np.uint8)
    >>> similarity(grid, 2, (-0.5, -0.5))          # about the canvas's top-left corner
    array([[1, 1, 2, 2],
           [1, 1, 2, 2],
           [3, 3, 4, 4],
           [3, 3, 4, 4]], dtype=uint8)
    """
    try:
        factor = float(factor)
    except (TypeError, ValueError):
        raise InputError(f"the zoom factor must be a number, got {factor!r}") from None
    if not (math.isfinite(factor) and factor > 0):
        raise InputError(f"the zoom factor must be a positive number, got {factor}")
    (a, b), (c, d) = rotation_matrix(angle)
    return warp(levels, ((factor * a, factor * b), (factor * c, factor * d)), centre=centre,
                mask=mask, wrap=wrap, fill=fill, keep_source=keep_source)


def affinity(levels, matrix, centre: Point = (0.0, 0.0), *, offset: Point = (0.0, 0.0), mask=None,
             wrap: bool = False, fill: int = 0, keep_source: bool = False) -> np.ndarray:
    """AFFINITE: any invertible affine map (shear, stretch...); parallels stay parallel and square
    cells become parallelograms — a grid of motifs becomes a triangular arrangement.

    The shear below moves each row right by its index (rows counted from ``centre``): the
    columns of a square grid lean into parallelograms.

    >>> grid = np.zeros((4, 6), np.uint8); grid[:, 0] = 1; grid[:, 3] = 2
    >>> affinity(grid, ((1, 0), (1, 1)))
    array([[1, 0, 0, 2, 0, 0],
           [0, 1, 0, 0, 2, 0],
           [0, 0, 1, 0, 0, 2],
           [0, 0, 0, 1, 0, 0]], dtype=uint8)
    """
    return warp(levels, matrix, centre=centre, offset=offset, mask=mask, wrap=wrap, fill=fill,
                keep_source=keep_source)
