"""The region and global operators of thesis §3.4 as Actions: fill, translate, copy, the local
manipulations of a selection, the four global operators and the random manipulation of every
region, each a small replayable record.

Tools (GUI, CLI) build these from clicks and fields; `regions` and `transforms` do the work. A
selection is stored as the recipe that extracted it — a point, the extraction kind, the scope,
the connectivity and, for one neighbour isolated among several, its number — so replaying the
log finds the same points again, bit for bit.
"""

from __future__ import annotations

import dataclasses
import hashlib
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from . import extractext as regions
from . import scatter, transforms
from ..recipe.actions import MAX_CANVAS_PIXELS, MAX_CANVAS_SIDE, Action, param, register
from ..markov.dpj import MAX_LEVELS
from ..errors import InputError

MAX_FACTOR = 64.0
MAX_REPEAT = 256
_KIND_NAMES = {"region": "region", "region_in_region": "region in region",
               "regions_in_region": "regions in region", "neighbours": "neighbours",
               "partial": "partial region"}


# -- parameter fields ------------------------------------------------------------------------------

def _point(doc: str, *, optional: bool = False):
    default = None if optional else dataclasses.MISSING
    return param("int", 0, MAX_CANVAS_SIDE - 1, default=default, optional=optional, doc=doc)


def _target(doc: str):
    return param("int", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, doc=doc)


def _level(doc: str, default=dataclasses.MISSING):
    return param("int", 0, MAX_LEVELS - 1, default=default, doc=doc)


def _kind():
    return param("str", hi=32, default="region",
                 doc="extraction: region, region_in_region, regions_in_region, neighbours, partial")


def _scope():
    return param("str", hi=16, default="region",
                 doc="region: the connected region at the point; global: every point of its level")


def _neighbour():
    return param("int", 1, MAX_CANVAS_PIXELS, default=None, optional=True,
                 doc="with kind neighbours: only the k-th (1 = the first ISOLER finds); none: "
                     "all of them")


def _connectivity():
    return param("int", 4, 8, default=4, doc="4 (edges) or 8 (edges and corners)")


def _wrap():
    return param("bool", default=False, doc="what leaves one side of the canvas comes back on "
                                            "the other (tileable textures stay tileable)")


def _fill():
    return _level("level left where the selection was", default=0)


def _keep():
    return param("bool", default=False, doc="leave the original in place (a transformed copy)")


def _coordinate(doc: str, default=dataclasses.MISSING):
    return param("float", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, default=default, doc=doc)


def changed_boxes(changed: np.ndarray, *, min_gap: int = 8, max_boxes: int = 16) -> list:
    """Boxes (top, left, bottom, right) covering the True points: their bounding box, cut along
    empty bands of at least ``min_gap`` rows or columns into at most ``max_boxes`` boxes."""
    boxes, todo = [], [(0, changed.shape[0], 0, changed.shape[1])]
    while todo:
        t, b, l, r = todo.pop()
        box = transforms.bbox(changed[t:b, l:r])
        if box is None:
            continue
        t, l, b, r = t + box[0], l + box[1], t + box[2], l + box[3]
        sub = changed[t:b, l:r]
        if len(boxes) + len(todo) + 2 <= max_boxes:
            rows = np.flatnonzero(sub.any(axis=1))
            gap = np.flatnonzero(np.diff(rows) > min_gap)
            if len(gap):
                cut = t + int(rows[gap[0]]) + 1
                todo += [(cut, b, l, r), (t, cut, l, r)]
                continue
            cols = np.flatnonzero(sub.any(axis=0))
            gap = np.flatnonzero(np.diff(cols) > min_gap)
            if len(gap):
                cut = l + int(cols[gap[0]]) + 1
                todo += [(t, b, cut, r), (t, b, l, cut)]
                continue
        boxes.append((t, l, b, r))
    return boxes


def _digest(mask: np.ndarray) -> str:
    return hashlib.blake2b(np.packbits(mask).tobytes() + repr(mask.shape).encode(),
                           digest_size=16).hexdigest()


# -- the common base -------------------------------------------------------------------------------

