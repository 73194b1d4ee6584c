"""Brushes (thesis §3.2.2, Fig. 3.2): a block of points of a chosen size, shape and distribution,
painted along a stroke as a line of dabs or a cloud of points.

Between the pointer and the document: the brush tool feeds pointer positions to a StrokePainter,
which places dabs along the path at the brush's spacing (fast strokes have no gaps) and returns
the points each dab paints — for the live preview, and identically when the Stroke action replays
the same points. Every random choice comes from the stroke's seed.

Conventions: points are (row, col); a dab's centre is the pointer cell, on which the brush's
footprint lands by its centre of gravity (as grains do, see `grains.anchor`).
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import FormatError, InputError
from .grains import MAX_GRAIN_SIZE, anchor, grain_mask, parse_bitmap, format_bitmap
from ..userdata import ITEM_ERRORS, data_dir, read_library, write_library

BRUSH_SHAPES = ("square", "disc", "diamond", "line", "bitmap")
DISTRIBUTIONS = ("solid", "cloud")
MAX_BRUSH_SIZE = MAX_GRAIN_SIZE
MAX_CONCENTRATION = 16.0
MIN_SPACING, MAX_SPACING = 0.05, 10.0
MAX_DABS = 2**20          # dabs (or grains) one stroke may place: refused beyond, never cut short
MAX_LEVEL = 15
PRESETS_FILE = "brushes.json"
PRESETS_KIND = "texeditor-brushes"
_LEVELS = re.compile(r"^\s*\d{1,2}(\s*[,\s]\s*\d{1,2})*\s*$")
_GRAIN_SHAPE = {"disc": "circle"}

__all__ = ["BRUSH_SHAPES", "DISTRIBUTIONS", "Brush", "Footprint", "parse_levels", "PathWalker",
           "StrokePainter", "paint_stroke", "last_wins", "standard_brushes", "BrushLibrary"]


# -- the brush ------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Footprint:
    """A dab: the points' offsets from the pointer cell, and for a cloud each point's chance."""

    rows: np.ndarray
    cols: np.ndarray
    chance: np.ndarray | None        # None: solid, every point painted

    def __len__(self) -> int:
        return len(self.rows)


@dataclass(frozen=True)
class Brush:
    """A brush preset: plain values (JSON in the library, parameters of the Stroke action).

    ``distribution`` is ``solid`` (every point of the footprint) or ``cloud`` (a spray: each
    point painted with probability ``density``; ``concentration`` > 0 gathers the points toward
    the centre, keeping the mean density). ``spacing`` is the distance between dabs as a
    fraction of the size (at least one point).
    """

    name: str = "Round 5"
    size: int = 5
    shape: str = "disc"
    angle: float = 0.0
    bitmap: str | None = None
    distribution: str = "solid"
    density: float = 0.25
    concentration: float = 0.0
    spacing: float = 0.25

    def __post_init__(self):
        if not isinstance(self.name, str) or len(self.name) > 80:
            raise InputError("a brush's name is a text of at most 80 characters")
        if self.shape not in BRUSH_SHAPES:
            raise InputError(f"brush shape must be one of {', '.join(BRUSH_SHAPES)}, "
                             f"got {self.shape!r}")
        if self.distribution not in DISTRIBUTIONS:
            raise InputError(f"brush distribution must be solid or cloud, "
                             f"got {self.distribution!r}")
        if isinstance(self.size, bool) or not isinstance(self.size, (int, np.integer)) \
                or not 1 <= self.size <= MAX_BRUSH_SIZE:
            raise InputError(f"brush size must be 1..{MAX_BRUSH_SIZE} points, got {self.size!r}")
        for name, lo, hi in (("angle", -3600.0, 3600.0), ("density", 0.0, 1.0),
                             ("concentration", 0.0, MAX_CONCENTRATION),
                             ("spacing", MIN_SPACING, MAX_SPACING)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.number)) \
                    or not (math.isfinite(value) and lo <= value <= hi):
                raise InputError(f"brush {name} must be {lo:g}..{hi:g}, got {value!r}")
            object.__setattr__(self, name, float(value))
        if self.shape == "bitmap":
            object.__setattr__(self, "bitmap", format_bitmap(parse_bitmap(self.bitmap)))
        elif self.bitmap is not None:
            raise InputError("only a bitmap brush has a drawing")

    def mask(self) -> np.ndarray:
        """The solid footprint (a grain mask: the same shapes, placed the same way)."""
        return grain_mask(_GRAIN_SHAPE.get(self.shape, self.shape), self.size,
                          angle=self.angle, bitmap=self.bitmap)

    def footprint(self) -> Footprint:
        return _footprint(self.shape, self.size, self.angle, self.bitmap, self.distribution,
                          self.density, self.concentration)

    @property
    def step(self) -> float:
        """Points between two dabs along the stroke."""
        return max(1.0, self.spacing * self.size)

    def replace(self, **changes) -> "Brush":
        return dataclasses.replace(self, **changes)

    def to_json(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_json(cls, obj) -> "Brush":
        if not isinstance(obj, dict):
            raise InputError("a brush must be a JSON object")
        unknown = sorted(set(obj) - {f.name for f in dataclasses.fields(cls)})
        if unknown:
            raise InputError(f"a brush has unexpected fields {unknown}")
        return cls(**obj)


@lru_cache(maxsize=64)
def _footprint(shape, size, angle, bitmap, distribution, density, concentration) -> Footprint:
    mask = grain_mask(_GRAIN_SHAPE.get(shape, shape), size, angle=angle, bitmap=bitmap)
    ys, xs = np.nonzero(mask)
    ay, ax = anchor(mask)
    rows, cols = (ys - ay).astype(np.int64), (xs - ax).astype(np.int64)
    chance = None
    if distribution == "cloud":
        d = np.hypot(ys - ys.mean(), xs - xs.mean())
        chance = _spread(density, (1.0 - d / (d.max() + 0.5)) ** concentration)
    for a in (rows, cols, chance):
        if a is not None:
            a.flags.writeable = False
    return Footprint(rows, cols, chance)


def _spread(density: float, weight: np.ndarray) -> np.ndarray:
    """Chances proportional to ``weight``, none above 1, whose mean is ``density``: the centre
    saturates first and the rest of the footprint takes up what it cannot hold."""
    lo, hi = 0.0, 1.0 / max(weight.min(), 1e-12)
    for _ in range(80):                                 # bisection on the scale: monotone
        k = (lo + hi) / 2
        lo, hi = (k, hi) if np.minimum(1.0, k * weight).mean() < density else (lo, k)
    return np.minimum(1.0, hi * weight)


def parse_levels(text: str | None) -> tuple[int, ...] | None:
    """The levels a stroke draws from at random, e.g. ``"1, 3, 3, 5"`` (a level listed twice is
    twice as likely); None or an empty text: no random level.

    >>> parse_levels("1, 3 3,5")
    (1, 3, 3, 5)
    """
    if text is None or not text.strip():
        return None
    if not _LEVELS.match(text):
        raise InputError(f"random levels are numbers separated by commas, like 1, 2, 5; "
                         f"got {text!r}")
    levels = tuple(int(v) for v in re.split(r"[,\s]+", text.strip()))
    if max(levels) > MAX_LEVEL:
        raise InputError(f"levels are 0..{MAX_LEVEL}, got {max(levels)}")
    return levels


# -- strokes ---------------------------------------------------------------------------------------

class PathWalker:
    """Positions every ``step`` points along a polyline given one vertex at a time.

    The distance left over at the end of a segment carries into the next, so the dabs are evenly
    spaced however the pointer events fall (the tool framework thins them to ~100 per second).
    """

    def __init__(self, step: float, limit: int | None = None):
        if not step > 0:
            raise InputError("the spacing along a stroke must be positive")
        self.step = float(step)
        self.last: tuple[float, float] | None = None
        self.to_next = 0.0
        self.on_last = False
        self.limit = limit          # at most this many positions in all (InputError beyond)
        self.count = 0

    def add(self, point) -> list[tuple[float, float]]:
        r, c = float(point[0]), float(point[1])
        if self.last is None:
            self.last, self.to_next, self.on_last = (r, c), self.step, True
            self._count(1)
            return [(r, c)]
        r0, c0 = self.last
        length = math.hypot(r - r0, c - c0)
        if length == 0:
            return []
        out, t = [], self.to_next
        if self.limit is not None and self.count + (length + 1e-9 - t) / self.step \
                > self.limit + 2:
            self._refuse()
        while t <= length + 1e-9:
            out.append((r0 + (r - r0) * t / length, c0 + (c - c0) * t / length))
            t += self.step
        self._count(len(out))
        self.to_next = t - length
        self.on_last = bool(out) and abs(t - self.step - length) <= 1e-9
        self.last = (r, c)
        return out

    def finish(self) -> list[tuple[float, float]]:
        """The stroke's last point, when no position fell on it: strokes end where they end."""
        out = [] if self.last is None or self.on_last else [self.last]
        self._count(len(out))
        return out

    def _count(self, n: int) -> None:
        self.count += n
        if self.limit is not None and self.count > self.limit:
            self._refuse()

    def _refuse(self):
        raise InputError(f"this path places more than {self.limit:,} dabs or grains: use a "
                         f"larger spacing or a shorter path")


