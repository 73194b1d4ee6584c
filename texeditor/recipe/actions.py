"""Actions: every change to a Document is a small immutable record of plain parameters.

The action log is a texture's recipe (thesis §5.4, digest §10): files, the bank, undo and replay all
walk it. A new kind of edit is one small ``@register``-ed dataclass whose fields are ``param(...)``.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass
from typing import Any, Callable, ClassVar

import numpy as np

from ..markov.dpj import MAX_LEVELS, grey_ramp
from ..markov.scan import ROWS, SCANS, check_scan
from ..markov.multiscale import (COARSE_REDRAWS, COARSE_ROW_REDRAWS, DRAFT_TRIGGER,
                                 GIVEN_REDRAWS, LEAN_DRAFTS, NO_ROW_LIMIT, OLD_REDRAWS,
                                 SCALES_CLOSURE, scales_phrase)
from ..markov.particles import DRAFT_POINTS, MAX_PARTICLES, MORE_PARTICLES, PARTICLES
from ..markov.synthesis import CLOSURE, MAX_SEED
from ..errors import FormatError, InputError, check_unicode

MAX_CANVAS_SIDE = 16384
MAX_CANVAS_PIXELS = 2**26
MAX_POINTS = 1_000_000
MAX_REFS = 64                  # a "refs" parameter without its own bound (a .texture's limit)
MAX_TEXT = 2**24               # each text of a "texts" parameter (a texture recipe's limit)
_REF = re.compile(r"^[0-9a-f]{16}$")

REGISTRY: dict[str, type["Action"]] = {}


# -- parameters -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class ParamSpec:
    """What a form needs to edit one parameter: its name, kind, bounds, value and a hint."""

    name: str
    kind: str            # int, float, bool, str, ref, refs, seed, palette, points, texts, exemplar
    minimum: float | None
    maximum: float | None
    optional: bool
    value: Any
    doc: str


def param(kind: str, lo=None, hi=None, *, default=dataclasses.MISSING, optional=False, doc=""):
    """A dataclass field with the metadata that drives validation, JSON and edit forms."""
    if kind not in _KINDS:
        raise ValueError(f"unknown parameter kind {kind!r}")
    meta = {"kind": kind, "lo": lo, "hi": hi, "optional": optional, "doc": doc}
    return dataclasses.field(default=default, metadata=meta)


def _int(name, value, lo, hi):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{name} must be an integer, got {value!r}")
    value = int(value)
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        raise InputError(f"{name} = {value} is out of range {_range(lo, hi)}")
    return value


def _float(name, value, lo, hi):
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{name} must be a number, got {value!r}")
    value = float(value)
    if not np.isfinite(value) or (lo is not None and value < lo) or (hi is not None and value > hi):
        raise InputError(f"{name} = {value} is out of range {_range(lo, hi)}")
    return value


def _bool(name, value, lo, hi):
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name} must be true or false, got {value!r}")
    return bool(value)


def _str(name, value, lo, hi):
    if not isinstance(value, str) or len(value) > (hi or 10_000):
        raise InputError(f"{name} must be a text of at most {hi or 10_000} characters")
    return check_unicode(value, name)


def _ref(name, value, lo, hi):
    if not isinstance(value, str) or not _REF.match(value):
        raise InputError(f"{name} must be a DPJ reference (16 hex digits), got {value!r}")
    return value


def _exemplar(name, value, lo, hi):
    """The reference of an exemplar photo the document holds (`exemplars.exemplar_ref`)."""
    if not isinstance(value, str) or not _REF.match(value):
        raise InputError(f"{name} must be an exemplar reference (16 hex digits), got {value!r}")
    return value


def _refs(name, value, lo, hi):
    """A tuple of distinct DPJ references (the DPJs a texture recipe uses), at most ``hi``."""
    most = hi or MAX_REFS
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)):
        raise InputError(f"{name} must be a list of DPJ references (16 hex digits each), "
                         f"got {_short(value)}")
    if len(value) > most:
        raise InputError(f"{name} names {len(value)} DPJs; at most {most} are allowed")
    refs = tuple(_ref(f"each of {name}", v, None, None) for v in value)
    if len(set(refs)) != len(refs):
        raise InputError(f"{name} names a DPJ more than once")
    return refs


def _texts(name, value, lo, hi):
    """A tuple of ``lo``..``hi`` texts (the recipes of a composition's textures), each at most
    MAX_TEXT characters; what each holds is the Action's to check."""
    lo, hi = lo or 0, hi or MAX_REFS
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)) or not lo <= len(value) <= hi:
        raise InputError(f"{name} must be a list of {lo}..{hi} texts, got {_short(value)}")
    return tuple(_str(f"each of {name}", v, None, MAX_TEXT) for v in value)


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def palette_param(name, value, lo, hi):
    """A palette parameter: 2..MAX_LEVELS colours (r, g, b), each component 0..255."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)) or not 2 <= len(value) <= MAX_LEVELS:
        raise InputError(f"{name} must list 2..{MAX_LEVELS} colours (r, g, b)")
    colours = []
    for colour in value:
        if isinstance(colour, np.ndarray):
            colour = colour.tolist()
        if not isinstance(colour, (list, tuple)) or len(colour) != 3:
            raise InputError(f"{name}: each colour must be three components (r, g, b)")
        colours.append(tuple(_int(f"{name} component", c, 0, 255) for c in colour))
    return tuple(colours)


def _points(name, value, lo, hi):
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)) or len(value) > MAX_POINTS:
        raise InputError(f"{name} must be a list of at most {MAX_POINTS} (row, col) points")
    points = []
    for p in value:
        if not isinstance(p, (list, tuple)) or len(p) != 2:
            raise InputError(f"{name}: each point must be (row, col)")
        points.append((_int(f"{name} row", p[0], lo, hi), _int(f"{name} col", p[1], lo, hi)))
    return tuple(points)


_KINDS: dict[str, Callable] = {
    "int": _int, "seed": lambda n, v, lo, hi: _int(n, v, 0, MAX_SEED), "float": _float,
    "bool": _bool, "str": _str, "ref": _ref, "refs": _refs, "palette": palette_param,
    "points": _points, "texts": _texts, "exemplar": _exemplar,
}


def _range(lo, hi) -> str:
    return f"{'-inf' if lo is None else lo}..{'inf' if hi is None else hi}"


def _check_field(f: dataclasses.Field, value):
    meta = f.metadata
    if value is None and meta["optional"]:
        return None
    return _KINDS[meta["kind"]](f.name, value, meta["lo"], meta["hi"])


def _to_plain(value):
    if isinstance(value, tuple):
        return [_to_plain(v) for v in value]
    return value


# -- what a step reads and writes ------------------------------------------------------------------

@dataclass(frozen=True)
class Access:
    """What one step reads and writes, for the log optimiser's commutation test (`logopt`).

    ``reads`` and ``writes`` are rectangles (top, left, height, width) of points in canvas
    coordinates; writing a point may change its level or whether it exists (a canvas change).
    A step's Access holds for the canvas shape it was asked about. The palette is read or
    written as a whole.
    """

    reads: tuple = ()
    writes: tuple = ()
    reads_palette: bool = False
    writes_palette: bool = False


EVERYWHERE = (-2**20, -2**20, 2**21, 2**21)    # a rectangle holding every point a canvas can have


def extent_change(before: tuple[int, int], after: tuple[int, int]) -> tuple:
    """The points a canvas change from shape ``before`` to ``after`` (both anchored top-left)
    creates or removes, as at most two rectangles: the box of both minus what both keep."""
    (h1, w1), (h2, w2) = before, after
    low, high = (min(h1, h2), min(w1, w2)), (max(h1, h2), max(w1, w2))
    rects = ((0, low[1], high[0], high[1] - low[1]), (low[0], 0, high[0] - low[0], low[1]))
    return tuple(r for r in rects if r[2] and r[3])


# -- the base class and the registry --------------------------------------------------------------

@dataclass(frozen=True)
class Action:
    """An immutable edit. Subclasses set TYPE, VERSION, EFFECT and define apply() and label().

    EFFECT tells the log optimiser what an action may touch: "reset" (the result does not depend
    on the state before: NewCanvas, Synthesize), "levels" (changes only level values; shape and
    palette stay), "palette" (changes only colours), "canvas" (changes the shape, not by content:
    define canvas_shape), "other" (anything: the optimiser never moves or drops across it).
    """

    TYPE: ClassVar[str] = ""
    VERSION: ClassVar[int] = 1
    EFFECT: ClassVar[str] = "other"

    def __post_init__(self):
        for f in dataclasses.fields(self):
            object.__setattr__(self, f.name, _check_field(f, getattr(self, f.name)))
        self._validate()

    def _validate(self) -> None:
        """Checks across parameters (a subclass hook)."""

    def prepare(self, doc, progress=None, cancel=None):
        """Do the slow part ahead of apply() (in a worker thread, cancellable); optional. What it
        returns is handed to ``apply(doc, prepared)`` (None: apply does it all). A History keeps
        it for the next replay of an equal step on a canvas of the same shape, so it must not
        depend on the levels before (return None then, or compute them in apply)."""
        return None

    def apply(self, doc, prepared=None) -> None:
        """Change ``doc`` through its edit interface; ``prepared`` is what prepare() returned."""
        raise NotImplementedError

    def label(self) -> str:
        return self.TYPE

    def canvas_shape(self, shape: tuple[int, int]) -> tuple[int, int]:
        """The canvas shape after this action, from the shape before (for "canvas"/"reset")."""
        return shape

    def picked_region(self, levels) -> str | None:
        """A digest of the region this step picks from the levels before it (None: it picks
        none). An edit of an earlier step can change it: History then marks the step."""
        return None

    def covers(self, shape: tuple[int, int]) -> bool:
        """True when this action overwrites every level of a canvas of this shape."""
        return False

    def access(self, shape: tuple[int, int] | None) -> Access | None:
        """What this step reads and writes on a canvas of ``shape`` (``shape`` None: not known).
        Returning None says the step cannot tell: the log optimiser moves nothing across it."""
        return None

    def refers_to(self, log, at: int) -> tuple[int, ...]:
        """The indices (< ``at``) in ``log``, where this step is ``log[at]``, of the steps it
        finds by their place in the log, as a deletion finds its placement: the log optimiser
        keeps them."""
        return ()

    def to_json(self) -> dict:
        params = {f.name: _to_plain(getattr(self, f.name)) for f in dataclasses.fields(self)}
        return {"type": self.TYPE, "version": self.VERSION, **params}

    @classmethod
    def upgrade(cls, version: int, params: dict) -> dict:
        """Turn the parameters of an older VERSION into current ones (override when bumping)."""
        raise FormatError(f"action {cls.TYPE!r} version {version} is not supported "
                          f"(this program reads version {cls.VERSION})")


def register(cls: type[Action]) -> type[Action]:
    """Class decorator: make an Action type known to the JSON reader."""
    if not cls.TYPE or cls.TYPE in REGISTRY:
        raise ValueError(f"action type {cls.TYPE!r} is empty or already registered")
    REGISTRY[cls.TYPE] = cls
    return cls


def registry() -> dict[str, type["Action"]]:
    """Every Action type by name. Complete as soon as any engine module is imported: the
    `texeditor` package imports every operator package (each registers its Actions)."""
    return REGISTRY


def action_params(action: Action) -> dict:
    """The parameters as a dict of plain values (name → value), in declaration order."""
    return {f.name: getattr(action, f.name) for f in dataclasses.fields(action)}


def param_specs(action: Action | type[Action]) -> list[ParamSpec]:
    """Each parameter's name, kind, bounds and current (or default) value: an edit form's rows."""
    specs = []
    for f in dataclasses.fields(action):
        m = f.metadata
        value = getattr(action, f.name) if isinstance(action, Action) else (
            None if f.default is dataclasses.MISSING else f.default)
        lo, hi = (0, MAX_SEED) if m["kind"] == "seed" else (m["lo"], m["hi"])
        specs.append(ParamSpec(f.name, m["kind"], lo, hi, m["optional"], value, m["doc"]))
    return specs


def dpj_refs(actions) -> list[str]:
    """The DPJ references a log uses (parameters of kind "ref" and "refs"), in order of first
    use. A step that carries a texture recipe names every DPJ the recipe needs, at any depth
    (`texture_actions.check_recipe`), so this list is complete without opening recipes."""
    seen: dict[str, None] = {}
    for a in actions:
        for f in dataclasses.fields(a):
            kind, value = f.metadata.get("kind"), getattr(a, f.name)
            if kind == "ref" and value is not None:
                seen.setdefault(value)
            elif kind == "refs":
                for ref in value or ():
                    seen.setdefault(ref)
    return list(seen)


def exemplar_refs(actions) -> list[str]:
    """The exemplar photos a log uses (parameters of kind "exemplar"), in order of first use."""
    seen: dict[str, None] = {}
    for a in actions:
        for f in dataclasses.fields(a):
            if f.metadata.get("kind") == "exemplar" and getattr(a, f.name) is not None:
                seen.setdefault(getattr(a, f.name))
    return list(seen)


def replace_params(action: Action, **changes) -> Action:
    """A copy with some parameters changed, validated like a new action (for "edit step k")."""
    try:
        return dataclasses.replace(action, **changes)
    except TypeError as exc:
        raise InputError(f"{action.TYPE}: {exc}") from None


# -- helpers ---------------------------------------------------------------------------------------

def _check_canvas(width: int, height: int) -> None:
    if width * height > MAX_CANVAS_PIXELS:
        raise InputError(f"a {width}x{height} canvas has more than {MAX_CANVAS_PIXELS} points")


def clip_rect(top, left, height, width, shape) -> tuple[int, int, int, int]:
    """A rectangle intersected with the canvas: (top, left, height, width), maybe empty."""
    H, W = shape
    t, l = min(max(top, 0), H), min(max(left, 0), W)
    b, r = min(max(top + height, 0), H), min(max(left + width, 0), W)
    return t, l, max(b - t, 0), max(r - l, 0)


def drop_plates(doc) -> None:
    """A step whose result does not depend on the state before it (EFFECT "reset": a new
    canvas, a synthesis) starts without plates, as the log optimiser and spot deletion,
    which replay from the last reset, assume."""
    if doc.plates is not None:
        doc.set_plates(None, None)


def _side(doc="") -> dataclasses.Field:
    return param("int", 1, MAX_CANVAS_SIDE, doc=doc)


def _coord(doc="") -> dataclasses.Field:
    return param("int", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, doc=doc)


# -- the first actions -----------------------------------------------------------------------------

@register
@dataclass(frozen=True)
class NewCanvas(Action):
    """A blank canvas (every point level 0, the background) of G levels."""

    TYPE: ClassVar[str] = "new_canvas"
    EFFECT: ClassVar[str] = "reset"
    width: int = _side("points across")
    height: int = _side("points down")
    levels: int = param("int", 2, MAX_LEVELS, doc="number of levels G")
    palette: tuple | None = param("palette", default=None, optional=True,
                                  doc="G colours (r, g, b); grey ramp when empty")

    def _validate(self):
        _check_canvas(self.width, self.height)
        if self.palette is not None and len(self.palette) != self.levels:
            raise InputError(f"the palette has {len(self.palette)} colours for G = {self.levels}")

    def apply(self, doc, prepared=None) -> None:
        palette = grey_ramp(self.levels) if self.palette is None else self.palette
        drop_plates(doc)
        doc.set_levels(np.zeros((self.height, self.width), np.uint8), palette, copy=False)

    def canvas_shape(self, shape):
        return (self.height, self.width)

    def covers(self, shape):
        return True

    def label(self) -> str:
        return f"New canvas {self.width}×{self.height}, G = {self.levels}"


def _tileable():
    return param("bool", default=False, doc="drawn on the torus: the texture repeats without a "
                                            "seam (windows across the seams are DPJ windows)")


def _closure():
    return param("int", 1, CLOSURE, default=CLOSURE,
                 doc="how a tileable texture's seams are closed: 8 (current: as 7, the "
                     "pull at its full strength, the bottom seam redrawn only where its "
                     "windows leave the DPJ), 7 (as 6, the last "
                     "rows weighed towards the first row's levels), 6 (each row drawn "
                     "on its ring, the bottom seam as 5), 5 (every window an "
                     "earlier redraw changed and the corner kept in the DPJ, over stretches "
                     "from one window), 4 (as 5, the last column also redrawn far up from a "
                     "row's failed closure), 2 (4 over stretches from 4 windows; 3 is 2 for "
                     "one DPJ), 1 (the first way); older ways are kept so older recipes replay "
                     "the same")


def _scales_closure():
    return param("int", 1, SCALES_CLOSURE, default=SCALES_CLOSURE,
                 doc="how a tileable texture's seams are closed: 8 (current: as 7, the "
                     "pull at its full strength, each scale's bottom seam redrawn only where "
                     "its windows leave the DPJ), 7 (as 6, the "
                     "last rows of each scale drawn given its parents weighed towards the "
                     "first row's levels), 6 (as 5, each scale's rows drawn on their ring), "
                     "5 (as 4, the "
                     "coarsest window chosen quicker still), 4 (as 3 over stretches from one "
                     "window), 3 (the scales as 2, a quicker choice of the coarsest window, "
                     "the tone drawn beside the levels on two lanes), 2 and 1 (earlier ways, "
                     "kept so older recipes replay the same)")


def _closure_of_version_1(cls, version: int, params: dict) -> dict:
    """Version 1 had no ``closure``: its tileable textures were closed the first way."""
    if version != 1 or "closure" in params:
        raise FormatError(f"action {cls.TYPE!r} version {version} is not supported "
                          f"(this program reads versions 1 to {cls.VERSION})")
    return {**params, "closure": 1}


def _closure_as_written(cls, version: int, params: dict, default: int) -> dict:
    """A version that named its closure, 1 to ``default`` (its own default when absent)."""
    closure = params.get("closure", default)
    if isinstance(closure, int) and not isinstance(closure, bool) and closure > default:
        raise FormatError(f"action {cls.TYPE!r} version {version} has no seam closure {closure}")
    return {**params, "closure": closure}


def _synthesis_of_version(cls, version: int, params: dict) -> dict:
    """Version 1 had no ``closure`` (closed the first way); version 2 closures 1 and 2
    (default 2), closed over stretches from CLOSE_SPAN windows; version 3 closures 1 to 4
    (default 4); version 4 closures 1 to 5 (default 5); version 5 closures 1 to 7 (default
    7)."""
    if version == 5:
        return _closure_as_written(cls, version, params, 7)
    if version == 4:
        return _closure_as_written(cls, version, params, 5)
    if version == 3:
        return _closure_as_written(cls, version, params, 4)
    if version == 2:
        return _closure_as_written(cls, version, params, 2)
    return _closure_of_version_1(cls, version, params)


# the parameters SynthesizeScales gained, newest first: the version each came with, and the value
# a step of an older version reads (it cannot name the parameter)
_SCALES_GAINED = (
    (16, "lean_drafts", False),                 # drafted past DRAFT_TRIGGER, whatever the parents
    (15, "forced_moves", False),                # shares left off after the free moves
    (14, "free_moves", False),                  # moves free of the parents after the bound ones
    (13, "coarse_row_redraws", NO_ROW_LIMIT),   # a coarsest row redrew without limit
    (12, "given_redraws", OLD_REDRAWS),         # 16 tries at a dead end of a finer scale
    (11, "tone_finish", False),                 # the tone shown as drawn
    (10, "more_drafts", False),                 # every scale drafted as ``particles``
    (9, "steer", False),                        # every scale drawn unsteered
    (8, "rebalance", False),                    # the finest scale's shares kept as drawn
    (6, "particles", 0),                        # a coarse scale drawn again whole
)


def _scales_of_version(cls, version: int, params: dict) -> dict:
    """An older step with the parameters it lacks (_SCALES_GAINED) and its closure: version 18
    had closures 1 to 7 (default 7), version 17 1 to 6 (default 6), versions 7 to 16 1 to 5 (default 5), 5 and 6 1 to 4
    (default 4), 4 1 to 3 (default 3).
    Versions 1 to 3 also tried OLD_REDRAWS times at a dead end of the coarsest scale and drew
    their tone without balance; version 1 had no ``closure`` (closed the first way), version 2
    closures 1 and 2 (default 2), version 3 1 to 3 (default 3)."""
    for since, name, older in _SCALES_GAINED:
        if version >= since:
            break
        if name in params:
            raise FormatError(f"action {cls.TYPE!r} version {version} has no {name}")
        params = {**params, name: older}
    if version >= 4:
        return _closure_as_written(cls, version, params, 7 if version == 18 else
                                   6 if version == 17 else
                                   5 if version >= 7 else 4 if version >= 5 else 3)
    if version not in (1, 2, 3) or "coarse_redraws" in params or "tone_balance" in params:
        raise FormatError(f"action {cls.TYPE!r} version {version} is not supported "
                          f"(this program reads versions 1 to {cls.VERSION})")
    params = {**params, "coarse_redraws": OLD_REDRAWS, "tone_balance": False}
    if version == 1:
        return _closure_of_version_1(cls, version, params)
    return _closure_as_written(cls, version, params, version)


@register
@dataclass(frozen=True)
class Synthesize(Action):
    """A new canvas drawn from a DPJ by the 2-D Markov process (thesis ch. 4); palette = DPJ's."""

    TYPE: ClassVar[str] = "synthesize"
    VERSION: ClassVar[int] = 6
    EFFECT: ClassVar[str] = "reset"
    dpj: str = param("ref", doc="reference of a DPJ of the document")
    width: int = _side("points across")
    height: int = _side("points down")
    seed: int = param("seed", default=0, doc="random seed: same seed, same texture")
    tileable: bool = _tileable()
    scan: str = param("str", hi=16, default=ROWS,
                      doc="scan direction (§5.2.1b): " + ", ".join(SCANS) + "; the DPJ's rows "
                          "run along the scan")
    closure: int = _closure()

    upgrade = classmethod(_synthesis_of_version)

    def _validate(self):
        _check_canvas(self.width, self.height)
        check_scan(self.scan)

    def render_result(self, dpj, progress=None, cancel=None):
        """Synthesise (slow; safe in a worker thread): the SynthesisResult, whose ``levels`` are
        what ``apply(doc, prepared=levels)`` then takes as they are."""
        from ..markov.scan import synthesize
        if not dpj.has_ref(self.dpj):
            raise InputError(f"this DPJ is not {self.dpj}, the one the action refers to")
        return synthesize(dpj, (self.height, self.width), seed=self.seed, progress=progress,
                          cancel=cancel, tileable=self.tileable, scan=self.scan,
                          closure=self.closure)

    def prepare(self, doc, progress=None, cancel=None) -> np.ndarray:
        return self.render_result(self._dpj_of(doc), progress, cancel).levels

    def apply(self, doc, prepared=None) -> None:
        _apply_synthesis(self, doc, prepared, self._dpj_of(doc).palette, self.dpj)

    def _dpj_of(self, doc):
        dpj = doc.dpjs.get(self.dpj)
        if dpj is None:
            raise InputError(f"DPJ {self.dpj} is not part of this document: add it first")
        if not dpj.has_ref(self.dpj):
            raise InputError(f"this DPJ is not {self.dpj}, the one the action refers to")
        return dpj

    def canvas_shape(self, shape):
        return (self.height, self.width)

    def covers(self, shape):
        return True

    def label(self) -> str:
        tiles = ", tileable" if self.tileable else ""
        scan = f", scan {self.scan}" if self.scan != ROWS else ""
        return f"Synthesise {self.width}×{self.height}, seed {self.seed}{tiles}{scan}"


