"""Iterated function systems (companion 002, Guérin; digest §11): K_{n+1} = ∪ T_i(K_n), drawn by
the chaos game into a density of any size — motifs an artist stamps on a texture.

Maps are affine in (x, y) with y up, x' = a x + b y + e, y' = c x + d y + f; the picture puts
the attractor's box in the middle of the frame, its aspect kept, y drawn upwards.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..errors import InputError

MAX_POINTS = 1 << 26            # chaos-game points: one byte of choice each
MAX_SIDE = 8192
BURN_IN = 32                    # points dropped before the orbit is on the attractor (2^-32 away)


@dataclass(frozen=True)
class IFS:
    """Affine maps (K, 6) as rows (a, b, c, d, e, f) and the chance of each in the chaos game."""

    maps: tuple
    probs: tuple

    def matrices(self) -> np.ndarray:
        return np.asarray(self.maps, np.float64).reshape(-1, 6)

    def apply(self, i: int, xy: np.ndarray) -> np.ndarray:
        """Map T_i applied to points (N, 2) in (x, y)."""
        a, b, c, d, e, f = self.matrices()[i]
        return np.column_stack([a * xy[:, 0] + b * xy[:, 1] + e, c * xy[:, 0] + d * xy[:, 1] + f])


def similitude(scale: float, angle: float = 0.0, dx: float = 0.0, dy: float = 0.0) -> tuple:
    """T(dx, dy) R(angle) H(scale) as (a, b, c, d, e, f): the digest's notation."""
    c, s = math.cos(angle) * scale, math.sin(angle) * scale
    return (c, -s, s, c, dx, dy)


def _tree() -> IFS:
    """The digest's tree: T0 = H(½), T1 = T(0,½)H(½), T2 = T(0,1)R(π/4)H(½),
    T3 = T(0,1)R(−π/4)H(½): a trunk [0, 1] that bears two half-size copies of the tree."""
    maps = (similitude(0.5), similitude(0.5, 0, 0, 0.5), similitude(0.5, math.pi / 4, 0, 1),
            similitude(0.5, -math.pi / 4, 0, 1))
    return IFS(maps, (0.25, 0.25, 0.25, 0.25))


BUILTINS = {
    "tree": _tree(),
    "fern": IFS(((0.0, 0.0, 0.0, 0.16, 0.0, 0.0), (0.85, 0.04, -0.04, 0.85, 0.0, 1.6),
                 (0.2, -0.26, 0.23, 0.22, 0.0, 1.6), (-0.15, 0.28, 0.26, 0.24, 0.0, 0.44)),
                (0.01, 0.85, 0.07, 0.07)),                      # Barnsley's fern
    "sierpinski": IFS((similitude(0.5), similitude(0.5, 0, 0.5, 0),
                       similitude(0.5, 0, 0.25, math.sqrt(3) / 4)), (1 / 3, 1 / 3, 1 / 3)),
}


def builtin(name) -> IFS:
    if not isinstance(name, str) or name not in BUILTINS:
        raise InputError(f"the IFS motif must be one of {', '.join(BUILTINS)}, got {name!r}")
    return BUILTINS[name]


def _choices(ifs: IFS, points: int, seed: int) -> np.ndarray:
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) \
            or not 1 <= points <= MAX_POINTS:
        raise InputError(f"the number of points must be 1..{MAX_POINTS}, got {points!r}")
    p = np.asarray(ifs.probs, np.float64)
    return np.random.default_rng(int(seed)).choice(len(p), size=int(points) + BURN_IN,
                                                   p=p / p.sum()).astype(np.uint8)


@njit(cache=True)
def _orbit(maps, choices, out):
    x, y = 0.0, 0.0
    for k in range(choices.shape[0]):
        m = maps[choices[k]]
        x, y = m[0] * x + m[1] * y + m[4], m[2] * x + m[3] * y + m[5]
        if k >= BURN_IN:
            out[k - BURN_IN, 0] = x
            out[k - BURN_IN, 1] = y


