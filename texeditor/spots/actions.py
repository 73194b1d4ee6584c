"""Spots as Actions (thesis §3.3.3b, "disposer sur l'écran des taches… les superposer, les
mélanger ou en supprimer"): place one spot, scatter many, delete one — each a replayable record.

The spot tool and the CLI build these; `spots` makes the points. A placement carries its envelope
(as compact JSON), its perturbation, fill, blend rule and seed, so replaying the log draws the
same spots bit for bit. A "texture" fill carries the recipe of another texture (a bank entry,
see `texture_actions`) and the DPJs it needs (``texture_dpjs``), and reads it where the spot
lands, repeated, its levels mapped onto the document's G on the grey scale. A deletion names the
placement by its log index and its fingerprint (`spot_ref`, a hash of its JSON), and restores
what the log gives without it (see DeleteSpot).

Versions and fingerprints. Version 1 named a texture fill's one DPJ in ``dpj``; version 2 lists
them in ``texture_dpjs`` (`upgrade` migrates version 1). A placement is still written in the
version-1 form whenever that form can say it — every placement but a texture fill whose recipe
needs two DPJs or more — and without ``texture`` when it has none, exactly as before those
parameters existed: placements keep their JSON and hence the fingerprints DeleteSpot steps name.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from functools import lru_cache
from typing import ClassVar

import numpy as np

from ..recipe.actions import MAX_CANVAS_SIDE, Action, Synthesize, param, register
from ..texture.composition import convert_levels
from ..markov.dpj import bytes_ref
from ..recipe.document import Document
from ..recipe.cache import Cache
from ..recipe.replay import apply_step, replay_log
from ..markov.dpj import MAX_LEVELS
from ..errors import Cancelled, FormatError, InputError
from .envelope import (BLENDS, INTERIORS, Envelope, Perturbation, Placement, Stamp, blend, pieces,
                    placed_outline, real_spot, spot_levels)
from ..recipe.sources import MAX_RECIPE_CHARS, check_recipe, refs_field, source_levels, upgrade_ref

FILLS = ("level", "document", "dpj", "texture")
MAX_ENVELOPE_CHARS = 400_000
MAX_SCATTER = 10_000
MAX_SCALE = 64.0
LOWER_TEXTURE_SIDE = 256        # a DPJ fill synthesises at most this many points a side, tiled
MAX_LOG = 10_000_000


# -- parameter fields (shared by PlaceSpot and ScatterSpots) ---------------------------------------

def _envelope():
    return param("str", hi=MAX_ENVELOPE_CHARS, doc="the envelope (equator, meridians, parallels, "
                                                   "outline kind) as JSON")


def _level(doc: str, default=dataclasses.MISSING, optional=False):
    return param("int", 0, MAX_LEVELS - 1, default=default, optional=optional, doc=doc)


def _fill():
    return param("str", hi=16, default="level", doc="level: one level; document: the texture "
                 "already there, read elsewhere; dpj: a lower-level texture synthesised from a "
                 "DPJ; texture: another texture, from its recipe")


def _dpj():
    return param("ref", default=None, optional=True, doc="the DPJ of a dpj fill")


def _texture():
    return param("str", hi=MAX_RECIPE_CHARS, default=None, optional=True,
                 doc="texture fill: the recipe of the texture (the log that rebuilds it, JSON)")


def _texture_dpjs():
    return refs_field("texture fill: the DPJs the texture's recipe needs, at every depth")


def _contour():
    return param("float", 0.0, 1.0, default=0.0, doc="depth of the smooth bumps of the contour "
                                                      "(share of the radius)")


def _frequency():
    return param("int", 1, 64, default=6, doc="bumps around the contour")


def _fractal():
    return param("float", 0.0, 1.0, default=0.0, doc="depth of the fractal roughening")


def _roughness():
    return param("float", 0.0, 1.0, default=0.5, doc="roughness exponent h of the fractal "
                                                      "(0 rough, 1 smooth)")


def _interior():
    return param("str", hi=16, default="none",
                 doc="interior perturbation: none, holes, levels (patches) or relief (shading)")


def _density():
    return param("float", 0.0, 1.0, default=0.0, doc="share of the spot in holes or in "
                                                      "another level")


def _grain():
    return param("float", 0.1, 1000.0, default=3.0, doc="size of the holes or patches "
                                                         "(envelope points)")


def _shift():
    return param("int", -(MAX_LEVELS - 1), MAX_LEVELS - 1, default=1,
                 doc="level change of the interior patches")


def _blend():
    return param("str", hi=16, default="over", doc="over: covers; under: only on the background; "
                                                    "max or min of the levels")


def _wrap():
    return param("bool", default=False, doc="a spot crossing an edge comes back on the other "
                                            "side (tileable textures stay tileable)")


# -- the common base -------------------------------------------------------------------------------

@dataclass(frozen=True)
class SpotAction(Action):
    """A placement of one or more spots of one envelope: EFFECT "levels", never covers."""

    VERSION: ClassVar[int] = 2
    EFFECT: ClassVar[str] = "levels"

    def _validate(self) -> None:
        self.envelope_model()      # a bad envelope is refused when the action is made
        self.perturbation()
        for name, value, allowed in (("fill", self.fill, FILLS), ("blend", self.blend, BLENDS),
                                     ("interior", self.interior, INTERIORS)):
            if value not in allowed:
                raise InputError(f"{name} must be one of {', '.join(allowed)}, got {value!r}")
        if self.fill == "dpj" and self.dpj is None:
            raise InputError("a dpj fill needs the reference of a DPJ of the document")
        if self.fill == "texture":
            if self.texture is None:
                raise InputError("a texture fill needs the recipe of its texture")
            if self.dpj is not None:
                raise InputError("a texture fill names its DPJs in texture_dpjs, not dpj")
            check_recipe(self.texture, self.texture_dpjs, "the spots' texture")
        elif self.texture is not None or self.texture_dpjs:
            raise InputError(f"a texture recipe goes with a texture fill, not a {self.fill} fill")

    @classmethod
    def upgrade(cls, version: int, params: dict) -> dict:
        """Version 1 named a texture fill's one DPJ (or none) in ``dpj``."""
        if params.get("fill") == "texture":
            return upgrade_ref(params, "dpj", "texture_dpjs")
        if "texture_dpjs" in params:
            raise FormatError("version 1 has no parameter 'texture_dpjs'")
        return params

    def to_json(self) -> dict:
        """In the version-1 form when it can say it (see the module's docstring): placements
        keep their JSON and their fingerprints."""
        obj = super().to_json()
        if len(self.texture_dpjs) > 1:
            return obj
        del obj["texture_dpjs"]
        obj["version"] = 1
        if self.texture_dpjs:
            obj["dpj"] = self.texture_dpjs[0]
        if obj["texture"] is None:
            del obj["texture"]
        return obj

    def envelope_model(self) -> Envelope:
        return _parse_envelope(self.envelope)

    def perturbation(self) -> Perturbation:
        return Perturbation(self.contour, self.frequency, self.fractal, self.roughness,
                            self.interior, self.density, self.grain)

    # -- what subclasses define ---------------------------------------------------------------
    def spots(self, shape) -> list["Spot"]:
        """The spots this action places on a canvas of ``shape``, in placing order."""
        raise NotImplementedError

    # -- geometry -------------------------------------------------------------------------------
    def stamp(self, index: int, shape) -> Stamp:
        """The points of spot ``index`` (cached: replays and the delete tool reuse them); without
        wrap only its part on the canvas (the rest can never be written)."""
        key = (self, index, tuple(shape))
        stamp = _STAMPS.get(key)
        if stamp is None:
            spot = self.spots(shape)[index]
            clip = None if self.wrap else (0, 0, shape[0], shape[1])   # only what can land
            stamp = real_spot(self.envelope_model(), self.perturbation(), seed=spot.seed,
                              placement=spot.placement, clip=clip)
            stamp.mask.flags.writeable = False
            stamp.steps.flags.writeable = False
            _STAMPS.put(key, stamp)
        return stamp

    def outline(self, index: int, shape) -> np.ndarray:
        """The real outline of spot ``index`` on the plane (for a tool's highlight)."""
        spot = self.spots(shape)[index]
        return placed_outline(self.envelope_model(), self.perturbation(), spot.seed,
                              spot.placement)

    def contains(self, index: int, shape, point) -> bool:
        """True when spot ``index`` covers ``point`` (row, col) of a canvas of ``shape``."""
        stamp = self.stamp(index, shape)
        r, c = point
        if self.wrap:
            H, W = shape
            r = stamp.top + (r - stamp.top) % H
            c = stamp.left + (c - stamp.left) % W
        r, c = r - stamp.top, c - stamp.left
        return 0 <= r < stamp.shape[0] and 0 <= c < stamp.shape[1] and bool(stamp.mask[r, c])

    # -- applying -------------------------------------------------------------------------------
    def prepare(self, doc, progress=None, cancel=None) -> None:
        self.rasterise(doc.shape, progress, cancel)
        if self.fill == "dpj" and self.dpj in doc.dpjs:
            self._lower_texture(doc)
        elif self.fill == "texture" and all(r in doc.dpjs for r in self.texture_dpjs):
            source_levels(doc, self.texture, self.texture_dpjs, progress, cancel)

    def rasterise(self, shape, progress=None, cancel=None) -> None:
        """Rasterise every spot ahead of apply(), which then only writes: the slow part of a big
        scatter, safe in a worker thread and cancellable."""
        spots = self.spots(shape)
        for i in range(len(spots)):
            if cancel is not None and cancel():
                raise Cancelled("spot placement cancelled: nothing was changed")
            self.stamp(i, shape)
            if progress is not None and i % 16 == 15:
                progress((i + 1) / len(spots))

    def apply(self, doc, prepared=None) -> None:
        self.place(doc, skip=frozenset())

    def place(self, doc, skip) -> None:
        """Place every spot but those in ``skip`` (their indices; None skips them all)."""
        if skip is None:
            return
        for value in self._levels_used():
            doc.check_levels(np.uint8(value))
        lower = self._lower_texture(doc)
        for i, spot in enumerate(self.spots(doc.shape)):
            if i in skip:
                continue
            stamp = self.stamp(i, doc.shape)
            if lower is None:
                fill, offset = spot.level, (0, 0)
            else:
                fill, offset = (doc.levels, spot.offset) if self.fill == "document" \
                    else (lower, (0, 0))
            for t, l, rs, cs in pieces(stamp, doc.shape, self.wrap):
                part = Stamp(stamp.top + rs.start, stamp.left + cs.start, stamp.mask[rs, cs],
                             stamp.steps[rs, cs])           # its levels: those of the whole
                values = spot_levels(part, fill, shift=self.shift, num_levels=doc.num_levels,
                                     offset=offset)
                current = doc.levels[t:t + rs.stop - rs.start, l:l + cs.stop - cs.start]
                new = blend(current, part.mask, values, self.blend)
                if (new != current).any():
                    doc.write(t, l, new)

    def _levels_used(self) -> tuple[int, ...]:
        return (self.level,) if self.fill == "level" else ()

    def _lower_texture(self, doc) -> np.ndarray | None:
        """The lower-level texture a spot is filled with (None for a level fill)."""
        if self.fill == "level":
            return None
        if self.fill == "document":
            if not doc.levels.size:
                raise InputError("a document fill needs a texture in the document")
            return doc.levels
        if self.fill == "texture":
            levels, g = source_levels(doc, self.texture, self.texture_dpjs)
            return convert_levels(levels, g, doc.num_levels)
        dpj = doc.dpjs.get(self.dpj)
        if dpj is None:
            raise InputError(f"DPJ {self.dpj} is not part of this document: add it first")
        if dpj.levels > doc.num_levels:
            raise InputError(f"the DPJ has G = {dpj.levels} levels but the document only "
                             f"{doc.num_levels}: its texture cannot fill a spot here")
        h, w = (min(max(n, 1), LOWER_TEXTURE_SIDE) for n in doc.shape)
        return Synthesize(self.dpj, w, h, self.seed).render_result(dpj).levels