@register
@dataclass(frozen=True)
class SynthesizeScales(Action):
    """A new canvas drawn from a multi-scale DPJ: the coarsest scale as ``synthesize`` does,
    each finer one given the one under it (markov.multiscale); palette = the finest DPJ's."""

    TYPE: ClassVar[str] = "synthesize_scales"
    VERSION: ClassVar[int] = 19
    EFFECT: ClassVar[str] = "reset"
    dpjs: tuple = param("refs", hi=6, doc="the scales' DPJs of the document, coarsest first")
    width: int = _side("points across")
    height: int = _side("points down")
    seed: int = param("seed", default=0, doc="random seed: same seed, same texture")
    tileable: bool = _tileable()
    closure: int = _scales_closure()
    coarse_redraws: int = param("int", 0, OLD_REDRAWS, default=COARSE_REDRAWS,
                                doc="a dead end of the coarsest scale: tries redrawing the rows "
                                    f"above before it backs off ({COARSE_REDRAWS}: current; "
                                    f"{OLD_REDRAWS} in recipes before version 4)")
    tone_photo: str | None = param("exemplar", default=None, optional=True,
                                   doc="the photo whose greys and colours show the texture "
                                       "(a photo model's tone), or none")
    tone_levels: str | None = param("exemplar", default=None, optional=True,
                                    doc="that photo's finest levels, which say where its tone "
                                        "is drawn from")
    tone_balance: bool = param("bool", default=True,
                               doc="the tone keeps each level's histogram of the photo's greys "
                                   "(current; recipes before version 4 drew it without)")
    tone_finish: bool = param("bool", default=True,
                              doc="the tone's pixel-scale sharpness is brought to the photo's "
                                  "(current; recipes before version 11 showed it as drawn)")
    particles: int = param("int", 0, MAX_PARTICLES, default=PARTICLES,
                           doc="a scale whose level shares come out off is drawn again as this "
                               f"many drafts side by side ({PARTICLES}: current; 0: drawn "
                               "again whole, as recipes before version 6)")
    rebalance: bool = param("bool", default=True,
                            doc="the finest scale's level shares, when they come out off, are "
                                "brought back by moving region borders (current; recipes "
                                "before version 8 kept them as drawn)")
    steer: bool = param("bool", default=True,
                        doc="every scale's level shares are steered towards its DPJ's as its "
                            "rows are drawn (current; recipes before version 9 drew them "
                            "unsteered)")
    more_drafts: bool = param("bool", default=True,
                              doc="a small scale is drafted as more particles: as many as fit "
                                  f"in {DRAFT_POINTS} points, up to {MORE_PARTICLES} (current; "
                                  "recipes before version 10 drafted every scale as "
                                  "`particles`)")
    given_redraws: int = param("int", 0, OLD_REDRAWS, default=GIVEN_REDRAWS,
                               doc="a dead end of a scale drawn given its parents: tries "
                                   "redrawing the rows above before it backs off "
                                   f"({GIVEN_REDRAWS}: current; {OLD_REDRAWS} in recipes before "
                                   "version 12)")
    coarse_row_redraws: float = param("float", 0, NO_ROW_LIMIT, default=COARSE_ROW_REDRAWS,
                                      doc="a row of the coarsest scale redraws at most this many "
                                          "times per point of its width, then its dead ends "
                                          f"back off at once ({COARSE_ROW_REDRAWS:g}: current; "
                                          f"{NO_ROW_LIMIT:g}, no limit, in recipes before "
                                          "version 13)")
    free_moves: bool = param("bool", default=True,
                             doc="when the moves its parents allow leave a level's share of the "
                                 "finest scale off, more moves follow, free of them (current; "
                                 "recipes before version 14 stopped there)")
    forced_moves: bool = param("bool", default=True,
                               doc="when a level's share is off even then (a level the "
                                   "texture lacks), forced moves follow, which may leave "
                                   "windows outside the DPJ (current; recipes before version "
                                   "15 stopped there)")
    lean_drafts: bool = param("bool", default=LEAN_DRAFTS,
                              doc="a scale is drafted only when its level shares come out "
                                  f"more than {DRAFT_TRIGGER} further off than its parents' "
                                  "(current: the parents hold it about as far off, and drafts "
                                  "could not take it closer; recipes before version 16 drafted "
                                  f"it whenever more than {DRAFT_TRIGGER} off)")

    upgrade = classmethod(_scales_of_version)

    def _validate(self):
        _check_canvas(self.width, self.height)
        if not self.dpjs:
            raise InputError("a multi-scale synthesis needs at least one DPJ")
        if (self.tone_photo is None) != (self.tone_levels is None):
            raise InputError("a tone names both its photo and the photo's levels, or neither")

    def render_result(self, dpjs, progress=None, cancel=None):
        """Synthesise (slow; safe in a worker thread): the finest scale's SynthesisResult."""
        from ..markov.multiscale import synthesize_scales
        return synthesize_scales(_scales(dpjs), (self.height, self.width),
                                 seed=self.seed, progress=progress, cancel=cancel,
                                 tileable=self.tileable, closure=self.closure,
                                 coarse_redraws=self.coarse_redraws, particles=self.particles,
                                 rebalance=self.rebalance, steer=self.steer,
                                 more_drafts=self.more_drafts,
                                 given_redraws=self.given_redraws,
                                 coarse_row_redraws=self.coarse_row_redraws,
                                 free_moves=self.free_moves,
                                 forced_moves=self.forced_moves,
                                 lean_drafts=self.lean_drafts)

    def prepare(self, doc, progress=None, cancel=None) -> np.ndarray:
        return self.render_result(self._dpjs_of(doc), progress, cancel).levels

    def apply(self, doc, prepared=None) -> None:
        for ref in (self.tone_photo, self.tone_levels):
            if ref is not None and ref not in doc.exemplars:
                raise InputError(f"the tone's picture {ref} is not part of this document")
        _apply_synthesis(self, doc, prepared, _scales(self._dpjs_of(doc)).palette,
                         self.dpjs[-1])

    def _dpjs_of(self, doc):
        return [Synthesize(ref, self.width, self.height)._dpj_of(doc) for ref in self.dpjs]

    def canvas_shape(self, shape):
        return (self.height, self.width)

    def covers(self, shape):
        return True

    def label(self) -> str:
        tiles = ", tileable" if self.tileable else ""
        tone = ", with its photo's tone" if self.tone_photo is not None else ""
        return (f"Synthesise {self.width}×{self.height} on {scales_phrase(len(self.dpjs))}, "
                f"seed {self.seed}{tiles}{tone}")


