"""The DPJ (distribution de probabilités jointes, thesis §4.2): a sparse law over u×v windows.

It sits between acquisition (a photo's window counts, or a DPJ entered by hand) and synthesis.
Only non-zero configurations are stored; each is also known by an integer *code* (its levels read
row by row, top-left most significant, in base G), so look-ups are binary searches.
"""

from __future__ import annotations

import functools
import hashlib
import io
import json
import math
import zipfile
import zlib
from dataclasses import asdict, dataclass

import numpy as np

from ..errors import FormatError, InputError
from ..fileio import load_json, read_limited, write_file

MAX_LEVELS = 16
MAX_SIDE = 6
MAX_ENTRIES = 4_000_000
MAX_FILE_BYTES = 512 * 2**20
DPJ_FORMAT_VERSION = 1
MAX_META_CHARS = 2**20     # the meta JSON text
REF_LENGTH = 16            # hex digits of a DPJ reference
_MEMBERS = {"configs.npy", "probs.npy", "meta.npy"}


def whole(x, what: str) -> int:
    """``x`` as an int when it is a whole number (3, np.int64(3), 3.0); a bool, 2.5, inf, NaN or
    "3" is refused naming ``what`` (int() would truncate 2.5 and read "3")."""
    if isinstance(x, (bool, np.bool_, str, bytes)) or not isinstance(x, (int, float, np.number)):
        raise InputError(f"{what} must be a whole number, got {x!r:.40}")
    try:
        n = int(x)
    except (OverflowError, ValueError):
        raise InputError(f"{what} must be a whole number, got {x!r:.40}") from None
    if n != x:
        raise InputError(f"{what} must be a whole number, got {x!r:.40}")
    return n


def check_window(window: tuple[int, int], levels: int) -> tuple[int, int]:
    """Validate (u, v) and G; refuse windows whose G**(u*v) codes do not fit 63 bits."""
    try:
        u, v = window
    except (TypeError, ValueError):
        raise InputError(f"window must be two integers (u columns, v rows), got {window!r}") from None
    u, v = whole(u, "a window's width"), whole(v, "a window's height")
    levels = whole(levels, "the number of levels G")
    if not (1 <= u <= MAX_SIDE and 1 <= v <= MAX_SIDE):
        raise InputError(f"window {u}x{v} is out of range: each side must be 1..{MAX_SIDE}")
    if not 2 <= levels <= MAX_LEVELS:
        raise InputError(f"G = {levels} levels is out of range: choose 2..{MAX_LEVELS}")
    if levels ** (u * v) - 1 > 2**63 - 1:
        raise InputError(
            f"a {u}x{v} window with {levels} levels has {levels}^{u * v} configurations, "
            "too many to index in 63 bits: use a smaller window or fewer levels")
    return u, v


def encode(configs: np.ndarray, levels: int) -> np.ndarray:
    """Codes of configurations (n, v, u) (or any (n, ...)): row-major digits in base G.

    Two 2×2 windows of G = 3 levels, ``0 1 / 1 0`` (0·27 + 1·9 + 1·3 + 0 = 12) and ``2 2 / 0 1``:

    >>> codes = encode(np.array([[[0, 1], [1, 0]], [[2, 2], [0, 1]]]), 3)
    >>> codes
    array([12, 73])
    >>> decode(codes, 3, 2, 2)[1]
    array([[2, 2],
           [0, 1]], dtype=uint8)
    """
    configs = np.asarray(configs)
    flat = configs.reshape(len(configs), int(np.prod(configs.shape[1:])))
    codes = np.zeros(len(flat), dtype=np.int64)
    for k in range(flat.shape[1]):
        codes = codes * levels + flat[:, k]
    return codes


def decode(codes: np.ndarray, levels: int, v: int, u: int) -> np.ndarray:
    """Inverse of :func:`encode`: configurations (n, v, u) uint8."""
    codes = np.array(codes, dtype=np.int64)
    flat = np.empty((len(codes), u * v), dtype=np.uint8)
    for k in range(u * v - 1, -1, -1):
        flat[:, k] = codes % levels
        codes //= levels
    return flat.reshape(len(flat), v, u)


