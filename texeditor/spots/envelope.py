"""Spots (taches, thesis §3.3.3b): an envelope drawn like a globe, its outline, the random
perturbation that turns it into a real spot, and the spot's points on the level matrix.

The spot editor and the spot library build Envelopes; `spot_actions` places the Stamps made here
into a Document. Everything is pure: same envelope, perturbation and seed, same points.

Vocabulary (digest §3.2). The **equator** (directrix) is the longest straight line inside the
envelope, from end ``a`` to end ``b``. **Meridians** cross it: each sits at a position ``t`` along
the equator (0 at ``a``, 1 at ``b``) and gives the half-widths on its left and right (left of the
walk from a to b, as seen on the screen). The widest, or the one marked ``main``, is the main
meridian. **Parallels** run along the equator at a signed distance, from ``t0`` to ``t1``: they
shape the long profile (a flat flank). The outline passes through every end point, by straight
lines, closed cubic Bézier curves or a periodic cubic B-spline. A **freehand contour** may replace
the globe construction. Coordinates are (row, col) in points, row 0 on top.

Outline kinds (digest §3.2: "linear interpolation, Bézier curves or B-splines"). The envelope's
points — a, the meridians' and parallels' ends, b — are joined by straight lines (``linear``),
or are the control polygon of one closed Bézier curve (``bezier_curve``, Bernstein form) or of a
closed uniform cubic B-spline (``uniform_bspline``: moving a point changes exactly the four
pieces around it, the locality the thesis praises). Two smooth curves *through* the points are
kept under their own names: ``catmull_rom`` and ``interpolating_spline``. Files written before
those names existed called them "bezier" and "bspline": `Envelope.from_json` reads those stored
names with the meaning they had (LEGACY_KINDS), so old placements draw the same points.
``fractal_curve`` is the projected-IFS curve through the points (companion 002): the Catmull–Rom
curve roughened by a ``roughness`` in [0, 1] from a ``seed``; only its envelopes store those two.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, replace
from functools import lru_cache

import numpy as np

from ..errors import InputError
from ..regions.transforms import rotation_matrix

KINDS = ("linear", "bezier_curve", "uniform_bspline", "catmull_rom", "interpolating_spline",
         "fractal_curve")
DEFAULT_KIND = "interpolating_spline"
APPROXIMATING = ("bezier_curve", "uniform_bspline")    # follow their points, not through them
LEGACY_KINDS = {"bezier": "catmull_rom", "bspline": "interpolating_spline"}   # stored names
MAX_BEZIER_POINTS = 128         # one Bézier curve of degree n: beyond that, use a B-spline
INTERIORS = ("none", "holes", "levels", "relief")
LIGHT = (-0.7071067811865476, -0.7071067811865476)     # relief: light from the top left (row, col)
BLENDS = ("over", "under", "max", "min")
MAX_COORD = 100_000.0           # envelope coordinates and widths, in points
MAX_CONTOUR = 4096              # points of a freehand contour
MAX_MERIDIANS = 256
MIN_GAP = 1e-6                  # two meridians closer than this along the equator are one place
MIN_AREA = 1e-6                 # an envelope with less area (points²) has no width
MAX_STAMP_SIDE = 16384
MAX_RELIEF_POINTS = 2**24       # a relief is shaded from the whole spot: 4096² points at most
MARK_POINTS = 2**20             # interior marks are mapped this many points of the spot at a time
FRACTAL_ROUGHNESS = 0.5         # a fractal curve's roughness and seed when none is given
MAX_CURVE_SEED = 2**32 - 1


# -- the envelope ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class Meridian:
    """A width across the equator at ``t`` (0 < t < 1): half-widths ``left`` and ``right`` ≥ 0."""

    t: float
    left: float
    right: float
    main: bool = False


@dataclass(frozen=True)
class Parallel:
    """A line along the equator at signed distance ``offset`` (> 0: left), from t0 to t1."""

    offset: float
    t0: float
    t1: float


@dataclass(frozen=True)
class Envelope:
    """The ideal spot (l'enveloppe): equator a→b, meridians, parallels, outline kind; or a contour.

    Meridians are kept sorted along the equator, so meridians given "crossed" (out of order) make
    the same envelope as sorted ones. Building one checks everything: a zero-length equator, a
    meridian off the equator or two at one place, negative widths are an InputError that says
    what to change. An envelope whose widths are all 0 is valid (the editor passes through it)
    but has no area: rasterising it is an InputError.
    """

    a: tuple[float, float]
    b: tuple[float, float]
    meridians: tuple[Meridian, ...] = ()
    parallels: tuple[Parallel, ...] = ()
    kind: str = DEFAULT_KIND
    contour: tuple[tuple[float, float], ...] | None = None
    roughness: float = FRACTAL_ROUGHNESS       # the fractal curve's (other kinds: the default)
    seed: int = 0

    def __post_init__(self):
        a, b = _point("equator end a", self.a), _point("equator end b", self.b)
        if math.dist(a, b) < 1e-6:
            raise InputError("the equator has zero length: its two end points must be different "
                             "points")
        _check_kind(self.kind)
        meridians = tuple(sorted((_meridian(m) for m in self.meridians), key=lambda m: m.t))
        if len(meridians) > MAX_MERIDIANS:
            raise InputError(f"an envelope has at most {MAX_MERIDIANS} meridians")
        for m, n in zip(meridians, meridians[1:]):
            if n.t - m.t < MIN_GAP:
                raise InputError(f"two meridians sit at the same place along the equator "
                                 f"(t = {m.t:g}): move one of them or remove it")
        if sum(m.main for m in meridians) > 1:
            raise InputError("only one meridian can be the main meridian")
        parallels = tuple(_parallel(p) for p in self.parallels)
        if len(parallels) > MAX_MERIDIANS:
            raise InputError(f"an envelope has at most {MAX_MERIDIANS} parallels")
        contour = None if self.contour is None else _contour(self.contour)
        roughness, seed = _fractal(self.roughness, self.seed) if self.kind == "fractal_curve" \
            else (FRACTAL_ROUGHNESS, 0)
        for name, value in (("a", a), ("b", b), ("meridians", meridians),
                            ("parallels", parallels), ("contour", contour),
                            ("roughness", roughness), ("seed", seed)):
            object.__setattr__(self, name, value)
        if self.kind == "bezier_curve" and len(self.control_points()) > MAX_BEZIER_POINTS:
            raise InputError(f"a Bézier curve takes at most {MAX_BEZIER_POINTS} points (this "
                             f"envelope has {len(self.control_points())}): choose the B-spline")

    # -- constructors ------------------------------------------------------------------------------
    @classmethod
    def ellipse(cls, length: float = 40.0, width: float = 24.0, kind: str = DEFAULT_KIND):
        """An equator of ``length`` across the screen with one main meridian of ``width``."""
        half = width / 2
        return cls((0.0, -length / 2), (0.0, length / 2),
                   (Meridian(0.5, half, half, main=True),), kind=kind)

    @classmethod
    def from_contour(cls, points, kind: str = DEFAULT_KIND) -> "Envelope":
        """A freehand contour (thesis: "entrer directement son contour"). Its equator is, by the
        definition, the longest straight line between two of its points (the diameter)."""
        pts = np.asarray(_contour(points), dtype=float)
        d = np.linalg.norm(pts[:, None, :] - pts[None, :, :], axis=-1)
        i, j = np.unravel_index(int(np.argmax(d)), d.shape)
        return cls(tuple(pts[i]), tuple(pts[j]), kind=kind, contour=tuple(map(tuple, pts)))

    # -- the frame of the equator ----------------------------------------------------------------
    @property
    def length(self) -> float:
        return math.dist(self.a, self.b)

    @property
    def direction(self) -> np.ndarray:
        """Unit vector from a to b, (row, col)."""
        return (np.subtract(self.b, self.a)) / self.length

    @property
    def normal(self) -> np.ndarray:
        """Unit vector to the left of a→b on the screen (row 0 on top)."""
        u = self.direction
        return np.array([-u[1], u[0]])

    @property
    def centre(self) -> np.ndarray:
        """The middle of the equator: the point a placement puts at the clicked point."""
        return (np.asarray(self.a) + np.asarray(self.b)) / 2

    @property
    def main_index(self) -> int | None:
        """Index of the main meridian: the one marked main, else the widest."""
        if not self.meridians:
            return None
        for i, m in enumerate(self.meridians):
            if m.main:
                return i
        return int(np.argmax([m.left + m.right for m in self.meridians]))

    def at(self, t: float, offset: float = 0.0) -> np.ndarray:
        """The point at ``t`` along the equator and ``offset`` to its left."""
        return np.asarray(self.a) + t * self.length * self.direction + offset * self.normal

    def frame_of(self, point) -> tuple[float, float]:
        """(t, offset) of a point: its place along the equator and its distance to the left."""
        d = np.asarray(point, dtype=float) - np.asarray(self.a)
        return float(d @ self.direction) / self.length, float(d @ self.normal)

    # -- editing: each returns a new envelope --------------------------------------------------
    def with_meridian(self, t: float, left: float, right: float, *, main: bool = False):
        return replace(self, meridians=self.meridians + (Meridian(t, left, right, main),))

    def without_meridian(self, index: int):
        return replace(self, meridians=self.meridians[:index] + self.meridians[index + 1:])

    def with_moved_meridian(self, index: int, **changes):
        m = replace(self.meridians[index], **changes)
        return replace(self, meridians=self.meridians[:index] + (m,) + self.meridians[index + 1:])

    def with_parallel(self, offset: float, t0: float, t1: float):
        return replace(self, parallels=self.parallels + (Parallel(offset, t0, t1),))

    def without_parallel(self, index: int):
        return replace(self, parallels=self.parallels[:index] + self.parallels[index + 1:])

    def with_kind(self, kind: str):
        return replace(self, kind=kind)

    def with_fractal(self, roughness: float, seed: int | None = None):
        """The fractal curve of this envelope's points with ``roughness`` (and ``seed``)."""
        return replace(self, kind="fractal_curve", roughness=roughness,
                       seed=self.seed if seed is None else seed)

    def width_at(self, t: float) -> tuple[float, float]:
        """The (left, right) half-widths of the outline at ``t``: a new meridian placed there
        leaves the shape as it is (linear reading of the neighbours)."""
        pts = self.control_points()
        frames = np.array([self.frame_of(p) for p in pts])
        left = frames[frames[:, 1] >= 0]
        right = frames[frames[:, 1] <= 0]
        return (float(np.interp(t, *_sorted_profile(left))),
                float(-np.interp(t, *_sorted_profile(right))))

    # -- the outline -------------------------------------------------------------------------------
    def control_points(self) -> np.ndarray:
        """The points the outline passes through, in order around it: a, the left side from a to
        b, b, the right side back (or the freehand contour)."""
        if self.contour is not None:
            return _dedupe(np.asarray(self.contour, dtype=float))
        left, right = [], []
        for m in self.meridians:
            left.append((m.t, m.left))
            right.append((m.t, -m.right))
        for p in self.parallels:
            (left if p.offset > 0 else right).extend([(p.t0, p.offset), (p.t1, p.offset)])
        left.sort()
        right.sort(reverse=True)
        frame = [(0.0, 0.0), *left, (1.0, 0.0), *right]
        return _dedupe(np.array([self.at(t, o) for t, o in frame]))

    def outline(self, step: float = 0.5) -> np.ndarray:
        """The closed outline (N, 2), points at most about ``step`` apart (the first is not
        repeated at the end); it passes through every control point except for the Bézier
        curve and the B-spline, which only follow them. Read-only: it is cached, with
        ``step`` rounded down to a power of two, since a scatter draws one envelope many times."""
        return _outline(self, 2.0 ** math.floor(math.log2(min(max(float(step), 1e-3), 64.0))))

    def area(self) -> float:
        return abs(polygon_area(self.outline()))

    def bbox(self) -> tuple[float, float, float, float]:
        """(top, left, bottom, right) of the outline."""
        o = self.outline()
        return float(o[:, 0].min()), float(o[:, 1].min()), float(o[:, 0].max()), \
            float(o[:, 1].max())

    # -- JSON ------------------------------------------------------------------------------------
    def to_json(self) -> dict:
        obj = {"a": list(self.a), "b": list(self.b), "kind": self.kind,
               "meridians": [[m.t, m.left, m.right] + ([True] if m.main else [])
                             for m in self.meridians],
               "parallels": [[p.offset, p.t0, p.t1] for p in self.parallels]}
        if self.contour is not None:
            obj["contour"] = [list(p) for p in self.contour]
        if self.kind == "fractal_curve":         # other kinds write what they always wrote
            obj["roughness"], obj["seed"] = self.roughness, self.seed
        return obj

    def dumps(self) -> str:
        """Compact JSON text (the form stored in an action's parameters)."""
        return json.dumps(self.to_json(), separators=(",", ":"))

    @classmethod
    def from_json(cls, obj) -> "Envelope":
        """An envelope from its JSON object, every field checked (InputError when wrong)."""
        if not isinstance(obj, dict):
            raise InputError("an envelope must be a JSON object")
        unknown = sorted(set(obj) - {"a", "b", "kind", "meridians", "parallels", "contour",
                                     "roughness", "seed"})
        if unknown:
            raise InputError(f"an envelope has unexpected fields {unknown}")
        if "a" not in obj or "b" not in obj:
            raise InputError("an envelope needs its equator's end points a and b")
        meridians = _list(obj.get("meridians", []), "meridians", MAX_MERIDIANS)
        parallels = _list(obj.get("parallels", []), "parallels", MAX_MERIDIANS)
        ms = []
        for m in meridians:
            if not isinstance(m, list) or len(m) not in (3, 4):
                raise InputError("each meridian must be [t, left, right] or [t, left, right, true]")
            ms.append(Meridian(*m[:3], main=len(m) == 4 and m[3] is True))
        ps = []
        for p in parallels:
            if not isinstance(p, list) or len(p) != 3:
                raise InputError("each parallel must be [offset, t0, t1]")
            ps.append(Parallel(*p))
        contour = obj.get("contour")
        if contour is not None:
            contour = _list(contour, "contour", MAX_CONTOUR)
        kind = obj.get("kind", "bspline")
        if not isinstance(kind, str):
            raise InputError("the outline kind must be a text")
        kind = LEGACY_KINDS.get(kind, kind)          # a stored name keeps its meaning
        return cls(obj["a"], obj["b"], tuple(ms), tuple(ps), kind, contour,
                   obj.get("roughness", FRACTAL_ROUGHNESS), obj.get("seed", 0))

    @classmethod
    def loads(cls, text: str) -> "Envelope":
        from ..fileio import load_json      # size and nesting bounded before parsing
        obj = load_json(text, "the envelope", limit=2**20, error=InputError,
                        constants=True)
        return cls.from_json(obj)


def _check_kind(kind) -> None:
    if kind in LEGACY_KINDS:
        raise InputError(f"{kind!r} is the stored name of the {LEGACY_KINDS[kind]} outline "
                         f"(files read it so); say {LEGACY_KINDS[kind]!r}, or one of "
                         f"{', '.join(KINDS)}")
    if kind not in KINDS:
        raise InputError(f"the outline kind must be one of {', '.join(KINDS)}, got {kind!r}")


def _fractal(roughness, seed) -> tuple[float, int]:
    roughness = _number("the fractal curve's roughness", roughness, 0.0, 1.0)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) \
            or not 0 <= seed <= MAX_CURVE_SEED:
        raise InputError(f"the fractal curve's seed must be a whole number 0..{MAX_CURVE_SEED}, "
                         f"got {seed!r}")
    return roughness, int(seed)