@dataclass(frozen=True)
class Spot:
    """One spot of a placement: where it goes, its perturbation seed, its level, and (document
    fill) how far away the texture that fills it is read."""

    placement: Placement
    seed: int
    level: int
    offset: tuple[int, int] = (0, 0)


@lru_cache(maxsize=256)
def _parse_envelope(text: str) -> Envelope:
    return Envelope.loads(text)


# -- the actions -----------------------------------------------------------------------------------

@register
@dataclass(frozen=True)
class PlaceSpot(SpotAction):
    """One real spot: the envelope's centre on (row, col), turned and scaled, perturbed by its
    seed, filled and superposed by the blend rule."""

    TYPE: ClassVar[str] = "place_spot"
    envelope: str = _envelope()
    row: float = param("float", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, doc="row of the spot's centre")
    col: float = param("float", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE,
                       doc="column of the spot's centre")
    angle: float = param("float", -3600, 3600, default=0.0, doc="turn, degrees counter-clockwise")
    scale: float = param("float", 1 / MAX_SCALE, MAX_SCALE, default=1.0,
                         doc="size (1: as drawn in the editor)")
    seed: int = param("seed", default=0, doc="perturbation seed: one envelope, many real spots")
    level: int = _level("the level of a level fill", default=1)
    fill: str = _fill()
    dpj: str | None = _dpj()
    texture: str | None = _texture()
    texture_dpjs: tuple = _texture_dpjs()
    source_row: float | None = param("float", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, default=None,
                                     optional=True, doc="document fill: where the texture is "
                                                        "read (row of the spot's centre)")
    source_col: float | None = param("float", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, default=None,
                                     optional=True, doc="document fill: column read")
    contour: float = _contour()
    frequency: int = _frequency()
    fractal: float = _fractal()
    roughness: float = _roughness()
    interior: str = _interior()
    density: float = _density()
    grain: float = _grain()
    shift: int = _shift()
    blend: str = _blend()
    wrap: bool = _wrap()

    def spots(self, shape) -> list[Spot]:
        offset = (0, 0)
        if self.fill == "document":
            src = (self.row if self.source_row is None else self.source_row,
                   self.col if self.source_col is None else self.source_col)
            offset = (int(round(src[0] - self.row)), int(round(src[1] - self.col)))
        return [Spot(Placement((self.row, self.col), self.angle, self.scale), self.seed,
                     self.level, offset)]

    def label(self) -> str:
        fill = {"level": f"level {self.level}", "document": "texture", "dpj": "DPJ texture",
                "texture": "another texture"}
        return f"Spot at ({self.row:g}, {self.col:g}), {fill[self.fill]}"