def _numbers(values, what: str, finite: bool = True) -> np.ndarray:
    """An array of real numbers (no strings, objects, complex numbers, ragged lists; no NaN or
    infinity where ``finite``: a hand-entered probability may be one, which the report names)."""
    try:
        array = np.asarray(values)
    except (ValueError, TypeError):
        raise InputError(f"the {what} must be an array of numbers") from None
    if array.dtype.kind not in "buif" or (finite and array.dtype.kind == "f" and
                                          not np.all(np.isfinite(array))):
        raise InputError(f"the {what} must be {'finite ' * finite}real numbers, got "
                         f"{array.dtype}")
    return array


def grey_ramp(levels: int) -> np.ndarray:
    """The default palette: G evenly spaced greys, black to white, as (G, 3) uint8 RGB."""
    grey = np.round(np.linspace(0, 255, levels)).astype(np.uint8)
    return np.repeat(grey[:, None], 3, axis=1)


def check_palette(palette, levels: int) -> np.ndarray:
    """A palette as a read-only (G, 3) uint8 array; greys (G,) are expanded to RGB."""
    try:
        pal = np.asarray(palette, dtype=float)
    except (TypeError, ValueError):
        raise InputError("palette must be a list of G greys or G [r, g, b] triples") from None
    if pal.ndim == 1:
        pal = np.repeat(pal[:, None], 3, axis=1)
    if pal.shape != (levels, 3) or not np.all(np.isfinite(pal)) or pal.min() < 0 or pal.max() > 255:
        raise InputError(f"palette must hold {levels} colours with components 0..255")
    pal = np.round(pal).astype(np.uint8)
    pal.flags.writeable = False
    return pal


@dataclass(frozen=True)
class DPJReport:
    """What the thesis asks a user to check (§5.2.2) and what Massaloux adds (§4.5)."""

    window: tuple[int, int]
    levels: int
    entries: int
    total: float
    negative: int
    above_one: int
    nonfinite: int
    horizontal_residual: float
    vertical_residual: float
    states: int
    closed_classes: int
    transient_states: int
    dead_ends: int        # entries leading where no configuration continues (right or below)
    period: int           # of the main closed class: 1 aperiodic, 0 none

    @property
    def is_valid(self) -> bool:
        """Probabilities in [0, 1] summing to 1 (stationarity is reported, not required)."""
        return (self.negative == 0 and self.above_one == 0 and self.nonfinite == 0
                and abs(self.total - 1.0) < 1e-9)

    def to_dict(self) -> dict:
        return {**asdict(self), "window": list(self.window), "is_valid": self.is_valid}

    def lines(self) -> list[str]:
        u, v = self.window
        return [
            f"window           {u}x{v} (u columns x v rows), G = {self.levels}",
            f"entries          {self.entries} configurations stored",
            f"sum              {self.total:.12g}" + ("" if abs(self.total - 1) < 1e-9 else "  (not 1)"),
            f"out of [0, 1]    {self.negative} negative, {self.above_one} above 1, "
            f"{self.nonfinite} not finite",
            f"stationarity     horizontal residual {self.horizontal_residual:.3g}, "
            f"vertical residual {self.vertical_residual:.3g} (L1, 0 = stationary)",
            f"horizontal chain {self.states} states, {self.closed_classes} closed classes, "
            f"{self.transient_states} transient states, {self.dead_ends} entries to dead ends",
            "main class       " + ("none" if not self.period else "aperiodic" if self.period == 1
                                   else f"PERIODIC, period {self.period}: along a row the "
                                        f"patterns cycle through {self.period} families"),
            "valid            " + ("yes" if self.is_valid else "no"),
        ]


