"""Heeger–Bergen synthesis as an Action: a new canvas drawn from an exemplar photo's pyramid
sub-band histograms, cut into G levels like the other models (`spectral.actions.ModelCanvas`).

It names its exemplar by reference, so it replays from a file or the bank; being slow (about a
second at 512²), it runs in the worker with progress and Cancel (`prepare`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..recipe.actions import param, register
from ..spectral.actions import MAX_MODEL_SIDE, ModelCanvas, levels_param
from .synthesis import ITERATIONS, MAX_ITERATIONS, heeger_bergen

MAX_SIDE = MAX_MODEL_SIDE


@register
@dataclass(frozen=True)
class HeegerBergen(ModelCanvas):
    """A canvas of Heeger–Bergen texture of an exemplar: seeded noise given the photo's
    histograms of steerable-pyramid sub-bands and of grey levels (colour: of its principal
    components), any size, tileable."""

    TYPE: ClassVar[str] = "heeger_bergen"
    EFFECT: ClassVar[str] = "reset"
    exemplar: str = param("exemplar", doc="reference of an exemplar photo of the document")
    width: int = param("int", 16, MAX_SIDE, doc="points across (16 at least: the pyramid's)")
    height: int = param("int", 16, MAX_SIDE, doc="points down (16 at least: the pyramid's)")
    seed: int = param("seed", default=0, doc="random seed of the noise: same seed, same texture")
    iterations: int = param("int", 0, MAX_ITERATIONS, default=ITERATIONS,
                            doc="rounds of histogram matching (about five suffice)")
    levels: int = levels_param()

    def picture(self, image, progress=None, cancel=None):
        return heeger_bergen(image, (self.height, self.width), seed=self.seed,
                             iterations=self.iterations, progress=progress, cancel=cancel)

    def canvas_shape(self, shape):
        return (self.height, self.width)

    def covers(self, shape):
        return True

    def label(self) -> str:
        return (f"Heeger–Bergen {self.width}×{self.height}, seed {self.seed}, "
                f"{self.iterations} iterations, G = {self.levels}")