class StrokePainter:
    """The points a stroke paints, dab by dab, as the pointer moves (then ``finish``).

    Each call returns ``(rows, cols, values)`` of the new dabs' points, on the canvas: folded
    back with ``wrap`` (a stroke leaving one edge continues on the opposite one), else clipped.
    Later points win where they overlap earlier ones.
    """

    def __init__(self, brush: Brush, canvas_shape, level: int, *, choices=None, seed: int = 0,
                 wrap: bool = False):
        self.brush, self.shape, self.wrap = brush, tuple(canvas_shape), wrap
        self.level = int(level)
        self.choices = None if choices is None else np.asarray(choices, np.uint8)
        self.footprint = brush.footprint()
        self.walker = PathWalker(brush.step)
        self.rng = np.random.default_rng(seed)
        self.dabs = 0

    def add(self, point):
        return self._dab(self.walker.add(point))

    def finish(self):
        return self._dab(self.walker.finish())

    def _dab(self, positions):
        fp = self.footprint
        if self.choices is None:
            return self._dab_one_level(positions)
        rows, cols, values = [], [], []
        off = self._off_canvas(positions)
        for k, (r, c) in enumerate(positions):
            if off[k] and self.choices is None:       # nothing of it lands: only its draws
                if fp.chance is not None:
                    self.rng.random(len(fp))
                continue
            keep = slice(None) if fp.chance is None else self.rng.random(len(fp)) < fp.chance
            rows.append(fp.rows[keep] + math.floor(r + 0.5))
            cols.append(fp.cols[keep] + math.floor(c + 0.5))
            n = len(rows[-1])
            if self.choices is None:
                values.append(np.full(n, self.level, np.uint8))
            else:
                values.append(self.choices[self.rng.integers(len(self.choices), size=n)])
        self.dabs += len(positions)
        if not rows:
            return _EMPTY_I, _EMPTY_I, _EMPTY_U8
        return on_canvas(np.concatenate(rows), np.concatenate(cols), np.concatenate(values),
                         self.shape, self.wrap)

    def _dab_one_level(self, positions):
        """_dab without random levels, all dabs at once: the same draws in the same order (a
        cloud's chances, one row per dab, drawn also for the dabs off the canvas)."""
        fp = self.footprint
        self.dabs += len(positions)
        if not len(positions):
            return _EMPTY_I, _EMPTY_I, _EMPTY_U8
        centres = np.floor(np.asarray(positions, float).reshape(-1, 2) + 0.5).astype(np.int64)
        keep = None if fp.chance is None else \
            self.rng.random((len(centres), len(fp))) < fp.chance
        if not self.wrap and len(fp):
            on = ~off_canvas(centres, fp.rows, fp.cols, self.shape)
            centres = centres[on]
            keep = None if keep is None else keep[on]
        rows = (centres[:, :1] + fp.rows).ravel()
        cols = (centres[:, 1:] + fp.cols).ravel()
        if keep is not None:
            rows, cols = rows[keep.ravel()], cols[keep.ravel()]
        values = np.full(len(rows), self.level, np.uint8)
        return on_canvas(rows, cols, values, self.shape, self.wrap)

    def _off_canvas(self, positions) -> np.ndarray:
        """Which dabs' footprints miss the canvas entirely (never, with wrap)."""
        if self.wrap or not len(positions) or not len(self.footprint):
            return np.zeros(len(positions), bool)
        centres = np.floor(np.asarray(positions, float) + 0.5)
        return off_canvas(centres, self.footprint.rows, self.footprint.cols, self.shape)


