"""Random manipulation of every region at once (thesis §3.4.3): each region of a selection, of a
level or of the whole texture moved, turned and rescaled by its own similarity drawn from a seed.

A global operator made of local ones: the regions are found as EXTRACTEXT finds one (connected
points of one level), each is carried about the centre of its box by `transforms.carry_region`,
the map every local manipulation uses, and the `ScatterRegions` Action records the seed and the
ranges, so a replay draws the same maps and paints the same points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .transforms import as_level, as_levels, as_mask, carry_region, rotation_matrix

ROTATIONS = ("none", "quarter", "any")
CONNECTIVITIES = (4, 8)
LABEL_BAND = 2**20          # labels looked through at once for each region's first point


@dataclass(frozen=True)
class RegionMap:
    """One region's draw: a move of (rows, cols) points, a turn in degrees, a zoom factor."""

    offset: tuple[int, int]
    angle: float
    factor: float

    def matrix(self):
        (a, b), (c, d) = rotation_matrix(self.angle)
        f = self.factor
        return ((f * a, f * b), (f * c, f * d))


def _half_up(x: float) -> int:
    """Rounded half up, after rounding to 9 decimals (a last-bit difference of sin or cos on
    another machine never moves a region)."""
    return math.floor(round(x, 9) + 0.5)


def random_maps(count: int, seed: int, *, radius: float = 0.0, rotation: str = "none",
                scale: tuple[float, float] = (1.0, 1.0)) -> list[RegionMap]:
    """The maps of ``count`` regions, in painting order: four uniform draws per region from
    ``numpy.random.default_rng(seed)`` — a move uniform in the disc of ``radius`` (rounded to
    whole points), a turn (none, a multiple of 90° or any angle), a factor uniform in ``scale``.
    Each region's maps use the same four draws whatever the options, so widening one range
    leaves the others' draws alone.

    >>> [m.angle % 90 for m in random_maps(5, 3, rotation="quarter")]
    [0.0, 0.0, 0.0, 0.0, 0.0]
    >>> random_maps(1, 3, radius=0)[0].offset
    (0, 0)
    """
    if rotation not in ROTATIONS:
        raise InputError(f"rotation must be one of {', '.join(ROTATIONS)}, got {rotation!r}")
    low, high = (float(v) for v in scale)
    if not 0 < low <= high:
        raise InputError(f"the scale range must be two positive numbers, the smaller first; "
                         f"got {low:g}..{high:g}")
    if not (math.isfinite(radius) and radius >= 0):
        raise InputError(f"the radius must be a number of points ≥ 0, got {radius}")
    maps = []
    for u_radius, u_direction, u_turn, u_scale in np.random.default_rng(seed).random((count, 4)):
        rho, phi = radius * math.sqrt(u_radius), 2 * math.pi * u_direction
        offset = (_half_up(rho * math.sin(phi)), _half_up(rho * math.cos(phi)))
        angle = {"none": 0.0, "quarter": 90.0 * math.floor(4 * u_turn),
                 "any": round(360.0 * u_turn, 6)}[rotation]
        maps.append(RegionMap(offset, angle, round(low + (high - low) * u_scale, 9)))
    return maps


def region_labels(levels, mask=None, *, connectivity: int = 4):
    """The regions the operator moves: connected points of one level among the selected ones
    (``mask`` None: every point but the background, level 0). Returns (labels, order, boxes):
    the label matrix (0 outside), the labels in the scan order of their first point — the
    order regions are drawn and painted in — and each label's box (top, left, bottom, right).

    >>> grid = np.array([[0, 2, 2],
    ...                  [1, 0, 2],
    ...                  [1, 1, 0]], np.uint8)
    >>> labels, order, boxes = region_labels(grid)
    >>> [boxes[k] for k in order]
    [(0, 1, 2, 3), (1, 0, 3, 2)]
    """
    from scipy import ndimage
    from skimage.measure import label

    levels = as_levels(levels)
    chosen = levels > 0 if mask is None else as_mask(mask, levels.shape)
    if connectivity not in CONNECTIVITIES:
        raise InputError(f"connectivity must be 4 or 8, got {connectivity!r}")
    labels = label(np.where(chosen, levels.astype(np.int16), -1), background=-1,
                   connectivity=1 if connectivity == 4 else 2)
    ids, first = _first_points(labels)
    order = [int(k) for k in ids[np.argsort(first, kind="stable")] if k]
    boxes = {k: (rows.start, cols.start, rows.stop, cols.stop)
             for k, (rows, cols) in enumerate(ndimage.find_objects(labels), start=1)}
    return labels, order, boxes


def _first_points(labels: np.ndarray):
    """``np.unique(labels.ravel(), return_index=True)``: the labels there are, in increasing
    order, and the place of each one's first point in scan order — found LABEL_BAND points at
    a time (sorting 2^26 labels at once took 1.6 GB): a label's first point is in the first band
    that holds it, at its first place there."""
    flat = labels.ravel()
    first = np.full(int(flat.max(initial=0)) + 1, -1, np.int64)
    for start in range(0, flat.size, LABEL_BAND):
        ids, places = np.unique(flat[start:start + LABEL_BAND], return_index=True)
        new = first[ids] < 0
        first[ids[new]] = places[new] + start
    ids = np.flatnonzero(first >= 0)
    return ids, first[ids]


def scatter_regions(levels, seed: int, *, mask=None, radius: float = 0.0,
                    rotation: str = "none", scale: tuple[float, float] = (1.0, 1.0),
                    fill: int = 0, wrap: bool = False, connectivity: int = 4) -> np.ndarray:
    """Move, turn and rescale every region of the selection (see :func:`region_labels`), each
    about the centre of its box by its own map (:func:`random_maps`); a new matrix.

    Every region leaves ``fill`` behind; then each is painted where its map takes it, in the
    scan order of their first points, a later one over an earlier one. Points leaving the canvas
    are lost, or come back on the other side with ``wrap``. With no move, no turn and factor 1
    the texture is unchanged; with quarter turns only, each region turns in its box.

    >>> grid = np.array([[0, 0, 0, 0, 0],
    ...                  [1, 1, 1, 0, 2],
    ...                  [0, 0, 0, 0, 2],
    ...                  [0, 0, 0, 0, 2]], np.uint8)
    >>> [m.angle for m in random_maps(2, 3, rotation="quarter")]   # the 1s, then the 2s
    [270.0, 90.0]
    >>> scatter_regions(grid, 3, rotation="quarter")             # a 2 leaves the canvas
    array([[0, 1, 0, 0, 0],
           [0, 1, 0, 0, 0],
           [0, 1, 0, 2, 2],
           [0, 0, 0, 0, 0]], dtype=uint8)
    """
    levels = as_levels(levels)
    fill = as_level(fill, "fill")
    labels, order, boxes = region_labels(levels, mask, connectivity=connectivity)
    maps = random_maps(len(order), seed, radius=radius, rotation=rotation, scale=scale)
    out = levels.copy()
    out[labels > 0] = fill
    for k, region_map in zip(order, maps):
        t, l, b, r = boxes[k]
        carry_region(out, levels, labels, k, boxes[k], region_map.matrix(),
                     centre=((t + b - 1) / 2, (l + r - 1) / 2), offset=region_map.offset,
                     wrap=wrap)
    return out
