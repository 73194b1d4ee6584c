"""Grain rendering and density (thesis §5.3): each point of a normalised texture drawn as a grain
of pixels — its shape, size and orientation — on a lattice whose pitch sets the density.

It sits after synthesis and the edits of the normalised texture, before display: the RenderGrains
action (`texture_actions`) calls :func:`render_grains`. The grain masks are `grains.grain_mask`'s;
this module owns the *lattice*: where each point's grain goes.

Geometry. Point (r, c) of an H×W texture owns the cell of ``pitch_y × pitch_x`` pixels at
(r·pitch_y, c·pitch_x + offset_r), where ``offset_r`` is ``row_offset`` on odd rows and 0 on even
ones (a honeycomb: alternate rows shifted by half a pitch). Its grain's box is centred on the cell:
the mask's cell (h // 2, w // 2) lands on the cell's (pitch_y // 2, pitch_x // 2), so at the
natural pitch the boxes tile the picture even for a lopsided drawn grain (for a symmetric grain
that cell holds its centre of gravity, as `grains.anchor` would place it). The picture is
(H·pitch_y) × (W·pitch_x) pixels and is a torus: what passes one edge comes back on the other, so
a tileable texture stays tileable.

Density. The *natural* pitch makes grains touch: the mask's box on a grid; for hexagons, the
honeycomb pitch with no hole between grains and the least overlap (found once per mask). The
explosion factors stretch it along x and y (blank space between grains, §5.3.2); compression
shrinks it until grains overlap, in both directions or along each axis by its own amount (like
explosion): pitch = round(natural · explosion · (1 − compression)) on each axis, at least 1. Where grains overlap, the *overlap rule* decides: ``last`` (the
grain drawn later, in scan order, wins), ``max`` or ``min`` level. Level 0 is the background: its
points draw no grain, so they never hide a neighbour's.

A primitive per level (§5.3: a point's state selects its grain). Each level may have its own
grain; the others use the texture's grain. The lattice is then the one of all those grains
stacked on their centres (their union), so at the natural pitch the largest ones touch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numba
import numpy as np

from ..errors import Cancelled, InputError
from ..paint.grains import GrainType, grain_mask, parse_grain_spec

OVERLAP_RULES = ("last", "max", "min")
LATTICES = ("auto", "grid", "honeycomb")
MAX_EXPLOSION = 8.0
MAX_COMPRESSION = 0.9
MAX_PIXELS = 2**26                 # the largest picture a render may make (the canvas limit)
MAX_SIDE = 16384
MAX_GRAIN = 64                     # the largest grain, pixels (RenderGrains' size)
MAX_LEVEL = 15


@dataclass(frozen=True)
class Lattice:
    """Where grains go: the cell pitch (pixels) and the shift of odd rows."""

    pitch_y: int
    pitch_x: int
    row_offset: int = 0

    def shape(self, texture_shape: tuple[int, int]) -> tuple[int, int]:
        """The rendered picture's shape for a texture of ``texture_shape`` points."""
        h, w = texture_shape
        return h * self.pitch_y, w * self.pitch_x


# -- the lattice -----------------------------------------------------------------------------------

def natural_lattice(mask, honeycomb: bool = False) -> Lattice:
    """The pitch at which grains of this mask touch (explosion 1, no compression).

    On a grid that is the mask's box. On a honeycomb (odd rows shifted by half the pitch) it is
    the pitch that leaves no hole between grains with the least overlap — for a hexagon, the
    cells of a beehive, continuous in both directions (§5.3.1).
    """
    mask = np.asarray(mask, dtype=bool)
    if not honeycomb:
        return Lattice(*mask.shape)
    return _honeycomb(mask.tobytes(), mask.shape)


