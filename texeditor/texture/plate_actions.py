"""Colour plates as Actions (thesis §1.2.3–1.2.4): add, take from a photo, paint and remove the
plates layer of a document.

The Plates dock and the "paint on plates" switch build these; `texture.plates` does the work and
`recipe.document` keeps the layer. Painting reuses every level edit: ``OnPlates`` carries one
step (a brush stroke, a fill, a palette) and applies it to the plates instead of the levels.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from . import plates as pl
from ..errors import FormatError, ImageError, InputError
from ..markov.dpj import MAX_LEVELS
from ..recipe.actions import Action, dpj_refs, param, register
from ..recipe.codec import action_from_json
from ..fileio import load_json

MAX_STEP_CHARS = 2**20          # the JSON of the step an OnPlates carries
_PAINTS = ("levels", "palette")     # the effects a step on the plates may have


@register
@dataclass(frozen=True)
class AddPlates(Action):
    """A plates layer: every point on plate ``fill``, P plate colours (the texture's greys are
    laid on them, `texture.plates.laid_on_plates`). Replaces any plates the document had."""

    TYPE: ClassVar[str] = "add_plates"
    EFFECT: ClassVar[str] = "other"
    colours: tuple = param("palette", doc="the P plate colours (r, g, b), 2..16")
    fill: int = param("int", 0, MAX_LEVELS - 1, default=0, doc="the plate of every point")

    def _validate(self) -> None:
        if self.fill >= len(self.colours):
            raise InputError(f"plate {self.fill} does not exist: P = {len(self.colours)}")

    def apply(self, doc, prepared=None) -> None:
        _check_canvas(doc)
        doc.set_plates(np.full(doc.shape, self.fill, np.uint8), self.colours)

    def label(self) -> str:
        return f"Add plates ({len(self.colours)} colours)"


@register
@dataclass(frozen=True)
class PlatesFromPhoto(Action):
    """Plates taken from a photo: its blurred colours (the grid ``texture.plates.photo_grid``
    made, recorded here) stretched over the canvas and cut into P plates in CIELAB."""

    TYPE: ClassVar[str] = "plates_from_photo"
    EFFECT: ClassVar[str] = "other"
    grid: str = param("str", hi=pl.MAX_GRID_CHARS,
                      doc="the blurred photo, rows of rrggbb joined by / (at most 64×64)")
    plates: int = param("int", 2, MAX_LEVELS, default=6, doc="number of plates P")
    name: str = param("str", hi=128, default="", doc="the photo's name (shown in the history)")

    def _validate(self) -> None:
        pl.grid_of_text(self.grid)

    def prepare(self, doc, progress=None, cancel=None):
        _check_canvas(doc)
        try:
            return pl.grid_plates(pl.grid_of_text(self.grid), doc.shape, self.plates)
        except ImageError as exc:      # a flat photo: too few colours for P plates
            raise InputError(f"plates from a photo: {exc}") from None

    def apply(self, doc, prepared=None) -> None:
        plates, colours = self.prepare(doc) if prepared is None else prepared
        doc.set_plates(plates, colours)

    def label(self) -> str:
        return f"Plates from {self.name or 'a photo'} ({self.plates} plates)"


@register
@dataclass(frozen=True)
class RemovePlates(Action):
    """Take the plates layer away: the texture shows in its palette again."""

    TYPE: ClassVar[str] = "remove_plates"
    EFFECT: ClassVar[str] = "other"

    def apply(self, doc, prepared=None) -> None:
        if doc.plates is None:
            raise InputError("the document has no plates to remove")
        doc.set_plates(None, None)

    def label(self) -> str:
        return "Remove the plates"


@register
@dataclass(frozen=True)
class OnPlates(Action):
    """One level edit — a stroke, a fill, a region operator, a palette — applied to the plates:
    inside it the plates are the levels (a plate per point) and their colours the palette.

    The step is stored whole, as its JSON; it may change levels or colours only (not the
    canvas), and may not name DPJs (a composition, a texture spot) or delete a spot (that
    replays the texture's own log)."""

    TYPE: ClassVar[str] = "on_plates"
    EFFECT: ClassVar[str] = "other"
    step: str = param("str", hi=MAX_STEP_CHARS, doc="the step painted on the plates (its JSON)")

    @classmethod
    def of(cls, action: Action) -> "OnPlates":
        return cls(json.dumps(action.to_json(), separators=(",", ":"), ensure_ascii=False,
                              allow_nan=False))

    def _validate(self) -> None:
        try:
            inner = action_from_json(load_json(self.step, "the step on the plates",
                                               limit=MAX_STEP_CHARS))
        except FormatError as exc:
            raise InputError(f"the step on the plates: {exc}") from None
        if inner.EFFECT not in _PAINTS or inner.TYPE == "delete_spot":
            raise InputError(f"“{inner.label()}” cannot be done on the plates: only steps "
                             "that change levels or colours can")
        if dpj_refs([inner]):
            raise InputError(f"“{inner.label()}” names DPJs: it cannot be done on the plates")
        object.__setattr__(self, "_inner", inner)

    @property
    def inner(self) -> Action:
        """The step painted on the plates."""
        return self._inner

    def apply(self, doc, prepared=None) -> None:
        with doc.on_plates():
            self._inner.apply(doc)

    def label(self) -> str:
        return f"Plates: {self._inner.label()}"


def _check_canvas(doc) -> None:
    if not doc.levels.size:
        raise InputError("an empty canvas has no room for plates: make a canvas first")


PLATE_ACTIONS = (AddPlates, PlatesFromPhoto, RemovePlates, OnPlates)
