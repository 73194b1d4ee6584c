"""Zone duplication and frontier scrambling (thesis §3.3.3a), for grain textures made by hand.

The eye sees symmetries but not repetitions, so a user duplicates zones of a texture elsewhere
(a rectangle or a lasso, copied with the copy operator of `regions`); where the frontier of a
copy shows, grains added at random in a band along it scramble it. The DuplicateZone and
ScrambleFrontier actions of `paint_actions` call these pure functions.
"""

from __future__ import annotations

import math

import numpy as np

from ..regions import extractext as regions
from .brushes import last_wins
from ..errors import InputError
from .grains import anchor, grain_mask
from ..regions.transforms import as_levels, as_mask, bbox

ZONES = ("rectangle", "lasso")
MAX_BAND = 256

__all__ = ["ZONES", "zone_mask", "duplicate", "frontier_band", "scramble"]


def zone_mask(canvas_shape, zone: str, points) -> np.ndarray:
    """The points of a zone: a rectangle between two opposite corners (both included), or the
    inside of a lasso through its vertices (its border included), cut to the canvas.

    >>> zone_mask((3, 4), "rectangle", [(2, 2), (1, 0)]).astype(int)
    array([[0, 0, 0, 0],
           [1, 1, 1, 0],
           [1, 1, 1, 0]])
    """
    h, w = canvas_shape
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if zone == "rectangle":
        if len(pts) != 2:
            raise InputError("a rectangular zone is given by two opposite corners")
        (r0, r1), (c0, c1) = sorted(pts[:, 0].astype(int)), sorted(pts[:, 1].astype(int))
        mask = np.zeros((h, w), bool)
        mask[max(r0, 0):max(r1 + 1, 0), max(c0, 0):max(c1 + 1, 0)] = True
        return mask
    if zone == "lasso":
        if len(pts) < 3:
            raise InputError("a lasso needs at least three points")
        from skimage.draw import polygon2mask
        return polygon2mask((h, w), pts)
    raise InputError(f"a zone is a rectangle or a lasso, got {zone!r}")


def duplicate(levels, mask, offset, *, wrap: bool = False) -> np.ndarray:
    """Copy the zone's levels by ``offset`` (rows, cols): COPIER applied to a drawn zone.

    >>> duplicate(np.array([[1, 2, 0, 0]], np.uint8), [[1, 1, 0, 0]], (0, 2))
    array([[1, 2, 1, 2]], dtype=uint8)
    """
    levels = as_levels(levels)
    return regions.move(levels, as_mask(mask, levels.shape), offset, keep_source=True, wrap=wrap)


def frontier_band(mask, width: int, *, wrap: bool = False) -> np.ndarray:
    """The points within a band of ``width`` points along the zone's outline: ⌈width/2⌉ rings
    inside the zone and ⌊width/2⌋ outside (Euclidean distance). The canvas's edge is not a
    frontier unless ``wrap`` makes the canvas a tile, whose edges meet.

    >>> frontier_band(np.pad(np.ones((3, 3), bool), 2), 2).astype(int)
    array([[0, 0, 0, 0, 0, 0, 0],
           [0, 0, 1, 1, 1, 0, 0],
           [0, 1, 1, 1, 1, 1, 0],
           [0, 1, 1, 0, 1, 1, 0],
           [0, 1, 1, 1, 1, 1, 0],
           [0, 0, 1, 1, 1, 0, 0],
           [0, 0, 0, 0, 0, 0, 0]])
    """
    from scipy.ndimage import distance_transform_edt
    mask = np.asarray(mask)
    mask = as_mask(mask, mask.shape)
    if isinstance(width, bool) or not 1 <= int(width) <= MAX_BAND:
        raise InputError(f"the band is 1..{MAX_BAND} points wide, got {width!r}")
    h, w = mask.shape
    out = np.zeros((h, w), bool)
    box = bbox(mask)
    if box is None:
        return out
    margin = int(width) + 1
    t, l, b, r = box[0] - margin, box[1] - margin, box[2] + margin, box[3] + margin
    if not wrap:
        t, l, b, r = max(t, 0), max(l, 0), min(b, h), min(r, w)
    rows, cols = np.arange(t, b), np.arange(l, r)
    window = mask[np.ix_(rows % h, cols % w)]
    if window.all():
        return out
    inside = window & (distance_transform_edt(window) <= math.ceil(width / 2))
    outside = ~window & (distance_transform_edt(~window) <= width // 2)
    rr, cc = np.nonzero(inside | outside)
    out[rows[rr] % h, cols[cc] % w] = True
    return out


def scramble(levels, band, *, density: float, grain_size: int = 1, reach: int | None = None,
             seed: int = 0, wrap: bool = False) -> np.ndarray:
    """Scramble a frontier: grains dropped at random in the band, each taking the level found a
    random step away (within ``reach`` points, by default the band's own depth), so the textures
    on both sides mix. Only points of the band change.

    ``density`` is the chance that a band point receives a grain centre; grains are squares of
    ``grain_size`` points, cut to the band; later grains lie over earlier ones.
    """
    levels = as_levels(levels)
    band = as_mask(band, levels.shape)
    if not 0.0 <= density <= 1.0:
        raise InputError(f"the density is a chance 0..1, got {density!r}")
    h, w = levels.shape
    rng = np.random.default_rng(seed)
    rows, cols = np.nonzero(band)
    if not len(rows):
        return levels.copy()
    reach = max(1, grain_size) if reach is None else reach
    chosen = rng.random(len(rows)) < density
    rows, cols = rows[chosen], cols[chosen]
    step = rng.integers(-reach, reach + 1, size=(2, len(rows)))
    src_r, src_c = rows + step[0], cols + step[1]
    if wrap:
        src_r, src_c = src_r % h, src_c % w
    else:
        src_r, src_c = src_r.clip(0, h - 1), src_c.clip(0, w - 1)
    values = levels[src_r, src_c]
    grain = grain_mask("square", grain_size)
    ay, ax = anchor(grain)
    gy, gx = np.nonzero(grain)
    pr = (rows[:, None] + (gy - ay)[None, :]).ravel()
    pc = (cols[:, None] + (gx - ax)[None, :]).ravel()
    pv = np.repeat(values, len(gy))
    if wrap:
        pr, pc = pr % h, pc % w
    else:
        keep = (pr >= 0) & (pr < h) & (pc >= 0) & (pc < w)
        pr, pc, pv = pr[keep], pc[keep], pv[keep]
    keep = band[pr, pc]
    pr, pc, pv = last_wins(pr[keep], pc[keep], pv[keep], levels.shape)
    out = levels.copy()
    out[pr, pc] = pv
    return out