class DPJ:
    """A sparse joint distribution over u×v windows of G levels.

    ``configs`` is (n, v, u) uint8 indexed [entry, row, col]; ``probs`` is (n,) float64. Entries are
    kept sorted by code and are unique. Instances are immutable: methods return new DPJs.
    """

    def __init__(self, configs, probs, levels: int, palette=None, meta: dict | None = None):
        configs = _numbers(configs, "configurations")
        probs = _numbers(probs, "probabilities", finite=False)
        if configs.dtype.kind == "f" and not np.array_equal(configs, np.floor(configs)):
            raise InputError("configurations must hold whole levels, got fractions")
        probs = probs.astype(np.float64)
        if configs.ndim != 3 or probs.ndim != 1 or len(configs) != len(probs):
            raise InputError("configs must be (n, v, u) and probs (n,) with the same n")
        if meta is not None and not isinstance(meta, dict):
            raise InputError(f"a DPJ's meta must be a dict, got {type(meta).__name__}")
        v, u = configs.shape[1:]
        check_window((u, v), levels)
        if len(configs) and (configs.min() < 0 or configs.max() >= levels):
            raise InputError(f"a configuration uses a level outside 0..{levels - 1}")
        configs = configs.astype(np.uint8)
        codes = encode(configs, levels)
        order = np.argsort(codes, kind="stable")
        codes = codes[order]
        if len(codes) > 1 and np.any(codes[1:] == codes[:-1]):
            raise InputError("the same configuration appears twice")
        self._levels = int(levels)
        self._window = (int(u), int(v))
        self._codes = _frozen(codes)
        self._configs = _frozen(configs[order])
        self._probs = _frozen(probs[order])
        self._palette = check_palette(grey_ramp(levels) if palette is None else palette, levels)
        self.meta = dict(meta or {})

    # -- construction -------------------------------------------------------------------------
    @classmethod
    def from_codes(cls, codes, probs, levels: int, window: tuple[int, int], **kw) -> "DPJ":
        u, v = check_window(window, levels)
        codes = _numbers(codes, "codes")
        if codes.dtype.kind not in "ui" or (codes.size and (codes.min() < 0 or
                                                            codes.max() > levels ** (u * v) - 1)):
            raise InputError(f"configuration codes must be whole numbers 0..{levels}^{u * v} - 1")
        return cls(decode(codes, levels, v, u), probs, levels, **kw)

    @classmethod
    def empty(cls, window: tuple[int, int], levels: int, **kw) -> "DPJ":
        """The hand-entry start (§5.2.2): every probability 0."""
        u, v = check_window(window, levels)
        return cls(np.zeros((0, v, u), np.uint8), np.zeros(0), levels, **kw)

    def _with(self, configs, probs, **overrides) -> "DPJ":
        kw = {"palette": self._palette, "meta": self.meta, **overrides}
        return DPJ(configs, probs, self._levels, **kw)

    # -- read access --------------------------------------------------------------------------
    @property
    def configs(self) -> np.ndarray:
        return self._configs

    @property
    def probs(self) -> np.ndarray:
        return self._probs

    @property
    def codes(self) -> np.ndarray:
        return self._codes

    @property
    def window(self) -> tuple[int, int]:
        """(u, v): u columns by v rows."""
        return self._window

    @property
    def levels(self) -> int:
        return self._levels

    @property
    def palette(self) -> np.ndarray:
        return self._palette

    def __len__(self) -> int:
        return len(self._codes)

    def __repr__(self) -> str:
        u, v = self._window
        return f"<DPJ {u}x{v} G={self._levels} entries={len(self)} sum={self.total:.6g}>"

    def __eq__(self, other) -> bool:
        return (isinstance(other, DPJ) and self._window == other._window
                and self._levels == other._levels and np.array_equal(self._codes, other._codes)
                and np.array_equal(self._probs, other._probs)
                and np.array_equal(self._palette, other._palette))

    __hash__ = None

    @functools.cached_property
    def total(self) -> float:
        """The sum of the probabilities (cached: a table asks it for every row it paints);
        inf when they overflow (a hand-entered 1e308 or two), without numpy's warning."""
        with np.errstate(over="ignore"):
            return float(self._probs.sum())

    def prob(self, config) -> float:
        """P(config) for one (v, u) configuration; 0 for a configuration not stored."""
        config = np.asarray(config)
        u, v = self._window
        if config.shape != (v, u):
            raise InputError(f"a configuration of this DPJ is {v} rows x {u} columns")
        code = encode(config[None], self._levels)[0]
        i = np.searchsorted(self._codes, code)
        return float(self._probs[i]) if i < len(self) and self._codes[i] == code else 0.0

    def with_probs(self, probs) -> "DPJ":
        return self._with(self._configs, probs)

    def with_palette(self, palette) -> "DPJ":
        return self._with(self._configs, self._probs, palette=palette)

    # -- derived laws -------------------------------------------------------------------------
    def normalized(self) -> "DPJ":
        """Divide by the sum so the entries sum to 1."""
        total = self.total
        if not np.isfinite(total) or total <= 0:
            raise InputError("cannot normalise: the probabilities sum to "
                             + ("zero" if total == 0 else f"{total:g}, not a positive number"))
        return self.with_probs(self._probs / total)

    def marginal(self, rows: slice = slice(None), cols: slice = slice(None)) -> "DPJ":
        """The law of a sub-window: sum over the rows and columns left out."""
        sub = np.ascontiguousarray(self._configs[:, rows, cols])
        if sub.shape[1] == 0 or sub.shape[2] == 0:
            raise InputError("a marginal needs at least one row and one column")
        codes, inverse = np.unique(encode(sub, self._levels), return_inverse=True)
        probs = np.bincount(inverse.ravel(), weights=self._probs, minlength=len(codes))
        keep = probs != 0
        v, u = sub.shape[1:]
        return DPJ.from_codes(codes[keep], probs[keep], self._levels, (u, v),
                              palette=self._palette, meta=self.meta)

    def horizontal_states(self) -> tuple[np.ndarray, np.ndarray]:
        """Codes of each entry's left and right (u-1)-column sub-windows (the chain's states).
        With u = 1 every entry's are the empty sub-window, code 0."""
        left = encode(np.ascontiguousarray(self._configs[:, :, :-1]), self._levels)
        right = encode(np.ascontiguousarray(self._configs[:, :, 1:]), self._levels)
        return left, right

    def vertical_states(self) -> tuple[np.ndarray, np.ndarray]:
        """Codes of each entry's top and bottom (v-1)-row sub-windows (the vertical chain's)."""
        top = encode(np.ascontiguousarray(self._configs[:, :-1, :]), self._levels)
        bottom = encode(np.ascontiguousarray(self._configs[:, 1:, :]), self._levels)
        return top, bottom

    @functools.cached_property
    def chain(self):
        """The horizontal chain once dead ends are pruned: its classes, each entry's role and the
        main class's period (:mod:`texeditor.markov.chain`; cached, DPJs are immutable)."""
        from . import chain
        return chain.analyse(self)

    def report(self) -> DPJReport:
        """The validation report of §5.2.2: range, sum, stationarity, chain structure."""
        p = self._probs
        u, v = self._window
        hres = vres = 0.0
        if len(self):
            if u > 1:
                hres = _residual(self.marginal(cols=slice(0, u - 1)), self.marginal(cols=slice(1, u)))
            if v > 1:
                vres = _residual(self.marginal(rows=slice(0, v - 1)), self.marginal(rows=slice(1, v)))
        c = self.chain
        return DPJReport(
            window=self._window, levels=self._levels, entries=len(self), total=float(p.sum()),
            negative=int(np.count_nonzero(p < 0)), above_one=int(np.count_nonzero(p > 1)),
            nonfinite=int(np.count_nonzero(~np.isfinite(p))),
            horizontal_residual=hres, vertical_residual=vres, states=c.states,
            closed_classes=c.closed_classes, transient_states=c.transient_states,
            dead_ends=c.dead_ends, period=c.period)

    def restrict(self) -> "DPJ":
        """Massaloux's restriction (§4.5): prune the dead ends, keep the main closed class of the
        horizontal chain (the one carrying the most probability), normalised.

        A DPJ whose chain is already one closed class without dead ends comes back unchanged in
        law."""
        kept = self.chain.kept
        if len(self) and not kept.any():
            raise InputError("the horizontal chain has no closed class: every path ends in a "
                             "dead end (a sub-window no configuration continues)")
        return self._with(self._configs[kept], self._probs[kept]).normalized()

    # -- files ----------------------------------------------------------------------------------
    _bytes: bytes | None = None      # this DPJ's file bytes, once read or encoded
    _ref: str | None = None

    def to_bytes(self) -> bytes:
        """The `.dpj` file content: an .npz of configs, probs and a JSON meta string.

        A DPJ read from bytes gives back exactly those bytes (another numpy or zlib may encode
        the same arrays differently, and the bytes are what its reference names); one made
        here is encoded once and keeps its bytes (DPJs are immutable)."""
        data = self._bytes
        if data is None:
            data = self._bytes = self._encode()
        return data

    @property
    def ref(self) -> str:
        """The DPJ's reference: the first 16 hex digits of the SHA-256 of its file bytes."""
        ref = self._ref
        if ref is None:
            ref = self._ref = bytes_ref(self.to_bytes())
        return ref

    def has_ref(self, ref) -> bool:
        """Whether ``ref`` names this DPJ's content (its bytes hash to it)."""
        return isinstance(ref, str) and ref == self.ref

    def _encode(self) -> bytes:
        meta = {**self.meta, "format_version": DPJ_FORMAT_VERSION, "levels": self._levels,
                "window": list(self._window), "palette": self._palette.tolist()}
        buf = io.BytesIO()
        np.savez_compressed(buf, configs=self._configs, probs=self._probs,
                            meta=np.array(json.dumps(meta)))
        return buf.getvalue()

    def save(self, path) -> None:
        """Write a `.dpj` file atomically."""
        write_file(path, self.to_bytes())

    @classmethod
    def from_bytes(cls, data: bytes, name: str = "DPJ", ref: str | None = None) -> "DPJ":
        """Parse and validate `.dpj` content; any defect is a :class:`FormatError`.

        ``ref``: the reference the content is stored under (a `.texture` member, a bank row, a
        journal record). It must name these bytes — or, for a file an earlier release re-saved
        on a machine whose numpy/zlib encodes differently, this machine's encoding of the same
        arrays — else the DPJ is refused as forged or damaged: a reference always names one
        content, so every cache keyed by it is sound."""
        try:
            dpj = _parse_dpj(data, name)
        except FormatError:
            raise
        except InputError as exc:
            raise FormatError(f"{name}: {exc}") from None
        except Exception as exc:  # zipfile and numpy fail in many ways on hostile bytes
            raise FormatError(f"{name}: damaged DPJ file ({type(exc).__name__}: "
                              f"{_short(exc)})") from None
        dpj._bytes = bytes(data)
        if ref is not None and not dpj.has_ref(ref):
            fresh = dpj._encode()
            if bytes_ref(fresh) != ref:
                raise FormatError(
                    f"{name}: its content is not DPJ {ref!s:.{REF_LENGTH}} (the SHA-256 of its "
                    f"bytes begins {dpj.ref}): a forged or damaged DPJ, refused")
            dpj._bytes, dpj._ref = fresh, None
        return dpj

    @classmethod
    def load(cls, path) -> "DPJ":
        return cls.from_bytes(read_limited(path, MAX_FILE_BYTES, "DPJ file"), str(path))