@dataclass(frozen=True)
class RegionAction(Action):
    """A level edit that reads the levels it changes: EFFECT "levels", never covers the canvas.

    Subclasses name the selection with ``row``, ``col`` and, where they have them, ``kind``,
    ``scope``, ``connectivity`` and ``neighbour``; ``apply`` computes the new matrix with a pure
    function and writes only the points that change (the undo record is their bounding box).
    """

    EFFECT: ClassVar[str] = "levels"

    def _validate(self) -> None:
        kind = getattr(self, "kind", "region")
        if kind not in regions.KINDS:
            raise InputError(f"kind must be one of {', '.join(regions.KINDS)}, got {kind!r}")
        scope = getattr(self, "scope", "region")
        if scope not in regions.SCOPES:
            raise InputError(f"scope must be 'region' or 'global', got {scope!r}")
        if getattr(self, "connectivity", 4) not in regions.CONNECTIVITIES:
            raise InputError(f"connectivity must be 4 or 8, got {self.connectivity}")
        if (getattr(self, "row", 0) is None) != (getattr(self, "col", 0) is None):
            raise InputError("give both row and col of the selection's point, or neither")
        if getattr(self, "neighbour", None) is not None and kind != "neighbours":
            raise InputError(f"neighbour picks one of the neighbours: it goes with kind "
                             f"'neighbours', not {kind!r}")

    @property
    def point(self) -> tuple[int, int] | None:
        return None if self.row is None else (self.row, self.col)

    def selection(self, levels) -> np.ndarray | None:
        """The presence mask this action works on (None: the whole texture)."""
        if self.point is None:
            return None
        return regions.select(levels, self.point, kind=getattr(self, "kind", "region"),
                              scope=getattr(self, "scope", "region"),
                              connectivity=getattr(self, "connectivity", 4),
                              neighbour=getattr(self, "neighbour", None))

    def picked_region(self, levels) -> str | None:
        """The selection's points, as a digest (the whole texture: "texture")."""
        if self.point is None:
            return "texture"
        if not 0 <= self.row < levels.shape[0] or not 0 <= self.col < levels.shape[1]:
            return "outside"
        return _digest(self.selection(levels))

    def _check_levels(self, doc, *values) -> None:
        for value in values:
            doc.check_levels(np.uint8(value))
        if self.point is not None:
            transforms.check_point(self.point, doc.shape)

    @staticmethod
    def _commit(doc, new: np.ndarray) -> None:
        """Write the points that changed, box by box (a far move records two small patches)."""
        for t, l, b, r in changed_boxes(new != doc.levels):
            doc.write(t, l, new[t:b, l:r])

    def _what(self) -> str:
        """The selection in a label: "region at (3, 2)", "every point like (3, 2)"..."""
        if self.point is None:
            return "texture"
        kind = getattr(self, "kind", "region")
        glob = getattr(self, "scope", "region") == "global"
        neighbour = getattr(self, "neighbour", None)
        if kind == "region":
            what = f"every point like {self.point}" if glob else f"region at {self.point}"
        elif neighbour is not None:
            what = f"neighbour {neighbour} of {'level at' if glob else 'region at'} {self.point}"
        else:
            what = f"{_KIND_NAMES[kind]} {'of level at' if glob else 'at'} {self.point}"
        return what + (", 8-conn." if getattr(self, "connectivity", 4) == 8 else "")


# -- local operators (§3.4.2 a–c) ------------------------------------------------------------------

@register
@dataclass(frozen=True)
class Fill(RegionAction):
    """REMPLIR: the region at the point (or every point of its level) takes ``value``."""

    TYPE: ClassVar[str] = "fill"
    row: int = _point("row of the point clicked")
    col: int = _point("column of the point clicked")
    value: int = _level("the level written")
    scope: str = _scope()
    connectivity: int = _connectivity()

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc, self.value)
        self._commit(doc, regions.fill(doc.levels, self.point, self.value, scope=self.scope,
                                       connectivity=self.connectivity))

    def label(self) -> str:
        return f"Fill {self._what()} with {self.value}"


