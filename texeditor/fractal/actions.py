"""The fractal models as Actions: a canvas of midpoint-displacement heights cut into G levels
(its grey palette is the relief preview's height), and an IFS motif stamped on the canvas.

Both are drawn from their parameters and a seed alone, so they replay bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import InputError
from ..recipe.actions import Access, Action, drop_plates, param, register
from ..spectral.actions import MAX_MODEL_SIDE, levels_param, model_levels
from .ifs import BUILTINS, builtin, ifs_attractor
from .midpoint import midpoint_displacement

MAX_MOTIF_SIDE = 4096
MAX_MOTIF_POINTS = 1 << 24


def heights_picture(heights: np.ndarray) -> np.ndarray:
    """Heights as greys 0..255 (lowest black, highest white): what the levels are cut from."""
    lo, hi = float(heights.min()), float(heights.max())
    span = hi - lo if hi > lo else 1.0
    return np.round((heights - lo) * (255 / span)).astype(np.uint8)


@register
@dataclass(frozen=True)
class FractalRelief(Action):
    """A canvas of 2-D midpoint-displacement heights (companion 003), any size, tileable, cut
    into G levels whose greys rise with the height: the Relief dock shades it as terrain."""

    TYPE: ClassVar[str] = "fractal_relief"
    EFFECT: ClassVar[str] = "reset"
    width: int = param("int", 1, MAX_MODEL_SIDE, doc="points across")
    height: int = param("int", 1, MAX_MODEL_SIDE, doc="points down")
    seed: int = param("seed", default=0, doc="random seed of the displacements")
    roughness: float = param("float", 0.0, 1.0, default=0.5,
                             doc="H: 1 smooth hills, 0 rough (deviation ×2^−H a level)")
    levels: int = levels_param()

    def prepare(self, doc, progress=None, cancel=None):
        field = midpoint_displacement((self.height, self.width), self.roughness, seed=self.seed)
        return model_levels(heights_picture(field), self.levels)

    def apply(self, doc, prepared=None) -> None:
        levels, palette = self.prepare(doc) if prepared is None else prepared
        drop_plates(doc)
        doc.set_levels(levels, palette)

    def canvas_shape(self, shape):
        return (self.height, self.width)

    def covers(self, shape):
        return True

    def label(self) -> str:
        return (f"Fractal relief {self.width}×{self.height}, H {self.roughness:g}, "
                f"seed {self.seed}, G = {self.levels}")


@register
@dataclass(frozen=True)
class IFSMotif(Action):
    """An IFS attractor (the digest's tree, Barnsley's fern, Sierpinski's triangle) stamped
    in one level on the canvas, in a ``size``-point square centred on (row, col), the points
    the chaos game reaches at least ``density`` times painted."""

    TYPE: ClassVar[str] = "ifs_motif"
    EFFECT: ClassVar[str] = "levels"
    motif: str = param("str", hi=32, doc=f"built-in IFS: {', '.join(BUILTINS)}")
    row: int = param("int", -MAX_MOTIF_SIDE, 65536, doc="row of the motif's centre")
    col: int = param("int", -MAX_MOTIF_SIDE, 65536, doc="column of the motif's centre")
    size: int = param("int", 1, MAX_MOTIF_SIDE, doc="side of the motif's square, points")
    level: int = param("int", 0, 255, doc="level painted")
    seed: int = param("seed", default=0, doc="random seed of the chaos game")
    points: int = param("int", 1, MAX_MOTIF_POINTS, default=200_000,
                        doc="chaos-game points (more: a denser motif)")
    density: int = param("int", 1, 1000, default=1,
                         doc="hits a point needs to be painted (higher: only the densest parts)")

    def _validate(self) -> None:
        builtin(self.motif)

    def box(self) -> tuple[int, int, int, int]:
        """(top, left, height, width) of the motif's square on the plane."""
        return self.row - self.size // 2, self.col - self.size // 2, self.size, self.size

    def mask(self) -> np.ndarray:
        return ifs_attractor(self.motif, (self.size, self.size), points=self.points,
                             seed=self.seed) >= self.density

    def apply(self, doc, prepared=None) -> None:
        if not doc.levels.size:
            raise InputError("an IFS motif is stamped on a texture: make or open one first")
        if self.level >= doc.num_levels:
            raise InputError(f"level {self.level} is not one of this texture's "
                             f"0..{doc.num_levels - 1}")
        mask = self.mask() if prepared is None else prepared
        top, left, h, w = self.box()
        H, W = doc.shape
        t, l, b, r = max(top, 0), max(left, 0), min(top + h, H), min(left + w, W)
        if b <= t or r <= l:
            return
        block = doc.levels[t:b, l:r].copy()
        block[mask[t - top:b - top, l - left:r - left]] = self.level
        doc.write(t, l, block)

    def prepare(self, doc, progress=None, cancel=None):
        return self.mask()

    def access(self, shape):
        return Access(writes=(self.box(),))

    def label(self) -> str:
        return f"IFS {self.motif} {self.size}² at ({self.row}, {self.col}), level {self.level}"
