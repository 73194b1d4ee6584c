"""EXTRACTEXT and the local operators on regions (thesis §3.4.1–3.4.2): presence masks and edits.

Mask producers (``extractext``, the four extractions, ``select``) find the points an operator works
on; appliers (``transfert``, ``fill``, ``translate``, ``copy`` and the local manipulations) write a
new level matrix through a mask. Region actions in `region_actions` compose them, one per tool.

Conventions: ``levels`` is an (H, W) uint8 matrix, 0 the background; points are (row, col), row 0
on top (the thesis counts from the bottom-left corner); masks are bool (H, W). A *region* is a
connected set of points of one level, 4-connected (edges) or 8-connected (edges and corners).
Every function returns a new array and leaves its inputs alone.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .transforms import (Point, as_level, as_levels, as_mask, as_point, bbox, check_point, paste,
                         rotation_matrix, selection_centre, warp)

SCOPES = ("region", "global")
KINDS = ("region", "region_in_region", "regions_in_region", "neighbours", "partial")
CONNECTIVITIES = (4, 8)
LABEL_MARGIN = 32                 # points around a region searched for its neighbours at once
MAX_NEIGHBOUR_BYTES = 2 * 2**30     # nominal: zeroed pages are committed only where written

__all__ = ["SCOPES", "KINDS", "CONNECTIVITIES", "extractext", "shift_mask", "transfert", "valeur",
           "etendre", "compresser", "trouver", "difference", "enclosed", "fill", "translate",
           "copy", "move", "extract_region_in_region", "extract_regions_in_region",
           "neighbour_labels", "extract_neighbours", "extract_partial", "select", "change_level",
           "delete", "scale", "rotate", "flip"]


# SciPy and scikit-image load on first use, so that importing the actions stays quick.

def _flood(image, point, *, connectivity):
    from skimage.segmentation import flood
    return flood(image, point, connectivity=connectivity)


def _label(image, *, background, connectivity):
    from skimage.measure import label
    return label(image, background=background, connectivity=connectivity)


def _ndi():
    from scipy import ndimage
    return ndimage


def _check_options(scope: str = "region", connectivity: int = 4) -> None:
    if scope not in SCOPES:
        raise InputError(f"scope must be 'region' (the connected region) or 'global' (every "
                         f"point of the level), got {scope!r}")
    if connectivity not in CONNECTIVITIES or isinstance(connectivity, bool):
        raise InputError(f"connectivity must be 4 (edges) or 8 (edges and corners), "
                         f"got {connectivity!r}")


def _sk(connectivity: int) -> int:
    return 1 if connectivity == 4 else 2


def _structure(connectivity: int) -> np.ndarray:
    return _ndi().generate_binary_structure(2, _sk(connectivity))


def _grow(box, margin: int, shape) -> tuple[slice, slice]:
    t, l, b, r = box
    h, w = shape
    return (slice(max(t - margin, 0), min(b + margin, h)),
            slice(max(l - margin, 0), min(r + margin, w)))


def _empty(shape) -> np.ndarray:
    return np.zeros(shape, dtype=bool)


# -- EXTRACTEXT and its helpers (§3.4.1, §3.4.2d) -------------------------------------------------

def extractext(levels, point1, point2=None, *, scope: str = "region", connectivity: int = 4,
               wrap: bool = False) -> np.ndarray:
    """EXTRACTEXT: the presence matrix of the level found at ``point1``, implanted at ``point2``.

    ``scope="region"`` marks the connected region containing ``point1``; ``"global"`` marks every
    point of that level (the thesis's literal wording). With ``point2`` the marks are translated by
    ``point2 - point1``; points leaving the canvas are dropped (or wrap around with ``wrap``).

    >>> grid = np.array([[0, 0, 0, 0, 0],
    ...                  [0, 2, 2, 0, 2],
    ...                  [0, 2, 0, 0, 0],
    ...                  [0, 0, 0, 0, 0]], np.uint8)
    >>> extractext(grid, (1, 1)).astype(int)
    array([[0, 0, 0, 0, 0],
           [0, 1, 1, 0, 0],
           [0, 1, 0, 0, 0],
           [0, 0, 0, 0, 0]])
    >>> extractext(grid, (1, 1), scope="global").astype(int)[1]
    array([0, 1, 1, 0, 1])
    >>> extractext(grid, (1, 1), (2, 3)).astype(int)
    array([[0, 0, 0, 0, 0],
           [0, 0, 0, 0, 0],
           [0, 0, 0, 1, 1],
           [0, 0, 0, 1, 0]])
    """
    levels = as_levels(levels)
    p1 = check_point(point1, levels.shape, "point1")
    _check_options(scope, connectivity)
    if scope == "global":
        mask = levels == levels[p1]
    else:
        mask = _flood(levels, p1, connectivity=_sk(connectivity))
    if point2 is None:
        return mask
    p2 = as_point(point2, "point2")
    return shift_mask(mask, (p2[0] - p1[0], p2[1] - p1[1]), wrap=wrap)


def shift_mask(mask, offset, *, wrap: bool = False) -> np.ndarray:
    """A presence mask translated by ``offset`` (rows, cols): the GUI's ghost of a moved region.

    >>> shift_mask(np.eye(3, dtype=bool), (0, 1)).astype(int)
    array([[0, 1, 0],
           [0, 0, 1],
           [0, 0, 0]])
    >>> shift_mask(np.eye(3, dtype=bool), (0, 1), wrap=True).astype(int)[2]
    array([1, 0, 0])
    """
    mask = np.asarray(mask)
    mask = as_mask(mask, mask.shape)
    out = _empty(mask.shape)
    paste(out, mask, mask, as_point(offset, "offset"), wrap=wrap)
    return out


def transfert(levels, mask, value) -> np.ndarray:
    """TRANSFERT: write ``value`` wherever the presence matrix holds 1.

    ``value`` is a level, or an (H, W) matrix whose levels are copied at the marked points.

    >>> grid = np.array([[1, 1, 0],
    ...                  [0, 1, 0]], np.uint8)
    >>> transfert(grid, grid == 1, 7)
    array([[7, 7, 0],
           [0, 7, 0]], dtype=uint8)
    """
    levels = as_levels(levels)
    mask = as_mask(mask, levels.shape)
    out = levels.copy()
    box = bbox(mask)
    if box is None:
        return out
    t, l, b, r = box
    m = mask[t:b, l:r]
    if np.ndim(value) == 0:
        out[t:b, l:r][m] = as_level(value)
    else:
        source = as_levels(value, "value")
        if source.shape != levels.shape:
            raise InputError(f"the values have shape {source.shape}, the canvas {levels.shape}")
        out[t:b, l:r][m] = source[t:b, l:r][m]
    return out


def valeur(levels, point) -> int:
    """VALEUR: the level at ``point``.

    >>> valeur(np.array([[0, 3]], np.uint8), (0, 1))
    3
    """
    levels = as_levels(levels)
    return int(levels[check_point(point, levels.shape)])


def etendre(mask, *, connectivity: int = 4) -> np.ndarray:
    """ETENDRE: grow a region by one point (a dilation by the 4- or 8-neighbourhood).

    >>> etendre(np.pad(np.ones((1, 1), bool), 1)).astype(int)
    array([[0, 1, 0],
           [1, 1, 1],
           [0, 1, 0]])
    """
    mask = np.asarray(mask)
    mask = as_mask(mask, mask.shape)
    _check_options(connectivity=connectivity)
    vertical = mask.copy()
    vertical[1:] |= mask[:-1]
    vertical[:-1] |= mask[1:]
    across = vertical if connectivity == 8 else mask     # the square is the cross of a column
    out = vertical.copy()
    out[:, 1:] |= across[:, :-1]
    out[:, :-1] |= across[:, 1:]
    return out


def compresser(mask, *, connectivity: int = 4) -> np.ndarray:
    """COMPRESSER: reduce a region to its one-point frontier (the points of the region with a
    neighbour outside it, the canvas's edge counting as outside).

    >>> compresser(np.ones((3, 4), bool)).astype(int)
    array([[1, 1, 1, 1],
           [1, 0, 0, 1],
           [1, 1, 1, 1]])
    """
    mask = np.asarray(mask)
    mask = as_mask(mask, mask.shape)
    _check_options(connectivity=connectivity)
    vertical = mask.copy()                  # the canvas's edge counts as outside
    vertical[0] = vertical[-1] = False
    vertical[1:] &= mask[:-1]
    vertical[:-1] &= mask[1:]
    across = vertical if connectivity == 8 else mask
    inner = vertical.copy()
    inner[:, 0] = inner[:, -1] = False
    inner[:, 1:] &= across[:, :-1]
    inner[:, :-1] &= across[:, 1:]
    return mask & ~inner


def trouver(mask) -> tuple[int, int] | None:
    """TROUVER: the first marked point in scan order (row after row, left to right), or None.

    >>> trouver(np.array([[0, 0, 0], [0, 1, 1]], bool))
    (1, 1)
    """
    mask = np.asarray(mask)
    mask = as_mask(mask, mask.shape)
    flat = mask.ravel()
    i = int(np.argmax(flat)) if flat.size else 0
    if not flat.size or not flat[i]:
        return None
    r, c = divmod(i, mask.shape[1])
    return r, c


def difference(mask1, mask2) -> np.ndarray:
    """DIFFERENCE: the exclusive or of two presence matrices.

    >>> difference(np.array([1, 1, 0], bool)[None], np.array([0, 1, 1], bool)[None]).astype(int)
    array([[1, 0, 1]])
    """
    a = np.asarray(mask1)
    a = as_mask(a, a.shape, "mask1")
    return a ^ as_mask(mask2, a.shape, "mask2")


def enclosed(mask, *, connectivity: int = 4) -> np.ndarray:
    """The points a region encloses (its holes and what fills them), the region excluded.

    A region of connectivity 4 encloses what 8-connected paths cannot leave and vice versa (the
    usual dual rule of digital topology); a pocket open to the canvas's edge is not enclosed.

    >>> ring = np.array([[1, 1, 1, 0],
    ...                  [1, 0, 1, 0],
    ...                  [1, 1, 1, 0]], bool)
    >>> enclosed(ring).astype(int)
    array([[0, 0, 0, 0],
           [0, 1, 0, 0],
           [0, 0, 0, 0]])
    """
    mask = np.asarray(mask)
    mask = as_mask(mask, mask.shape)
    _check_options(connectivity=connectivity)
    labels, window = _holes(mask, connectivity)
    out = _empty(mask.shape)
    if labels is not None:
        out[window] = labels > 0
    return out


def _holes(mask, connectivity):
    """Label the holes of ``mask`` inside its box: (labels, window), or (None, None)."""
    box = bbox(mask)
    if box is None:
        return None, None
    window = _grow(box, 0, mask.shape)
    outside = ~np.pad(mask[window], 1)         # the padded frame joins every open pocket
    dual = 8 if connectivity == 4 else 4
    labels, _ = _ndi().label(outside, structure=_structure(dual))
    labels[labels == labels[0, 0]] = 0
    return labels[1:-1, 1:-1], window


# -- local operators (§3.4.2 a–c) -----------------------------------------------------------------

def fill(levels, point, value, *, scope: str = "region", connectivity: int = 4) -> np.ndarray:
    """REMPLIR: EXTRACTEXT at ``point``, then TRANSFERT ``value`` (a flood fill).

    >>> grid = np.array([[0, 1, 1, 0],
    ...                  [0, 1, 0, 0],
    ...                  [1, 1, 0, 1]], np.uint8)
    >>> fill(grid, (0, 1), 7)
    array([[0, 7, 7, 0],
           [0, 7, 0, 0],
           [7, 7, 0, 1]], dtype=uint8)
    >>> fill(grid, (0, 1), 7, scope="global")[2]
    array([7, 7, 0, 7], dtype=uint8)
    """
    value = as_level(value)
    mask = extractext(levels, point, scope=scope, connectivity=connectivity)
    return transfert(levels, mask, value)


def move(levels, mask, offset, *, fill: int = 0, keep_source: bool = False,
         wrap: bool = False) -> np.ndarray:
    """Move the selected points by ``offset`` (rows, cols), carrying their levels.

    The points left behind get ``fill`` (none with ``keep_source``: a copy); the moved points lie
    over what was there; points leaving the canvas are lost (or wrap around with ``wrap``).

    >>> grid = np.array([[5, 6, 0, 0]], np.uint8)
    >>> move(grid, grid > 0, (0, 1))
    array([[0, 5, 6, 0]], dtype=uint8)
    >>> move(grid, grid > 0, (0, 3), keep_source=True, wrap=True)
    array([[6, 6, 0, 5]], dtype=uint8)
    """
    levels = as_levels(levels)
    mask = as_mask(mask, levels.shape)
    offset, fill = as_point(offset, "offset"), as_level(fill, "fill")
    out = levels.copy()
    box = bbox(mask)
    if box is None:
        return out
    if not keep_source:
        t, l, b, r = box
        out[t:b, l:r][mask[t:b, l:r]] = fill
    paste(out, levels, mask, offset, wrap=wrap, box=box)
    return out


def translate(levels, point1, point2, *, fill: int = 0, scope: str = "region",
              connectivity: int = 4, wrap: bool = False) -> np.ndarray:
    """TRANSLATER: move the region at ``point1`` so that ``point1`` lands on ``point2``.

    What is left behind gets the level ``fill`` (the thesis's VAL; default the background). The
    moved region lies over what it lands on; the part leaving the canvas is lost (or wraps).

    >>> grid = np.array([[3, 3, 0, 0],
    ...                  [0, 3, 0, 1],
    ...                  [0, 0, 0, 1]], np.uint8)
    >>> translate(grid, (0, 0), (1, 2))
    array([[0, 0, 0, 0],
           [0, 0, 3, 3],
           [0, 0, 0, 3]], dtype=uint8)
    """
    levels = as_levels(levels)
    p1, p2 = check_point(point1, levels.shape, "point1"), as_point(point2, "point2")
    mask = extractext(levels, p1, scope=scope, connectivity=connectivity)
    return move(levels, mask, (p2[0] - p1[0], p2[1] - p1[1]), fill=fill, wrap=wrap)


def copy(levels, point1, point2, *, scope: str = "region", connectivity: int = 4,
         wrap: bool = False) -> np.ndarray:
    """COPIER: as TRANSLATER, the source region staying where it was.

    >>> grid = np.array([[3, 3, 0, 0],
    ...                  [0, 3, 0, 1]], np.uint8)
    >>> copy(grid, (0, 1), (0, 3))
    array([[3, 3, 3, 3],
           [0, 3, 0, 3]], dtype=uint8)
    """
    levels = as_levels(levels)
    p1, p2 = check_point(point1, levels.shape, "point1"), as_point(point2, "point2")
    mask = extractext(levels, p1, scope=scope, connectivity=connectivity)
    return move(levels, mask, (p2[0] - p1[0], p2[1] - p1[1]), keep_source=True, wrap=wrap)


# -- extractions of particular regions (§3.4.2d) --------------------------------------------------

def extract_region_in_region(levels, point, *, scope: str = "region",
                             connectivity: int = 4) -> np.ndarray:
    """EXTRAIRE REGION DANS REGION: a region embedded in the one at ``point``.

    The region R at ``point`` is extracted; of what R encloses, the first point in scan order is
    found (it lies just inside R's first hole) and the region at that point is returned, kept
    inside that hole. Empty when R encloses nothing. Handy to pick a motif too small to click.

    >>> grid = np.array([[1, 1, 1, 1, 1, 0],
    ...                  [1, 0, 0, 0, 1, 0],
    ...                  [1, 0, 2, 0, 1, 0],
    ...                  [1, 0, 0, 0, 1, 0],
    ...                  [1, 1, 1, 1, 1, 0]], np.uint8)
    >>> extract_region_in_region(grid, (0, 0)).astype(int)[1:4]
    array([[0, 1, 1, 1, 0, 0],
           [0, 1, 0, 1, 0, 0],
           [0, 1, 1, 1, 0, 0]])
    """
    levels = as_levels(levels)
    region = extractext(levels, point, scope=scope, connectivity=connectivity)
    labels, window = _holes(region, connectivity)
    out = _empty(levels.shape)
    if labels is None or not labels.any():
        return out
    r, c = trouver(labels > 0)
    hole = np.where(labels == labels[r, c], levels[window].astype(np.int16), -1)
    out[window] = _flood(hole, (r, c), connectivity=_sk(connectivity))
    return out


def extract_regions_in_region(levels, point, *, scope: str = "region",
                              connectivity: int = 4) -> np.ndarray:
    """EXTRAIRE REGIONS DANS REGION: every region the one at ``point`` encloses (its holes and
    all they contain, nested or not); empty when it encloses nothing.

    >>> grid = np.array([[1, 1, 1, 1, 1, 0],
    ...                  [1, 0, 0, 0, 1, 0],
    ...                  [1, 0, 2, 0, 1, 0],
    ...                  [1, 1, 1, 1, 1, 0]], np.uint8)
    >>> extract_regions_in_region(grid, (0, 0)).astype(int)[1:3]
    array([[0, 1, 1, 1, 0, 0],
           [0, 1, 1, 1, 0, 0]])
    """
    region = extractext(levels, point, scope=scope, connectivity=connectivity)
    return enclosed(region, connectivity=connectivity)


def _ring(region, connectivity):
    """DIFFERENCE(ETENDRE(R), R) inside R's box grown by one: (ring, window), or (None, None)."""
    box = bbox(region)
    if box is None:
        return None, None
    window = _grow(box, 1, region.shape)
    sub = region[window]
    return etendre(sub, connectivity=connectivity) & ~sub, window


def neighbour_labels(levels, point, *, scope: str = "region", connectivity: int = 4) -> np.ndarray:
    """The regions sharing a frontier with the one at ``point``, as an int32 label matrix:
    0 elsewhere, k on the k-th neighbour (numbered in the scan order of the first of their points
    that touches the region, as the thesis's ISOLER finds them one by one).

    >>> grid = np.array([[0, 0, 0, 0, 3],
    ...                  [1, 2, 2, 0, 3],
    ...                  [0, 0, 2, 1, 1]], np.uint8)
    >>> neighbour_labels(grid, (1, 1))
    array([[1, 1, 1, 1, 0],
           [2, 0, 0, 1, 0],
           [3, 3, 0, 4, 4]], dtype=int32)
    """
    levels = as_levels(levels)
    region = extractext(levels, point, scope=scope, connectivity=connectivity)
    ring, window = _ring(region, connectivity)
    out = np.zeros(levels.shape, np.int32)
    if ring is None or not ring.any():
        return out
    seeds = _empty(levels.shape)
    seeds[window] = ring
    return _regions_at(levels, seeds, connectivity, out)


def _regions_at(levels, seeds, connectivity, out):
    """Label (into ``out``) the level regions holding the seed points, in the scan order of their
    first seed. Regions are labelled in a window around the seeds; one that reaches the window's
    edge (not the canvas's) may go on beyond it and is flood-filled on the whole canvas."""
    h, w = levels.shape
    window = _grow(bbox(seeds), LABEL_MARGIN, levels.shape)
    (r0, r1), (c0, c1) = (window[0].start, window[0].stop), (window[1].start, window[1].stop)
    labels = _label(levels[window].astype(np.int16), background=-1,     # -1: no background
                    connectivity=_sk(connectivity))
    ids = labels[seeds[window]]
    uniq, first = np.unique(ids, return_index=True)
    order = uniq[np.argsort(first, kind="stable")]
    edges = [labels[0] if r0 > 0 else (), labels[-1] if r1 < h else (),
             labels[:, 0] if c0 > 0 else (), labels[:, -1] if c1 < w else ()]
    open_ids = set(np.unique(np.concatenate([np.asarray(e, labels.dtype).ravel()
                                             for e in edges])).tolist())
    rank = np.zeros(int(labels.max()) + 1, np.int32)
    rank[order] = np.arange(1, len(order) + 1, dtype=np.int32)
    closed = rank.copy()
    closed[list(open_ids)] = 0
    out[window] = closed[labels]
    seed_rows, seed_cols = np.nonzero(seeds[window])
    merged = []
    for k, lab in enumerate(order, start=1):
        if int(lab) not in open_ids:
            continue
        i = int(np.argmax(ids == lab))
        p = (int(seed_rows[i]) + r0, int(seed_cols[i]) + c0)
        if out[p]:                  # one region entering the window twice: it keeps its first k
            merged.append(k)
            continue
        region = _flood(levels, p, connectivity=_sk(connectivity))
        t, l, b, r = bbox(region)
        box = out[t:b, l:r]
        box[region[t:b, l:r]] = k
    if merged:                      # close the gaps: labels stay 1..n
        keep = np.ones(len(order) + 1, bool)
        keep[[0] + merged] = False
        table = np.zeros(len(order) + 1, np.int32)
        table[keep] = np.arange(1, keep.sum() + 1, dtype=np.int32)
        out = table[out]
    return out


def extract_neighbours(levels, point, *, scope: str = "region",
                       connectivity: int = 4) -> list[np.ndarray]:
    """EXTRAIRE LIMITROPHES: each region sharing a frontier with the one at ``point``, as a
    separate presence mask, in the order ISOLER finds them. An empty list when the region
    touches no other. Each mask is canvas-sized (only the pages around its region are touched);
    :func:`neighbour_labels` is the compact form, and the only one for thousands of neighbours.

    >>> grid = np.array([[0, 0, 1],
    ...                  [2, 2, 1]], np.uint8)
    >>> [m.astype(int).tolist() for m in extract_neighbours(grid, (1, 0))]
    [[[1, 1, 0], [0, 0, 0]], [[0, 0, 1], [0, 0, 1]]]
    """
    labels = neighbour_labels(levels, point, scope=scope, connectivity=connectivity)
    n = int(labels.max())
    if n * labels.size > MAX_NEIGHBOUR_BYTES:
        raise InputError(f"the region has {n} neighbours: too many to list as separate masks "
                         "(use neighbour_labels, or the region scope)")
    masks = []
    if n:
        t, l, b, r = bbox(labels > 0)
        sub = labels[t:b, l:r]
        for k, (rows, cols) in enumerate(_ndi().find_objects(sub), start=1):
            mask = _empty(labels.shape)
            mask[t + rows.start:t + rows.stop, l + cols.start:l + cols.stop] = sub[rows, cols] == k
            masks.append(mask)
    return masks


def extract_partial(levels, point, *, scope: str = "region", connectivity: int = 4) -> np.ndarray:
    """EXTRAIRE PARTIEL: the region partly covered by the one at ``point``, completed by it.

    The first point next to the covering region R (scan order) names the covered region Q; the
    result is Q together with R's area — Q's whole shape, as if R were lifted off it. Empty when R
    touches no other region.

    >>> grid = np.array([[0, 1, 1, 1, 0],
    ...                  [0, 1, 2, 1, 0],
    ...                  [0, 1, 2, 1, 0],
    ...                  [0, 0, 2, 0, 0]], np.uint8)
    >>> extract_partial(grid, (1, 2)).astype(int)
    array([[0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 0, 1, 0, 0]])
    """
    levels = as_levels(levels)
    region = extractext(levels, point, scope=scope, connectivity=connectivity)
    ring, window = _ring(region, connectivity)
    out = _empty(levels.shape)
    if ring is None or not ring.any():
        return out
    r, c = trouver(ring)
    p = (r + window[0].start, c + window[1].start)
    return _flood(levels, p, connectivity=_sk(connectivity)) | region


def select(levels, point, *, kind: str = "region", scope: str = "region",
           connectivity: int = 4, neighbour: int | None = None) -> np.ndarray:
    """The selection an extraction tool makes at ``point``: one presence mask for every kind.

    ``kind`` is "region" (EXTRACTEXT), "region_in_region", "regions_in_region", "neighbours"
    or "partial"; ``scope`` and ``connectivity`` apply to the region found at ``point``. The
    neighbours are all of them, as one mask, or with ``neighbour=k`` the k-th alone, isolated
    as ISOLER finds them (1 the first; none when there are fewer). The Actions store these few
    values and replay the same selection.

    >>> grid = np.array([[0, 0, 0, 0, 3],
    ...                  [1, 2, 2, 0, 3],
    ...                  [0, 0, 2, 1, 1]], np.uint8)
    >>> select(grid, (1, 1), kind="neighbours", neighbour=2).astype(int)
    array([[0, 0, 0, 0, 0],
           [1, 0, 0, 0, 0],
           [0, 0, 0, 0, 0]])
    """
    if kind not in KINDS:
        raise InputError(f"unknown extraction {kind!r}: choose one of {', '.join(KINDS)}")
    if neighbour is not None and kind != "neighbours":
        raise InputError(f"a neighbour number picks one of the neighbours: it goes with the "
                         f"extraction 'neighbours', not {kind!r}")
    if neighbour is not None and neighbour < 1:
        raise InputError(f"neighbours are numbered from 1, got {neighbour}")
    if kind == "region":
        return extractext(levels, point, scope=scope, connectivity=connectivity)
    if kind == "neighbours":
        labels = neighbour_labels(levels, point, scope=scope, connectivity=connectivity)
        return labels > 0 if neighbour is None else labels == neighbour
    extract = {"region_in_region": extract_region_in_region,
               "regions_in_region": extract_regions_in_region,
               "partial": extract_partial}[kind]
    return extract(levels, point, scope=scope, connectivity=connectivity)


# -- local manipulations of a selection (§3.4.2f) -------------------------------------------------

def change_level(levels, mask, value) -> np.ndarray:
    """Give every selected point the level ``value`` (TRANSFERT under the name a user looks for).

    >>> change_level(np.array([[1, 2]], np.uint8), np.array([[1, 1]], bool), 3)
    array([[3, 3]], dtype=uint8)
    """
    return transfert(levels, mask, value)


def delete(levels, mask, *, background: int = 0) -> np.ndarray:
    """Delete the selection: its points become background.

    >>> delete(np.array([[1, 2]], np.uint8), np.array([[0, 1]], bool))
    array([[1, 0]], dtype=uint8)
    """
    return transfert(levels, mask, background)


def _manipulate(levels, mask, matrix, centre, fill, wrap) -> np.ndarray:
    """Carry a selection through ``matrix`` about its centre (an empty one changes nothing)."""
    levels = as_levels(levels)
    mask = as_mask(mask, levels.shape)
    if not mask.any():
        return levels.copy()
    centre = selection_centre(mask) if centre is None else centre
    return warp(levels, matrix, centre=centre, mask=mask, wrap=wrap, fill=fill)


def scale(levels, mask, factor, *, centre: Point | None = None, fill: int = 0,
          wrap: bool = False) -> np.ndarray:
    """Scale the selection by ``factor`` (one number, or (rows, cols)) about ``centre`` (default:
    the centre of its box); what it leaves gets ``fill``, nearest neighbour keeps levels exact.

    >>> grid = np.zeros((4, 4), np.uint8); grid[1:3, 1:3] = [[1, 2], [3, 4]]
    >>> scale(grid, grid > 0, 2)
    array([[1, 1, 2, 2],
           [1, 1, 2, 2],
           [3, 3, 4, 4],
           [3, 3, 4, 4]], dtype=uint8)
    """
    fr, fc = (factor, factor) if np.ndim(factor) == 0 else factor
    try:
        fr, fc = float(fr), float(fc)
    except (TypeError, ValueError):
        raise InputError(f"the scale factor must be a number or two, got {factor!r}") from None
    if not (np.isfinite(fr) and np.isfinite(fc) and fr > 0 and fc > 0):
        raise InputError(f"scale factors must be positive numbers, got {factor!r}")
    return _manipulate(levels, mask, ((fr, 0.0), (0.0, fc)), centre, fill, wrap)


def rotate(levels, mask, angle: float, *, centre: Point | None = None, fill: int = 0,
           wrap: bool = False) -> np.ndarray:
    """Turn the selection ``angle`` degrees counter-clockwise about ``centre`` (default: the
    centre of its box); what it leaves gets ``fill``.

    >>> grid = np.array([[0, 0, 0],
    ...                  [1, 2, 3],
    ...                  [0, 0, 0]], np.uint8)
    >>> rotate(grid, grid > 0, 90)
    array([[0, 3, 0],
           [0, 2, 0],
           [0, 1, 0]], dtype=uint8)
    """
    return _manipulate(levels, mask, rotation_matrix(angle), centre, fill, wrap)


def flip(levels, mask, axis: str, *, centre: Point | None = None, fill: int = 0,
         wrap: bool = False) -> np.ndarray:
    """Mirror the selection: ``axis="horizontal"`` swaps left and right, ``"vertical"`` top and
    bottom, about ``centre`` (default: the centre of its box, so it stays in place).

    >>> grid = np.array([[1, 2, 0],
    ...                  [3, 0, 0]], np.uint8)
    >>> flip(grid, grid > 0, "horizontal")
    array([[2, 1, 0],
           [0, 3, 0]], dtype=uint8)
    """
    if axis not in ("horizontal", "vertical"):
        raise InputError(f"axis must be 'horizontal' (left-right) or 'vertical' (top-bottom), "
                         f"got {axis!r}")
    matrix = ((1, 0), (0, -1)) if axis == "horizontal" else ((-1, 0), (0, 1))
    return _manipulate(levels, mask, matrix, centre, fill, wrap)