@register
@dataclass(frozen=True)
class Translate(RegionAction):
    """TRANSLATER: move the selection so (row, col) lands on (to_row, to_col); ``fill`` is left."""

    TYPE: ClassVar[str] = "translate"
    row: int = _point("row of the point dragged from")
    col: int = _point("column of the point dragged from")
    to_row: int = _target("row the point is dropped on (may be off the canvas)")
    to_col: int = _target("column the point is dropped on (may be off the canvas)")
    fill: int = _fill()
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    wrap: bool = _wrap()
    neighbour: int | None = _neighbour()

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc, self.fill)
        mask = self.selection(doc.levels)
        offset = (self.to_row - self.row, self.to_col - self.col)
        self._commit(doc, regions.move(doc.levels, mask, offset, fill=self.fill, wrap=self.wrap))

    def label(self) -> str:
        return f"Translate {self._what()} to ({self.to_row}, {self.to_col})"


@register
@dataclass(frozen=True)
class Copy(RegionAction):
    """COPIER: copy the selection so (row, col) lands on (to_row, to_col)."""

    TYPE: ClassVar[str] = "copy"
    row: int = _point("row of the point dragged from")
    col: int = _point("column of the point dragged from")
    to_row: int = _target("row the point is dropped on (may be off the canvas)")
    to_col: int = _target("column the point is dropped on (may be off the canvas)")
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    wrap: bool = _wrap()
    neighbour: int | None = _neighbour()

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc)
        mask = self.selection(doc.levels)
        offset = (self.to_row - self.row, self.to_col - self.col)
        self._commit(doc, regions.move(doc.levels, mask, offset, keep_source=True,
                                       wrap=self.wrap))

    def label(self) -> str:
        return f"Copy {self._what()} to ({self.to_row}, {self.to_col})"


# -- local manipulations of a selection (§3.4.2f) --------------------------------------------------

@register
@dataclass(frozen=True)
class ChangeLevel(RegionAction):
    """Give the whole selection one level (its "aspect": grey level or colour)."""

    TYPE: ClassVar[str] = "change_level"
    row: int = _point("row of the selection's point")
    col: int = _point("column of the selection's point")
    value: int = _level("the new level")
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    neighbour: int | None = _neighbour()

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc, self.value)
        self._commit(doc, regions.change_level(doc.levels, self.selection(doc.levels),
                                               self.value))

    def label(self) -> str:
        return f"Set {self._what()} to level {self.value}"


@register
@dataclass(frozen=True)
class DeleteSelection(RegionAction):
    """Delete the selection: its points become background (level 0)."""

    TYPE: ClassVar[str] = "delete_selection"
    row: int = _point("row of the selection's point")
    col: int = _point("column of the selection's point")
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    neighbour: int | None = _neighbour()

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc)
        self._commit(doc, regions.delete(doc.levels, self.selection(doc.levels)))

    def label(self) -> str:
        return f"Delete {self._what()}"


@register
@dataclass(frozen=True)
class ScaleSelection(RegionAction):
    """Scale the selection about the centre of its box (one factor, or rows and columns apart)."""

    TYPE: ClassVar[str] = "scale_selection"
    row: int = _point("row of the selection's point")
    col: int = _point("column of the selection's point")
    factor: float = param("float", 1 / MAX_FACTOR, MAX_FACTOR, doc="zoom (rows, and columns "
                                                                   "unless factor_cols is set)")
    factor_cols: float | None = param("float", 1 / MAX_FACTOR, MAX_FACTOR, default=None,
                                      optional=True, doc="zoom across, when it differs")
    fill: int = _fill()
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    wrap: bool = _wrap()
    neighbour: int | None = _neighbour()

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc, self.fill)
        cols = self.factor if self.factor_cols is None else self.factor_cols
        self._commit(doc, regions.scale(doc.levels, self.selection(doc.levels),
                                        (self.factor, cols), fill=self.fill, wrap=self.wrap))

    def label(self) -> str:
        zoom = f"×{self.factor:g}" if self.factor_cols is None else \
            f"×{self.factor:g} down, ×{self.factor_cols:g} across"
        return f"Scale {self._what()} {zoom}"