def _number(name: str, value, lo=-MAX_COORD, hi=MAX_COORD) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{name} must be a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value) or not lo <= value <= hi:
        raise InputError(f"{name} = {value:g} is out of range {lo:g}..{hi:g}")
    return value


def _point(name: str, p) -> tuple[float, float]:
    if isinstance(p, np.ndarray):
        p = p.tolist()
    if not isinstance(p, (list, tuple)) or len(p) != 2:
        raise InputError(f"{name} must be a point (row, col)")
    return (_number(f"{name} row", p[0]), _number(f"{name} col", p[1]))


def _meridian(m) -> Meridian:
    if not isinstance(m, Meridian):
        m = Meridian(*m)
    t = _number("a meridian's place t", m.t, -MAX_COORD, MAX_COORD)
    if not 0.0 < t < 1.0:
        raise InputError(f"a meridian must cross the equator between its end points "
                         f"(0 < t < 1), got t = {t:g}")
    left, right = (_number("a meridian's half-width", w) for w in (m.left, m.right))
    if left < 0 or right < 0:
        raise InputError("a meridian's half-widths must be ≥ 0 (left and right of the equator)")
    return Meridian(t, left, right, bool(m.main))


def _parallel(p) -> Parallel:
    if not isinstance(p, Parallel):
        p = Parallel(*p)
    offset = _number("a parallel's offset", p.offset)
    t0, t1 = (_number("a parallel's end t", t, 0.0, 1.0) for t in (p.t0, p.t1))
    if offset == 0:
        raise InputError("a parallel must lie off the equator (offset ≠ 0)")
    if t1 <= t0:
        raise InputError(f"a parallel must run forwards along the equator (t0 < t1), got "
                         f"{t0:g}..{t1:g}")
    return Parallel(offset, t0, t1)