_EMPTY_I = np.zeros(0, np.int64)
_EMPTY_U8 = np.zeros(0, np.uint8)


def off_canvas(centres, rows, cols, shape) -> np.ndarray:
    """Which of the (n, 2) ``centres`` put no point of the footprint (offsets ``rows``, ``cols``)
    on the canvas."""
    h, w = shape
    r, c = centres[:, 0], centres[:, 1]
    return (r + rows.max() < 0) | (r + rows.min() >= h) | (c + cols.max() < 0) | \
        (c + cols.min() >= w)


class Painted:
    """The points of a stroke or a grain placement, painted part after part, each canvas point
    once with the value painted last (as `last_wins` of all the parts), in a bounded memory:
    past a few million points the parts are folded onto two canvas-sized grids."""

    FOLD = 1 << 22

    def __init__(self, shape):
        self.shape = tuple(shape)
        self.parts, self.n = [], 0
        self.grid = self.painted = None

    def add(self, rows, cols, values) -> None:
        if len(rows):
            self.parts.append((rows, cols, values))
            self.n += len(rows)
            if self.n > self.FOLD:
                self._fold()

    def _fold(self) -> None:
        if not self.parts:
            return
        rows, cols, values = last_wins(*(np.concatenate(a) for a in zip(*self.parts)),
                                       self.shape)
        self.parts, self.n = [], 0
        if self.grid is None:
            self.grid = np.zeros(self.shape, np.uint8)
            self.painted = np.zeros(self.shape, bool)
        self.grid[rows, cols] = values
        self.painted[rows, cols] = True

    def result(self):
        """(rows, cols, values), each point once, in row-major order (as `last_wins`)."""
        if self.grid is None:
            if not self.parts:
                return _EMPTY_I, _EMPTY_I, _EMPTY_U8
            return last_wins(*(np.concatenate(a) for a in zip(*self.parts)), self.shape)
        self._fold()
        rows, cols = np.nonzero(self.painted)
        return rows.astype(np.int64), cols.astype(np.int64), self.grid[rows, cols]