def _apply_synthesis(action, doc, prepared, palette, current: str) -> None:
    """A synthesis step's levels (drawn now, or ``prepared`` by a worker) become a new canvas
    with ``palette``; its plates go, and ``current`` becomes the current DPJ."""
    levels = action.prepare(doc) if prepared is None else np.asarray(prepared)
    if levels.dtype != np.uint8 or levels.shape != (action.height, action.width):
        raise InputError(f"a synthesis result must be a {action.width}x{action.height} uint8 "
                         f"matrix, got {levels.shape} {levels.dtype}")
    drop_plates(doc)
    doc.set_levels(levels, palette)
    doc.set_current_dpj(current)


def _scales(dpjs):
    from ..markov.multiscale import MultiScaleDPJ
    return MultiScaleDPJ(tuple(dpjs))


@register
@dataclass(frozen=True)
class SetPalette(Action):
    """New colours for the G levels (the levels themselves do not change)."""

    TYPE: ClassVar[str] = "set_palette"
    EFFECT: ClassVar[str] = "palette"
    palette: tuple = param("palette", doc="G colours (r, g, b)")

    def apply(self, doc, prepared=None) -> None:
        if len(self.palette) != doc.num_levels:
            raise InputError(f"the palette has {len(self.palette)} colours but the document "
                             f"has G = {doc.num_levels} levels")
        doc.set_palette(self.palette)

    def access(self, shape):
        return Access(writes_palette=True)

    def label(self) -> str:
        return f"Set palette ({len(self.palette)} colours)"