@register
@dataclass(frozen=True)
class ScatterSpots(SpotAction):
    """``count`` real spots of one envelope at random places of a rectangle (or the canvas),
    turns and sizes; every spot has its own perturbation seed (and level, given a range)."""

    TYPE: ClassVar[str] = "scatter_spots"
    envelope: str = _envelope()
    count: int = param("int", 1, MAX_SCATTER, doc="how many spots")
    seed: int = param("seed", default=0, doc="places, turns, sizes and perturbations")
    top: int | None = param("int", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, default=None, optional=True,
                            doc="region's first row (none: the whole canvas)")
    left: int | None = param("int", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, default=None,
                             optional=True, doc="region's first column")
    height: int | None = param("int", 1, MAX_CANVAS_SIDE, default=None, optional=True,
                               doc="region's rows")
    width: int | None = param("int", 1, MAX_CANVAS_SIDE, default=None, optional=True,
                              doc="region's columns")
    angle: float = param("float", -3600, 3600, default=0.0, doc="mean turn, degrees")
    angle_spread: float = param("float", 0.0, 180.0, default=180.0,
                                doc="turns vary by up to ± this many degrees")
    scale: float = param("float", 1 / MAX_SCALE, MAX_SCALE, default=1.0, doc="smallest size")
    scale_max: float | None = param("float", 1 / MAX_SCALE, MAX_SCALE, default=None,
                                    optional=True, doc="largest size (none: all the same)")
    level: int = _level("level of a level fill (the lowest, given a range)", default=1)
    level_max: int | None = _level("highest level of a level fill", default=None, optional=True)
    fill: str = _fill()
    dpj: str | None = _dpj()
    texture: str | None = _texture()
    texture_dpjs: tuple = _texture_dpjs()
    contour: float = _contour()
    frequency: int = _frequency()
    fractal: float = _fractal()
    roughness: float = _roughness()
    interior: str = _interior()
    density: float = _density()
    grain: float = _grain()
    shift: int = _shift()
    blend: str = _blend()
    wrap: bool = _wrap()

    def _validate(self) -> None:
        super()._validate()
        region = (self.top, self.left, self.height, self.width)
        if any(v is None for v in region) and any(v is not None for v in region):
            raise InputError("give the region's top, left, height and width, or none of them")
        if self.scale_max is not None and self.scale_max < self.scale:
            raise InputError(f"the largest size {self.scale_max:g} is below the smallest "
                             f"{self.scale:g}")
        if self.level_max is not None and self.level_max < self.level:
            raise InputError(f"the highest level {self.level_max} is below the lowest "
                             f"{self.level}")

    def _levels_used(self):
        if self.fill != "level":
            return ()
        return (self.level if self.level_max is None else self.level_max,)

    def spots(self, shape) -> list[Spot]:
        """Drawn all at once, one row of numbers per spot in a fixed order, so that changing a
        range (sizes, levels) keeps the places and the other draws."""
        return list(_scatter(self, tuple(shape)))

    def region(self, shape) -> tuple[int, int, int, int]:
        if self.top is None:
            return (0, 0, shape[0], shape[1])
        return (self.top, self.left, self.height, self.width)

    def label(self) -> str:
        where = "" if self.top is None else f" in {self.width}×{self.height} at " \
                                            f"({self.top}, {self.left})"
        return f"Scatter {self.count} spots{where}"