def _contour(points) -> tuple[tuple[float, float], ...]:
    if isinstance(points, np.ndarray):
        points = points.tolist()
    if not isinstance(points, (list, tuple)) or len(points) > MAX_CONTOUR:
        raise InputError(f"a contour must be a list of at most {MAX_CONTOUR} points")
    pts = tuple(_point("a contour point", p) for p in points)
    if len(_dedupe(np.asarray(pts, dtype=float).reshape(-1, 2))) < 3:
        raise InputError("a contour needs at least three different points")
    return pts


def _list(value, name: str, limit: int) -> list:
    if not isinstance(value, list) or len(value) > limit:
        raise InputError(f"{name} must be a list of at most {limit} entries")
    return value


def _dedupe(pts: np.ndarray) -> np.ndarray:
    """Drop points equal to the one before them (and the last if it equals the first): zero-length
    pieces would make the spline fit fail."""
    if len(pts) < 2:
        return pts
    keep = np.r_[True, np.any(np.abs(np.diff(pts, axis=0)) > 1e-9, axis=1)]
    pts = pts[keep]
    if len(pts) > 1 and np.all(np.abs(pts[-1] - pts[0]) <= 1e-9):
        pts = pts[:-1]
    return pts


def _sorted_profile(frames: np.ndarray):
    order = np.argsort(frames[:, 0], kind="stable")
    return frames[order, 0], frames[order, 1]


