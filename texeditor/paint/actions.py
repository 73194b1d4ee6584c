"""Manual acquisition as Actions (thesis §3.2.2, §3.3.1, §3.3.3a): brush strokes, placed grains,
duplicated zones, scrambled frontiers, Peano sub-region levels, dominance trees and zones laid
along a fill order, each a small replayable record.

The tools of `app.tools.brush`, `grain`, `zone` and `tree` and the Peano dialog build these;
`brushes`, `grains`, `zones`, `peano`, `trees` and `orders` do the work. Each keeps its randomness
in a seed and writes only the points it changes, so undo costs the size of the edit and replay
gives the same levels bit for bit.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from . import brushes
from . import grains
from . import orders
from . import peano
from . import trees
from . import zones
from ..recipe.actions import MAX_CANVAS_SIDE, Access, Action, param, register
from ..markov.dpj import MAX_LEVELS
from ..errors import InputError
from ..regions.actions import changed_boxes

MAX_REACH = 2**20            # pointer positions may leave the canvas (and wrap many times)
MAX_JITTER = 256
MAX_CELL = 4096


def _points(doc: str):
    return param("points", -MAX_REACH, MAX_REACH, doc=doc)


def _level(doc: str, default=dataclasses.MISSING):
    return param("int", 0, MAX_LEVELS - 1, default=default, doc=doc)


def _wrap():
    return param("bool", default=False, doc="what leaves one edge comes back on the opposite "
                                            "one (seamless tiles)")


def _seed():
    return param("seed", default=0, doc="random seed: same seed, same points")


def _zone():
    return param("str", hi=16, default="rectangle",
                 doc="rectangle (two opposite corners) or lasso (its vertices)")


def _zone_points():
    return param("points", -MAX_CANVAS_SIDE, 2 * MAX_CANVAS_SIDE, doc="the zone's points "
                                                                      "(row, col)")


def commit_points(doc, rows, cols, values) -> None:
    """Write points (each once) through a few dense boxes: one when they fill a good part of
    it, else the boxes of `changed_boxes` (a stroke wrapping round an edge records two or four)."""
    if not len(rows):
        return
    h, w = doc.shape
    t, b, l, r = rows.min(), rows.max() + 1, cols.min(), cols.max() + 1
    if (b - t) * (r - l) <= 4 * len(rows) + 256:
        boxes = [(t, l, b, r)]
    else:
        mask = np.zeros((h, w), bool)
        mask[rows, cols] = True
        boxes = changed_boxes(mask)
    grid = np.zeros((h, w), np.int32) if len(boxes) > 1 else None
    if grid is not None:
        grid[rows, cols] = np.arange(1, len(rows) + 1)
    for t, l, b, r in boxes:
        block = doc.levels[t:b, l:r].copy()
        if grid is None:
            block[rows - t, cols - l] = values
        else:
            idx = grid[t:b, l:r]
            block[idx > 0] = values[idx[idx > 0] - 1]
        doc.write(int(t), int(l), block)


def _check_levels(doc, *levels) -> None:
    for level in levels:
        doc.check_levels(np.uint8(level))


# -- brush strokes (§3.2.2) ------------------------------------------------------------------------

@register
@dataclass(frozen=True)
class Stroke(Action):
    """A brush stroke: the pointer's path, the brush and the level, plus its seed.

    The dabs fall every ``spacing × size`` points along the path and at its end; a cloud brush
    paints each footprint point with its chance; ``level_choices`` draws each point's level at
    random from a list (e.g. "1, 2, 2, 5").
    """

    TYPE: ClassVar[str] = "stroke"
    EFFECT: ClassVar[str] = "levels"
    points: tuple = _points("the pointer's path (row, col), in order")
    level: int = _level("the level painted")
    size: int = param("int", 1, brushes.MAX_BRUSH_SIZE, default=5, doc="brush diameter, points")
    shape: str = param("str", hi=16, default="disc",
                       doc="square, disc, diamond, line or bitmap")
    distribution: str = param("str", hi=16, default="solid",
                              doc="solid, or cloud (a spray of points)")
    density: float = param("float", 0.0, 1.0, default=0.25,
                           doc="cloud: the chance of each footprint point")
    concentration: float = param("float", 0.0, brushes.MAX_CONCENTRATION, default=0.0,
                                 doc="cloud: 0 even, higher gathers points toward the centre")
    spacing: float = param("float", brushes.MIN_SPACING, brushes.MAX_SPACING, default=0.25,
                           doc="distance between dabs, as a fraction of the size")
    angle: float = param("float", -3600, 3600, default=0.0, doc="brush turn, degrees "
                                                                "counter-clockwise")
    bitmap: str | None = param("str", hi=5000, default=None, optional=True,
                               doc="bitmap brush: rows of hex digits separated by /")
    level_choices: str | None = param("str", hi=200, default=None, optional=True,
                                      doc="draw each point's level from these, e.g. 1, 2, 5")
    wrap: bool = _wrap()
    seed: int = _seed()

    def _validate(self) -> None:
        if not self.points:
            raise InputError("a stroke needs at least one point")
        self.brush()
        brushes.parse_levels(self.level_choices)

    @classmethod
    def from_brush(cls, brush: brushes.Brush, points, level: int, **options) -> "Stroke":
        fields = {f.name for f in dataclasses.fields(cls)}
        params = {k: v for k, v in brush.to_json().items() if k in fields}
        return cls(points=tuple(map(tuple, points)), level=level, **params, **options)

    def brush(self) -> brushes.Brush:
        return brushes.Brush(size=self.size, shape=self.shape, angle=self.angle,
                             bitmap=self.bitmap, distribution=self.distribution,
                             density=self.density, concentration=self.concentration,
                             spacing=self.spacing)

    def painter(self, canvas_shape) -> brushes.StrokePainter:
        """The painter a live preview feeds: the same points as apply() will paint."""
        return brushes.StrokePainter(self.brush(), canvas_shape, self.level,
                                     choices=brushes.parse_levels(self.level_choices),
                                     seed=self.seed, wrap=self.wrap)

    def apply(self, doc, prepared=None) -> None:
        choices = brushes.parse_levels(self.level_choices)
        _check_levels(doc, self.level, *(choices or ()))
        rows, cols, values = brushes.paint_stroke(
            self.brush(), doc.shape, self.points, self.level, choices=choices, seed=self.seed,
            wrap=self.wrap)
        commit_points(doc, rows, cols, values)

    def access(self, shape):
        """The box of its dabs: its draws do not depend on the canvas, so the points it paints
        inside a box two canvases share are the same (a wrapping stroke: unknown)."""
        if self.wrap:
            return None
        fp = self.brush().footprint()
        centres = np.floor(np.asarray(self.points, float) + 0.5).astype(np.int64)
        return Access(writes=(_box(centres, fp.rows, fp.cols),)) if len(fp) else Access()

    def label(self) -> str:
        kind = "Spray" if self.distribution == "cloud" else "Stroke"
        levels = f"levels {self.level_choices}" if self.level_choices else f"level {self.level}"
        return f"{kind}, {self.shape} {self.size}, {levels}"


def _box(centres, rows, cols) -> tuple:
    """(top, left, height, width) holding every footprint (offsets ``rows``, ``cols``) placed
    at the (n, 2) ``centres`` and on the segments between them (a path's dabs lie on them)."""
    top, left = int(centres[:, 0].min() + rows.min()), int(centres[:, 1].min() + cols.min())
    bottom = int(centres[:, 0].max() + rows.max()) + 1
    right = int(centres[:, 1].max() + cols.max()) + 1
    return (top, left, bottom - top, right - left)


# -- grains (§3.3.3a) ------------------------------------------------------------------------------

@register
@dataclass(frozen=True)
class PlaceGrains(Action):
    """Grains of one type placed by their centre of gravity: at each point (clicks), or every
    ``spacing`` points along the path (a drag), each moved at random by up to ``jitter``."""

    TYPE: ClassVar[str] = "place_grains"
    EFFECT: ClassVar[str] = "levels"
    points: tuple = _points("grain centres, or the path they are placed along")
    level: int = _level("the level painted (a drawn grain may keep its own levels)")
    shape: str = param("str", hi=16, default="square", doc=", ".join(grains.SHAPES))
    size: int = param("int", 1, grains.MAX_GRAIN_SIZE, default=3, doc="grain diameter, points")
    aspect: float = param("float", grains.MIN_ASPECT, grains.MAX_ASPECT, default=1.0,
                          doc="height / width (rectangle, circle, diamond, polygons)")
    sides: int = param("int", grains.MIN_SIDES, grains.MAX_SIDES, default=6,
                       doc="polygon: number of sides")
    angle: float = param("float", -3600, 3600, default=0.0,
                         doc="orientation, degrees counter-clockwise")
    bitmap: str | None = param("str", hi=5000, default=None, optional=True,
                               doc="drawn grain: rows of hex digits (levels) separated by /")
    own_levels: bool = param("bool", default=False,
                             doc="drawn grain: keep the levels of the drawing")
    spacing: float = param("float", 0.0, MAX_CANVAS_SIDE, default=0.0,
                           doc="0: a grain at each point; else one every so many points "
                               "along the path")
    jitter: float = param("float", 0.0, MAX_JITTER, default=0.0,
                          doc="each grain moved at random by up to this many points")
    wrap: bool = _wrap()
    seed: int = _seed()

    def _validate(self) -> None:
        if not self.points:
            raise InputError("place at least one grain")
        self.grain()

    @classmethod
    def from_grain(cls, grain: grains.GrainType, points, level: int, **options):
        """The action for a library grain (its fixed level, if it has one, wins)."""
        params = {k: v for k, v in grain.to_json().items()
                  if k in ("shape", "size", "aspect", "sides", "angle", "bitmap", "own_levels")}
        level = grain.level if grain.level is not None else level
        return cls(points=tuple(map(tuple, points)), level=level, **params, **options)

    def grain(self) -> grains.GrainType:
        return grains.GrainType("placed", self.shape, self.size, self.aspect, self.sides,
                                self.angle, None, self.own_levels, self.bitmap)

    def centres(self) -> np.ndarray:
        """(n, 2) int centres: the points, or positions along the path; then the jitter."""
        painter = GrainPainter(self, (1, 1), limit=brushes.MAX_DABS)
        return np.concatenate([painter.centres(p) for p in self.points])

    def painter(self, canvas_shape) -> "GrainPainter":
        """The painter a live preview feeds: the same grains as apply() will paint."""
        return GrainPainter(self, canvas_shape)

    def apply(self, doc, prepared=None) -> None:
        grain = self.grain()
        _check_levels(doc, grain.max_level(self.level))
        painter = GrainPainter(self, doc.shape, limit=brushes.MAX_DABS)
        painted = brushes.Painted(doc.shape)
        for p in self.points:
            painter.add(p, painted)
        commit_points(doc, *painted.result())

    def access(self, shape):
        """The box of its grains, jitter included (see Stroke.access)."""
        if self.wrap:
            return None
        painter = GrainPainter(self, (1, 1), limit=brushes.MAX_DABS)
        return Access(writes=(_box(self.centres(), painter.ys, painter.xs),)) \
            if len(painter.ys) else Access()

    def label(self) -> str:
        n = len(self.points)
        where = f"along a path of {n} points" if self.spacing else \
            f"at ({self.points[0][0]}, {self.points[0][1]})" if n == 1 else f"at {n} points"
        return f"Grain {self.shape} {self.size} {where}"


class GrainPainter:
    """The grains of a PlaceGrains, point by point as the pointer moves (for a live preview).

    Jitter is drawn grain after grain from one generator, so feeding the points one at a time
    gives the grains apply() gives.
    """

    def __init__(self, action: PlaceGrains, canvas_shape, limit: int | None = None):
        self.action, self.shape = action, tuple(canvas_shape)
        grain = action.grain()
        mask = grain.mask()
        self.ys, self.xs = np.nonzero(mask)
        ay, ax = grains.anchor(mask)
        self.ys, self.xs = self.ys - ay, self.xs - ax
        self.values = grain.values(action.level)[mask]
        self.walker = brushes.PathWalker(action.spacing, limit) if action.spacing else None
        self.rng = np.random.default_rng(action.seed)

    def centres(self, point) -> np.ndarray:
        """The centres the next point brings (none, one, or several along the path)."""
        positions = [point] if self.walker is None else self.walker.add(point)
        centres = np.array(positions, float).reshape(-1, 2)
        if self.action.jitter:
            j = self.action.jitter
            centres += self.rng.uniform(-j, j, size=centres.shape)
        return np.floor(centres + 0.5).astype(np.int64)

    def add(self, point, painted: brushes.Painted | None = None):
        """(rows, cols, values) of the grains the next point brings, on the canvas; or, given
        ``painted``, added to it in parts (a long drag stays in a bounded memory)."""
        centres = self.centres(point)
        if not self.action.wrap and len(centres) and len(self.ys):
            centres = centres[~brushes.off_canvas(centres, self.ys, self.xs, self.shape)]
        if painted is None:
            return self._points(centres)
        batch = max(1, (1 << 20) // max(len(self.ys), 1))
        for k in range(0, len(centres), batch):
            painted.add(*self._points(centres[k:k + batch]))

    def _points(self, centres):
        rows = (centres[:, :1] + self.ys).ravel()
        cols = (centres[:, 1:] + self.xs).ravel()
        values = np.tile(self.values, len(centres))
        return brushes.on_canvas(rows, cols, values, self.shape, self.action.wrap)


# -- zones (§3.3.3a) -------------------------------------------------------------------------------

@register
@dataclass(frozen=True)
class DuplicateZone(Action):
    """Copy a rectangle or lasso zone by an offset (COPIER on a drawn zone)."""

    TYPE: ClassVar[str] = "duplicate_zone"
    EFFECT: ClassVar[str] = "levels"
    points: tuple = _zone_points()
    offset_row: int = param("int", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, doc="rows down")
    offset_col: int = param("int", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, doc="columns across")
    zone: str = _zone()
    wrap: bool = _wrap()

    def _validate(self) -> None:
        zones.zone_mask((1, 1), self.zone, self.points)

    def mask(self, canvas_shape) -> np.ndarray:
        return zones.zone_mask(canvas_shape, self.zone, self.points)

    def moved_points(self) -> tuple:
        """The zone's points after the move (where the copy is, for scrambling its frontier)."""
        return tuple((r + self.offset_row, c + self.offset_col) for r, c in self.points)

    def apply(self, doc, prepared=None) -> None:
        new = zones.duplicate(doc.levels, self.mask(doc.shape),
                              (self.offset_row, self.offset_col), wrap=self.wrap)
        for t, l, b, r in changed_boxes(new != doc.levels):
            doc.write(t, l, new[t:b, l:r])

    def label(self) -> str:
        return f"Duplicate {self.zone} zone by ({self.offset_row}, {self.offset_col})"


@register
@dataclass(frozen=True)
class ScrambleFrontier(Action):
    """Scramble the frontier of a zone: grains at random in a band along its outline, each with
    the level found a random step away, so the two sides mix. Only the band changes."""

    TYPE: ClassVar[str] = "scramble_frontier"
    EFFECT: ClassVar[str] = "levels"
    points: tuple = _zone_points()
    zone: str = _zone()
    band: int = param("int", 1, zones.MAX_BAND, default=4, doc="band width, points")
    density: float = param("float", 0.0, 1.0, default=0.3,
                           doc="chance of a grain at each band point")
    grain_size: int = param("int", 1, 16, default=1, doc="grain side, points")
    wrap: bool = _wrap()
    seed: int = _seed()

    def _validate(self) -> None:
        zones.zone_mask((1, 1), self.zone, self.points)

    def band_mask(self, canvas_shape) -> np.ndarray:
        return zones.frontier_band(zones.zone_mask(canvas_shape, self.zone, self.points),
                                   self.band, wrap=self.wrap)

    def apply(self, doc, prepared=None) -> None:
        new = zones.scramble(doc.levels, self.band_mask(doc.shape), density=self.density,
                             grain_size=self.grain_size, reach=self.band, seed=self.seed,
                             wrap=self.wrap)
        for t, l, b, r in changed_boxes(new != doc.levels):
            doc.write(t, l, new[t:b, l:r])

    def label(self) -> str:
        return f"Scramble the frontier of a {self.zone} zone ({self.band}-point band)"


# -- Peano sub-regions (§3.3.3a, Fig. 3.5–3.6) -----------------------------------------------------

@register
@dataclass(frozen=True)
class PeanoLevels(Action):
    """Give the sub-regions named by a dominance expression levels that satisfy it.

    The canvas (from ``top``, ``left``) is cut into cells of ``cell`` points, numbered from 1
    along a Hilbert scan (or another fill ``order``, `orders.grid_order`); each named cell is
    filled with its level (or, with ``grain`` set to a grain shape, receives a grain of that
    level at its centre). The ranks of the expression are spread from ``low`` to ``high``
    (default: the top level G-1).
    """

    TYPE: ClassVar[str] = "peano_levels"
    EFFECT: ClassVar[str] = "levels"
    cell: int = param("int", 1, MAX_CELL, doc="cell side, points")
    expression: str = param("str", hi=peano.MAX_EXPRESSION,
                            doc="dominance expression, e.g. 6:7(2(1,2(2,3)),6:7(4,5,8))")
    low: int = _level("level of the dimmest sub-regions", default=1)
    high: int | None = param("int", 0, MAX_LEVELS - 1, default=None, optional=True,
                             doc="level of the brightest (default: the top level)")
    top: int = param("int", 0, MAX_CANVAS_SIDE - 1, default=0, doc="first row of the cut")
    left: int = param("int", 0, MAX_CANVAS_SIDE - 1, default=0, doc="first column of the cut")
    cells_down: int | None = param("int", 1, MAX_CANVAS_SIDE, default=None, optional=True,
                                   doc="cells down (default: to the bottom edge)")
    cells_across: int | None = param("int", 1, MAX_CANVAS_SIDE, default=None, optional=True,
                                     doc="cells across (default: to the right edge)")
    grain: str = param("str", hi=16, default="cell",
                       doc="cell (fill the whole cell) or a grain shape placed at its centre")
    grain_size: int | None = param("int", 1, grains.MAX_GRAIN_SIZE, default=None, optional=True,
                                   doc="grain diameter (default: the cell side)")
    order: str = param("str", hi=8, default="peano",
                       doc="how the cells are numbered: peano (Hilbert), tv, polar or spiral")

    def _validate(self) -> None:
        peano.parse_dominance(self.expression)
        if self.grain != "cell" and self.grain not in grains.SHAPES[:-1]:
            raise InputError(f"grain must be 'cell' or one of "
                             f"{', '.join(grains.SHAPES[:-1])}, got {self.grain!r}")
        _check_order(self.order)

    def cells(self, canvas_shape) -> tuple[int, int]:
        return peano.cell_grid(canvas_shape, self.cell, self.top, self.left, self.cells_down,
                               self.cells_across)

    def levels_of(self, num_levels: int) -> dict[int, int]:
        high = num_levels - 1 if self.high is None else self.high
        if high >= num_levels:
            raise InputError(f"level {high} does not exist: G = {num_levels}")
        return peano.assign_levels(self.expression, self.low, high)

    def apply(self, doc, prepared=None) -> None:
        assigned = self.levels_of(doc.num_levels)
        down, across = self.cells(doc.shape)
        last = max(assigned)
        if last > down * across:
            raise InputError(f"the expression names sub-region {last} but the cut has only "
                             f"{down * across} cells ({across}×{down} of {self.cell} points)")
        order = orders.grid_order(down, across, self.order, limit=last)
        if self.grain == "cell":
            boxes = peano.cell_boxes(order, self.cell, self.top, self.left, doc.shape)
            for index, level in assigned.items():
                t, l, b, r = (int(v) for v in boxes[index - 1])
                if b > t and r > l:
                    doc.fill(t, l, b - t, r - l, level)
            return
        mask = grains.grain_mask(self.grain, self.grain_size or self.cell)
        rows, cols, values = [], [], []
        for index, level in assigned.items():
            centre = (self.top + order[index - 1][0] * self.cell + self.cell // 2,
                      self.left + order[index - 1][1] * self.cell + self.cell // 2)
            r, c, _ = grains.stamp_points(mask, centre, doc.shape)
            rows.append(r)
            cols.append(c)
            values.append(np.full(len(r), level, np.uint8))
        commit_points(doc, *brushes.last_wins(np.concatenate(rows), np.concatenate(cols),
                                              np.concatenate(values), doc.shape))

    def label(self) -> str:
        expr = self.expression if len(self.expression) <= 40 else self.expression[:37] + "…"
        scan = "" if self.order == "peano" else f" ({self.order} order)"
        return f"Peano levels, cells of {self.cell}{scan}: {expr}"


def _check_order(order: str) -> None:
    if order not in orders.ORDERS:
        raise InputError(f"the fill order must be one of {', '.join(orders.ORDERS)}, "
                         f"got {order!r}")


# -- dominance trees placed on screen (§3.3.3a, Fig. 3.6) -----------------------------------------

MIXES = ("over", "brighter")


@register
@dataclass(frozen=True)
class DominanceTree(Action):
    """One dominance tree placed on screen: a grain at each vertex, and levels that make every
    vertex brighter than the vertices under it, spread from ``low`` to ``high`` (default: the
    top level). Dominant grains are drawn over the dominated ones they overlap; ``mix`` says
    how the tree meets what is already there (another tree, a texture).
    """

    TYPE: ClassVar[str] = "dominance_tree"
    EFFECT: ClassVar[str] = "levels"
    points: tuple = _points("the vertices (row, col), numbered from 1 in the order placed")
    expression: str = param("str", hi=peano.MAX_EXPRESSION,
                            doc="the tree over the vertex numbers, e.g. 1(2(4),3): a vertex is "
                                "brighter than those in its brackets")
    grains: str = param("str", hi=2**20, doc="each vertex's grain in order, separated by commas: "
                                             "shape size [aspect= sides= angle= bitmap=]")
    low: int = _level("level of the dimmest vertices", default=1)
    high: int | None = param("int", 0, MAX_LEVELS - 1, default=None, optional=True,
                             doc="level of the brightest (default: the top level)")
    mix: str = param("str", hi=16, default="over",
                     doc="over (the tree covers what is under it) or brighter (each point keeps "
                         "the brighter level)")
    wrap: bool = _wrap()

    def _validate(self) -> None:
        if not 1 <= len(self.points) <= trees.MAX_VERTICES:
            raise InputError(f"a tree has 1..{trees.MAX_VERTICES} vertices, "
                             f"got {len(self.points)}")
        if len(self.grain_types()) != len(self.points):
            raise InputError(f"the tree has {len(self.points)} vertices but "
                             f"{len(self.grain_types())} grains: give one grain per vertex")
        if self.mix not in MIXES:
            raise InputError(f"mix must be one of {', '.join(MIXES)}, got {self.mix!r}")
        trees.vertex_tree(self.expression, len(self.points))

    @classmethod
    def from_vertices(cls, points, parents, grain_list, **options) -> "DominanceTree":
        """The action for vertices placed one by one, each with its parent's index (-1 for the
        root) and its grain."""
        return cls(points=tuple(map(tuple, points)), expression=trees.tree_expression(parents),
                   grains=", ".join(grains.grain_spec(g) for g in grain_list), **options)

    def grain_types(self) -> list[grains.GrainType]:
        return [grains.parse_grain_spec(text) for text in self.grains.split(",")]

    def levels(self, num_levels: int):
        """Each vertex's level and rank in a document of ``num_levels`` levels."""
        high = num_levels - 1 if self.high is None else self.high
        if high >= num_levels:
            raise InputError(f"level {high} does not exist: G = {num_levels}")
        return trees.vertex_levels(self.expression, len(self.points), self.low, high)

    def apply(self, doc, prepared=None) -> None:
        commit_points(doc, *self.points_on(doc.levels, doc.num_levels))

    def points_on(self, before: np.ndarray, num_levels: int):
        """(rows, cols, values) the tree writes over the levels ``before`` (also the tool's
        preview): its grains, mixed with what is there."""
        levels, ranks = self.levels(num_levels)
        rows, cols, values = trees.draw_tree(before.shape, self.points, self.grain_types(),
                                             levels, ranks, wrap=self.wrap)
        if self.mix == "brighter":
            values = np.maximum(values, before[rows, cols])
        return rows, cols, values

    def label(self) -> str:
        expr = self.expression if len(self.expression) <= 24 else self.expression[:21] + "…"
        return f"Tree of {len(self.points)} grains: {expr}"


# -- fill orders (§3.3.1, Fig. 3.4) ----------------------------------------------------------------

@register
@dataclass(frozen=True)
class LayAlongOrder(Action):
    """Lay a zone's levels along a fill order: read in television order (as the texture was
    produced), they are written back along the polar, spiral or Peano order — a texture filled
    in another frame, such as rings about a knot of wood.
    """

    TYPE: ClassVar[str] = "lay_along_order"
    EFFECT: ClassVar[str] = "levels"
    order: str = param("str", hi=8, doc="tv, polar (by angle, then distance), spiral or peano")
    zone: str = param("str", hi=16, default="canvas",
                      doc="canvas (the whole canvas), rectangle (two opposite corners) or lasso")
    points: tuple = param("points", -MAX_CANVAS_SIDE, 2 * MAX_CANVAS_SIDE, default=(),
                          doc="the zone's points (row, col); none for the canvas")
    centre_row: int | None = param("int", -MAX_CANVAS_SIDE, 2 * MAX_CANVAS_SIDE, default=None,
                                   optional=True, doc="centre of the polar and spiral orders "
                                                      "(default: the middle of the zone)")
    centre_col: int | None = param("int", -MAX_CANVAS_SIDE, 2 * MAX_CANVAS_SIDE, default=None,
                                   optional=True, doc="its column")

    def _validate(self) -> None:
        _check_order(self.order)
        if self.zone == "canvas":
            if self.points:
                raise InputError("the whole canvas needs no zone points")
        else:
            zones.zone_mask((1, 1), self.zone, self.points)
        if (self.centre_row is None) != (self.centre_col is None):
            raise InputError("give both the centre's row and column, or neither")

    def mask(self, canvas_shape) -> np.ndarray:
        if self.zone == "canvas":
            return np.ones(canvas_shape, bool)
        return zones.zone_mask(canvas_shape, self.zone, self.points)

    def centre(self):
        return None if self.centre_row is None else (self.centre_row, self.centre_col)

    def apply(self, doc, prepared=None) -> None:
        new = orders.lay_along(doc.levels, self.mask(doc.shape), self.order, self.centre())
        for t, l, b, r in changed_boxes(new != doc.levels):
            doc.write(t, l, new[t:b, l:r])

    def label(self) -> str:
        where = "the canvas" if self.zone == "canvas" else f"a {self.zone} zone"
        about = "" if self.centre_row is None or self.order in ("tv", "peano") else \
            f" about ({self.centre_row}, {self.centre_col})"
        return f"Lay {where} along the {self.order} order{about}"


PAINT_ACTIONS = (Stroke, PlaceGrains, DuplicateZone, ScrambleFrontier, PeanoLevels, DominanceTree,
                 LayAlongOrder)
