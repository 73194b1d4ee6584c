"""The Document: the level matrix, its palette, the DPJs and exemplar photos it was made from and
the log that made it.

It sits at the end of the data flow (synthesis and every edit arrive here as Actions) and at the
start of display, files and the bank. Only Actions change it: its edit interface (``set_levels``,
``write``, ``fill``, ``write_where``, ``set_palette``, ``set_current_dpj``, ``set_plates``,
``on_plates``) works only inside a ``step()`` — which `apply` and History open around an Action —
and records what each call overwrites, so History can undo a step at the cost of its size.

A document may also hold a layer of colour plates (thesis §1.2.3–1.2.4: a colour texture is a grey
texture laid on a map of coloured plates): a plate index per point and P plate colours, painted by
the same steps as the levels inside ``on_plates()``.
"""

from __future__ import annotations

import hashlib
import struct
from contextlib import contextmanager

import numpy as np

from ..markov.dpj import DPJ, check_palette, grey_ramp
from ..errors import InputError
from .exemplars import check_exemplar, exemplar_ref

EMPTY_LEVELS = 2            # the palette of a document no action has touched yet
REF_LENGTH = 16             # hex characters of a DPJ reference
HASH_TAG = b"texeditor-levels-v1"
PLATES_TAG = b"texeditor-plates-v1"


def dpj_ref(dpj: DPJ) -> str:
    """A DPJ's reference in logs and files: the first 16 hex digits of SHA-256 of its file bytes
    (the bytes it was read from, or its encoding; computed once per DPJ)."""
    return dpj.ref


def result_hash(levels: np.ndarray, palette: np.ndarray, plates=None, plate_colours=None) -> str:
    """SHA-256 of a tag, (H, W, G) as little-endian uint32, the levels (C order), the palette;
    then, for a document with plates only (so every older result keeps its hash), a second tag,
    P as a little-endian uint32, the plates (C order) and their colours."""
    h, w = levels.shape
    digest = hashlib.sha256(HASH_TAG)
    digest.update(struct.pack("<3I", h, w, len(palette)))
    digest.update(np.ascontiguousarray(levels, dtype=np.uint8).tobytes())
    digest.update(np.ascontiguousarray(palette, dtype=np.uint8).tobytes())
    if plates is not None:
        digest.update(PLATES_TAG + struct.pack("<I", len(plate_colours)))
        digest.update(np.ascontiguousarray(plates, dtype=np.uint8).tobytes())
        digest.update(np.ascontiguousarray(plate_colours, dtype=np.uint8).tobytes())
    return digest.hexdigest()