@lru_cache(maxsize=64)
def _scatter(action: ScatterSpots, shape) -> tuple[Spot, ...]:
    rng = np.random.default_rng(action.seed)
    u = rng.random((action.count, 7))
    seeds = rng.integers(0, 2**63 - 1, action.count, dtype=np.int64)
    top, left, height, width = action.region(shape)
    H, W = max(shape[0], 1), max(shape[1], 1)
    lo, hi = action.scale, action.scale if action.scale_max is None else action.scale_max
    top_level = action.level if action.level_max is None else action.level_max
    out = []
    for k in range(action.count):
        centre = (top + u[k, 0] * height, left + u[k, 1] * width)
        angle = action.angle + (2 * u[k, 2] - 1) * action.angle_spread
        scale = lo * (hi / lo) ** u[k, 3]             # sizes spread evenly on a log scale
        level = action.level + min(int(u[k, 4] * (top_level - action.level + 1)),
                                   top_level - action.level)
        offset = (int(u[k, 5] * H), int(u[k, 6] * W))
        out.append(Spot(Placement(centre, angle, scale), int(seeds[k]), level, offset))
    return tuple(out)


@register
@dataclass(frozen=True)
class DeleteSpot(Action):
    """Delete a placed spot: the texture becomes what the log gives without that placement.

    ``step`` is the placement's index in the log (0 = first step); ``spot`` picks one spot of a
    scatter (none: the whole placement); ``placement`` is the placement's fingerprint, so a log
    whose indices shifted (an optimised or edited log) still finds it. Applying replays the log
    from its last reset (a new canvas or a synthesis) without the deleted placements — this one
    and those of earlier deletions — and writes the points that differ. Spots placed later
    stay as they are, what lay under the spot comes back, and the result depends on the log
    only: deterministic on every replay.
    """

    TYPE: ClassVar[str] = "delete_spot"
    EFFECT: ClassVar[str] = "levels"
    step: int = param("int", 0, MAX_LOG, doc="log index of the placement (0 = first step)")
    placement: str = param("str", hi=64, doc="fingerprint of the placement (spot_ref): not a DPJ")
    spot: int | None = param("int", 0, MAX_SCATTER - 1, default=None, optional=True,
                             doc="which spot of a scatter (none: all of that placement)")

    def placement_step(self, actions) -> int:
        """The log index of the placement this deletion names, among ``actions`` before it: the
        step itself when its fingerprint matches, else the latest placement with that
        fingerprint (the log was optimised or edited), else the step if it still places spots
        (that placement was edited: it stays deleted)."""
        def is_spot(k):
            return 0 <= k < len(actions) and isinstance(actions[k], SpotAction)
        if is_spot(self.step) and spot_ref(actions[self.step]) == self.placement:
            return self.step
        for k in range(len(actions) - 1, -1, -1):
            if is_spot(k) and spot_ref(actions[k]) == self.placement:
                return k
        if is_spot(self.step):
            return self.step
        raise InputError(f"the spot placement this deletion names (step {self.step + 1}) is "
                         f"not in the log before it")

    def refers_to(self, log, at: int) -> tuple[int, ...]:
        """The placement it deletes: a log without it would make this step fail."""
        try:
            return (self.placement_step(log[:at]),)
        except InputError:
            return ()

    def apply(self, doc, prepared=None) -> None:
        actions = doc.actions
        k = self.placement_step(actions)
        if self.spot is not None and self.spot >= len(actions[k].spots(doc.shape)):
            raise InputError(f"step {k + 1} placed {len(actions[k].spots(doc.shape))} spots: "
                             f"there is no spot {self.spot + 1}")
        skipped = deleted_spots(actions)
        _skip(skipped, k, self.spot)
        without = replay_without(actions, doc, skipped)
        if without.shape != doc.shape:
            raise InputError("the canvas changed size since the spot was placed: it cannot be "
                             "deleted on its own")
        from ..regions.actions import changed_boxes
        for t, l, b, r in changed_boxes(without != doc.levels):
            doc.write(t, l, without[t:b, l:r])

    def label(self) -> str:
        which = "the spot" if self.spot is None else f"spot {self.spot + 1}"
        return f"Delete {which} of step {self.step + 1}"