@register
@dataclass(frozen=True)
class SetLevels(Action):
    """Fill a rectangle with one level (clipped to the canvas): the generic point edit."""

    TYPE: ClassVar[str] = "set_levels"
    EFFECT: ClassVar[str] = "levels"
    top: int = _coord("first row")
    left: int = _coord("first column")
    height: int = _side("rows")
    width: int = _side("columns")
    value: int = param("int", 0, MAX_LEVELS - 1, doc="the level written")

    def apply(self, doc, prepared=None) -> None:
        t, l, h, w = clip_rect(self.top, self.left, self.height, self.width, doc.shape)
        if h and w:
            doc.fill(t, l, h, w, self.value)
        elif self.value >= doc.num_levels:
            doc.check_levels(self.value)

    def covers(self, shape):
        return clip_rect(self.top, self.left, self.height, self.width, shape)[2:] == shape

    def access(self, shape):
        """Its rectangle, whatever the shape: only whether its own points exist matters."""
        rect = (self.top, self.left, self.height, self.width)
        return Access(reads=(rect,), writes=(rect,))

    def label(self) -> str:
        if self.height == self.width == 1:
            return f"Set ({self.top}, {self.left}) to {self.value}"
        return f"Set {self.width}×{self.height} at ({self.top}, {self.left}) to {self.value}"