def bytes_ref(data: bytes) -> str:
    """The reference of `.dpj` bytes: the first 16 hex digits of their SHA-256."""
    return hashlib.sha256(data).hexdigest()[:REF_LENGTH]


def _residual(a: DPJ, b: DPJ) -> float:
    """L1 distance between two laws on the same sub-window."""
    codes = np.concatenate([a.codes, b.codes])
    codes.sort()       # not np.union1d: numpy 2's hashing unique takes 20× longer on 8M codes
    first = np.ones(len(codes), bool)       # none at all when every probability is 0
    first[1:] = codes[1:] != codes[:-1]
    codes = codes[first]
    pa = np.zeros(len(codes))
    pb = np.zeros(len(codes))
    pa[np.searchsorted(codes, a.codes)] = a.probs
    pb[np.searchsorted(codes, b.codes)] = b.probs
    return float(np.abs(pa - pb).sum())


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.flags.writeable = False
    return a


def _parse_dpj(data: bytes, name: str) -> DPJ:
    try:
        zf = zipfile.ZipFile(io.BytesIO(data))
        infos = zf.infolist()
    except (zipfile.BadZipFile, OSError, ValueError):
        raise FormatError(f"{name}: not a DPJ file (not an .npz archive)") from None
    names = {i.filename for i in infos}
    if "model.json" in names:
        raise FormatError(f"{name}: a multi-scale photo model, not a single DPJ: open it with "
                          "texeditor.load_model (or `texeditor synth`)")
    if names != _MEMBERS or len(infos) != len(_MEMBERS):
        raise FormatError(f"{name}: a DPJ file holds exactly configs, probs and meta; found "
                          f"{sorted(names)}")
    if sum(i.file_size for i in infos) > MAX_FILE_BYTES:
        raise FormatError(f"{name}: declared content is larger than {MAX_FILE_BYTES} bytes")
    check_npy_headers(zf, name, _LARGEST)
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as npz:
            configs, probs, meta_raw = npz["configs"], npz["probs"], npz["meta"]
    except (ValueError, OSError, zipfile.BadZipFile, EOFError, KeyError) as exc:
        raise FormatError(f"{name}: damaged or unsafe content ({_short(exc)})") from None
    meta = _parse_meta(meta_raw, name)
    levels, (u, v) = meta.pop("levels"), meta.pop("window")
    if configs.dtype != np.uint8 or configs.ndim != 3 or configs.shape[1:] != (v, u):
        raise FormatError(f"{name}: configs must be uint8 of shape (n, {v}, {u}), got "
                          f"{configs.dtype} {configs.shape}")
    if probs.dtype != np.float64 or probs.shape != (len(configs),):
        raise FormatError(f"{name}: probs must be float64 of shape ({len(configs)},), got "
                          f"{probs.dtype} {probs.shape}")
    if len(configs) > MAX_ENTRIES:
        raise FormatError(f"{name}: more than {MAX_ENTRIES} entries")
    if not np.all(np.isfinite(probs)):
        raise FormatError(f"{name}: a probability is NaN or infinite")
    if np.any(probs < 0) or np.any(probs > 1):
        raise FormatError(f"{name}: a probability is outside [0, 1]")
    if len(configs) and configs.max() >= levels:
        raise FormatError(f"{name}: a configuration uses level {configs.max()} but G = {levels}")
    palette = meta.pop("palette", None)
    meta.pop("format_version", None)
    return DPJ(configs, probs, levels, palette=palette, meta=meta)