# -- finding and deleting placed spots -------------------------------------------------------------

def spot_ref(action: SpotAction) -> str:
    """A placement's fingerprint: 16 hex digits of SHA-256 of its canonical JSON."""
    return bytes_ref(json.dumps(action.to_json(), sort_keys=True, separators=(",", ":"))
                     .encode("utf-8"))


def _skip(skipped: dict, step: int, spot: int | None) -> None:
    if spot is None or skipped.get(step, set()) is None:
        skipped[step] = None
    else:
        skipped.setdefault(step, set()).add(spot)


def deleted_spots(actions) -> dict:
    """step → the spot indices its later deletions removed (None: all of them)."""
    skipped: dict = {}
    for j, a in enumerate(actions):
        if isinstance(a, DeleteSpot):
            _skip(skipped, a.placement_step(actions[:j]), a.spot)
    return skipped


def replay_without(actions, sources, skipped: dict) -> np.ndarray:
    """The levels the log gives with the ``skipped`` spots left out (and deletions doing nothing,
    their effect being in ``skipped``), replayed from the last reset with the DPJs and exemplar
    photos of ``sources`` (the document: a model step after the spot reads its photo)."""
    actions = list(actions)
    start = max((i for i, a in enumerate(actions) if a.EFFECT == "reset"), default=0)
    scratch = Document()
    scratch.dpjs = sources.dpjs
    scratch.exemplars = sources.exemplars
    scratch.set_log(actions[:start])

    def run(i, action, _progress):
        if isinstance(action, SpotAction):
            with scratch.step():
                action.place(scratch, skipped.get(i, frozenset()))
        elif not isinstance(action, DeleteSpot):
            apply_step(scratch, action)
        scratch.append_log(action)

    replay_log(actions, run, start=start)
    return scratch.levels


def placed_spots(actions, shape) -> list[tuple[int, int]]:
    """(step, spot) of every spot still in place, oldest first."""
    skipped = deleted_spots(actions)
    out = []
    for k, a in enumerate(actions):
        if isinstance(a, SpotAction):
            gone = skipped.get(k, set())
            if gone is not None:
                out += [(k, i) for i in range(len(a.spots(shape))) if i not in gone]
    return out


def spot_at(actions, shape, point) -> tuple[int, int | None] | None:
    """(step, spot) of the latest spot still in place that covers ``point`` (row, col); spot is
    None for a single placement. None when no spot is there."""
    start = max((i for i, a in enumerate(actions) if a.EFFECT == "reset"), default=0)
    for k, i in reversed(placed_spots(actions, shape)):
        if k < start:
            break
        action = actions[k]
        if action.contains(i, shape, point):
            return k, (None if isinstance(action, PlaceSpot) else i)
    return None


# -- the stamp cache: recently rasterised spots ---------------------------------------------------

_STAMPS = Cache(max_bytes=128 * 2**20)

SPOT_ACTIONS = (PlaceSpot, ScatterSpots, DeleteSpot)
