"""Grain rendering, composition and grey-level doubling as Actions (thesis §5.3, §5.4.1, §4.5).

Tools build these from the Grain & density dock, the composition panel and the doubling dialog;
`grain_render`, `composition` and `doubling` do the work. Each is a replayable record: editing a
RenderGrains step later replays the edits made after it on the newly sized canvas.

How a log refers to another texture. A composition source, or the texture a spot is filled
with (`spot_actions`), is a *recipe*: the action log that rebuilds it, as the JSON text of a
`.texture`'s actions.json (``{"actions": [...]}``), plus the DPJs it needs, which the document
keeps in its DPJ store (so a saved file carries them, like any DPJ it refers to). A synthesis of
a stored DPJ is the one-step recipe ``[Synthesize(ref, w, h, seed)]``; an opened `.texture` is
its own log; "this document at step k" is its log cut at k; a bank entry is its optimised log,
replayed once when it is chosen and checked against the SHA-256 the bank recorded
(`bank_source`). The step carries the whole recipe, so it replays bit for bit after save and load
even if the bank entry is later changed or deleted. Replaying a recipe gives the same levels on
every machine, and the result is kept in a small memo so a preview and the apply that follows it
synthesise once. A doubling table is a DPJ (`doubling.learn`) in the same store, referred to by
its reference.

Any number of DPJs per recipe, at any depth. A step names the DPJs of each recipe it carries in a
parameter of kind "refs" (a list of references: ``source_dpjs``, ``mask_dpjs``, a spot's
``texture_dpjs``), and that list must be exactly the DPJs the recipe's log names (`check_recipe`),
its own "refs" parameters included. A recipe may itself hold a composition or a texture spot
whose recipe needs DPJs (a bank entry that was a composition, used again): its step names them,
so the outer step names them too, and `actions.dpj_refs` of any log is every DPJ needed at every
depth without opening a recipe. That list is what a saved file and a bank entry carry, and
replaying a recipe on a scratch document holding just those DPJs gives the same levels after
save and load. Limits, each refused with a message: recipes nest at most MAX_RECIPE_DEPTH deep, a
recipe needs at most MAX_RECIPE_DPJS DPJs, and its text (the recipes nested in it included) is at
most MAX_RECIPE_CHARS characters.

Versions. Mix and Incrust version 1 (and spot placements version 1, see `spot_actions`) named a
recipe's one DPJ, or none, in a "ref" parameter (``source_dpj``, ``mask_dpj``); version 2 lists
them. `Action.upgrade` turns version-1 JSON into version 2 on load (`upgrade_ref`): the same steps,
the same levels.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import threading
from collections import OrderedDict
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from . import composition
from ..markov import doubling
from . import grain_render as gr
from ..recipe.actions import Action, dpj_refs, param, register
from ..recipe.document import dpj_ref
from ..errors import FormatError, InputError
from ..fileio import load_json

MAX_RECIPE_CHARS = 2**24       # a recipe's text, the recipes nested in it included
MAX_RECIPE_ACTIONS = 100_000
MAX_RECIPE_DEPTH = 8           # a recipe in a recipe in a recipe… at most this many levels
MAX_RECIPE_DPJS = 32           # the DPJs one recipe needs, at every depth together
MASKS = ("texture", "levels", "points")


class _RecipeMemo:
    """The last few recipes replayed, (levels, G): a preview and the apply that follows it, or
    the replay of a log, synthesise a source once."""

    def __init__(self, max_items: int = 6):
        self.max_items = max_items
        self._items: OrderedDict = OrderedDict()
        self._lock = threading.Lock()

    def get(self, key):
        with self._lock:
            if key in self._items:
                self._items.move_to_end(key)
            return self._items.get(key)

    def put(self, key, value) -> None:
        with self._lock:
            self._items[key] = value
            while len(self._items) > self.max_items:
                self._items.popitem(last=False)


_RECIPES = _RecipeMemo()


# -- recipes: how a composition names another texture ---------------------------------------------

def recipe_of(actions) -> str:
    """The canonical text of a log (compact JSON, as a .texture's actions.json holds it)."""
    return json.dumps({"actions": [a.to_json() for a in actions]}, separators=(",", ":"),
                      ensure_ascii=False, allow_nan=False)


def synthesis_recipe(ref: str, width: int, height: int, seed: int) -> str:
    """The recipe of one synthesis of a stored DPJ."""
    from ..recipe.actions import Synthesize
    return recipe_of([Synthesize(ref, width, height, seed)])


class _TooDeep(Exception):
    """Recipes nested deeper than MAX_RECIPE_DEPTH: raised where it is found, and turned into one
    InputError by the outermost recipe (not wrapped again by every level in between)."""


_NESTING = threading.local()


def parse_recipe(text: str) -> tuple[Action, ...]:
    """The actions of a recipe, every one checked (InputError says what is wrong). The recipes
    inside it are parsed as its actions are made, one level deeper each: the depth is counted
    here, per thread, so a too deep nesting is refused before it is all read."""
    depth = getattr(_NESTING, "depth", 0) + 1
    if depth > MAX_RECIPE_DEPTH:
        raise _TooDeep
    _NESTING.depth = depth
    try:
        return _parse_recipe(text)
    except _TooDeep:
        if depth > 1:
            raise
        raise InputError(f"texture recipes nest at most {MAX_RECIPE_DEPTH} deep (a source whose "
                         "log composes a source whose log composes…): choose a texture made "
                         "with fewer levels of composition") from None
    finally:
        _NESTING.depth = depth - 1


def _parse_recipe(text: str) -> tuple[Action, ...]:
    from ..recipe.actions import action_from_json
    if not isinstance(text, str) or len(text) > MAX_RECIPE_CHARS:
        raise InputError(f"a texture recipe is a JSON text of at most {MAX_RECIPE_CHARS} "
                         "characters, the recipes nested in it included")
    obj = load_json(text, "the texture recipe", limit=MAX_RECIPE_CHARS, error=InputError)
    if not isinstance(obj, dict) or set(obj) != {"actions"} or not isinstance(obj["actions"], list):
        raise InputError('a texture recipe is {"actions": [...]}, the log that rebuilds it')
    if not 0 < len(obj["actions"]) <= MAX_RECIPE_ACTIONS:
        raise InputError(f"a texture recipe holds 1..{MAX_RECIPE_ACTIONS} actions")
    try:
        return tuple(action_from_json(a) for a in obj["actions"])
    except (FormatError, RecursionError) as exc:
        raise InputError(f"the texture recipe: {exc}") from None


def check_recipe(text: str, refs: tuple, what: str) -> None:
    """A valid recipe whose DPJs are exactly ``refs``: every DPJ its log names, the DPJs of the
    recipes nested in it included (their steps name them in turn), so a log's `dpj_refs` is
    all a saved file or a bank entry must carry. Order does not matter."""
    used = dpj_refs(parse_recipe(text))
    if len(used) > MAX_RECIPE_DPJS:
        raise InputError(f"{what} is made from {len(used)} DPJs; a texture used as a source may "
                         f"use at most {MAX_RECIPE_DPJS}")
    missing = [r for r in used if r not in refs]
    if missing:
        raise InputError(f"{what} uses DPJ {', '.join(missing)}, which the step does not name "
                         f"(it names {', '.join(refs) or 'none'})")
    extra = [r for r in refs if r not in used]
    if extra:
        raise InputError(f"{what} does not use DPJ {', '.join(extra)}, which the step names")


def render_recipe(text: str, dpjs: dict, progress=None, cancel=None) -> tuple[np.ndarray, int]:
    """(levels, G) of a recipe replayed on an empty document with ``dpjs`` (reference → DPJ, a
    reference naming its DPJ's content); memoised."""
    from ..recipe.history import replay
    wrong = sorted(r for r, d in dpjs.items() if not d.has_ref(r))
    if wrong:      # the memo is keyed by references: each must name its DPJ
        raise InputError(f"DPJ {', '.join(wrong)} of a texture recipe is another DPJ's content")
    hit = _RECIPES.get(_recipe_key(text, dpjs))
    if hit is not None:
        return hit
    doc = replay(parse_recipe(text), dpjs, progress=progress, cancel=cancel)
    if not doc.levels.size:
        raise InputError("the texture recipe gives an empty canvas")
    return _remember(text, dpjs, doc)


def _recipe_key(text: str, dpjs: dict) -> tuple:
    return (hashlib.sha256(text.encode("utf-8")).hexdigest(), tuple(sorted(dpjs)))


def _remember(text: str, dpjs: dict, doc) -> tuple[np.ndarray, int]:
    levels = doc.levels.copy()
    levels.flags.writeable = False
    result = (levels, doc.num_levels)
    _RECIPES.put(_recipe_key(text, dpjs), result)
    return result


def store_dpj(doc, dpj) -> str:
    """Keep a DPJ in the document's store without making it the current one (a composition
    source's DPJ, a doubling table); returns its reference."""
    ref = dpj_ref(dpj)
    doc.dpjs.setdefault(ref, dpj)
    return ref


def _recipe_field(doc: str, optional: bool = False):
    return param("str", hi=MAX_RECIPE_CHARS, default=None if optional else dataclasses.MISSING,
                 optional=optional, doc=doc)


def refs_field(doc: str):
    """The DPJs a recipe needs, at every depth (see `check_recipe`)."""
    return param("refs", hi=MAX_RECIPE_DPJS, default=(), doc=doc)


def source_levels(doc, text: str, refs: tuple, progress=None, cancel=None):
    """(levels, G) of a recipe whose DPJs ``refs`` are in the document's store."""
    missing = [r for r in refs if r not in doc.dpjs]
    if missing:
        raise InputError(f"DPJ {', '.join(missing)} of a texture recipe is not part of this "
                         "document")
    return render_recipe(text, {r: doc.dpjs[r] for r in refs}, progress, cancel)


def upgrade_ref(params: dict, old: str, new: str) -> dict:
    """Version-1 JSON named a recipe's one DPJ (or none) in ``old``; now ``new`` lists them."""
    if new in params:
        raise FormatError(f"version 1 has no parameter {new!r} (it names one DPJ in {old!r})")
    params = dict(params)
    ref = params.pop(old, None)
    params[new] = [] if ref is None else [ref]
    return params


@dataclass(frozen=True)
class TextureSource:
    """A texture ready to be named by a step: its recipe, the DPJs it needs at every depth (their
    references, and the DPJs themselves for the document's store), its number of levels G, a
    name."""

    recipe: str
    refs: tuple
    dpjs: dict
    levels: int
    name: str

    def store(self, doc) -> None:
        """Keep the recipe's DPJs in ``doc`` (before a step that names them is made)."""
        for dpj in self.dpjs.values():
            store_dpj(doc, dpj)


def bank_source(bank, entry_id: int, progress=None, cancel=None) -> TextureSource:
    """A bank entry (of a `bank.Bank`) as a recipe: its log and every DPJ it needs.

    The entry is replayed here and must give the texture the bank recorded (its SHA-256), so a
    damaged entry is refused before a step names it; the levels stay in the memo for the preview
    or the apply that follows. Slow: call it in a worker."""
    entry, recipe = bank.get(entry_id), bank.recipe(entry_id)
    refs = tuple(dpj_refs(recipe.actions))
    text = recipe_of(recipe.actions)
    check_recipe(text, refs, f"bank entry {entry.id} “{entry.name}”")
    doc = bank.render(entry_id, progress=progress, cancel=cancel)     # hash checked
    dpjs = {r: recipe.dpjs[r] for r in refs}
    _remember(text, dpjs, doc)
    return TextureSource(text, refs, dpjs, doc.num_levels, entry.name)


# -- grains and density (§5.3) ---------------------------------------------------------------------

@register
@dataclass(frozen=True)
class RenderGrains(Action):
    """Draw each point of the normalised texture as a grain: a new, larger canvas (§5.3).

    The canvas becomes (H·pitch_y) × (W·pitch_x) pixels, see `grain_render`; the levels and
    palette keep their meaning, level 0 stays background.
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
                               doc="brings grains together until they overlap (0 = touching)")
    overlap: str = param("str", hi=8, default="last",
                         doc="where grains overlap: last (drawn later wins), max or min level")
    lattice: str = param("str", hi=16, default="auto",
                         doc="auto (honeycomb for hexagons), grid or honeycomb")
    bitmap: str | None = param("str", hi=64 * 65, default=None, optional=True,
                               doc="a drawn grain: rows of hex digits separated by /")

    def _validate(self) -> None:
        if self.overlap not in gr.OVERLAP_RULES:
            raise InputError(f"overlap rule must be one of {', '.join(gr.OVERLAP_RULES)}")
        if self.lattice not in gr.LATTICES:
            raise InputError(f"lattice must be one of {', '.join(gr.LATTICES)}")
        self.grain_lattice()

    def mask(self) -> np.ndarray:
        return gr.grain_of(self.shape, self.size, aspect=self.aspect, sides=self.sides,
                           angle=self.angle, bitmap=self.bitmap)

    def grain_lattice(self) -> gr.Lattice:
        return gr.grain_lattice(self.mask(), shape=self.shape, lattice=self.lattice,
                                explosion_x=self.explosion_x, explosion_y=self.explosion_y,
                                compression=self.compression)

    def render(self, levels, progress=None, cancel=None) -> np.ndarray:
        return gr.render_grains(levels, self.mask(), self.grain_lattice(), self.overlap,
                                progress=progress, cancel=cancel)

    def render_cost(self, texture_shape) -> float:
        """`grain_render.render_cost` of this render on a texture of ``texture_shape``."""
        return gr.render_cost(texture_shape, self.mask(), self.grain_lattice())

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

    def apply(self, doc) -> None:
        levels, picture = self.__dict__.pop("_result", (None, None))
        current = doc.levels
        if picture is None or levels.shape != current.shape or not np.array_equal(levels,
                                                                                  current):
            picture = self.render(current)
        doc._set_levels(picture, copy=False)

    def canvas_shape(self, shape):
        return self.grain_lattice().shape(shape)

    def label(self) -> str:
        what = f"{self.shape} {self.size} px" + (f", {self.angle:g}°" if self.angle else "")
        density = []
        if self.explosion_x != 1 or self.explosion_y != 1:
            density.append(f"explosion {self.explosion_x:g}×{self.explosion_y:g}")
        if self.compression:
            density.append(f"compression {self.compression:g} ({self.overlap})")
        return "Grains: " + ", ".join([what] + density)


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
    source: str = _recipe_field("T2's recipe: the log that rebuilds it (JSON)")
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

    def apply(self, doc) -> None:
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
    its own levels of one mask texture.
    """

    TYPE: ClassVar[str] = "incrust"
    VERSION: ClassVar[int] = 2
    EFFECT: ClassVar[str] = "levels"
    source: str = _recipe_field("T2's recipe: the log that rebuilds it (JSON)")
    source_dpjs: tuple = refs_field("the DPJs T2's recipe needs, at every depth")
    mask: str = param("str", hi=8, default="texture",
                      doc="texture (a third texture's levels), levels (the document's), points")
    levels: str = param("str", hi=64, default="1-15",
                        doc="the mask's levels where T2 shows, like 1,3-5")
    mask_source: str | None = _recipe_field("the mask texture's recipe", optional=True)
    mask_dpjs: tuple = refs_field("the DPJs the mask texture's recipe needs, at every depth")
    points: tuple = param("points", 0, 16383, default=(),
                          doc="painted (row, col) points where T2 shows")

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
        """Where T2 shows, on the document's canvas."""
        if self.mask == "points":
            return composition.membership_from_points(self.points, doc.shape)
        chosen = composition.parse_level_set(self.levels)
        if self.mask == "levels":
            return composition.membership_from_levels(doc.levels, chosen)
        m, _ = source_levels(doc, self.mask_source, self.mask_dpjs)
        return composition.membership_from_levels(composition.fit(m, doc.shape), chosen)

    def apply(self, doc) -> None:
        t2, g2 = source_levels(doc, self.source, self.source_dpjs)
        t2 = composition.convert_levels(composition.fit(t2, doc.shape), g2, doc.num_levels)
        _commit(doc, composition.incrust(self.membership(doc), [doc.levels, t2]))

    def label(self) -> str:
        where = {"texture": f"levels {self.levels} of a mask texture",
                 "levels": f"the document's levels {self.levels}",
                 "points": f"{len(self.points)} painted points"}[self.mask]
        return f"Incrust T2 where {where}"


def _commit(doc, new: np.ndarray) -> None:
    """Write only the points that change (the undo record is their bounding box)."""
    changed = new != doc.levels
    if changed.any():
        doc._write_where(changed, new)


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

    def apply(self, doc) -> None:
        table = doc.dpjs.get(self.table)
        if table is None:
            raise InputError(f"doubling table {self.table} is not part of this document")
        g = doubling.check_table(table)
        if doc.num_levels != g:
            raise InputError(f"this table doubles textures of G = {g} levels; the document has "
                             f"G = {doc.num_levels}")
        result = doubling.double_levels(doc.levels, table, self.seed)
        doc._set_levels(result.levels, table.palette, copy=False)

    def label(self) -> str:
        return f"Double the levels, seed {self.seed}"


TEXTURE_ACTIONS = (RenderGrains, Mix, Incrust, DoubleLevels)