@register
@dataclass(frozen=True)
class CropCanvas(Action):
    """Keep a rectangle of the canvas (clipped to it); it must overlap the canvas."""

    TYPE: ClassVar[str] = "crop_canvas"
    EFFECT: ClassVar[str] = "canvas"
    top: int = _coord("first row kept")
    left: int = _coord("first column kept")
    height: int = _side("rows kept")
    width: int = _side("columns kept")

    def apply(self, doc, prepared=None) -> None:
        t, l, h, w = clip_rect(self.top, self.left, self.height, self.width, doc.shape)
        if not (h and w):
            H, W = doc.shape
            raise InputError(f"the crop {self.width}x{self.height} at ({self.top}, {self.left}) "
                             f"lies outside the {W}x{H} canvas")
        plates = None if doc.plates is None else doc.plates[t:t + h, l:l + w]
        doc.set_levels(doc.levels[t:t + h, l:l + w].copy(), copy=False, plates=plates)

    def canvas_shape(self, shape):
        return clip_rect(self.top, self.left, self.height, self.width, shape)[2:]

    def access(self, shape):
        """A crop at the corner only removes points; elsewhere it moves every point."""
        if shape is None:
            return Access(reads=(EVERYWHERE,), writes=(EVERYWHERE,))
        t, l, h, w = clip_rect(self.top, self.left, self.height, self.width, shape)
        if not (h and w):
            return None                          # it fails: nothing is known
        if t == l == 0:
            return Access(writes=extent_change(shape, (h, w)))
        whole = ((0, 0) + tuple(shape),)
        return Access(reads=whole, writes=whole)

    def label(self) -> str:
        return f"Crop to {self.width}×{self.height} at ({self.top}, {self.left})"


