"""The flow texture as an Action: a new canvas of noise smoothed along a photo's orientation
field or along strokes the user drew (`texture.flow_texture`), cut into G levels like the other
models (`spectral.actions.ModelCanvas`).

The strokes are parameters (segments in the output's points), the photo an exemplar named by
reference, the noise seeded: the step replays bit for bit from a file or the bank. A 2048²
texture takes seconds, so it runs in the worker with progress and Cancel (`prepare`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import InputError
from ..recipe.actions import MAX_CANVAS_SIDE, param, register
from ..spectral.actions import MAX_MODEL_SIDE, ModelCanvas, exemplar_of, levels_param, model_levels
from .lic import MAX_LENGTH
from .texture import LENGTH, SIGMA, flow_texture

SOURCES = ("photo", "strokes")
MAX_SEGMENTS = 1024          # a drawn field costs grid nodes × segments (× 9 on the torus)
MAX_SIGMA = 64.0


@register
@dataclass(frozen=True)
class FlowTexture(ModelCanvas):
    """A canvas of line integral convolution: seeded noise smoothed along the orientation
    field of a photo (its structure tensor) or of drawn strokes, any size; with a photo its
    greys follow the photo's."""

    TYPE: ClassVar[str] = "flow_texture"
    EFFECT: ClassVar[str] = "reset"
    source: str = param("str", hi=16, doc="where the field comes from: photo or strokes")
    exemplar: str | None = param("exemplar", optional=True, doc="reference of an exemplar photo "
                                 "(the field of source photo; the greys); none: standard greys")
    strokes: tuple = param("points", -MAX_CANVAS_SIDE, 2 * MAX_CANVAS_SIDE, default=(),
                           doc="the drawn field's segments: pairs of (row, col) points in the "
                               "output's points (source strokes)")
    width: int = param("int", 16, MAX_MODEL_SIDE, default=256, doc="points across")
    height: int = param("int", 16, MAX_MODEL_SIDE, default=256, doc="points down")
    seed: int = param("seed", default=0, doc="random seed of the noise: same seed, same texture")
    length: float = param("float", 1, MAX_LENGTH, default=LENGTH,
                          doc="streamline length L (points): how long the grain is")
    sigma: float = param("float", 0.5, MAX_SIGMA, default=SIGMA,
                         doc="smoothing of the photo's field (photo points)")
    tileable: bool = param("bool", default=False, doc="on the torus: the texture repeats "
                                                      "without a seam when its field does")
    levels: int = levels_param()

    def _validate(self) -> None:
        if self.source not in SOURCES:
            raise InputError(f"source must be one of {', '.join(SOURCES)}, got {self.source!r}")
        if self.source == "photo":
            if self.exemplar is None:
                raise InputError("a flow texture from a photo's field needs the photo (exemplar)")
            if self.strokes:
                raise InputError("a flow texture from a photo's field takes no strokes")
            return
        if len(self.strokes) % 2:
            raise InputError("strokes are segments: an even number of (row, col) points")
        if not 1 <= len(self.strokes) // 2 <= MAX_SEGMENTS:
            raise InputError(f"a drawn field needs 1..{MAX_SEGMENTS} segments, "
                             f"got {len(self.strokes) // 2}")
        if all(a == b for a, b in zip(self.strokes[::2], self.strokes[1::2])):
            raise InputError("draw at least one stroke with a length to give a direction")

    def segments(self) -> list:
        """The strokes as two-point polylines, for `strokes_field`."""
        return [list(pair) for pair in zip(self.strokes[::2], self.strokes[1::2])]

    def prepare(self, doc, progress=None, cancel=None):
        photo = None if self.exemplar is None else exemplar_of(doc, self.exemplar)
        picture = flow_texture((self.height, self.width), photo=photo,
                               strokes=self.segments() if self.source == "strokes" else None,
                               seed=self.seed, length=self.length, sigma=self.sigma,
                               wrap=self.tileable, progress=progress, cancel=cancel)
        return model_levels(np.round(picture * 255).astype(np.uint8), self.levels)

    def canvas_shape(self, shape):
        return (self.height, self.width)

    def covers(self, shape):
        return True

    def label(self) -> str:
        field = "drawn field" if self.source == "strokes" else "photo's field"
        return (f"Flow texture ({field}) {self.width}×{self.height}, seed {self.seed}, "
                f"L = {self.length:g}, G = {self.levels}")


def strokes_param(polylines) -> tuple:
    """Polylines (lists of (row, col) points, floats allowed) as the step's ``strokes``:
    consecutive points rounded, repeated points dropped, each segment a pair."""
    out = []
    for line in polylines:
        points = [tuple(int(round(v)) for v in p) for p in line]
        points = [p for k, p in enumerate(points) if k == 0 or p != points[k - 1]]
        out.extend(x for a, b in zip(points, points[1:]) for x in (a, b))
    return tuple(out)