@register
@dataclass(frozen=True)
class RotateSelection(RegionAction):
    """Turn the selection about the centre of its box, counter-clockwise in degrees."""

    TYPE: ClassVar[str] = "rotate_selection"
    row: int = _point("row of the selection's point")
    col: int = _point("column of the selection's point")
    angle: float = param("float", -3600, 3600, doc="degrees, counter-clockwise")
    fill: int = _fill()
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    wrap: bool = _wrap()
    neighbour: int | None = _neighbour()

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc, self.fill)
        self._commit(doc, regions.rotate(doc.levels, self.selection(doc.levels), self.angle,
                                         fill=self.fill, wrap=self.wrap))

    def label(self) -> str:
        return f"Rotate {self._what()} by {self.angle:g}°"


@register
@dataclass(frozen=True)
class FlipSelection(RegionAction):
    """Mirror the selection in its box: horizontal swaps left and right, vertical top and bottom."""

    TYPE: ClassVar[str] = "flip_selection"
    row: int = _point("row of the selection's point")
    col: int = _point("column of the selection's point")
    axis: str = param("str", hi=16, default="horizontal",
                      doc="horizontal (left-right) or vertical (top-bottom)")
    fill: int = _fill()
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    neighbour: int | None = _neighbour()

    def _validate(self) -> None:
        super()._validate()
        if self.axis not in ("horizontal", "vertical"):
            raise InputError(f"axis must be 'horizontal' or 'vertical', got {self.axis!r}")

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc, self.fill)
        self._commit(doc, regions.flip(doc.levels, self.selection(doc.levels), self.axis,
                                       fill=self.fill))

    def label(self) -> str:
        way = "left-right" if self.axis == "horizontal" else "top-bottom"
        return f"Flip {self._what()} {way}"


# -- global operators (§3.4.3): on a selection, or the whole texture when row/col are None --------

@register
@dataclass(frozen=True)
class Identity(RegionAction):
    """IDENTITE: duplicate the selection (or the texture) to an offset, optionally on a grid."""

    TYPE: ClassVar[str] = "identity"
    offset_row: int = _target("rows down to the first copy")
    offset_col: int = _target("columns across to the first copy")
    repeat_rows: int = param("int", 1, MAX_REPEAT, default=1, doc="copies down the grid")
    repeat_cols: int = param("int", 1, MAX_REPEAT, default=1, doc="copies across the grid")
    step_rows: int | None = param("int", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, default=None,
                                  optional=True, doc="grid spacing down (default: box height)")
    step_cols: int | None = param("int", -MAX_CANVAS_SIDE, MAX_CANVAS_SIDE, default=None,
                                  optional=True, doc="grid spacing across (default: box width)")
    wrap: bool = _wrap()
    row: int | None = _point("row of the selection's point (none: the texture)", optional=True)
    col: int | None = _point("column of the selection's point", optional=True)
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    neighbour: int | None = _neighbour()

    def _validate(self) -> None:
        super()._validate()
        if (self.step_rows is None) != (self.step_cols is None):
            raise InputError("give both grid steps (rows and columns), or neither")

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc)
        step = None if self.step_rows is None else (self.step_rows, self.step_cols)
        self._commit(doc, transforms.identity(
            doc.levels, (self.offset_row, self.offset_col), mask=self.selection(doc.levels),
            repeat=(self.repeat_rows, self.repeat_cols), step=step, wrap=self.wrap))

    def label(self) -> str:
        grid = "" if self.repeat_rows == self.repeat_cols == 1 else \
            f", {self.repeat_rows}×{self.repeat_cols} grid"
        return f"Duplicate {self._what()} by ({self.offset_row}, {self.offset_col}){grid}"


@dataclass(frozen=True)
class _Warp(RegionAction):
    """A global operator through one affine map: the selection, or the whole texture."""

    def _map(self) -> tuple[tuple, tuple, tuple]:
        """(matrix, centre, offset) of the map."""
        raise NotImplementedError

    def _validate(self) -> None:
        super()._validate()
        transforms.linear_map(self._map()[0])

    def apply(self, doc, prepared=None) -> None:
        self._check_levels(doc, self.fill)
        matrix, centre, offset = self._map()
        self._commit(doc, transforms.warp(doc.levels, matrix, centre=centre, offset=offset,
                                          mask=self.selection(doc.levels), wrap=self.wrap,
                                          fill=self.fill, keep_source=self.keep_source))