@njit(cache=True)
def _box(maps, choices):
    x, y = 0.0, 0.0
    lo_x, lo_y, hi_x, hi_y = np.inf, np.inf, -np.inf, -np.inf
    for k in range(choices.shape[0]):
        m = maps[choices[k]]
        x, y = m[0] * x + m[1] * y + m[4], m[2] * x + m[3] * y + m[5]
        if k >= BURN_IN:
            lo_x, lo_y = min(lo_x, x), min(lo_y, y)
            hi_x, hi_y = max(hi_x, x), max(hi_y, y)
    return lo_x, lo_y, hi_x, hi_y


@njit(cache=True)
def _density(maps, choices, frame, counts):
    s, x0, y1, r0, c0 = frame[0], frame[1], frame[2], frame[3], frame[4]
    h, w = counts.shape
    x, y = 0.0, 0.0
    for k in range(choices.shape[0]):
        m = maps[choices[k]]
        x, y = m[0] * x + m[1] * y + m[4], m[2] * x + m[3] * y + m[5]
        if k >= BURN_IN:
            r = int(math.floor(r0 + (y1 - y) * s))
            c = int(math.floor(c0 + (x - x0) * s))
            if 0 <= r < h and 0 <= c < w:
                counts[r, c] += 1


def ifs_points(ifs: IFS, points: int, seed: int = 0) -> np.ndarray:
    """The chaos game's orbit (points, 2) in (x, y), after BURN_IN steps: on the attractor."""
    choices = _choices(ifs, points, seed)
    out = np.empty((int(points), 2))
    _orbit(ifs.matrices(), choices, out)
    return out


@dataclass(frozen=True)
class Frame:
    """Plane (x, y) → picture (row, col): row = r0 + (y1 − y)·scale, col = c0 + (x − x0)·scale."""

    scale: float
    x0: float
    y1: float
    r0: float
    c0: float

    def to_pixels(self, xy: np.ndarray) -> np.ndarray:
        return np.column_stack([self.r0 + (self.y1 - xy[:, 1]) * self.scale,
                                self.c0 + (xy[:, 0] - self.x0) * self.scale])


def fit(box, shape) -> Frame:
    """The frame that puts the box (x0, y0, x1, y1) in the middle of ``shape``, aspect kept."""
    x0, y0, x1, y1 = box
    h, w = shape
    scale = min(w / max(x1 - x0, 1e-12), h / max(y1 - y0, 1e-12)) * (1 - 1e-9)
    return Frame(scale, x0, y1, (h - (y1 - y0) * scale) / 2, (w - (x1 - x0) * scale) / 2)


def ifs_attractor(ifs, shape, *, points: int = 1_000_000, seed: int = 0,
                  frame: Frame | None = None) -> np.ndarray:
    """How many chaos-game points fell on each point of an (H, W) picture (uint32): > 0 is the
    attractor's mask. ``ifs`` is an IFS or a built-in's name ("tree", "fern", "sierpinski").
    The same seed draws the same orbit, so the picture replays bit for bit."""
    ifs = ifs if isinstance(ifs, IFS) else builtin(ifs)
    h, w = _shape(shape)
    choices = _choices(ifs, points, seed)
    maps = ifs.matrices()
    if frame is None:
        frame = fit(_box(maps, choices), (h, w))
    counts = np.zeros((h, w), np.uint32)
    _density(maps, choices, np.array([frame.scale, frame.x0, frame.y1, frame.r0, frame.c0]),
             counts)
    return counts


def attractor_frame(ifs, shape, *, points: int = 1_000_000, seed: int = 0) -> Frame:
    """The frame `ifs_attractor` draws in (to map plane points onto its picture)."""
    ifs = ifs if isinstance(ifs, IFS) else builtin(ifs)
    return fit(_box(ifs.matrices(), _choices(ifs, points, seed)), _shape(shape))


def _shape(shape) -> tuple[int, int]:
    return checked_shape(shape, MAX_SIDE, "an IFS picture")


def checked_shape(shape, most: int, what: str) -> tuple[int, int]:
    """(h, w) of whole numbers 1..most, or an InputError naming ``what``."""
    try:
        h, w = (int(v) for v in shape)
        ok = all(float(v) == int(v) for v in shape)
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or not (1 <= h <= most and 1 <= w <= most):
        raise InputError(f"{what} is 1..{most} points a side, got {shape!r}")
    return h, w
