"""Grains (thesis §3.3.3a, §5.3.1): the small shapes a texture is made of, their types and library.

A grain is a bool mask with a centre of gravity; the grain tool places grains by that centre, the
brushes use the same masks as footprints, and grain rendering draws every point of a normalised
texture with one. A GrainType is a grain's plain-JSON description; the GrainLibrary keeps the
standard grains and the user's own (in the user data folder).

Conventions: masks are bool (h, w), row 0 on top; ``size`` is the grain's diameter in points;
``angle`` turns it counter-clockwise on screen, in degrees. A point belongs to a grain when the
centre of its cell lies inside the shape or on its border (closed shapes), so small grains are
exact and symmetric: the same on every machine.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..errors import FormatError, InputError
from ..userdata import ITEM_ERRORS, data_dir, read_library, write_library

SHAPES = ("square", "rectangle", "circle", "diamond", "hexagon", "polygon", "line", "bitmap")
MAX_GRAIN_SIZE = 256
MAX_BITMAP_SIDE = 64
MIN_ASPECT, MAX_ASPECT = 1 / 16, 16.0
MIN_SIDES, MAX_SIDES = 3, 64
MAX_LEVEL = 15
MAX_NAME = 80
LIBRARY_FILE = "grains.json"
LIBRARY_KIND = "texeditor-grains"
_EPS = 1e-9
_BITMAP = re.compile(r"^[0-9a-fA-F]+(/[0-9a-fA-F]+)*$")

__all__ = ["SHAPES", "grain_mask", "bitmap_levels", "parse_bitmap", "format_bitmap",
           "centre_of_gravity", "anchor", "stamp_points", "GrainType", "grain_spec",
           "parse_grain_spec", "standard_grains", "GrainLibrary"]


# -- shapes ---------------------------------------------------------------------------------------

def grain_mask(shape: str, size: int, *, aspect: float = 1.0, sides: int = 6, angle: float = 0.0,
               bitmap: str | None = None) -> np.ndarray:
    """The points of one grain, cropped to its bounding box.

    ``square``, ``rectangle`` (``size`` long, ``size * aspect`` high), ``circle`` (an ellipse
    when ``aspect`` ≠ 1), ``diamond``, ``hexagon`` (pointy top, for a honeycomb of offset rows),
    ``polygon`` (regular, ``sides`` vertices, one at the top; ``size`` is the circumscribed
    circle's diameter), ``line`` (``size`` points along the axis, one thick, no gaps) and
    ``bitmap`` (a drawn grain, see :func:`parse_bitmap`, scaled so its longer side is ``size``).

    >>> grain_mask("circle", 4).astype(int)
    array([[0, 1, 1, 0],
           [1, 1, 1, 1],
           [1, 1, 1, 1],
           [0, 1, 1, 0]])
    >>> grain_mask("diamond", 5).astype(int)
    array([[0, 0, 1, 0, 0],
           [0, 1, 1, 1, 0],
           [1, 1, 1, 1, 1],
           [0, 1, 1, 1, 0],
           [0, 0, 1, 0, 0]])
    >>> grain_mask("line", 4, angle=90).T.astype(int)
    array([[1, 1, 1, 1]])
    """
    shape, size, aspect, sides, angle = _check(shape, size, aspect, sides, angle)
    if shape == "bitmap":
        return bitmap_levels(bitmap, size, angle) != 0
    return _geometric(shape, size, aspect, sides, angle).copy()


def _check(shape, size, aspect, sides, angle):
    if shape not in SHAPES:
        raise InputError(f"grain shape must be one of {', '.join(SHAPES)}, got {shape!r}")
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) \
            or not 1 <= size <= MAX_GRAIN_SIZE:
        raise InputError(f"grain size must be a whole number of points 1..{MAX_GRAIN_SIZE}, "
                         f"got {size!r}")
    aspect, angle = float(aspect), float(angle)
    if not (math.isfinite(aspect) and MIN_ASPECT <= aspect <= MAX_ASPECT):
        raise InputError(f"grain aspect must be {MIN_ASPECT:g}..{MAX_ASPECT:g}, got {aspect!r}")
    if not math.isfinite(angle):
        raise InputError(f"grain angle must be a number of degrees, got {angle!r}")
    if isinstance(sides, bool) or not isinstance(sides, (int, np.integer)) \
            or not MIN_SIDES <= sides <= MAX_SIDES:
        raise InputError(f"a polygon has {MIN_SIDES}..{MAX_SIDES} sides, got {sides!r}")
    return shape, int(size), aspect, int(sides), angle % 360.0


def _outline(shape: str, size: int, aspect: float, sides: int) -> np.ndarray | None:
    """The vertices (x right, y up) of a polygonal shape, counter-clockwise; None for circles."""
    a = size / 2
    b = a * aspect
    if shape == "square":
        b = a
    if shape in ("square", "rectangle"):
        return np.array([(a, -b), (a, b), (-a, b), (-a, -b)])
    if shape == "diamond":
        return np.array([(a, 0.0), (0.0, b), (-a, 0.0), (0.0, -b)])
    if shape in ("hexagon", "polygon"):
        n = 6 if shape == "hexagon" else sides
        t = np.pi / 2 + 2 * np.pi * np.arange(n) / n
        return np.stack([a * np.cos(t), b * np.sin(t)], axis=1)
    return None


@lru_cache(maxsize=512)
def _geometric(shape, size, aspect, sides, angle) -> np.ndarray:
    cos, sin = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    if shape == "line":
        return _line(size, cos, sin)
    a = size / 2
    b = a * aspect
    vertices = _outline(shape, size, aspect, sides)
    if vertices is None:                                  # an ellipse
        hx = math.hypot(a * cos, b * sin)
        hy = math.hypot(a * sin, b * cos)
    else:
        vertices = vertices @ np.array([[cos, sin], [-sin, cos]])   # turned counter-clockwise
        hx, hy = np.abs(vertices).max(axis=0)
    # an odd extent puts the centre on a cell, an even one on a cell corner
    nx, ny = max(1, math.floor(2 * hx + 0.5)), max(1, math.floor(2 * hy + 0.5))
    x = np.arange(nx) - (nx - 1) / 2
    y = (ny - 1) / 2 - np.arange(ny)[:, None]
    if vertices is None:
        u, v = x * cos + y * sin, -x * sin + y * cos
        inside = (u / a) ** 2 + (v / b) ** 2 <= 1 + _EPS
    else:
        inside = np.ones((ny, nx), bool)
        for p, q in zip(vertices, np.roll(vertices, -1, axis=0)):
            dx, dy = q - p
            cross = dx * (y - p[1]) - dy * (x - p[0])
            inside &= cross >= -_EPS * math.hypot(dx, dy)
    mask = _crop(inside)
    mask.flags.writeable = False
    return mask


def _line(size: int, cos: float, sin: float) -> np.ndarray:
    """A one-point-thick segment of ``size`` cells along the axis: the digital line between its
    end cells (skimage's Bresenham), so it has no gaps and no doubled cells at any angle."""
    from skimage.draw import line
    dx, dy = round(abs((size - 1) * cos)), round(abs((size - 1) * sin))
    mask = np.zeros((dy + 1, dx + 1), bool)
    rising = (cos >= 0) == (sin >= 0)          # up to the right on screen: row 0 at the top
    rr, cc = line(dy if rising else 0, 0, 0 if rising else dy, dx)
    mask[rr, cc] = True
    mask.flags.writeable = False
    return mask


def _crop(mask: np.ndarray) -> np.ndarray:
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    if not len(rows):                       # a shape thinner than a point keeps one
        return np.ones((1, 1), bool)
    return np.ascontiguousarray(mask[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1])


# -- drawn grains ---------------------------------------------------------------------------------

def parse_bitmap(text) -> np.ndarray:
    """A drawn grain from its text: rows of hex digits (levels 0..15, 0 = empty) separated by
    ``/`` (or given as a list of rows).

    >>> parse_bitmap("010/121/010")
    array([[0, 1, 0],
           [1, 2, 1],
           [0, 1, 0]], dtype=uint8)
    """
    if isinstance(text, (list, tuple)):
        text = "/".join(str(row) for row in text)
    if not isinstance(text, str) or len(text) > MAX_BITMAP_SIDE * (MAX_BITMAP_SIDE + 1):
        raise InputError("a drawn grain is rows of hex digits separated by '/'")
    text = text.strip().replace("\n", "/")
    if not _BITMAP.match(text):
        raise InputError(f"a drawn grain is rows of hex digits (levels 0..f) separated by '/', "
                         f"got {text[:40]!r}")
    rows = text.split("/")
    if len(rows) > MAX_BITMAP_SIDE or len({len(r) for r in rows}) != 1 \
            or len(rows[0]) > MAX_BITMAP_SIDE:
        raise InputError(f"a drawn grain's rows must all have the same length, at most "
                         f"{MAX_BITMAP_SIDE}×{MAX_BITMAP_SIDE} points")
    array = np.array([[int(ch, 16) for ch in row] for row in rows], np.uint8)
    if not array.any():
        raise InputError("a drawn grain needs at least one point (a digit other than 0)")
    return array


def format_bitmap(levels) -> str:
    """The text of a drawn grain (the inverse of parse_bitmap), cropped to its points."""
    levels = np.asarray(levels)
    if levels.ndim != 2 or not levels.size or levels.min() < 0 or levels.max() > MAX_LEVEL:
        raise InputError("a drawn grain is a 2-D matrix of levels 0..15")
    if not levels.any():
        raise InputError("a drawn grain needs at least one point (a level other than 0)")
    levels = _crop_levels(levels.astype(np.uint8))
    return "/".join("".join("0123456789abcdef"[v] for v in row) for row in levels)


def _crop_levels(levels: np.ndarray) -> np.ndarray:
    rows, cols = np.flatnonzero(levels.any(axis=1)), np.flatnonzero(levels.any(axis=0))
    return levels[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]


def bitmap_levels(bitmap, size: int | None = None, angle: float = 0.0) -> np.ndarray:
    """A drawn grain's levels (0 = not part of it), scaled so its longer side is ``size``
    (nearest neighbour) and turned by ``angle`` (quarter turns exactly)."""
    if bitmap is None:
        raise InputError("a bitmap grain needs its drawing (rows of hex digits)")
    levels = parse_bitmap(bitmap)
    natural = max(levels.shape)
    size = natural if size is None else size
    key = (format_bitmap(levels), int(size), float(angle) % 360.0)
    return _bitmap(*key).copy()


@lru_cache(maxsize=128)
def _bitmap(text: str, size: int, angle: float) -> np.ndarray:
    levels = parse_bitmap(text)
    h, w = levels.shape
    f = size / max(h, w)
    if f != 1:
        rows = np.minimum(((np.arange(max(1, round(h * f))) + 0.5) / f).astype(int), h - 1)
        cols = np.minimum(((np.arange(max(1, round(w * f))) + 0.5) / f).astype(int), w - 1)
        levels = levels[rows[:, None], cols]
    quarter, rest = divmod(angle, 90.0)
    if rest == 0:
        levels = np.rot90(levels, int(quarter))
    else:
        from skimage.transform import rotate
        levels = rotate(levels, angle, resize=True, order=0, preserve_range=True,
                        mode="constant", cval=0).round().astype(np.uint8)
    if not levels.any():                     # a drawing turned to nothing keeps one point
        levels = np.full((1, 1), parse_bitmap(text).max(), np.uint8)
    out = np.ascontiguousarray(_crop_levels(levels))
    out.flags.writeable = False
    return out


# -- placing a grain by its centre of gravity -----------------------------------------------------

def centre_of_gravity(mask) -> tuple[float, float]:
    """The mean (row, col) of a grain's points, in the mask's own coordinates.

    >>> centre_of_gravity(grain_mask("square", 4))
    (1.5, 1.5)
    """
    rows, cols = np.nonzero(np.asarray(mask))
    if not len(rows):
        raise InputError("an empty grain has no centre of gravity")
    return float(rows.mean()), float(cols.mean())


def anchor(mask) -> tuple[int, int]:
    """The cell of the mask that lands on the pointed cell: the grain's point nearest to its
    centre of gravity (below, then right, on ties), so the pointed cell is always painted.

    >>> anchor(grain_mask("square", 3)), anchor(grain_mask("square", 4))
    ((1, 1), (2, 2))
    >>> anchor(grain_mask("line", 5, angle=45))          # 4 cells: not the empty (2, 2)
    (2, 1)
    """
    return _anchor(np.ascontiguousarray(mask, dtype=bool).tobytes(), np.shape(mask))


@lru_cache(maxsize=1024)
def _anchor(data: bytes, shape) -> tuple[int, int]:
    mask = np.frombuffer(data, bool).reshape(shape)
    cy, cx = centre_of_gravity(mask)
    ys, xs = np.nonzero(mask)
    d2 = (ys - cy) ** 2 + (xs - cx) ** 2
    near = d2 <= d2.min() + _EPS
    k = np.lexsort((xs[near], ys[near]))[-1]          # the last in scan order among the nearest
    return int(ys[near][k]), int(xs[near][k])


def stamp_points(mask, centre, canvas_shape, *, wrap: bool = False):
    """The canvas points of a grain placed with its centre of gravity at ``centre`` (row, col).

    Returns ``(rows, cols, keep)``: ``keep`` selects, among the mask's points in scan order,
    those that land on the canvas (all of them with ``wrap``, which folds them back in).
    """
    mask = np.asarray(mask, dtype=bool)
    ys, xs = np.nonzero(mask)
    ay, ax = anchor(mask)
    rows = ys + (int(centre[0]) - ay)
    cols = xs + (int(centre[1]) - ax)
    h, w = canvas_shape
    if wrap:
        return rows % h, cols % w, np.ones(len(rows), bool)
    keep = (rows >= 0) & (rows < h) & (cols >= 0) & (cols < w)
    return rows[keep], cols[keep], keep


# -- grain types ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class GrainType:
    """A grain's description: plain values, JSON in the library and parameters of PlaceGrains.

    ``level`` is the level it is painted with (None: the level chosen when placing it, the
    palette's current one). A drawn grain (``shape="bitmap"``) with ``own_levels`` keeps the
    levels of its drawing (a small multi-level grain); otherwise its points take one level.
    """

    name: str = "Grain"
    shape: str = "square"
    size: int = 3
    aspect: float = 1.0
    sides: int = 6
    angle: float = 0.0
    level: int | None = None
    own_levels: bool = False
    bitmap: str | None = None

    def __post_init__(self):
        if not isinstance(self.name, str) or not 0 < len(self.name.strip()) <= MAX_NAME:
            raise InputError(f"a grain's name is 1..{MAX_NAME} characters")
        _check(self.shape, self.size, self.aspect, self.sides, self.angle)
        object.__setattr__(self, "aspect", float(self.aspect))
        object.__setattr__(self, "angle", float(self.angle))
        if self.level is not None and (isinstance(self.level, bool) or not isinstance(
                self.level, (int, np.integer)) or not 0 <= self.level <= MAX_LEVEL):
            raise InputError(f"a grain's level is 0..{MAX_LEVEL} or none, got {self.level!r}")
        if not isinstance(self.own_levels, (bool, np.bool_)):
            raise InputError("own_levels must be true or false")
        if self.shape == "bitmap":
            object.__setattr__(self, "bitmap", format_bitmap(parse_bitmap(self.bitmap)))
        elif self.bitmap is not None:
            raise InputError("only a bitmap grain has a drawing")

    def mask(self) -> np.ndarray:
        return grain_mask(self.shape, self.size, aspect=self.aspect, sides=self.sides,
                          angle=self.angle, bitmap=self.bitmap)

    def values(self, level: int) -> np.ndarray:
        """The level of each point of the grain's box (meaningful where mask() is True);
        ``level`` is used when the grain has no level of its own."""
        if self.shape == "bitmap" and self.own_levels and self.level is None:
            return bitmap_levels(self.bitmap, self.size, self.angle)
        painted = self.level if self.level is not None else level
        return np.full(self.mask().shape, painted, np.uint8)

    def max_level(self, level: int) -> int:
        """The highest level the grain paints (to check it against the document's G)."""
        return int(self.values(level)[self.mask()].max())

    def replace(self, **changes) -> "GrainType":
        return dataclasses.replace(self, **changes)

    def to_json(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_json(cls, obj) -> "GrainType":
        """A grain from its JSON object, every field checked (InputError names the problem)."""
        if not isinstance(obj, dict):
            raise InputError("a grain must be a JSON object")
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(obj) - names)
        if unknown:
            raise InputError(f"a grain has unexpected fields {unknown}")
        for key in ("aspect", "angle"):
            if key in obj and (isinstance(obj[key], bool)
                               or not isinstance(obj[key], (int, float))):
                raise InputError(f"a grain's {key} must be a number")
        return cls(**obj)


# -- a grain's shape as a short text (the per-vertex and per-level grains of a log) -----------------

_SPEC_KEYS = {"aspect": float, "sides": int, "angle": float, "bitmap": str}


def grain_spec(grain: GrainType) -> str:
    """A grain's shape in a few words, its defaults left out: what a log keeps for each grain of
    a dominance tree or of a per-level table (the inverse of :func:`parse_grain_spec`).

    >>> grain_spec(GrainType(shape="polygon", size=9, sides=5, angle=30.0))
    'polygon 9 sides=5 angle=30'
    """
    words = [grain.shape, str(grain.size)]
    default = GrainType()
    for key in _SPEC_KEYS:
        value = getattr(grain, key)
        if value != getattr(default, key):
            words.append(f"{key}={_number(value) if isinstance(value, float) else value}")
    return " ".join(words)


def _number(value: float) -> str:
    short = f"{value:g}"
    return short if float(short) == value else repr(value)


def parse_grain_spec(text: str) -> GrainType:
    """The grain of a text such as ``circle 5`` or ``rectangle 6 aspect=0.5 angle=30``: the
    shape, the size in points, then any of aspect, sides, angle and bitmap as key=value.

    >>> parse_grain_spec("circle 9 aspect=0.5").mask().shape
    (5, 9)
    """
    if not isinstance(text, str):
        raise InputError("a grain is written as its shape and size, e.g. 'circle 5'")
    words = text.split()
    if len(words) < 2 or not words[1].isdecimal():
        raise InputError(f"a grain is written as its shape and size, e.g. 'circle 5', "
                         f"got {text.strip()[:40]!r}")
    fields = {}
    for word in words[2:]:
        key, sep, value = word.partition("=")
        if not sep or key not in _SPEC_KEYS or key in fields:
            raise InputError(f"{word[:40]!r} in grain {text.strip()[:40]!r}: after the size come "
                             f"{', '.join(_SPEC_KEYS)} as key=value, each once")
        try:
            fields[key] = _SPEC_KEYS[key](value)
        except ValueError:
            raise InputError(f"{key} of grain {text.strip()[:40]!r} must be a number, "
                             f"got {value[:20]!r}") from None
    return GrainType("Grain", words[0], int(words[1]), **fields)


def standard_grains() -> list[GrainType]:
    """The grains every user has (thesis §5.3.1's shapes, a few sizes, two drawn grains)."""
    g = GrainType
    return [
        g("Point", "square", 1),
        g("Square 3", "square", 3),
        g("Square 5", "square", 5),
        g("Rectangle 6×3", "rectangle", 6, aspect=0.5),
        g("Circle 5", "circle", 5),
        g("Circle 9", "circle", 9),
        g("Ellipse 9×5, 30°", "circle", 9, aspect=5 / 9, angle=30.0),
        g("Diamond 7", "diamond", 7),
        g("Hexagon 8", "hexagon", 8),
        g("Hexagon 12", "hexagon", 12),
        g("Pentagon 9", "polygon", 9, sides=5),
        g("Needle 9, 45°", "line", 9, angle=45.0),
        g("Cross 5", "bitmap", 5, bitmap="00100/00100/11111/00100/00100"),
        g("Pebble 6", "bitmap", 6, own_levels=True,
          bitmap="011110/122221/123321/123321/122221/011110"),
    ]


class GrainLibrary:
    """The standard grains and the user's own, saved as JSON in the user data folder."""

    def __init__(self, folder: str | Path | None = None):
        self.path = Path(folder if folder is not None else data_dir()) / LIBRARY_FILE

    def standard(self) -> list[GrainType]:
        return standard_grains()

    def user(self) -> list[GrainType]:
        """The user's grains (a damaged file is a FormatError naming it and the grain)."""
        grains = []
        for k, item in enumerate(read_library(self.path, LIBRARY_KIND)):
            try:
                grains.append(GrainType.from_json(item))
            except ITEM_ERRORS as exc:
                raise FormatError(f"{self.path}: grain {k + 1}: {exc}") from None
        return grains

    def all(self) -> list[GrainType]:
        return self.standard() + self.user()

    def get(self, name: str) -> GrainType:
        for grain in self.all():
            if grain.name == name:
                return grain
        raise InputError(f"there is no grain called {name!r} in the library")

    def is_standard(self, name: str) -> bool:
        return any(g.name == name for g in self.standard())

    def save(self, grain: GrainType) -> None:
        """Add a user grain, or replace the user grain of the same name."""
        if self.is_standard(grain.name):
            raise InputError(f"{grain.name!r} is a standard grain: save yours under another name")
        grains = [g for g in self.user() if g.name != grain.name] + [grain]
        write_library(self.path, LIBRARY_KIND, [g.to_json() for g in grains])

    def remove(self, name: str) -> None:
        if self.is_standard(name):
            raise InputError(f"{name!r} is a standard grain: it cannot be removed")
        grains = self.user()
        if not any(g.name == name for g in grains):
            raise InputError(f"there is no user grain called {name!r}")
        write_library(self.path, LIBRARY_KIND,
                      [g.to_json() for g in grains if g.name != name])