def on_canvas(rows, cols, values, shape, wrap: bool):
    """Points folded back onto the canvas (wrap) or the ones outside it dropped."""
    h, w = shape
    if wrap:
        return rows % h, cols % w, values
    keep = (rows >= 0) & (rows < h) & (cols >= 0) & (cols < w)
    return rows[keep], cols[keep], values[keep]


def last_wins(rows, cols, values, shape):
    """Each canvas point once, with the value painted last (overlapping dabs, crossing strokes)."""
    if not len(rows):
        return rows, cols, values
    linear = rows * shape[1] + cols
    _, first_from_end = np.unique(linear[::-1], return_index=True)
    keep = len(linear) - 1 - first_from_end
    return rows[keep], cols[keep], values[keep]


def paint_stroke(brush: Brush, canvas_shape, points, level: int, *, choices=None, seed: int = 0,
                 wrap: bool = False):
    """Every point a whole stroke paints (each once, last value wins): what Stroke applies.

    >>> rows, cols, _ = paint_stroke(Brush(size=1, shape="square"), (3, 5), [(0, 0), (2, 4)], 1)
    >>> grid = np.zeros((3, 5), int); grid[rows, cols] = 1; grid
    array([[1, 1, 0, 0, 0],
           [0, 0, 1, 1, 0],
           [0, 0, 0, 0, 1]])
    """
    painter = StrokePainter(brush, canvas_shape, level, choices=choices, seed=seed, wrap=wrap)
    painter.walker.limit = MAX_DABS
    painted = Painted(canvas_shape)
    batch = max(1, (1 << 18) // max(len(painter.footprint), 1))
    for p in points:
        positions = painter.walker.add(p)
        for k in range(0, len(positions), batch):
            painted.add(*painter._dab(positions[k:k + batch]))
    painted.add(*painter.finish())
    return painted.result()


# -- presets ---------------------------------------------------------------------------------------

def standard_brushes() -> list[Brush]:
    """The brushes every user has: round and square pens, a calligraphic nib, sprays."""
    b = Brush
    return [
        b("Pen 1", 1, "square", spacing=1.0),
        b("Round 3", 3, "disc"),
        b("Round 7", 7, "disc"),
        b("Square 5", 5, "square"),
        b("Diamond 9", 9, "diamond"),
        b("Nib 9, 45°", 9, "line", angle=45.0, spacing=0.1),
        b("Spray 16", 16, "disc", distribution="cloud", density=0.3, spacing=0.25),
        b("Soft spray 24", 24, "disc", distribution="cloud", density=0.12, concentration=2.0,
          spacing=0.3),
        b("Speckle 9", 9, "square", distribution="cloud", density=0.08, spacing=0.5),
    ]


class BrushLibrary:
    """The standard brushes and the user's presets, saved as JSON in the user data folder."""

    def __init__(self, folder=None):
        from pathlib import Path
        self.path = Path(folder if folder is not None else data_dir()) / PRESETS_FILE

    def standard(self) -> list[Brush]:
        return standard_brushes()

    def user(self) -> list[Brush]:
        brushes = []
        for k, item in enumerate(read_library(self.path, PRESETS_KIND)):
            try:
                brushes.append(Brush.from_json(item))
            except ITEM_ERRORS as exc:
                raise FormatError(f"{self.path}: brush {k + 1}: {exc}") from None
        return brushes

    def all(self) -> list[Brush]:
        return self.standard() + self.user()

    def is_standard(self, name: str) -> bool:
        return any(b.name == name for b in self.standard())

    def save(self, brush: Brush) -> None:
        """Add a preset, or replace the user preset of the same name."""
        if not brush.name.strip():
            raise InputError("give the preset a name")
        if self.is_standard(brush.name):
            raise InputError(f"{brush.name!r} is a standard brush: save yours under another name")
        brushes = [b for b in self.user() if b.name != brush.name] + [brush]
        write_library(self.path, PRESETS_KIND, [b.to_json() for b in brushes])

    def remove(self, name: str) -> None:
        if self.is_standard(name):
            raise InputError(f"{name!r} is a standard brush: it cannot be removed")
        brushes = self.user()
        if not any(b.name == name for b in brushes):
            raise InputError(f"there is no user preset called {name!r}")
        write_library(self.path, PRESETS_KIND, [b.to_json() for b in brushes if b.name != name])