@register
@dataclass(frozen=True)
class Isometry(_Warp):
    """ISOMETRIE: turn the selection (or the texture) about a point — a new orientation."""

    TYPE: ClassVar[str] = "isometry"
    angle: float = param("float", -3600, 3600, doc="degrees, counter-clockwise")
    centre_row: float = _coordinate("row of the centre of rotation")
    centre_col: float = _coordinate("column of the centre of rotation")
    wrap: bool = _wrap()
    fill: int = _level("level where nothing lands", default=0)
    keep_source: bool = _keep()
    row: int | None = _point("row of the selection's point (none: the texture)", optional=True)
    col: int | None = _point("column of the selection's point", optional=True)
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    neighbour: int | None = _neighbour()

    def _map(self):
        return (transforms.rotation_matrix(self.angle), (self.centre_row, self.centre_col),
                (0.0, 0.0))

    def label(self) -> str:
        return (f"Rotate {self._what()} {self.angle:g}° about "
                f"({self.centre_row:g}, {self.centre_col:g})")


@register
@dataclass(frozen=True)
class Similarity(_Warp):
    """SIMILITUDE: zoom the selection (or the texture) about a point — density and fineness."""

    TYPE: ClassVar[str] = "similarity"
    factor: float = param("float", 1 / MAX_FACTOR, MAX_FACTOR, doc="zoom (below 1: finer)")
    centre_row: float = _coordinate("row of the zoom's centre")
    centre_col: float = _coordinate("column of the zoom's centre")
    angle: float = param("float", -3600, 3600, default=0.0, doc="and a turn, degrees")
    wrap: bool = _wrap()
    fill: int = _level("level where nothing lands", default=0)
    keep_source: bool = _keep()
    row: int | None = _point("row of the selection's point (none: the texture)", optional=True)
    col: int | None = _point("column of the selection's point", optional=True)
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    neighbour: int | None = _neighbour()

    def _map(self):
        (a, b), (c, d) = transforms.rotation_matrix(self.angle)
        f = self.factor
        return (((f * a, f * b), (f * c, f * d)), (self.centre_row, self.centre_col), (0.0, 0.0))

    def label(self) -> str:
        turn = f", {self.angle:g}°" if self.angle else ""
        return (f"Zoom {self._what()} ×{self.factor:g}{turn} about "
                f"({self.centre_row:g}, {self.centre_col:g})")


@register
@dataclass(frozen=True)
class Affinity(_Warp):
    """AFFINITE: any invertible affine map p ↦ M (p − centre) + centre + offset, in (row, col)."""

    TYPE: ClassVar[str] = "affinity"
    m00: float = param("float", -MAX_FACTOR, MAX_FACTOR, doc="row from row")
    m01: float = param("float", -MAX_FACTOR, MAX_FACTOR, doc="row from column")
    m10: float = param("float", -MAX_FACTOR, MAX_FACTOR, doc="column from row (a shear)")
    m11: float = param("float", -MAX_FACTOR, MAX_FACTOR, doc="column from column")
    centre_row: float = _coordinate("row of the fixed point", default=0.0)
    centre_col: float = _coordinate("column of the fixed point", default=0.0)
    offset_row: float = _coordinate("then move down", default=0.0)
    offset_col: float = _coordinate("then move across", default=0.0)
    wrap: bool = _wrap()
    fill: int = _level("level where nothing lands", default=0)
    keep_source: bool = _keep()
    row: int | None = _point("row of the selection's point (none: the texture)", optional=True)
    col: int | None = _point("column of the selection's point", optional=True)
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    neighbour: int | None = _neighbour()

    def _map(self):
        return (((self.m00, self.m01), (self.m10, self.m11)), (self.centre_row, self.centre_col),
                (self.offset_row, self.offset_col))

    def label(self) -> str:
        return (f"Affine map of {self._what()} "
                f"[{self.m00:g} {self.m01:g}; {self.m10:g} {self.m11:g}]")