class Document:
    """A texture being made: levels (H, W) uint8 with 0 = background, a (G, 3) palette, its DPJs.

    ``Document()`` is the empty 0×0 document every log starts from; ``Document.new(...)`` is the
    usual blank canvas. ``.actions`` is the recipe: replaying it on ``Document()`` with the same
    DPJs gives this document bit for bit.
    """

    def __init__(self):
        self._levels = np.zeros((0, 0), dtype=np.uint8)
        self._palette = grey_ramp(EMPTY_LEVELS)
        self._palette.flags.writeable = False
        self._dpj_ref: str | None = None
        self._plates: np.ndarray | None = None           # (H, W) uint8 plate of each point
        self._plate_colours: np.ndarray | None = None    # (P, 3) uint8
        self._on_plates = False       # inside on_plates(): levels and plates are swapped
        self.dpjs: dict[str, DPJ] = {}
        self.exemplars: dict[str, np.ndarray] = {}       # ref → read-only uint8 photo
        self._log: list = []
        self._recorder: list | None = None
        self._in_step = False

    @classmethod
    def new(cls, width: int, height: int, levels: int, palette=None) -> "Document":
        """A blank canvas (every point background), made by a logged NewCanvas action."""
        from .actions import NewCanvas
        doc = cls()
        doc.apply(NewCanvas(width, height, levels, palette))
        return doc

    # -- read access ----------------------------------------------------------------------------
    @property
    def levels(self) -> np.ndarray:
        """The level matrix as a read-only view (it follows later edits; copy to keep a state)."""
        view = self._levels.view()
        view.flags.writeable = False
        return view

    @property
    def palette(self) -> np.ndarray:
        return self._palette

    @property
    def num_levels(self) -> int:
        return len(self._palette)

    @property
    def shape(self) -> tuple[int, int]:
        return self._levels.shape

    @property
    def dpj(self) -> DPJ | None:
        """The current DPJ: the one last added or synthesised from (None for a hand-made canvas)."""
        return self.dpjs.get(self._dpj_ref) if self._dpj_ref else None

    @property
    def dpj_ref(self) -> str | None:
        return self._dpj_ref

    @property
    def actions(self) -> tuple:
        """The log that made this document, oldest first."""
        return tuple(self._log)

    @property
    def plates(self) -> np.ndarray | None:
        """The plate of each point (H, W) uint8 as a read-only view, or None: no plates layer.
        (Inside ``on_plates()`` the layers are swapped: this is then the texture's levels.)"""
        if self._plates is None:
            return None
        view = self._plates.view()
        view.flags.writeable = False
        return view

    @property
    def plate_colours(self) -> np.ndarray | None:
        """The P plate colours (P, 3) uint8, or None."""
        return self._plate_colours

    @property
    def nbytes(self) -> int:
        plates = 0 if self._plates is None else self._plates.nbytes
        return self._levels.nbytes + self._palette.nbytes + plates

    def result_hash(self) -> str:
        return result_hash(self._levels, self._palette, self._plates, self._plate_colours)

    def __repr__(self) -> str:
        h, w = self.shape
        plates = "" if self._plates is None else f" P={len(self._plate_colours)}"
        return f"<Document {w}x{h} G={self.num_levels}{plates} actions={len(self._log)}>"

    # -- building -------------------------------------------------------------------------------
    def add_dpj(self, dpj: DPJ, ref: str | None = None) -> str:
        """Register a DPJ so actions can refer to it; it becomes the current DPJ. ``ref`` is the
        reference a file stored it under, which names the bytes it was read from (another
        machine's encoding of the same arrays may differ); one that does not name the DPJ is
        refused: the synthesis results and every saved file trust a reference to name one
        content. Returns the reference."""
        if not isinstance(dpj, DPJ):
            raise InputError("only a DPJ can be added to a document")
        ref = dpj_ref(dpj) if ref is None else ref
        if not dpj.has_ref(ref):
            raise InputError(f"DPJ reference {ref!r:.20} does not name this DPJ (its reference "
                             f"is {dpj.ref})")
        self.dpjs.setdefault(ref, dpj)
        self._dpj_ref = ref
        return ref

    def store_dpj(self, dpj: DPJ) -> str:
        """Keep a DPJ without making it the current one (a composition source's DPJ, a doubling
        table); returns its reference."""
        if not isinstance(dpj, DPJ):
            raise InputError("only a DPJ can be added to a document")
        self.dpjs.setdefault(dpj.ref, dpj)
        return dpj.ref

    def add_exemplar(self, image, ref: str | None = None) -> str:
        """Keep a photo (uint8 grey or colour, at most 1024²) so model steps can refer to it;
        returns its reference. ``ref``, a file's name for it, must be the one its pixels give."""
        image = check_exemplar(image)
        own = exemplar_ref(image)
        if ref is not None and ref != own:
            raise InputError(f"exemplar reference {ref!r:.20} does not name this picture (its "
                             f"reference is {own})")
        self.exemplars.setdefault(own, image)
        return own

    def apply(self, action) -> "Document":
        """Apply an action and append it to the log (the logged way to change a document)."""
        with self.step():
            action.apply(self)
        self._log.append(action)
        return self

    @contextmanager
    def step(self, record: list | None = None):
        """The span of one Action's ``apply``: the edit interface works only inside it (so
        nothing but an Action changes a document). ``record`` collects the undo atoms."""
        if self._in_step:
            raise InputError("an Action is already being applied to this document")
        self._in_step, self._recorder = True, record
        try:
            yield record
        finally:
            self._in_step, self._recorder = False, None

    # -- the log (History and replay keep it equal to the steps applied) ------------------------
    def append_log(self, action) -> None:
        self._log.append(action)

    def truncate_log(self, length: int) -> None:
        del self._log[length:]

    def set_log(self, actions) -> None:
        self._log[:] = actions

    def copy(self) -> "Document":
        """An independent copy (the DPJs, being immutable, are shared)."""
        other = Document()
        other._levels = self._levels.copy()
        other._palette = self._palette
        other._dpj_ref = self._dpj_ref
        other._plates = None if self._plates is None else self._plates.copy()
        other._plate_colours = self._plate_colours
        other.dpjs = dict(self.dpjs)
        other.exemplars = dict(self.exemplars)
        other._log = list(self._log)
        return other

    # -- the edit interface of Actions (only inside a step) --------------------------------------
    def set_levels(self, levels, palette=None, *, copy: bool = True, plates=None) -> None:
        """Replace the whole matrix (any new shape), and the palette with it when given.

        ``copy=False`` hands over a fresh array the caller will not touch again. When the shape
        changes, plates follow the canvas: ``plates`` (a crop cuts them) or, by default,
        stretched to the new shape (grain rendering enlarges the canvas).
        """
        self._check_step()
        levels = np.array(levels, dtype=np.uint8, copy=True) if copy else levels
        if levels.ndim != 2 or levels.dtype != np.uint8:
            raise InputError("a level matrix must be a 2-D uint8 array")
        pal = self._palette if palette is None else check_palette(palette, len(palette))
        if levels.size and int(levels.max()) >= len(pal):
            raise InputError(f"the matrix uses level {int(levels.max())} but G = {len(pal)}")
        if levels.shape != self.shape and self._plates is not None:
            if self._on_plates:
                raise InputError("a step on the plates cannot change the canvas size")
            new = stretched(self._plates, levels.shape) if plates is None else plates
            self._set_plates(new, self._plate_colours, levels.shape)
        self._record(_Matrix(self._levels))
        if palette is not None:
            self.set_palette(pal)
        self._levels = np.ascontiguousarray(levels)

    def write(self, top: int, left: int, block) -> None:
        """Write a block of levels at (top, left); the block must lie inside the canvas."""
        self._check_step()
        block = np.asarray(block, dtype=np.uint8)
        h, w = block.shape
        H, W = self.shape
        if top < 0 or left < 0 or top + h > H or left + w > W:
            raise InputError(f"block {w}x{h} at ({top}, {left}) is outside the {W}x{H} canvas")
        self.check_levels(block)
        region = (slice(top, top + h), slice(left, left + w))
        self._record(_Patch(top, left, self._levels[region].copy()))
        self._levels[region] = block

    def fill(self, top: int, left: int, height: int, width: int, value: int) -> None:
        """Set a rectangle (already clipped to the canvas) to one level."""
        self._check_step()
        self.check_levels(np.uint8(value))
        region = (slice(top, top + height), slice(left, left + width))
        self._record(_Patch(top, left, self._levels[region].copy()))
        self._levels[region] = value

    def write_where(self, mask, values) -> None:
        """Set the points of an (H, W) bool mask to ``values`` (a level or an (H, W) array).

        The undo record is the mask's bounding box, so a small stroke costs little.
        """
        self._check_step()
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != self.shape:
            raise InputError(f"mask shape {mask.shape} differs from the canvas {self.shape}")
        rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
        if not len(rows):
            return
        region = (slice(rows[0], rows[-1] + 1), slice(cols[0], cols[-1] + 1))
        values = np.asarray(values, dtype=np.uint8)
        new = values if values.ndim == 0 else values[region][mask[region]]
        self.check_levels(new)
        self._record(_Patch(int(rows[0]), int(cols[0]), self._levels[region].copy()))
        self._levels[region][mask[region]] = new

    def set_palette(self, palette) -> None:
        """Change the colours of the current G levels (G itself changes only with the matrix)."""
        self._check_step()
        pal = check_palette(palette, len(palette))
        self._record(_Palette(self._palette))
        self._palette = pal

    def set_plates(self, plates, colours) -> None:
        """Give the document a plates layer — the plate of each point (H, W) uint8 and the P
        plate colours — or take it away (``None, None``)."""
        self._check_step()
        if self._on_plates:
            raise InputError("a step on the plates cannot replace the plates layer")
        self._set_plates(plates, colours, self.shape)

    def _set_plates(self, plates, colours, shape) -> None:
        if plates is not None:
            plates = np.array(plates, dtype=np.uint8)
            colours = check_palette(colours, len(colours))
            if plates.shape != shape:
                raise InputError(f"plates of shape {plates.shape} do not fit the canvas {shape}")
            if plates.size and int(plates.max()) >= len(colours):
                raise InputError(f"plate {int(plates.max())} does not exist: P = {len(colours)}")
        self._record(_Plates(self._plates, self._plate_colours))
        self._plates, self._plate_colours = plates, None if plates is None else colours

    @contextmanager
    def on_plates(self):
        """Inside, ``levels``, ``palette`` and the edit interface are the plates' (an index per
        point, P colours), so any level edit paints plates; its undo atoms are kept together."""
        self._check_step()
        if self._plates is None:
            raise InputError("the document has no plates: add a plates layer first")
        if self._on_plates:
            raise InputError("a step on the plates cannot hold another one")
        outer, inner = self._recorder, ([] if self._recorder is not None else None)
        self._recorder = inner
        self._swap_layers()
        try:
            yield
        finally:
            self._swap_layers()
            self._recorder = outer
            if inner:
                self._record(_OnPlates(inner))

    def _swap_layers(self) -> None:
        self._levels, self._plates = self._plates, self._levels
        self._palette, self._plate_colours = self._plate_colours, self._palette
        self._on_plates = not self._on_plates

    def set_current_dpj(self, ref: str | None) -> None:
        """Make a DPJ of the document (or none) the current one, as a synthesis does."""
        self._check_step()
        if ref is not None and ref not in self.dpjs:
            raise InputError(f"DPJ {ref} is not part of this document: add it first")
        self._record(_CurrentDPJ(self._dpj_ref))
        self._dpj_ref = ref

    def check_levels(self, values) -> None:
        """Refuse levels the palette has no colour for (G = number of levels)."""
        if np.size(values) and int(np.max(values)) >= self.num_levels:
            raise InputError(f"level {int(np.max(values))} does not exist: G = {self.num_levels}, "
                             f"levels are 0..{self.num_levels - 1}")

    def _check_step(self) -> None:
        if not self._in_step:
            raise InputError("a document changes only through an Action (Document.apply or "
                             "History.apply)")

    def _record(self, atom) -> None:
        if self._recorder is not None:
            self._recorder.append(atom)

    # -- snapshots (History) -------------------------------------------------------------------
    def state(self, *, copy: bool = True) -> "State":
        """What the log made: levels, palette, current DPJ, plates (not the log itself);
        ``copy=False`` for a document about to be dropped (its arrays are handed over)."""
        plates = self._plates.copy() if copy and self._plates is not None else self._plates
        return State(self._levels.copy() if copy else self._levels, self._palette, self._dpj_ref,
                     plates, self._plate_colours)

    def restore(self, state: "State", *, copy: bool = True) -> None:
        """Go back to a saved state (``copy=False``: take over its arrays)."""
        self._levels = state.levels.copy() if copy else state.levels
        self._palette = state.palette
        self._dpj_ref = state.dpj_ref
        plates = state.plates
        self._plates = plates.copy() if copy and plates is not None else plates
        self._plate_colours = state.plate_colours