# -- outlines through the control points -----------------------------------------------------------

def _pieces(length: float, step: float) -> int:
    return int(min(max(math.ceil(length / step), 4), 4096))


def linear_outline(pts: np.ndarray, step: float) -> np.ndarray:
    """Straight lines between the points (the thesis's simple linear interpolation)."""
    out = []
    for p, q in zip(pts, np.roll(pts, -1, axis=0)):
        s = np.arange(_pieces(np.linalg.norm(q - p), step))[:, None] / _pieces(
            np.linalg.norm(q - p), step)
        out.append(p + s * (q - p))
    return np.concatenate(out)


def catmull_rom_outline(pts: np.ndarray, step: float) -> np.ndarray:
    """Closed Catmull–Rom curve through the points: between P_i and P_i+1 a cubic whose inner
    control points follow the neighbours (tangent (P_i+1 − P_i−1)/2), smooth at every point.
    Stored as "bezier" before it had its true name."""
    prev, nxt, nxt2 = (np.roll(pts, k, axis=0) for k in (1, -1, -2))
    c1 = pts + (nxt - prev) / 6
    c2 = nxt - (nxt2 - pts) / 6
    out = []
    for i in range(len(pts)):
        n = _pieces(np.linalg.norm(c1[i] - pts[i]) + np.linalg.norm(c2[i] - c1[i])
                    + np.linalg.norm(nxt[i] - c2[i]), step)
        s = (np.arange(n) / n)[:, None]
        out.append((1 - s) ** 3 * pts[i] + 3 * (1 - s) ** 2 * s * c1[i]
                   + 3 * (1 - s) * s ** 2 * c2[i] + s ** 3 * nxt[i])
    return np.concatenate(out)


def interpolating_spline_outline(pts: np.ndarray, step: float) -> np.ndarray:
    """A periodic cubic spline through the points (SciPy's splprep, per=True, s=0). It is
    fitted to the whole contour: a point moved changes every piece a little. Stored as
    "bspline" before it had its true name."""
    from scipy.interpolate import splev, splprep
    closed = np.vstack([pts, pts[:1]])
    tck, u = splprep([closed[:, 0], closed[:, 1]], s=0, per=True, k=3, quiet=2)
    perimeter = float(np.sum(np.linalg.norm(np.diff(closed, axis=0), axis=1)))
    params = []
    for u0, u1 in zip(u[:-1], u[1:]):
        n = _pieces(perimeter * (u1 - u0) * 1.2, step)
        params.append(u0 + (u1 - u0) * np.arange(n) / n)
    rows, cols = splev(np.concatenate(params), tck)
    out = np.column_stack([rows, cols])
    out[np.searchsorted(np.concatenate(params), u[:-1])] = pts     # exactly through the points
    return out


def closed_bezier_polygon(pts: np.ndarray) -> np.ndarray:
    """The control polygon of the closed Bézier curve on the points: the points, with the middle
    M of the closing side first and last, so the curve closes smoothly at M (equal tangents)."""
    middle = (pts[-1] + pts[0]) / 2
    return np.vstack([middle, pts, middle])