@lru_cache(maxsize=64)
def _honeycomb(data: bytes, shape: tuple[int, int]) -> Lattice:
    mask = np.frombuffer(data, dtype=bool).reshape(shape)
    h, w = shape
    ys, xs = np.nonzero(mask)
    best = None
    for px in range(max(1, w - 2), w + 2):
        for py in range(max(1, h // 2), h + 1):
            count = np.zeros((2 * py, px), np.int32)      # one period: two rows, one column
            for top, left in ((0, 0), (py, px // 2)):
                np.add.at(count, ((top + ys) % (2 * py), (left + xs) % px), 1)
            if count.min() == 0:
                continue
            key = (int((count > 1).sum()) / count.size, -py * px)
            if best is None or key < best[0]:
                best = (key, Lattice(py, px, px // 2))
    if best is None:                   # cannot happen for a convex grain; a grid never fails
        return Lattice(h, w, w // 2)
    return best[1]


def density_lattice(natural: Lattice, *, explosion_x: float = 1.0, explosion_y: float = 1.0,
                    compression: float = 0.0, compression_x: float | None = None) -> Lattice:
    """The natural pitch stretched by the explosion factors and shrunk by the compression:
    ``compression`` down, and across too unless ``compression_x`` gives its own amount.

    >>> density_lattice(Lattice(8, 8), compression=0.5, compression_x=0.25)
    Lattice(pitch_y=4, pitch_x=6, row_offset=0)
    """
    if not (1.0 <= explosion_x <= MAX_EXPLOSION and 1.0 <= explosion_y <= MAX_EXPLOSION):
        raise InputError(f"explosion factors must lie in 1..{MAX_EXPLOSION:g} "
                         f"(got {explosion_x:g} across, {explosion_y:g} down)")
    across = compression if compression_x is None else compression_x
    for value in (compression, across):
        if not 0.0 <= value <= MAX_COMPRESSION:
            raise InputError(f"compression must lie in 0..{MAX_COMPRESSION:g}, got {value:g}")
    py = max(1, _round(natural.pitch_y * explosion_y * (1.0 - compression)))
    px = max(1, _round(natural.pitch_x * explosion_x * (1.0 - across)))
    return Lattice(py, px, px // 2 if natural.row_offset else 0)


def _round(x: float) -> int:
    return math.floor(x + 0.5 + 1e-9)


def grain_lattice(mask, *, shape: str = "square", lattice: str = "auto", explosion_x=1.0,
                  explosion_y=1.0, compression=0.0, compression_x=None) -> Lattice:
    """The lattice for a grain mask: ``auto`` is a honeycomb for hexagons and a grid otherwise."""
    if lattice not in LATTICES:
        raise InputError(f"lattice must be one of {', '.join(LATTICES)}, got {lattice!r}")
    honeycomb = lattice == "honeycomb" or (lattice == "auto" and shape == "hexagon")
    return density_lattice(natural_lattice(mask, honeycomb), explosion_x=explosion_x,
                           explosion_y=explosion_y, compression=compression,
                           compression_x=compression_x)


def grain_union(masks) -> np.ndarray:
    """The grains stacked as they are drawn, each box's cell (h // 2, w // 2) on one point:
    the mask the lattice of a per-level rendering is made for (one grain: that grain)."""
    masks = [np.asarray(m, dtype=bool) for m in masks]
    if len(masks) == 1:
        return masks[0]
    top = max(m.shape[0] // 2 for m in masks)
    left = max(m.shape[1] // 2 for m in masks)
    height = top + max(m.shape[0] - m.shape[0] // 2 for m in masks)
    width = left + max(m.shape[1] - m.shape[1] // 2 for m in masks)
    union = np.zeros((height, width), bool)
    for m in masks:
        t, l_ = top - m.shape[0] // 2, left - m.shape[1] // 2
        union[t:t + m.shape[0], l_:l_ + m.shape[1]] |= m
    return union


def parse_level_grains(text: str | None) -> dict[int, GrainType]:
    """The per-level grains of a text such as ``1: circle 5, 3: hexagon 8 angle=30``: level,
    colon, grain (`grains.parse_grain_spec`), entries separated by commas. Level 0 is the
    background, which draws no grain.

    >>> {k: g.shape for k, g in parse_level_grains("2: circle 5, 1: square 3").items()}
    {1: 'square', 2: 'circle'}
    """
    table: dict[int, GrainType] = {}
    for entry in (text or "").split(","):
        if not entry.strip():
            continue
        level, colon, spec = entry.partition(":")
        level = level.strip()
        if not colon or not level.isdecimal():
            raise InputError(f"a per-level grain is 'level: shape size', e.g. '2: circle 5', "
                             f"got {entry.strip()[:40]!r}")
        level = int(level)
        if not 1 <= level <= MAX_LEVEL or level in table:
            raise InputError(f"per-level grains are for levels 1..{MAX_LEVEL}, each once "
                             f"(level 0 is the background: it draws no grain), got {level}")
        grain = parse_grain_spec(spec)
        if grain.size > MAX_GRAIN:
            raise InputError(f"the grain of level {level} is {grain.size} px: at most "
                             f"{MAX_GRAIN}")
        table[level] = grain
    return dict(sorted(table.items()))


# -- drawing ---------------------------------------------------------------------------------------

def render_grains(levels, mask, lattice: Lattice, overlap: str = "last", *, level_masks=None,
                  progress=None, cancel=None) -> np.ndarray:
    """Draw every non-background point of ``levels`` as the grain ``mask`` on ``lattice`` (or,
    for a level of ``level_masks``, as that level's grain).

    With ``progress`` (called with 0..1) or ``cancel`` (Cancelled when it returns True), the
    rows are drawn in bands, in the same order, so the picture is the same either way.

    >>> render_grains(np.array([[1, 2], [0, 3]]), np.ones((2, 2), bool), Lattice(2, 2))
    array([[1, 1, 2, 2],
           [1, 1, 2, 2],
           [0, 0, 3, 3],
           [0, 0, 3, 3]], dtype=uint8)
    """
    levels = np.asarray(levels)
    mask = np.asarray(mask, dtype=bool)
    if levels.ndim != 2 or levels.dtype.kind not in "ui":
        raise InputError("grains are drawn from a 2-D matrix of levels")
    if mask.ndim != 2 or not mask.any():
        raise InputError("a grain needs at least one point")
    if overlap not in OVERLAP_RULES:
        raise InputError(f"overlap rule must be one of {', '.join(OVERLAP_RULES)}, "
                         f"got {overlap!r}")
    out_shape = check_size(levels.shape, lattice)
    out = np.zeros(out_shape, dtype=np.uint8)
    if not levels.size:
        return out
    src = np.ascontiguousarray(levels, dtype=np.uint8)
    dy, dx, starts = _offsets(mask, level_masks or {}, int(src.max()), lattice)
    h = src.shape[0]
    band = h if progress is None and cancel is None else max(1, -(-h // 100))   # ≤ 100 bands
    for r0 in range(0, h, band):
        if cancel is not None and cancel():
            raise Cancelled("grain rendering cancelled")
        _draw(src, dy, dx, starts, lattice.pitch_y, lattice.pitch_x, lattice.row_offset,
              OVERLAP_RULES.index(overlap), out, r0, min(h, r0 + band))
        if progress is not None:
            progress(min(h, r0 + band) / h)
    return out


def _offsets(mask, level_masks: dict, top_level: int, lattice: Lattice):
    """Each level's grain points relative to its cell, one after another: level v's are
    ``dy[starts[v]:starts[v + 1]]`` (and dx); a grain's box cell (h // 2, w // 2) lands on the
    cell's (pitch_y // 2, pitch_x // 2)."""
    dys, dxs, starts = [], [], [0]
    for v in range(max(top_level, max(level_masks, default=0)) + 1):
        m = np.asarray(level_masks.get(v, mask), dtype=bool)
        if m.ndim != 2 or not m.any():
            raise InputError("a grain needs at least one point")
        ys, xs = np.nonzero(m)
        dys.append(ys - m.shape[0] // 2 + lattice.pitch_y // 2)
        dxs.append(xs - m.shape[1] // 2 + lattice.pitch_x // 2)
        starts.append(starts[-1] + len(ys))
    return (np.concatenate(dys).astype(np.int64), np.concatenate(dxs).astype(np.int64),
            np.array(starts, np.int64))


def render_cost(texture_shape: tuple[int, int], mask, lattice: Lattice) -> float:
    """A rough cost of a render in grain points drawn plus pixels cleared (for the GUI to
    decide whether to show progress): about 0.3 s per 10^8 on one core."""
    h, w = texture_shape
    oh, ow = lattice.shape(texture_shape)
    return float(h * w * int(np.count_nonzero(mask)) + oh * ow)


def check_size(shape: tuple[int, int], lattice: Lattice) -> tuple[int, int]:
    """The rendered shape, refused (InputError) beyond the canvas limits."""
    oh, ow = lattice.shape(shape)
    if oh > MAX_SIDE or ow > MAX_SIDE or oh * ow > MAX_PIXELS:
        raise InputError(f"grains of {lattice.pitch_x}×{lattice.pitch_y} pixels on a "
                         f"{shape[1]}×{shape[0]} texture make a {ow}×{oh} picture, more than "
                         f"the largest canvas ({MAX_SIDE} a side, {MAX_PIXELS // 2**20} M "
                         "points): use smaller grains, less explosion or a smaller texture")
    return oh, ow


@numba.njit(cache=True, nogil=True)
def _draw(levels, dy, dx, starts, py, px, row_offset, rule, out, r0, r1):   # pragma: no cover
    h, w = levels.shape
    oh, ow = out.shape
    for r in range(r0, r1):
        shift = row_offset if r % 2 == 1 else 0
        top = r * py
        for c in range(w):
            v = levels[r, c]
            if v == 0:
                continue
            left = c * px + shift
            for k in range(starts[v], starts[v + 1]):
                y = (top + dy[k]) % oh
                x = (left + dx[k]) % ow
                if rule == 0:
                    out[y, x] = v
                elif rule == 1:
                    if v > out[y, x]:
                        out[y, x] = v
                else:
                    old = out[y, x]
                    if old == 0 or v < old:
                        out[y, x] = v
    return out


# -- one call for the Action and the dock ----------------------------------------------------------

def grain_of(shape: str = "square", size: int = 8, *, aspect: float = 1.0, sides: int = 6,
             angle: float = 0.0, bitmap: str | None = None) -> np.ndarray:
    """The grain mask (`grains.grain_mask`), named here so callers need one import."""
    return grain_mask(shape, size, aspect=aspect, sides=sides, angle=angle, bitmap=bitmap)


def render(levels, shape: str = "square", size: int = 8, *, aspect: float = 1.0, sides: int = 6,
           angle: float = 0.0, bitmap: str | None = None, explosion_x: float = 1.0,
           explosion_y: float = 1.0, compression: float = 0.0, compression_x: float | None = None,
           overlap: str = "last", lattice: str = "auto",
           level_grains: str | None = None) -> np.ndarray:
    """A texture drawn with grains of one shape, size and orientation at one density — or, for
    the levels ``level_grains`` lists (see :func:`parse_level_grains`), their own grains."""
    mask = grain_of(shape, size, aspect=aspect, sides=sides, angle=angle, bitmap=bitmap)
    level_masks = {v: g.mask() for v, g in parse_level_grains(level_grains).items()}
    lat = grain_lattice(grain_union([mask, *level_masks.values()]), shape=shape,
                        lattice=lattice, explosion_x=explosion_x, explosion_y=explosion_y,
                        compression=compression, compression_x=compression_x)
    return render_grains(levels, mask, lat, overlap, level_masks=level_masks)