@register
@dataclass(frozen=True)
class ScatterRegions(RegionAction):
    """The random manipulation of every region at once (§3.4.3): each region of the selection,
    of one level or of the texture (every level but the background) moved, turned and rescaled
    about the centre of its box by its own map drawn from ``seed`` (`scatter`)."""

    TYPE: ClassVar[str] = "scatter_regions"
    seed: int = param("seed", default=0, doc="random seed: same seed, same maps")
    radius: float = param("float", 0, MAX_CANVAS_SIDE, default=0.0,
                          doc="each region moves at most this many points (uniform in the disc)")
    rotation: str = param("str", hi=8, default="none",
                          doc="none, quarter (a multiple of 90°) or any (any angle)")
    scale_min: float = param("float", 1 / MAX_FACTOR, MAX_FACTOR, default=1.0,
                             doc="the smallest zoom drawn")
    scale_max: float = param("float", 1 / MAX_FACTOR, MAX_FACTOR, default=1.0,
                             doc="the largest zoom drawn")
    fill: int = _fill()
    wrap: bool = _wrap()
    level: int | None = param("int", 0, MAX_LEVELS - 1, default=None, optional=True,
                              doc="every region of this level (with no selection's point)")
    row: int | None = _point("row of the selection's point (none: the texture)", optional=True)
    col: int | None = _point("column of the selection's point", optional=True)
    kind: str = _kind()
    scope: str = _scope()
    connectivity: int = _connectivity()
    neighbour: int | None = _neighbour()

    def _validate(self) -> None:
        super()._validate()
        if self.level is not None and self.row is not None:
            raise InputError("scatter the regions of a selection or of a level, not both")
        if self.scale_min > self.scale_max:
            raise InputError(f"scale_min {self.scale_min:g} is above scale_max "
                             f"{self.scale_max:g}")
        if self.rotation not in scatter.ROTATIONS:
            raise InputError(f"rotation must be one of {', '.join(scatter.ROTATIONS)}, got "
                             f"{self.rotation!r}")

    def selection(self, levels) -> np.ndarray | None:
        if self.level is not None:
            return np.asarray(levels) == self.level
        return super().selection(levels)

    def picked_region(self, levels) -> str | None:
        if self.level is not None:
            return _digest(self.selection(levels))
        return super().picked_region(levels)

    def scattered(self, doc) -> np.ndarray:
        """The scattered levels: seconds for every region of a 2048² texture, so a window
        draws them in its worker (on a copy of the document) and hands them to apply() as
        ``prepared``. (Not ``prepare``: they depend on the levels before, which a replay's
        cache of prepared results does not look at.)"""
        self._check_levels(doc, self.fill, *(() if self.level is None else (self.level,)))
        return scatter.scatter_regions(
            doc.levels, self.seed, mask=self.selection(doc.levels), radius=self.radius,
            rotation=self.rotation, scale=(self.scale_min, self.scale_max), fill=self.fill,
            wrap=self.wrap, connectivity=self.connectivity)

    def apply(self, doc, prepared=None) -> None:
        if prepared is None:
            self._commit(doc, self.scattered(doc))
            return
        new = np.asarray(prepared)
        if new.dtype != np.uint8 or new.shape != doc.shape:
            raise InputError(f"scattered levels must be a {doc.shape[1]}x{doc.shape[0]} uint8 "
                             f"matrix, got {new.shape} {new.dtype}")
        self._check_levels(doc, self.fill, *(() if self.level is None else (self.level,)))
        self._commit(doc, new)

    def label(self) -> str:
        what = f"level {self.level}" if self.level is not None else self._what()
        return f"Scatter regions of {what}, seed {self.seed}"


REGION_ACTIONS = (Fill, Translate, Copy, ChangeLevel, DeleteSelection, ScaleSelection,
                  RotateSelection, FlipSelection, Identity, Isometry, Similarity, Affinity,
                  ScatterRegions)