class State:
    """A saved document state (a History snapshot): levels copy, palette, current DPJ, plates."""

    __slots__ = ("levels", "palette", "dpj_ref", "plates", "plate_colours")

    def __init__(self, levels, palette, dpj_ref, plates=None, plate_colours=None):
        self.levels, self.palette, self.dpj_ref = levels, palette, dpj_ref
        self.plates, self.plate_colours = plates, plate_colours

    @property
    def nbytes(self) -> int:
        plates = 0 if self.plates is None else self.plates.nbytes
        return self.levels.nbytes + self.palette.nbytes + plates


def stretched(plates: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Plates resized to ``shape`` by their nearest point (each new point's centre falls in one
    old point: integer arithmetic, the same on every machine).

    >>> stretched(np.array([[0, 1], [2, 3]], np.uint8), (4, 3)).tolist()
    [[0, 1, 1], [0, 1, 1], [2, 3, 3], [2, 3, 3]]
    """
    (h, w), (new_h, new_w) = plates.shape, shape
    rows = (2 * np.arange(new_h) + 1) * h // (2 * new_h)
    cols = (2 * np.arange(new_w) + 1) * w // (2 * new_w)
    return plates[np.ix_(rows, cols)]


# -- undo atoms: each holds one old value and swaps it with the document's current one ----------
# (``differs``: the old value is not the current one, so the step changed something).
# A step's atoms undone in reverse order turn into its redo record, and redone in forward order
# back into its undo record (napari's Labels history keeps (indices, old, new) the same way).

class _Matrix:
    __slots__ = ("levels",)

    def __init__(self, levels):
        self.levels = levels

    def swap(self, doc: Document) -> None:
        self.levels, doc._levels = doc._levels, self.levels

    def differs(self, doc: Document) -> bool:
        return not np.array_equal(self.levels, doc._levels)

    @property
    def nbytes(self) -> int:
        return self.levels.nbytes


class _Patch:
    __slots__ = ("top", "left", "block")

    def __init__(self, top, left, block):
        self.top, self.left, self.block = top, left, block

    def swap(self, doc: Document) -> None:
        h, w = self.block.shape
        region = (slice(self.top, self.top + h), slice(self.left, self.left + w))
        current = doc._levels[region].copy()
        doc._levels[region] = self.block
        self.block = current

    def differs(self, doc: Document) -> bool:
        h, w = self.block.shape
        return not np.array_equal(self.block, doc._levels[self.top:self.top + h,
                                                          self.left:self.left + w])

    @property
    def nbytes(self) -> int:
        return self.block.nbytes


class _Palette:
    __slots__ = ("palette",)

    def __init__(self, palette):
        self.palette = palette

    def swap(self, doc: Document) -> None:
        self.palette, doc._palette = doc._palette, self.palette

    def differs(self, doc: Document) -> bool:
        return not np.array_equal(self.palette, doc._palette)

    nbytes = 48


class _Plates:
    __slots__ = ("plates", "colours")

    def __init__(self, plates, colours):
        self.plates, self.colours = plates, colours

    def swap(self, doc: Document) -> None:
        (self.plates, self.colours), (doc._plates, doc._plate_colours) = \
            (doc._plates, doc._plate_colours), (self.plates, self.colours)

    def differs(self, doc: Document) -> bool:
        if self.plates is None or doc._plates is None:
            return (self.plates is None) != (doc._plates is None)
        return not (np.array_equal(self.plates, doc._plates)
                    and np.array_equal(self.colours, doc._plate_colours))

    @property
    def nbytes(self) -> int:
        return 48 + (0 if self.plates is None else self.plates.nbytes)


class _OnPlates:
    """The atoms of a step on the plates, swapped with the layers swapped. Undone in reverse
    order and redone in order, like a step's own atoms: the list turns round at each swap."""

    __slots__ = ("atoms",)

    def __init__(self, atoms):
        self.atoms = atoms[::-1]

    def swap(self, doc: Document) -> None:
        doc._swap_layers()
        try:
            for atom in self.atoms:
                atom.swap(doc)
        finally:
            doc._swap_layers()
        self.atoms.reverse()

    def differs(self, doc: Document) -> bool:
        doc._swap_layers()
        try:
            return any(atom.differs(doc) for atom in self.atoms)
        finally:
            doc._swap_layers()

    @property
    def nbytes(self) -> int:
        return sum(atom.nbytes for atom in self.atoms)


class _CurrentDPJ:
    __slots__ = ("ref",)

    def __init__(self, ref):
        self.ref = ref

    def swap(self, doc: Document) -> None:
        self.ref, doc._dpj_ref = doc._dpj_ref, self.ref

    def differs(self, doc: Document) -> bool:
        return self.ref != doc._dpj_ref

    nbytes = 16


def footprint(atoms) -> tuple[frozenset, tuple | None]:
    """What a step's undo atoms changed — a subset of levels, palette, dpj, plates — and the
    box (top, left, height, width) of the levels changed (None: the whole matrix)."""
    what, boxes = set(), []
    for atom in atoms:
        if isinstance(atom, _Patch):
            what.add("levels")
            boxes.append((atom.top, atom.left, *atom.block.shape))
        elif isinstance(atom, _Matrix):
            what.add("levels")
            boxes.append(None)
        elif isinstance(atom, _Palette):
            what.add("palette")
        elif isinstance(atom, _CurrentDPJ):
            what.add("dpj")
        elif isinstance(atom, (_Plates, _OnPlates)):
            what.add("plates")
    box = boxes[0] if boxes else None
    for other in boxes[1:]:
        box = union_box(box, other)
    return frozenset(what), box


def union_box(a, b):
    """The bounding box of two (top, left, height, width) boxes; None (everywhere) wins."""
    if a is None or b is None:
        return None
    top, left = min(a[0], b[0]), min(a[1], b[1])
    return (top, left, max(a[0] + a[2], b[0] + b[2]) - top, max(a[1] + a[3], b[1] + b[3]) - left)
