"""Grain rendering, composition and grey-level doubling as Actions (thesis §5.3, §5.4.1, §4.5).

Tools build these from the Grain & density dock, the composition panel and the doubling dialog;
`grain_render`, `composition` and `doubling` do the work. Each is a replayable record: editing a
RenderGrains step later replays the edits made after it on the newly sized canvas.

A composition source and the texture a spot is filled with are *recipes* (`recipe.sources`).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from . import composition
from ..markov import doubling
from . import grain_render as gr
from ..recipe.actions import Action, dpj_refs, param, register
from ..recipe.sources import (check_recipe, parse_recipe, recipe_field, refs_field,
                              source_levels, upgrade_ref)
from ..errors import InputError

MASKS = ("texture", "levels", "points")
MAX_SOURCES = 7                # T2…T8: a mix of at most eight textures
MAX_BLOCK = 4096               # the side of an incrustation's block (pavé), points
DEFAULT_EXPRESSION = "(0.34 multiply T1) add (0.33 multiply T2) add (0.33 multiply T3)"


# -- grains and density (§5.3) ---------------------------------------------------------------------

@register
@dataclass(frozen=True)
class RenderGrains(Action):
    """Draw each point of the normalised texture as a grain: a new, larger canvas (§5.3).

    The canvas becomes (H·pitch_y) × (W·pitch_x) pixels, see `grain_render`; the levels and
    palette keep their meaning, level 0 stays background. ``level_grains`` gives some levels
    their own grain (a primitive per level, §5.3); the others use this one.
    """

    TYPE: ClassVar[str] = "render_grains"
    EFFECT: ClassVar[str] = "canvas"
    shape: str = param("str", hi=16, default="square",
                       doc="square, rectangle, circle, diamond, hexagon, polygon, line, bitmap")
    size: int = param("int", 1, 64, default=8, doc="grain diameter, pixels")
    aspect: float = param("float", 1 / 16, 16, default=1.0,
                          doc="height / width of a rectangle or an ellipse")
    sides: int = param("int", 3, 64, default=6, doc="vertices of a regular polygon")
    angle: float = param("float", -360, 360, default=0.0,
                         doc="orientation, degrees counter-clockwise")
    explosion_x: float = param("float", 1.0, gr.MAX_EXPLOSION, default=1.0,
                               doc="blank space between grains across (1 = touching)")
    explosion_y: float = param("float", 1.0, gr.MAX_EXPLOSION, default=1.0,
                               doc="blank space between grains down (1 = touching)")
    compression: float = param("float", 0.0, gr.MAX_COMPRESSION, default=0.0,
                               doc="brings grains together until they overlap (0 = touching): "
                                   "down, and across unless compression_x is set")
    overlap: str = param("str", hi=8, default="last",
                         doc="where grains overlap: last (drawn later wins), max or min level")
    lattice: str = param("str", hi=16, default="auto",
                         doc="auto (honeycomb for hexagons), grid or honeycomb")
    bitmap: str | None = param("str", hi=64 * 65, default=None, optional=True,
                               doc="a drawn grain: rows of hex digits separated by /")
    level_grains: str | None = param("str", hi=16 * 4500, default=None, optional=True,
                                     doc="a grain per level, e.g. 1: circle 5, 2: square 3 "
                                         "(the levels not listed use the grain above)")
    compression_x: float | None = param("float", 0.0, gr.MAX_COMPRESSION, default=None,
                                        optional=True, doc="compression across, when it differs")

    def _validate(self) -> None:
        if self.overlap not in gr.OVERLAP_RULES:
            raise InputError(f"overlap rule must be one of {', '.join(gr.OVERLAP_RULES)}")
        if self.lattice not in gr.LATTICES:
            raise InputError(f"lattice must be one of {', '.join(gr.LATTICES)}")
        self.grain_lattice()

    def mask(self) -> np.ndarray:
        return gr.grain_of(self.shape, self.size, aspect=self.aspect, sides=self.sides,
                           angle=self.angle, bitmap=self.bitmap)

    def level_masks(self) -> dict[int, np.ndarray]:
        """The grains of the levels that have their own (§5.3), by level."""
        return {v: g.mask() for v, g in gr.parse_level_grains(self.level_grains).items()}

    def union(self) -> np.ndarray:
        """Every grain of the render stacked on its centre: what the lattice is made for."""
        return gr.grain_union([self.mask(), *self.level_masks().values()])

    def grain_lattice(self) -> gr.Lattice:
        return gr.grain_lattice(self.union(), shape=self.shape, lattice=self.lattice,
                                explosion_x=self.explosion_x, explosion_y=self.explosion_y,
                                compression=self.compression,
                                compression_x=self.compression_x)

    def render(self, levels, progress=None, cancel=None) -> np.ndarray:
        return gr.render_grains(levels, self.mask(), self.grain_lattice(), self.overlap,
                                level_masks=self.level_masks(), progress=progress,
                                cancel=cancel)

    def render_cost(self, texture_shape) -> float:
        """`grain_render.render_cost` of this render on a texture of ``texture_shape``."""
        return gr.render_cost(texture_shape, self.union(), self.grain_lattice())

    def prepare(self, doc, progress=None, cancel=None) -> None:
        """In a replay with progress or cancel (the GUI's worker), render here, in bands that
        report progress and can stop; apply() then only swaps the picture in."""
        if progress is not None or cancel is not None:
            levels = doc.levels
            self.use_result(levels, self.render(levels, progress, cancel))

    def use_result(self, levels, picture) -> None:
        """Hand apply() the picture this action renders from ``levels``, made elsewhere (a
        worker): used once, and only if the document's levels are still equal to ``levels``."""
        object.__setattr__(self, "_result", (levels, picture))

    def apply(self, doc, prepared=None) -> None:
        levels, picture = self.__dict__.pop("_result", (None, None))
        current = doc.levels
        if picture is None or levels.shape != current.shape or not np.array_equal(levels,
                                                                                  current):
            picture = self.render(current)
        doc.set_levels(picture, copy=False)

    def canvas_shape(self, shape):
        return self.grain_lattice().shape(shape)

    def label(self) -> str:
        what = f"{self.shape} {self.size} px" + (f", {self.angle:g}°" if self.angle else "")
        if self.level_grains:
            what += ", own grains for levels " + ", ".join(map(str, self.level_masks()))
        density = []
        if self.explosion_x != 1 or self.explosion_y != 1:
            density.append(f"explosion {self.explosion_x:g}×{self.explosion_y:g}")
        if self.compression or self.compression_x:
            density.append(f"compression {self.compression_text()} ({self.overlap})")
        return "Grains: " + ", ".join([what] + density)

    def compression_text(self) -> str:
        """"0.3", or "0.5 across, 0 down" when the axes differ."""
        if self.compression_x is None or self.compression_x == self.compression:
            return f"{self.compression:g}"
        return f"{self.compression_x:g} across, {self.compression:g} down"


# -- composition (§5.4.1) --------------------------------------------------------------------------

@register
@dataclass(frozen=True)
class Mix(Action):
    """T3 = not[(a op1 T1) op2 (b op3 T2)] op4 c: T1 the document, T2 another texture.

    Levels are mixed on the grey scale (`composition`); T2 is repeated or cropped to the canvas.
    """

    TYPE: ClassVar[str] = "mix"
    VERSION: ClassVar[int] = 2
    EFFECT: ClassVar[str] = "levels"
    source: str = recipe_field("T2's recipe: the log that rebuilds it (JSON)")
    source_dpjs: tuple = refs_field("the DPJs T2's recipe needs, at every depth")
    a: float = param("float", 0, 1, default=1.0, doc="weight of T1 (0..1 of the grey scale)")
    op1: str = param("str", hi=8, default="multiply", doc="a op1 T1")
    op2: str = param("str", hi=8, default="max", doc="(a op1 T1) op2 (b op3 T2)")
    b: float = param("float", 0, 1, default=1.0, doc="weight of T2")
    op3: str = param("str", hi=8, default="multiply", doc="b op3 T2")
    negate: bool = param("bool", default=False, doc="take the complement (not) of the bracket")
    op4: str = param("str", hi=8, default="max", doc="[…] op4 c")
    c: float = param("float", 0, 1, default=0.0, doc="the constant C")

    def _validate(self) -> None:
        for op in (self.op1, self.op2, self.op3, self.op4):
            composition.check_op(op)
        check_recipe(self.source, self.source_dpjs, "T2")

    @classmethod
    def upgrade(cls, version: int, params: dict) -> dict:
        """Version 1 named T2's one DPJ in ``source_dpj``."""
        return upgrade_ref(params, "source_dpj", "source_dpjs")

    def prepare(self, doc, progress=None, cancel=None) -> None:
        source_levels(doc, self.source, self.source_dpjs, progress, cancel)

    def apply(self, doc, prepared=None) -> None:
        t2, g2 = source_levels(doc, self.source, self.source_dpjs)
        new = composition.mix(doc.levels, composition.fit(t2, doc.shape), levels=doc.num_levels,
                              levels2=g2, **self.ops())
        _commit(doc, new)

    def ops(self) -> dict:
        return {k: getattr(self, k) for k in ("a", "op1", "op2", "b", "op3", "negate", "op4", "c")}

    def label(self) -> str:
        inner = f"({self.a:g} {self.op1} T1) {self.op2} ({self.b:g} {self.op3} T2)"
        inner = f"not[{inner}]" if self.negate else inner
        return f"Mix {inner} {self.op4} {self.c:g}"


@register
@dataclass(frozen=True)
class Incrust(Action):
    """Incrustation: where the membership mask holds, another texture T2 shows; elsewhere the
    document stays (T3 = if bool then T2 else T1).

    The mask is a third texture's levels (``texture``: a recipe, the points whose level is in
    ``levels``), the document's own levels (``levels``), or painted points — a brush, or a
    selection frozen into its points (``points``). N textures are N − 1 incrustations, each with
    its own levels of one mask texture. With ``block`` > 1 T2 shows by blocks (the thesis's
    pavés, §5.4.1): each point of the mask texture says what a block shows.
    """

    TYPE: ClassVar[str] = "incrust"
    VERSION: ClassVar[int] = 2
    EFFECT: ClassVar[str] = "levels"
    source: str = recipe_field("T2's recipe: the log that rebuilds it (JSON)")
    source_dpjs: tuple = refs_field("the DPJs T2's recipe needs, at every depth")
    mask: str = param("str", hi=8, default="texture",
                      doc="texture (a third texture's levels), levels (the document's), points")
    levels: str = param("str", hi=64, default="1-15",
                        doc="the mask's levels where T2 shows, like 1,3-5")
    mask_source: str | None = recipe_field("the mask texture's recipe", optional=True)
    mask_dpjs: tuple = refs_field("the DPJs the mask texture's recipe needs, at every depth")
    points: tuple = param("points", 0, 16383, default=(),
                          doc="painted (row, col) points where T2 shows")
    block: int = param("int", 1, MAX_BLOCK, default=1,
                       doc="T2 shows by blocks of this many points a side (pavés): each point "
                           "of a mask texture is a block; another mask, at least half a block")

    def _validate(self) -> None:
        if self.mask not in MASKS:
            raise InputError(f"mask must be one of {', '.join(MASKS)}, got {self.mask!r}")
        composition.parse_level_set(self.levels)
        check_recipe(self.source, self.source_dpjs, "T2")
        if self.mask == "texture" and self.mask_source is None:
            raise InputError("a texture mask needs the mask texture's recipe")
        if self.mask_source is not None:
            check_recipe(self.mask_source, self.mask_dpjs, "the mask texture")
        elif self.mask_dpjs:
            raise InputError("mask_dpjs names DPJs, but there is no mask texture recipe")

    @classmethod
    def upgrade(cls, version: int, params: dict) -> dict:
        """Version 1 named each recipe's one DPJ in ``source_dpj`` and ``mask_dpj``."""
        return upgrade_ref(upgrade_ref(params, "source_dpj", "source_dpjs"), "mask_dpj",
                           "mask_dpjs")

    def prepare(self, doc, progress=None, cancel=None) -> None:
        source_levels(doc, self.source, self.source_dpjs, progress, cancel)
        if self.mask == "texture":
            source_levels(doc, self.mask_source, self.mask_dpjs, progress, cancel)

    def membership(self, doc) -> np.ndarray:
        """Where T2 shows, on the document's canvas (by whole blocks when ``block`` > 1)."""
        chosen = composition.parse_level_set(self.levels)
        if self.mask == "texture":
            m, _ = source_levels(doc, self.mask_source, self.mask_dpjs)
            return composition.membership_from_levels(
                composition.pave(m, self.block, doc.shape), chosen)
        if self.mask == "points":
            inside = composition.membership_from_points(self.points, doc.shape)
        else:
            inside = composition.membership_from_levels(doc.levels, chosen)
        return inside if self.block == 1 else composition.by_blocks(inside, self.block)

    def apply(self, doc, prepared=None) -> None:
        t2, g2 = source_levels(doc, self.source, self.source_dpjs)
        t2 = composition.convert_levels(composition.fit(t2, doc.shape), g2, doc.num_levels)
        _commit(doc, composition.incrust(self.membership(doc), [doc.levels, t2]))

    def label(self) -> str:
        where = {"texture": f"levels {self.levels} of a mask texture",
                 "levels": f"the document's levels {self.levels}",
                 "points": f"{len(self.points)} painted points"}[self.mask]
        blocks = f", by blocks of {self.block}" if self.block > 1 else ""
        return f"Incrust T2 where {where}{blocks}"


@register
@dataclass(frozen=True)
class MixTextures(Action):
    """T = an expression over T1 (the document) and T2…TN, other textures (§5.4.1: the mixing
    formula "extends to more than two textures"), point by point on the grey scale
    (`composition.evaluate`); each Ti repeated or cropped to the canvas."""

    TYPE: ClassVar[str] = "mix_textures"
    EFFECT: ClassVar[str] = "levels"
    sources: tuple = param("texts", 2, MAX_SOURCES,
                           doc="the recipes of T2, T3…: the logs that rebuild them (JSON)")
    sources_dpjs: tuple = refs_field("the DPJs the recipes need, at every depth")
    expression: str = param("str", hi=composition.MAX_EXPRESSION, default=DEFAULT_EXPRESSION,
                            doc="over T1 (this texture), T2…, e.g. (0.5 multiply T1) add "
                                "(0.5 multiply T2) max T3")

    def _validate(self) -> None:
        used = set()
        for k, text in enumerate(self.sources, start=2):
            used.update(_recipe_refs(text, self.sources_dpjs, f"T{k}"))
        extra = [r for r in self.sources_dpjs if r not in used]
        if extra:
            raise InputError(f"no texture uses DPJ {', '.join(extra)}, which the step names")
        composition.parse_expression(self.expression, 1 + len(self.sources))

    def prepare(self, doc, progress=None, cancel=None) -> None:
        for text in self.sources:
            source_levels(doc, text, _recipe_refs(text, self.sources_dpjs), progress, cancel)

    def apply(self, doc, prepared=None) -> None:
        textures = [(doc.levels, doc.num_levels)]
        for text in self.sources:
            textures.append(source_levels(doc, text, _recipe_refs(text, self.sources_dpjs)))
        # each Ti fitted to the canvas band by band, never whole (composition.evaluate_fitted)
        _commit(doc, composition.evaluate_fitted(self.expression, textures, doc.num_levels,
                                                 doc.shape))

    def label(self) -> str:
        text = " ".join(self.expression.split())
        return f"Mix T1…T{1 + len(self.sources)}: " + (text if len(text) <= 40 else
                                                         text[:39] + "…")


def _recipe_refs(text: str, refs: tuple, what: str = "a texture") -> tuple:
    """The DPJs one recipe of a step uses, each of which the step must name (``refs``: at
    most MAX_RECIPE_DPJS for all the recipes)."""
    try:
        used = tuple(dpj_refs(parse_recipe(text)))
    except InputError as exc:
        raise InputError(f"{what}: {exc}") from None
    missing = [r for r in used if r not in refs]
    if missing:
        raise InputError(f"{what} uses DPJ {', '.join(missing)}, which the step does not name "
                         f"(it names {', '.join(refs) or 'none'})")
    return used


def _commit(doc, new: np.ndarray) -> None:
    """Write only the points that change (the undo record is their bounding box)."""
    changed = new != doc.levels
    if changed.any():
        doc.write_where(changed, new)


# -- grey-level doubling (§4.5) --------------------------------------------------------------------

@register
@dataclass(frozen=True)
class DoubleLevels(Action):
    """Turn the G-level texture into 2G levels with a doubling table learnt from a photo: each
    point b becomes 2b or 2b + 1; the palette becomes the photo's 2G colours."""

    TYPE: ClassVar[str] = "double_levels"
    EFFECT: ClassVar[str] = "other"
    table: str = param("ref", doc="the doubling table (a 3×3 DPJ of the photo at 2G levels)")
    seed: int = param("seed", default=0, doc="random seed: same seed, same texture")

    def doubled(self, doc) -> np.ndarray:
        """The doubled levels: a second for a 2048² texture, so a window draws them in its
        worker and hands them to apply() as ``prepared``. (Not ``prepare``: they depend on the
        levels before, which a replay's cache of prepared results does not look at.)"""
        return doubling.double_levels(doc.levels, self._table(doc), self.seed).levels

    def apply(self, doc, prepared=None) -> None:
        table = self._table(doc)
        if prepared is None:
            doc.set_levels(self.doubled(doc), table.palette, copy=False)
            return
        levels = np.asarray(prepared)        # the caller's: copied
        if levels.dtype != np.uint8 or levels.shape != doc.shape:
            raise InputError(f"doubled levels must be a {doc.shape[1]}x{doc.shape[0]} uint8 "
                             f"matrix, got {levels.shape} {levels.dtype}")
        doc.set_levels(levels, table.palette)

    def _table(self, doc):
        table = doc.dpjs.get(self.table)
        if table is None:
            raise InputError(f"doubling table {self.table} is not part of this document")
        g = doubling.check_table(table)
        if doc.num_levels != g:
            raise InputError(f"this table doubles textures of G = {g} levels; the document has "
                             f"G = {doc.num_levels}")
        return table

    def label(self) -> str:
        return f"Double the levels, seed {self.seed}"


TEXTURE_ACTIONS = (RenderGrains, Mix, Incrust, MixTextures, DoubleLevels)
