"""The micro-texture models as Actions: a canvas from an exemplar photo's random-phase noise or
texton, and a palette that gives the picture an exemplar's histogram (digest §11).

Each names its exemplar by reference (`recipe.exemplars`), so the step replays from a file or
the bank bit for bit. A model's output becomes levels like a photo does (thesis §5.2.1): cut into
G classes by `markov.levels.quantize` — Lloyd–Max on greys, k-means in CIELAB on colours — with
each class's mean colour as the palette, so every brush and region tool works on it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import ImageError, InputError
from ..markov.dpj import MAX_LEVELS
from ..recipe.actions import Action, drop_plates, param, register
from .models import random_phase_noise, texton

MAX_MODEL_SIDE = 4096            # an RPN output: its float64 FFTs of 3 channels stay < 1.5 GB


def exemplar_of(doc, ref: str) -> np.ndarray:
    image = doc.exemplars.get(ref)
    if image is None:
        raise InputError(f"exemplar {ref} is not part of this document: add the photo first")
    return image


def model_levels(picture: np.ndarray, levels: int) -> tuple[np.ndarray, np.ndarray]:
    """A model's uint8 output as (levels, palette): G classes, Lloyd on grey, CIELAB on
    colour, each class's mean colour. A constant output (a flat photo) cannot be cut."""
    from ..markov.levels import quantize
    try:
        q = quantize(picture, levels, "lab")
    except ImageError as exc:
        raise InputError(f"the model's output cannot be cut into {levels} levels: {exc}") from None
    return q.levels, q.palette


def levels_param():
    return param("int", 2, MAX_LEVELS, default=8, doc="number of levels G the output is cut into")


class ModelCanvas(Action):
    """A new canvas made of a model's output (its plates go, as with a synthesis); ``picture``
    is the model, given the exemplar (and the worker's progress and cancel, for slow ones)."""

    EFFECT: ClassVar[str] = "other"

    def picture(self, image: np.ndarray, progress=None, cancel=None) -> np.ndarray:
        raise NotImplementedError

    def prepare(self, doc, progress=None, cancel=None):
        picture = self.picture(exemplar_of(doc, self.exemplar), progress, cancel)
        return model_levels(picture, self.levels)

    def apply(self, doc, prepared=None) -> None:
        levels, palette = self.prepare(doc) if prepared is None else prepared
        drop_plates(doc)
        doc.set_levels(levels, palette)


@register
@dataclass(frozen=True)
class RandomPhaseNoise(ModelCanvas):
    """A canvas of random-phase noise of an exemplar (Desolneux–Moisan–Ronsin): its Fourier
    modulus with the phase of a seeded white noise, any size, tileable."""

    TYPE: ClassVar[str] = "random_phase_noise"
    EFFECT: ClassVar[str] = "reset"
    exemplar: str = param("exemplar", doc="reference of an exemplar photo of the document")
    width: int = param("int", 1, MAX_MODEL_SIDE, doc="points across")
    height: int = param("int", 1, MAX_MODEL_SIDE, doc="points down")
    seed: int = param("seed", default=0, doc="random seed of the phase: same seed, same texture")
    levels: int = levels_param()

    def picture(self, image, progress=None, cancel=None):
        return random_phase_noise(image, (self.height, self.width), seed=self.seed)

    def canvas_shape(self, shape):
        return (self.height, self.width)

    def covers(self, shape):
        return True

    def label(self) -> str:
        return (f"Random-phase noise {self.width}×{self.height}, seed {self.seed}, "
                f"G = {self.levels}")


@register
@dataclass(frozen=True)
class Texton(ModelCanvas):
    """A canvas of an exemplar's texton (its Fourier modulus with zero phases, centred): the
    elementary shape of its micro-texture, at the exemplar's size."""

    TYPE: ClassVar[str] = "texton"
    exemplar: str = param("exemplar", doc="reference of an exemplar photo of the document")
    levels: int = levels_param()

    def picture(self, image, progress=None, cancel=None):
        return texton(image)

    def label(self) -> str:
        return f"Texton, G = {self.levels}"


@register
@dataclass(frozen=True)
class MatchHistogram(Action):
    """The palette that gives the picture shown an exemplar's grey or colour distribution:
    φ = c_f⁻¹ ∘ c_g applied to each level's colour (`matched_palette`). The levels stay."""

    TYPE: ClassVar[str] = "match_histogram"
    EFFECT: ClassVar[str] = "other"        # reads the levels and the palette's order
    exemplar: str = param("exemplar", doc="reference of an exemplar photo of the document")

    def apply(self, doc, prepared=None) -> None:
        if not doc.levels.size:
            raise InputError("an empty canvas has no histogram to match")
        doc.set_palette(matched_palette(doc.levels, doc.palette, exemplar_of(doc, self.exemplar)))

    def label(self) -> str:
        return "Match histogram to a photo"


def matched_palette(levels: np.ndarray, palette: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Each level's colour mapped, channel by channel, by φ = c_f⁻¹ ∘ c_g: c_g(v) is the share
    of the picture's points whose channel value is ≤ v (its levels counted, so no picture is
    drawn), c_f⁻¹ the reference's value at that quantile, interpolated — what scikit-image's
    ``match_histograms`` gives on the displayed picture, rounded. A grey reference serves the
    three channels. Levels no point uses get the same φ (a monotone extension)."""
    counts = np.bincount(levels.ravel(), minlength=len(palette)).astype(np.float64)
    ref = reference if reference.ndim == 3 else np.repeat(reference[..., None], 3, axis=2)
    out = np.empty(palette.shape)
    for c in range(3):
        values = palette[:, c].astype(np.float64)
        share = (counts[None, :] * (values[None, :] <= values[:, None])).sum(axis=1) / counts.sum()
        ref_values, ref_counts = np.unique(ref[..., c], return_counts=True)
        out[:, c] = np.interp(share, np.cumsum(ref_counts) / ref_counts.sum(), ref_values)
    return np.clip(np.round(out), 0, 255).astype(np.uint8)