_NPY_HEADERS = {(1, 0): np.lib.format.read_array_header_1_0,
                (2, 0): np.lib.format.read_array_header_2_0}


_LARGEST = {"configs.npy": MAX_ENTRIES * MAX_SIDE * MAX_SIDE, "probs.npy": 8 * MAX_ENTRIES,
            "meta.npy": 4 * MAX_META_CHARS}   # the bytes a DPJ's members decode to, at most


def check_npy_headers(zf: zipfile.ZipFile, name: str, largest: dict | None = None) -> None:
    """Refuse (as FormatError) object arrays (pickles), headers that declare more data than the
    member holds (numpy would allocate the declared shape before finding the data missing),
    and members declaring more than ``largest`` (file name → bytes) allows, or more than
    MAX_ENTRIES entries (rows): a small file of deflated zeros would otherwise be inflated
    before its size is read."""
    try:
        for info in zf.infolist():
            with zf.open(info) as f:
                read_header = _NPY_HEADERS.get(np.lib.format.read_magic(f))
                if read_header is None:
                    raise FormatError(f"{name}: {info.filename} has an unknown .npy version")
                shape, _, dtype = read_header(f, max_header_size=10_000)
            if dtype.hasobject:
                raise FormatError(f"{name}: {info.filename} holds Python objects: unsafe, refused")
            if math.prod(shape) * dtype.itemsize > info.file_size:
                raise FormatError(f"{name}: {info.filename} declares {shape} {dtype}, more than "
                                  f"its {info.file_size} bytes")
            most = (largest or {}).get(info.filename)
            if most is not None and (math.prod(shape) * dtype.itemsize > most
                                     or (shape and shape[0] > MAX_ENTRIES)):
                raise FormatError(f"{name}: {info.filename} declares {shape} {dtype}, more "
                                  f"than a DPJ holds (at most {MAX_ENTRIES} entries)")
    except FormatError:
        raise
    except (zipfile.BadZipFile, zlib.error, OSError, EOFError, ValueError, TypeError,
            SyntaxError) as exc:
        raise FormatError(f"{name}: damaged DPJ member ({_short(exc)})") from None


def _parse_meta(raw: np.ndarray, name: str) -> dict:
    if raw.dtype.kind != "U" or raw.ndim != 0:
        raise FormatError(f"{name}: meta must be one JSON string")
    meta = load_json(str(raw), f"{name}: meta", limit=MAX_META_CHARS, constants=True)
    if not isinstance(meta, dict):
        raise FormatError(f"{name}: meta must be a JSON object")
    version = meta.get("format_version", DPJ_FORMAT_VERSION)
    if version != DPJ_FORMAT_VERSION:
        raise FormatError(f"{name}: DPJ format version {version!r} is not supported "
                          f"(this program reads version {DPJ_FORMAT_VERSION})")
    levels, window = meta.get("levels"), meta.get("window")
    if (not isinstance(levels, int) or isinstance(levels, bool) or not isinstance(window, list)
            or len(window) != 2 or not all(isinstance(x, int) and not isinstance(x, bool)
                                           for x in window)):
        raise FormatError(f"{name}: meta needs integer 'levels' and 'window' [u, v]")
    try:
        check_window(window, levels)
    except InputError as exc:
        raise FormatError(f"{name}: {exc}") from None
    meta["window"] = tuple(window)
    return meta


def _short(exc: Exception) -> str:
    text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    return text[:160]