@register
@dataclass(frozen=True)
class ResizeCanvas(Action):
    """Change the canvas size, anchored top-left; new points get the level ``fill`` (and the
    plate of the nearest old point)."""

    TYPE: ClassVar[str] = "resize_canvas"
    EFFECT: ClassVar[str] = "canvas"
    height: int = _side("rows")
    width: int = _side("columns")
    fill: int = param("int", 0, MAX_LEVELS - 1, default=0, doc="level of the new points")

    def _validate(self):
        _check_canvas(self.width, self.height)

    def apply(self, doc, prepared=None) -> None:
        doc.check_levels(self.fill)
        new = np.full((self.height, self.width), self.fill, dtype=np.uint8)
        h, w = min(self.height, doc.shape[0]), min(self.width, doc.shape[1])
        new[:h, :w] = doc.levels[:h, :w]
        plates = None if doc.plates is None else np.pad(
            doc.plates[:h, :w], ((0, self.height - h), (0, self.width - w)), mode="edge")
        doc.set_levels(new, copy=False, plates=plates)

    def canvas_shape(self, shape):
        return (self.height, self.width)

    def access(self, shape):
        """It keeps the points both shapes share and writes the others (``fill`` or gone)."""
        if shape is None:
            return Access(reads=(EVERYWHERE,), writes=(EVERYWHERE,))
        return Access(writes=extent_change(shape, self.canvas_shape(shape)))

    def label(self) -> str:
        return f"Resize canvas to {self.width}×{self.height}"