def bezier_curve(control: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The Bézier curve of a control polygon at parameters ``s`` in [0, 1]: Σ B_i,n(s) P_i in
    Bernstein form (SciPy's BPoly). Every point pulls the whole curve (global control)."""
    from scipy.interpolate import BPoly
    return BPoly(np.asarray(control, float)[:, None, :], [0.0, 1.0])(s)


def bezier_curve_outline(pts: np.ndarray, step: float) -> np.ndarray:
    """One closed Bézier curve whose control polygon is the points (`closed_bezier_polygon`).
    Sampled so that points lie at most ``step`` apart: |B'(s)| ≤ n · the longest side."""
    control = closed_bezier_polygon(pts)
    sides = np.linalg.norm(np.diff(control, axis=0), axis=1)
    n = _pieces((len(control) - 1) * float(sides.max()), step)
    return bezier_curve(control, np.arange(n) / n)


def uniform_bspline(pts: np.ndarray):
    """The closed uniform cubic B-spline whose control points are ``pts`` (n ≥ 3), on [0, n):
    piece i (s in [i, i + 1)) depends on P_i .. P_i+3 (indices mod n) and on nothing else."""
    from scipy.interpolate import BSpline
    n = len(pts)
    coefficients = np.asarray(pts, float)[np.arange(n + 3) % n]
    return BSpline(np.arange(-3.0, n + 4), coefficients, 3, extrapolate=False)


def uniform_bspline_outline(pts: np.ndarray, step: float) -> np.ndarray:
    """The closed uniform cubic B-spline on the points, piece by piece, sampled at most ``step``
    apart: a piece's speed is at most 3 × the longest side of its Bézier polygon, whose sides
    are |P2 − P0|/6, |P2 − P1|/3 and |P3 − P1|/6."""
    curve, n = uniform_bspline(pts), len(pts)
    p1, p2 = np.roll(pts, -1, axis=0), np.roll(pts, -2, axis=0)
    sides = np.column_stack([np.linalg.norm(p2 - pts, axis=1) / 6,
                             np.linalg.norm(p2 - p1, axis=1) / 3,
                             np.linalg.norm(np.roll(pts, -3, axis=0) - p1, axis=1) / 6])
    params = []
    for i in range(n):
        k = _pieces(3 * float(sides[i].max()), step)
        params.append(i + np.arange(k) / k)
    return curve(np.concatenate(params))


_OUTLINES = {"linear": linear_outline, "bezier_curve": bezier_curve_outline,
             "uniform_bspline": uniform_bspline_outline, "catmull_rom": catmull_rom_outline,
             "interpolating_spline": interpolating_spline_outline}


def fractal_curve_outline(pts: np.ndarray, step: float, roughness: float = FRACTAL_ROUGHNESS,
                          seed: int = 0) -> np.ndarray:
    """The projected-IFS (fractal Bézier) curve through the points (companion 002,
    `fractal.curves`): the Catmull–Rom curve at roughness 0, rougher towards 1, from a seed."""
    from ..fractal.curves import fractal_outline
    return fractal_outline(pts, step, roughness, seed)


@lru_cache(maxsize=512)
def _outline(envelope: Envelope, step: float) -> np.ndarray:
    pts = envelope.control_points()
    if len(pts) >= 3 and envelope.kind == "fractal_curve":
        out = fractal_curve_outline(pts, step, envelope.roughness, envelope.seed)
    else:
        out = pts if len(pts) < 3 else _OUTLINES[envelope.kind](pts, step)
    out.flags.writeable = False
    return out


def polygon_area(pts: np.ndarray) -> float:
    """Signed area (shoelace) of a closed polygon given without its repeated first point."""
    r, c = pts[:, 0], pts[:, 1]
    return 0.5 * float(np.dot(r, np.roll(c, -1)) - np.dot(c, np.roll(r, -1)))


def polygon_centroid(pts: np.ndarray) -> np.ndarray:
    r, c = pts[:, 0], pts[:, 1]
    cross = r * np.roll(c, -1) - np.roll(r, -1) * c
    area = cross.sum() / 2
    if abs(area) < MIN_AREA:
        return pts.mean(axis=0)
    return np.array([((r + np.roll(r, -1)) * cross).sum(), ((c + np.roll(c, -1)) * cross).sum()]) \
        / (6 * area)


def resample(outline: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` points equally spaced along a closed outline, with their places s in [0, 1)."""
    closed = np.vstack([outline, outline[:1]])
    seg = np.linalg.norm(np.diff(closed, axis=0), axis=1)
    cum = np.r_[0.0, np.cumsum(seg)]
    s = np.arange(n) / n
    at = s * cum[-1]
    return np.column_stack([np.interp(at, cum, closed[:, 0]), np.interp(at, cum, closed[:, 1])]), s


# -- perturbation: from the envelope to a real spot ------------------------------------------------

@dataclass(frozen=True)
class Perturbation:
    """How a real spot departs from its envelope (all zero: the envelope itself).

    ``contour``: depth of smooth bumps, as a share of the distance to the spot's centre (0..1);
    ``frequency``: bumps around the contour (its highest harmonic); ``fractal``: depth of a
    fractal roughening (0..1) with roughness exponent ``h`` (0 rough .. 1 smooth); ``interior``:
    "holes" (points left out) or "levels" (points that take another level) over a ``density``
    share of the spot, in patches of about ``scale`` points (of the envelope); or "relief"
    (the spot shaded as if lit from the top left, over a rim ``density`` of its depth).
    """

    contour: float = 0.0
    frequency: int = 6
    fractal: float = 0.0
    h: float = 0.5
    interior: str = "none"
    density: float = 0.0
    scale: float = 3.0

    def __post_init__(self):
        _number("contour depth", self.contour, 0.0, 1.0)
        _number("fractal depth", self.fractal, 0.0, 1.0)
        _number("roughness exponent h", self.h, 0.0, 1.0)
        _number("interior density", self.density, 0.0, 1.0)
        _number("interior scale", self.scale, 0.1, 1000.0)
        if isinstance(self.frequency, bool) or not isinstance(self.frequency, (int, np.integer)) \
                or not 1 <= self.frequency <= 64:
            raise InputError(f"frequency must be a whole number of bumps 1..64, "
                             f"got {self.frequency!r}")
        if self.interior not in INTERIORS:
            raise InputError(f"interior must be one of {', '.join(INTERIORS)}, "
                             f"got {self.interior!r}")


def smooth_noise(s: np.ndarray, frequency: int, rng: np.random.Generator) -> np.ndarray:
    """Periodic smooth noise of the arc-length place s, scaled to [0, 1]: harmonics 1..frequency
    with random phases and amplitudes falling as 1/k."""
    k = np.arange(1, frequency + 1)
    amp = rng.standard_normal(frequency) / k
    phase = rng.uniform(0, 2 * np.pi, frequency)
    n = (amp[None, :] * np.cos(2 * np.pi * s[:, None] * k[None, :] + phase[None, :])).sum(axis=1)
    return _unit(n)


def midpoint_displacement(depth: int, h: float, rng: np.random.Generator,
                          sigma0: float = 1.0) -> np.ndarray:
    """A closed fractal profile of 2**depth values (companion 003, in one dimension).

    Level k puts a point halfway between each pair of known neighbours: their mean plus a normal
    draw of deviation σ0·2^(−k·h). Each point is computed once and then kept (erratum: the
    slides' recursion recomputes shared points and cracks); the profile is periodic (its end
    is its start). The variogram E[(g(x+d) − g(x))²] grows about as d^(2h).
    """
    n = 2 ** depth
    g = np.zeros(n + 1)
    step, k = n, 0
    while step > 1:
        half = step // 2
        ends = g[0:n + 1:step]
        g[half:n:step] = (ends[:-1] + ends[1:]) / 2 + rng.normal(
            0.0, sigma0 * 2.0 ** (-k * h), len(ends) - 1)
        step, k = half, k + 1
    return g[:n]


def _unit(x: np.ndarray) -> np.ndarray:
    span = float(x.max() - x.min()) if len(x) else 0.0
    return (x - x.min()) / span if span > 0 else np.zeros_like(x)


def real_outline(envelope: Envelope, perturbation: Perturbation, seed: int,
                 step: float = 0.5) -> np.ndarray:
    """The perturbed outline in the envelope's coordinates: each point pulled towards the
    envelope's centroid by a factor 1 − contour·n(s) − fractal·g(s), so the real spot stays
    inside its envelope (thesis: the spot is contained in the ideal spot)."""
    outline = envelope.outline(step)
    p = perturbation
    if p.contour == 0 and p.fractal == 0:
        return outline
    perimeter = float(np.sum(np.linalg.norm(np.diff(np.vstack([outline, outline[:1]]), axis=0),
                                            axis=1)))
    depth = int(np.clip(math.ceil(math.log2(max(perimeter / step, 2))), 6, 14))
    pts, s = resample(outline, 2 ** depth)
    contour_rng, fractal_rng, _ = _streams(seed)
    factor = np.ones(len(pts))
    if p.contour:
        factor -= p.contour * smooth_noise(s, p.frequency, contour_rng)
    if p.fractal:
        factor -= p.fractal * _unit(midpoint_displacement(depth, p.h, fractal_rng))
    centre = polygon_centroid(outline)
    return centre + np.clip(factor, 0.02, 1.0)[:, None] * (pts - centre)


def _streams(seed: int) -> list[np.random.Generator]:
    """Independent streams for the contour, the fractal and the interior: changing one setting
    keeps the others' draws (the editor's preview changes only what was changed)."""
    return [np.random.default_rng(s) for s in np.random.SeedSequence(int(seed)).spawn(3)]


# -- placing: the points of a real spot on the matrix ----------------------------------------------

@dataclass(frozen=True)
class Stamp:
    """A real spot's points in a box whose corner is (top, left) on the (unbounded) plane.

    ``mask``: the spot's points; ``steps``: how many times the level shift applies at each point
    (0 for most; 1 on interior patches; +1 and −1 on the lit and shaded rims of a relief).
    """

    top: int
    left: int
    mask: np.ndarray
    steps: np.ndarray = field(default=None)

    def __post_init__(self):
        steps = np.zeros(self.mask.shape, np.int8) if self.steps is None else \
            np.asarray(self.steps).astype(np.int8)
        object.__setattr__(self, "steps", steps)

    @property
    def alt(self) -> np.ndarray:
        """The points whose level is shifted (a subset of the mask)."""
        return self.steps != 0

    @property
    def shape(self) -> tuple[int, int]:
        return self.mask.shape

    @property
    def area(self) -> int:
        return int(self.mask.sum())

    @property
    def nbytes(self) -> int:
        return self.mask.nbytes + self.steps.nbytes


@dataclass(frozen=True)
class Placement:
    """Where a spot goes: the envelope's centre lands on ``centre`` (row, col), turned ``angle``
    degrees counter-clockwise and scaled by ``scale``."""

    centre: tuple[float, float]
    angle: float = 0.0
    scale: float = 1.0

    def matrix(self) -> np.ndarray:
        return self.scale * np.array(rotation_matrix(self.angle), dtype=float)

    def apply(self, envelope: Envelope, pts: np.ndarray) -> np.ndarray:
        """Envelope coordinates → plane coordinates."""
        return np.asarray(self.centre) + (pts - envelope.centre) @ self.matrix().T

    def invert(self, envelope: Envelope, pts: np.ndarray) -> np.ndarray:
        """Plane coordinates → envelope coordinates."""
        return envelope.centre + (pts - np.asarray(self.centre)) @ np.linalg.inv(self.matrix()).T


def placed_outline(envelope: Envelope, perturbation: Perturbation | None = None, seed: int = 0,
                   placement: Placement | None = None) -> np.ndarray:
    """The (real, when perturbed) outline on the plane: what a tool draws as a ghost."""
    placement = placement or Placement(tuple(envelope.centre))
    step = 0.5 / placement.scale
    local = envelope.outline(step) if perturbation is None else \
        real_outline(envelope, perturbation, seed, step)
    return placement.apply(envelope, local)


def real_spot(envelope: Envelope, perturbation: Perturbation | None = None, *, seed: int = 0,
              placement: Placement | None = None, clip=None) -> Stamp:
    """Rasterise a real spot: its perturbed outline (skimage.draw.polygon, point centres inside),
    kept within the envelope's own points, then the interior perturbation.

    An envelope without area is an InputError; a spot smaller than a point still marks the point
    nearest its centre, so a placement is never silently empty.

    ``clip`` (top, left, bottom, right) on the plane: only the spot's points in that box are
    rasterised (a placement's canvas), and the stamp covers only its part of the box (it may
    then be empty). Those points are exactly the whole spot's points there: each point of the
    outline mask and of the holes and patches depends on that point alone. A relief depends on
    the whole spot (its distance to the edge), so it is rasterised whole, then cut, and refused
    above MAX_RELIEF_POINTS.
    """
    perturbation = perturbation or Perturbation()
    placement = placement or Placement(tuple(envelope.centre))
    if not 1e-3 <= placement.scale <= 1e3:
        raise InputError(f"the scale must be within 0.001..1000, got {placement.scale:g}")
    step = 0.5 / placement.scale
    env_local = envelope.outline(step)
    if len(env_local) < 3 or abs(polygon_area(env_local)) < MIN_AREA:
        raise InputError("this envelope has no width: drag a meridian's end away from the "
                         "equator (or draw a contour that encloses an area)")
    env_plane = placement.apply(envelope, env_local)
    top, left = (int(math.floor(v)) for v in env_plane.min(axis=0))
    bottom, right = (int(math.ceil(v)) + 1 for v in env_plane.max(axis=0))
    if bottom - top > MAX_STAMP_SIDE or right - left > MAX_STAMP_SIDE:
        raise InputError(f"this spot would span {right - left}×{bottom - top} points, more "
                         f"than {MAX_STAMP_SIDE}: place it smaller")
    shape = (bottom - top, right - left)
    relief = perturbation.interior == "relief" and perturbation.density > 0
    if relief and shape[0] * shape[1] > MAX_RELIEF_POINTS:
        raise InputError(f"a relief spot may span at most {MAX_RELIEF_POINTS:,} points; this "
                         f"one spans {shape[1]}×{shape[0]}: place it smaller")
    window = None
    if clip is not None and not relief:
        window = (clip[0] - top, clip[2] - top, clip[1] - left, clip[3] - left)
    real = None
    if perturbation.contour or perturbation.fractal:
        real = placement.apply(envelope, real_outline(envelope, perturbation, seed, step))
    mask = _polygon_mask(env_plane, top, left, shape, window)
    if real is not None:
        mask &= _polygon_mask(real, top, left, shape, window)
    r_off, c_off = (0, 0) if window is None else (max(window[0], 0), max(window[2], 0))
    if not mask.any():
        centre = polygon_centroid(env_plane)
        r, c = (int(np.clip(math.floor(v + 0.5) - o, 0, n - 1))
                for v, o, n in zip(centre, (top, left), shape))
        if 0 <= r - r_off < mask.shape[0] and 0 <= c - c_off < mask.shape[1] and \
                (window is None or not _any_point(env_plane, real, top, left, shape)):
            mask[r - r_off, c - c_off] = True
    top, left = top + r_off, left + c_off
    steps = np.zeros(mask.shape, np.int8)
    if relief:
        steps = _relief(mask, perturbation.density)
    elif perturbation.interior != "none" and perturbation.density > 0 and mask.any():
        marked = _interior_marks(envelope, perturbation, seed, placement, env_local, top, left,
                                 mask)
        if perturbation.interior == "holes":
            mask &= ~marked
        else:
            steps[marked] = 1
    stamp = Stamp(top, left, mask, steps)
    if clip is not None and relief:
        stamp = _cut(stamp, clip)
    return stamp


def _any_point(env_plane, real, top: int, left: int, shape) -> bool:
    """Whether the whole spot (envelope ∩ real outline) has a point, by bands of rows."""
    band = max(1, (1 << 24) // max(shape[1], 1))
    for a in range(0, shape[0], band):
        window = (a, min(a + band, shape[0]), 0, shape[1])
        mask = _polygon_mask(env_plane, top, left, shape, window)
        if real is not None and mask.any():
            mask &= _polygon_mask(real, top, left, shape, window)
        if mask.any():
            return True
    return False


def _cut(stamp: Stamp, clip) -> Stamp:
    """The part of a stamp inside the box ``clip`` (top, left, bottom, right)."""
    t, l = max(stamp.top, clip[0]), max(stamp.left, clip[1])
    b = max(min(stamp.top + stamp.shape[0], clip[2]), t)
    r = max(min(stamp.left + stamp.shape[1], clip[3]), l)
    rs, cs = slice(t - stamp.top, b - stamp.top), slice(l - stamp.left, r - stamp.left)
    return Stamp(t, l, stamp.mask[rs, cs].copy(), stamp.steps[rs, cs].copy())


def _relief(mask: np.ndarray, density: float) -> np.ndarray:
    """A spot shaded as if lit from the top left: within ``density`` of the way from its edge to
    its heart, the rim that faces the light goes one step up and the other one step down (the
    light is the plane's, so a turned spot keeps its light)."""
    from scipy import ndimage
    depth = ndimage.distance_transform_edt(np.pad(mask, 1))[1:-1, 1:-1]
    rim = mask & (depth <= max(1.0, density * float(depth.max())))
    g_row, g_col = np.gradient(ndimage.gaussian_filter(depth, 1.0))
    norm = np.hypot(g_row, g_col) + 1e-12
    facing = -(g_row * LIGHT[0] + g_col * LIGHT[1]) / norm     # outward normal · light
    steps = np.zeros(mask.shape, np.int8)
    steps[rim & (facing > 0.35)] = 1
    steps[rim & (facing < -0.35)] = -1
    return steps


def _polygon_mask(pts: np.ndarray, top: int, left: int, shape, window=None) -> np.ndarray:
    return polygon_mask(pts[:, 0] - top, pts[:, 1] - left, shape, window)


def polygon_mask(rows, cols, shape, window=None) -> np.ndarray:
    """The points (centres at integer coordinates) inside a closed polygon, even-odd rule.

    Same points as ``skimage.draw.polygon`` (away from the outline itself), by scanlines:
    skimage tests every point of the box against every edge, and a spot outline has thousands of
    edges (0.4 s for a 500-point spot); here each edge only meets the rows it crosses. Rows and
    columns are half-open, [ceil(lo), ceil(hi)), as in GPU rasterisers: a vertex on a row counts
    once, a 10×10 square gives 100 points, and spots that share an edge share no point.

    ``window`` (r0, r1, c0, c1) computes only ``full[r0:r1, c0:c1]`` of the full mask, with the
    same arithmetic on the same coordinates, so the points are exactly those of the full mask
    (a spot clipped to the canvas). Rows are done in bands, so the scratch memory stays a small
    multiple of the mask's own (a mask of 16384² points no longer needs 3 GB of counters).
    """
    H, W = shape
    r0, r1, c0, c1 = (0, H, 0, W) if window is None else window
    r0, r1 = max(int(r0), 0), min(int(r1), H)
    c0, c1 = max(int(c0), 0), min(int(c1), W)
    mask = np.zeros((max(r1 - r0, 0), max(c1 - c0, 0)), dtype=bool)
    if not mask.size:
        return mask
    r, c = np.asarray(rows, dtype=float), np.asarray(cols, dtype=float)
    r2, c2 = np.roll(r, -1), np.roll(c, -1)
    lo_r, hi_r = np.ceil(np.minimum(r, r2)), np.ceil(np.maximum(r, r2))
    band = max(1, (1 << 24) // max(c1 - c0 + 1, 1))
    for a in range(r0, r1, band):
        b = min(a + band, r1)
        y0 = np.clip(lo_r, a, b).astype(np.int64)
        y1 = np.clip(hi_r, a, b).astype(np.int64)
        counts = y1 - y0
        edges = np.repeat(np.arange(len(r)), counts)
        if not len(edges):
            continue
        ys = y0[edges] + np.arange(len(edges)) - np.repeat(np.cumsum(counts) - counts, counts)
        dr = r2[edges] - r[edges]
        xs = c[edges] + (ys - r[edges]) * (c2[edges] - c[edges]) / dr
        order = np.lexsort((xs, ys))
        ys, xs = ys[order], xs[order]
        row = ys[0::2] - a
        start = np.clip(np.ceil(xs[0::2]), c0, c1).astype(np.int64) - c0
        stop = np.clip(np.ceil(xs[1::2]), c0, c1).astype(np.int64) - c0
        run = stop > start
        diff = np.zeros((b - a, c1 - c0 + 1), dtype=np.int8)     # a row's runs are disjoint:
        np.add.at(diff, (row[run], start[run]), 1)              # its sums are 0 or 1
        np.add.at(diff, (row[run], stop[run]), -1)
        mask[a - r0:b - r0] = np.cumsum(diff[:, :c1 - c0], axis=1, dtype=np.int8) > 0
    return mask


def _interior_marks(envelope, perturbation, seed, placement, env_local, top, left, mask):
    """The points of the spot that the interior perturbation marks: a smooth noise field drawn in
    the envelope's own coordinates (so holes turn and scale with the spot), thresholded so that
    a ``density`` share of the envelope is marked."""
    from scipy import ndimage
    lo, hi = env_local.min(axis=0) - 1, env_local.max(axis=0) + 1
    extent = float(max(hi - lo))
    cell = float(np.clip(perturbation.scale / 3, extent / 128, max(extent / 24, 1e-3)))
    grid = tuple(int(math.ceil(v / cell)) + 2 for v in hi - lo)
    rng = _streams(seed)[2]
    noise = ndimage.gaussian_filter(rng.standard_normal(grid), perturbation.scale / cell / 2,
                                    mode="wrap")
    inside = _polygon_mask((env_local - lo) / cell, 0, 0, grid)
    values = noise[inside] if inside.any() else noise.ravel()
    threshold = np.quantile(values, 1.0 - perturbation.density)
    marked = np.zeros_like(mask)
    band = max(1, MARK_POINTS // max(mask.shape[1], 1))
    for a in range(0, mask.shape[0], band):      # by bands: 32 bytes a point while mapped
        rows, cols = np.nonzero(mask[a:a + band])
        plane = np.column_stack([rows + a + top, cols + left]).astype(float)
        local = (placement.invert(envelope, plane) - lo) / cell
        sampled = ndimage.map_coordinates(noise, local.T, order=1, mode="nearest")
        marked[rows + a, cols] = sampled > threshold if perturbation.density < 1 else True
    return marked


# -- filling and blending: the spot's levels on the matrix -----------------------------------------

def tile(texture, top: int, left: int, shape, offset=(0, 0)) -> np.ndarray:
    """The block of a lower-level texture seen through a box at (top, left) of the plane, the
    texture repeated in both directions and read ``offset`` (rows, cols) away."""
    texture = np.asarray(texture)
    h, w = texture.shape
    rows = (np.arange(shape[0]) + top + offset[0]) % h
    cols = (np.arange(shape[1]) + left + offset[1]) % w
    return texture[np.ix_(rows, cols)]


def spot_levels(stamp: Stamp, fill, *, shift: int = 1, num_levels: int = 256,
                offset=(0, 0)) -> np.ndarray:
    """The levels a spot writes over its box: one level, or a lower-level texture (a level
    matrix, repeated, read ``offset`` away); each point moves ``steps`` × ``shift`` levels."""
    if np.ndim(fill) == 0:
        values = np.full(stamp.shape, int(fill), dtype=np.int16)
    else:
        values = tile(fill, stamp.top, stamp.left, stamp.shape, offset).astype(np.int16)
    if stamp.steps.any():
        values += stamp.steps.astype(np.int16) * shift
    return np.clip(values, 0, num_levels - 1).astype(np.uint8)


def blend(current: np.ndarray, mask: np.ndarray, values: np.ndarray, rule: str) -> np.ndarray:
    """Superpose a spot on a block: "over" (the spot covers), "under" (it shows only on the
    background, level 0), "max" or "min" of the two levels."""
    out = current.copy()
    if rule == "over":
        out[mask] = values[mask]
    elif rule == "under":
        where = mask & (current == 0)
        out[where] = values[where]
    elif rule == "max":
        out[mask] = np.maximum(current[mask], values[mask])
    elif rule == "min":
        out[mask] = np.minimum(current[mask], values[mask])
    else:
        raise InputError(f"blend must be one of {', '.join(BLENDS)}, got {rule!r}")
    return out


def pieces(stamp: Stamp, shape, wrap: bool = False):
    """Where a stamp lands on a canvas of ``shape``: (top, left, rows, cols) per piece, with the
    stamp's slices. Without wrap, the part outside is dropped; with wrap the canvas is one tile of
    a periodic plane and the stamp may land in up to four pieces (more for a huge stamp)."""
    H, W = shape
    h, w = stamp.shape
    if not wrap:
        t, l = max(stamp.top, 0), max(stamp.left, 0)
        b, r = min(stamp.top + h, H), min(stamp.left + w, W)
        if b <= t or r <= l:
            return []
        return [(t, l, slice(t - stamp.top, b - stamp.top), slice(l - stamp.left, r - stamp.left))]
    return [(t, l, rs, cs) for t, rs in _wrapped(stamp.top, h, H)
            for l, cs in _wrapped(stamp.left, w, W)]


def _wrapped(start: int, n: int, size: int):
    """Runs of a 1-D interval on a circle of ``size``: (canvas start, slice of the interval)."""
    out, k = [], 0
    while k < n:
        at = (start + k) % size
        run = min(size - at, n - k)
        out.append((at, slice(k, k + run)))
        k += run
    return out


def place(levels, stamp: Stamp, fill, *, blend_rule: str = "over", shift: int = 1,
          wrap: bool = False, num_levels: int = 256) -> np.ndarray:
    """A new level matrix with the spot placed (pure: the input is left alone)."""
    out = np.array(levels, dtype=np.uint8, copy=True)
    values = spot_levels(stamp, fill, shift=shift, num_levels=num_levels)
    for t, l, rs, cs in pieces(stamp, out.shape, wrap):
        block = out[t:t + rs.stop - rs.start, l:l + cs.stop - cs.start]
        block[...] = blend(block, stamp.mask[rs, cs], values[rs, cs], blend_rule)
    return out
