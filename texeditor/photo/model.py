"""A photo model: a multi-scale DPJ plus the photo's tone, saved as a `.dpj` of format 2.

It is what `texeditor acquire --scales` writes and `texeditor synth`, `texeditor resynth` and
:func:`texeditor.resynthesize` draw from. The file is a zip of ``model.json``, one
``scale-K.dpj`` per scale (each an ordinary format-1 DPJ, read with all its checks) and
``tone.npz`` (the photo's finest levels, its greys, its colours when it has them). Single-DPJ
files (format 1) still open as DPJs (:func:`load_model` returns either).
"""

from __future__ import annotations

import io
import json
import math
import os
import threading
import zipfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np

from ..errors import Cancelled, FormatError, InputError
from ..fileio import load_json, read_limited, write_file
from ..markov.dpj import DPJ, MAX_FILE_BYTES, check_npy_headers
from ..markov.levels import as_read, load_image, to_grey
from ..markov.particles import PARTICLES
from ..markov.synthesis import check_closure
from ..markov.multiscale import (COARSE_LEVELS, COARSE_REDRAWS, COARSE_ROW_REDRAWS,
                                 COARSE_WINDOW, GIVEN_REDRAWS, LEAN_DRAFTS,
                                 LEVELS, SCALES_CLOSURE, WINDOW,
                                 MultiScaleDPJ, estimate_scales,
                                 synthesize_scales)
from ..recipe.exemplars import MAX_SIDE
from .tone import (BALANCED, FINISHED, PLAIN, TILED, TILED_LANES, Rendered, Renderer, ToneIndex,
                   as_shown, rendering, tone_index)

MODEL_FORMAT_VERSION = 2
MAX_TONE_PIXELS = 4096 * 4096
TONE_ROWS = 256                      # a photo's greys for its tone: this many rows at a time
_ZIP_DATE = (1980, 1, 1, 0, 0, 0)    # fixed, so the same model always has the same bytes
_NPY_HEADERS = {(1, 0): np.lib.format.read_array_header_1_0,
                (2, 0): np.lib.format.read_array_header_2_0}


class Tone(NamedTuple):
    """The photo as tone is drawn from it: its levels at the finest scale, greys, colours."""

    levels: np.ndarray           # (h, w) uint8
    grey: np.ndarray             # (h, w) uint8
    colour: np.ndarray | None    # (h, w, 3) uint8, or None for a grey photo


@dataclass(frozen=True)
class Resynthesis:
    """A texture drawn from a photo model."""

    image: np.ndarray            # uint8: (H, W) grey or (H, W, 3) colour (tone, or the palette)
    levels: np.ndarray           # (H, W) uint8, the document's matrix
    model_frequencies: np.ndarray  # each level's share in the photo (the model's law)
    repairs: int
    seed: int
    moved: int = 0               # moves of points bringing the level shares back (markov.balance)


@dataclass(frozen=True, eq=False)
class PhotoModel:
    scales: MultiScaleDPJ
    tone: Tone | None = None

    @property
    def levels(self) -> int:
        return self.scales.levels

    @property
    def palette(self) -> np.ndarray:
        """(G, 3) uint8: each finest level's mean colour in the photo."""
        return self.scales.palette

    def frequencies(self) -> np.ndarray:
        """Each finest level's share: the photo's when the tone keeps it, else the DPJ's."""
        if self.tone is None:
            return self.scales.frequencies(self.scales.scales - 1)
        shares = self.__dict__.get("_tone_shares")     # counted once: a photo can be large
        if shares is None:
            counts = np.bincount(self.tone.levels.ravel(), minlength=self.levels)
            shares = counts / counts.sum()
            object.__setattr__(self, "_tone_shares", shares)
        return shares.copy()

    def synthesize(self, shape, *, seed: int = 0, tone: bool = True, tileable: bool = False,
                   closure: int = SCALES_CLOSURE, coarse_redraws: int = COARSE_REDRAWS,
                   tone_balance: bool = True, tone_finish: bool = True,
                   particles: int = PARTICLES,
                   rebalance: bool = True, steer: bool = True, more_drafts: bool = True,
                   given_redraws: int = GIVEN_REDRAWS,
                   coarse_row_redraws: float = COARSE_ROW_REDRAWS, free_moves: bool = True,
                   forced_moves: bool = True, lean_drafts: bool = LEAN_DRAFTS,
                   progress: Callable[[float], None] | None = None,
                   cancel: Callable[[], bool] | None = None) -> Resynthesis:
        """Levels from the scales, shown with the photo's tone (or the palette). The tone is
        drawn on a second thread as the finest rows come out (the same picture as
        ``render(levels, wrap=tone_wrap(tileable, closure, tone_balance, tone_finish))``, in
        about half the time on two cores). ``tileable``: the levels and the picture repeat
        without a seam (``closure``, ``coarse_redraws``, ``particles``, ``rebalance``,
        ``steer``, ``more_drafts``, ``given_redraws``, ``coarse_row_redraws``,
        ``free_moves``, ``forced_moves``, ``lean_drafts``: see
        markov.multiscale.synthesize_scales;
        ``tone_balance``: each level's greys keep the photo's histogram, tone.BALANCED;
        ``tone_finish``: its pixel-scale power is the photo's, tone.FINISHED)."""
        draw = dict(seed=seed, progress=progress, cancel=cancel, tileable=tileable,
                    closure=closure, coarse_redraws=coarse_redraws, particles=particles,
                    rebalance=rebalance, steer=steer, more_drafts=more_drafts,
                    given_redraws=given_redraws, coarse_row_redraws=coarse_row_redraws,
                    free_moves=free_moves, forced_moves=forced_moves, lean_drafts=lean_drafts)
        if not tone or self.tone is None:
            result = synthesize_scales(self.scales, shape, **draw)
            image = self.render(result.levels, seed=seed, tone=False)
        else:
            wrap = tone_wrap(tileable, closure, tone_balance, tone_finish)
            result, image = self._synthesize_with_tone(shape, draw, wrap)
        return Resynthesis(image, result.levels, self.frequencies(), result.repairs, int(seed),
                           result.moved)

    def _synthesize_with_tone(self, shape, draw, wrap):
        renderer, latest = [], [None]
        seed = draw["seed"]
        stale = threading.Event()           # the levels were rebalanced: stop this tone
        drawn = threading.Event()           # the levels are drawn: the tone takes both cores
        with ThreadPoolExecutor(1, thread_name_prefix="tone") as worker:
            index = worker.submit(self._index)     # built while the coarse scales are drawn
            jobs = []

            def catch_up():
                """Render every row final by now (a tone behind the levels takes all the rows
                that are ready at once, which its two lanes share better)."""
                renderer[0].advance(*latest[0])

            def rows_final(levels, n):
                if not renderer:
                    renderer.append(Renderer(levels.shape, self.levels, self.tone.levels,
                                             self.tone.grey, self.tone.colour, seed=seed,
                                             index=index.result(), wrap=wrap,
                                             cancel=stale.is_set))
                    renderer[0].beside = lambda: not drawn.is_set()
                if jobs and jobs[-1].done():
                    jobs[-1].result()                   # a tone error stops the synthesis
                latest[0] = (levels, n)
                jobs.append(worker.submit(catch_up))
            try:
                result = synthesize_scales(self.scales, shape, rows_final=rows_final, **draw)
            except BaseException:
                for job in jobs:
                    job.cancel()
                raise
            finally:
                drawn.set()
            if result.moved:            # rebalanced after its rows were told final: the
                stale.set()             # tone drawn so far is of other levels
            for job in jobs:
                _settle(job, stale.is_set())
        if result.moved:
            return result, self.render(result.levels, seed=seed, wrap=wrap)
        grey, colour = as_shown(*renderer[0].result(), wrap, renderer[0].index, self.tone.grey)
        return result, (grey if colour is None else colour)

    def render(self, levels, *, seed: int = 0, tone: bool = True,
               wrap: int = PLAIN | BALANCED | FINISHED) -> np.ndarray:
        """The picture of a level matrix: tone when the model has it, else the palette;
        ``wrap``: how it is drawn, as tone_wrap says (by default as a new plain synthesis
        shows it; tiling levels give a tiling picture)."""
        levels = np.asarray(levels)
        if not tone or self.tone is None:
            image = self.palette[levels]
            return image[..., 0].copy() if self._grey_palette() else image
        return self.rendering(levels, seed=seed, wrap=wrap).picture

    def rendering(self, levels, *, seed: int = 0, wrap=False,
                  before: Rendered | None = None) -> Rendered:
        """The tone picture of ``levels`` (``.picture``) with what a next rendering after an
        edit starts from: ``before``, this model's rendering of the levels before the edit
        (see tone.rendering)."""
        if self.tone is None:
            raise InputError("this photo model has no tone")
        return rendering(levels, self.levels, self.tone.levels, self.tone.grey,
                         self.tone.colour, seed=seed, index=self._index(), wrap=wrap,
                         before=before)

    def _grey_palette(self) -> bool:
        return bool(np.all(self.palette == self.palette[:, :1]))

    def _index(self) -> ToneIndex:
        index = self.__dict__.get("_tone_index")
        if index is None:
            index = tone_index(self.tone.levels, self.levels, self.tone.grey)
            object.__setattr__(self, "_tone_index", index)
        return index

    # -- files ------------------------------------------------------------------------------
    def to_bytes(self) -> bytes:
        meta = {"format": "texeditor photo model", "format_version": MODEL_FORMAT_VERSION,
                "scales": self.scales.scales, "levels": self.levels,
                "tone": self.tone is not None}
        buf = io.BytesIO()
        with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
            _member(zf, "model.json", json.dumps(meta).encode())
            for k, dpj in enumerate(self.scales.dpjs):
                _member(zf, f"scale-{k}.dpj", dpj.to_bytes(), zipfile.ZIP_STORED)
            if self.tone is not None:
                _member(zf, "tone.npz", _tone_bytes(self.tone), zipfile.ZIP_STORED)
        return buf.getvalue()

    def save(self, path) -> None:
        write_file(path, self.to_bytes())

    # -- in a document --------------------------------------------------------------------------
    def tone_pictures(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The tone as a document keeps it, two exemplar pictures: the photo (colour, or grey)
        and its finest levels, their top-left MAX_SIDE² at most (an exemplar's limit)."""
        if self.tone is None:
            return None
        photo = self.tone.grey if self.tone.colour is None else self.tone.colour
        return (np.ascontiguousarray(photo[:MAX_SIDE, :MAX_SIDE]),
                np.ascontiguousarray(self.tone.levels[:MAX_SIDE, :MAX_SIDE]))


def _settle(job, stale: bool) -> None:
    """Wait for a tone job to end. Once the tone is stale, a job not started yet is dropped and
    one stopped part way (Cancelled) is as good as done."""
    if stale and job.cancel():
        return
    try:
        job.result()
    except Cancelled:
        if not stale:
            raise


def document_tone(doc) -> np.ndarray | None:
    """The document's levels drawn with the tone of the synthesis that made its canvas (its
    seed, wrapping when it tiles), or None when that synthesis names no tone."""
    step = next((a for a in reversed(doc.actions) if a.EFFECT == "reset"), None)
    model = document_model(doc, step)
    if model is None:
        return None
    return model.render(doc.levels, seed=int(step.seed), wrap=step_wrap(step))


def tone_wrap(tileable: bool, closure: int = SCALES_CLOSURE, balance: bool = True,
              finish: bool = True) -> int:
    """How a synthesis's tone is drawn: tiling not at all, or as its seam closure says (3 on: on
    two lanes beside the levels, tone.TILED_LANES; 1 and 2: tone.TILED); ``balance``: each
    level's greys keep the photo's histogram (tone.BALANCED, since SynthesizeScales 4);
    ``finish``: its pixel-scale power is the photo's (tone.FINISHED, since version 11)."""
    way = PLAIN if not tileable else (      # one DPJ's steps name closures past the scales'
        TILED_LANES if check_closure(closure) >= 3 else TILED)
    return way | (BALANCED if balance else 0) | (FINISHED if finish else 0)


def step_wrap(step) -> int:
    """tone_wrap of a synthesis step (PLAIN for a step that does not tile; no balance, no
    finish for a multi-scale step recorded before them; a step that records no tone, or none,
    is shown with an attached model's tone the current way)."""
    return tone_wrap(bool(getattr(step, "tileable", False)), getattr(step, "closure", 1),
                     bool(getattr(step, "tone_balance", True)),
                     bool(getattr(step, "tone_finish", True)))


def document_model(doc, step=None) -> PhotoModel | None:
    """The photo model a document's texture is shown with: that of ``step`` (default: the
    synthesis that made the canvas, the last new canvas of the log), a multi-scale synthesis
    that names a tone; None when there is none."""
    if step is None:
        step = next((a for a in reversed(doc.actions) if a.EFFECT == "reset"), None)
    if getattr(step, "tone_photo", None) is None:
        return None
    scales = MultiScaleDPJ(tuple(doc.dpjs[r] for r in step.dpjs))
    levels = doc.exemplars[step.tone_levels]
    if levels.ndim != 2 or int(levels.max()) >= scales.levels:
        raise FormatError(f"the tone's levels {step.tone_levels} are not levels of these scales")
    return PhotoModel(scales, tone_of_pictures(levels, doc.exemplars[step.tone_photo]))


def acquire_model(image, *, scales: int | None = None, levels: int = LEVELS, window=WINDOW,
                  coarse_levels: int = COARSE_LEVELS, coarse_window=COARSE_WINDOW,
                  quantizer: str = "lab", tone: bool = True) -> PhotoModel:
    """Acquire a photo model: its multi-scale DPJ and (``tone``) its greys and colours."""
    image = as_photo(image)
    ms, lv = estimate_scales(image, scales=scales, levels=levels, window=window,
                             coarse_levels=coarse_levels, coarse_window=coarse_window,
                             quantizer=quantizer)
    return PhotoModel(ms, photo_tone(image, lv[-1]) if tone else None)


def as_photo(photo) -> np.ndarray:
    """A photo given as an array, or as an image file's path (read by load_image), as
    load_image reads its samples (as_read)."""
    if isinstance(photo, (str, bytes, os.PathLike)):
        return load_image(photo)
    return as_read(photo)


def photo_tone(image, finest: np.ndarray) -> Tone:
    """The photo's tone for its finest levels (``estimate_scales``'s last level matrix, which
    covers the photo's top-left corner): its greys, and its colours when it has them."""
    image = as_read(image)              # whole: its bands below are scaled alike
    h, w = finest.shape
    grey = np.empty((h, w), np.uint8)
    for top in range(0, h, TONE_ROWS):     # a large photo is never whole as float64
        band = to_grey(image[top:min(h, top + TONE_ROWS), :w])
        grey[top:top + len(band)] = np.round(band * 255)
    colour = None
    if image.ndim == 3 and image.shape[2] >= 3:
        colour = _as_uint8(image[:h, :w, :3])
    return Tone(finest, grey, colour)


def _as_uint8(pixels: np.ndarray) -> np.ndarray:
    if pixels.dtype == np.uint8:
        return np.ascontiguousarray(pixels)
    import skimage as ski
    return ski.util.img_as_ubyte(np.clip(ski.util.img_as_float(pixels), 0, 1))


# -- reading ---------------------------------------------------------------------------------

def load_model(path) -> PhotoModel | DPJ:
    """A `.dpj` file: a photo model (format 2) or a single DPJ (format 1)."""
    data = read_limited(path, MAX_FILE_BYTES, "DPJ file")
    return model_from_bytes(data, str(path))


def model_from_bytes(data: bytes, name: str = "model") -> PhotoModel | DPJ:
    try:
        zf = zipfile.ZipFile(io.BytesIO(data))
        names = [i.filename for i in zf.infolist()]
    except (zipfile.BadZipFile, OSError, ValueError, NotImplementedError):
        raise FormatError(f"{name}: not a DPJ file (not a zip archive)") from None
    if "model.json" not in names:
        return DPJ.from_bytes(data, name)
    try:
        return _parse_model(zf, names, name)
    except FormatError:
        raise
    except InputError as exc:
        raise FormatError(f"{name}: {exc}") from None
    except Exception as exc:  # zipfile and numpy fail in many ways on hostile bytes
        raise FormatError(f"{name}: damaged photo model ({type(exc).__name__})") from None


def _parse_model(zf: zipfile.ZipFile, names: list, name: str) -> PhotoModel:
    if sum(i.file_size for i in zf.infolist()) > MAX_FILE_BYTES:
        raise FormatError(f"{name}: declared content is larger than {MAX_FILE_BYTES} bytes")
    meta = load_json(zf.read("model.json"), f"{name}: model.json", limit=2**20)
    if not isinstance(meta, dict) or meta.get("format_version") != MODEL_FORMAT_VERSION:
        raise FormatError(f"{name}: photo model format {meta.get('format_version')!r} is not "
                          f"supported (this program reads {MODEL_FORMAT_VERSION})"
                          if isinstance(meta, dict) else f"{name}: model.json is not an object")
    scales = meta.get("scales")
    if not isinstance(scales, int) or isinstance(scales, bool) or not 1 <= scales <= 6:
        raise FormatError(f"{name}: 'scales' must be 1..6")
    expected = {"model.json", *(f"scale-{k}.dpj" for k in range(scales))}
    if meta.get("tone"):
        expected.add("tone.npz")
    if set(names) != expected or len(names) != len(expected):
        raise FormatError(f"{name}: a photo model of {scales} scales holds {sorted(expected)}; "
                          f"found {sorted(names)}")
    dpjs = tuple(DPJ.from_bytes(zf.read(f"scale-{k}.dpj"), f"{name}: scale {k}")
                 for k in range(scales))
    ms = MultiScaleDPJ(dpjs)
    tone = _parse_tone(zf.read("tone.npz"), ms.levels, name) if meta.get("tone") else None
    return PhotoModel(ms, tone)


def _member(zf, name, data, compress=zipfile.ZIP_DEFLATED) -> None:
    info = zipfile.ZipInfo(name, _ZIP_DATE)
    info.compress_type = compress
    zf.writestr(info, data)


def _tone_bytes(tone: Tone) -> bytes:
    arrays = {"levels": tone.levels}
    if tone.colour is None:
        arrays["grey"] = tone.grey
    else:
        arrays["colour"] = tone.colour
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
        for key, array in arrays.items():
            npy = io.BytesIO()
            np.lib.format.write_array(npy, np.ascontiguousarray(array), allow_pickle=False)
            _member(zf, f"{key}.npy", npy.getvalue())
    return buf.getvalue()


def _parse_tone(data: bytes, g: int, name: str) -> Tone:
    """The tone arrays, checked: uint8, one shape, levels below G; grey from colour if absent.
    Shapes and dtypes are checked from the .npy headers before any array is inflated: the
    model's 512 MiB limit counts tone.npz as stored, and its members may be deflated again."""
    zf = zipfile.ZipFile(io.BytesIO(data))
    members = sorted(i.filename for i in zf.infolist())
    if members not in (["grey.npy", "levels.npy"], ["colour.npy", "levels.npy"]):
        raise FormatError(f"{name}: tone holds levels and grey or colour; found {members}")
    check_npy_headers(zf, f"{name}: tone")
    picture = members[0]
    shape = _check_tone_levels(*_npy_header(zf, "levels.npy"), g, name)
    _check_picture(shape, *_npy_header(zf, picture), name)
    levels = _npy_array(zf, "levels.npy")
    if levels.max() >= g:
        raise FormatError(_bad_levels(g, name))
    return tone_of_pictures(levels, _npy_array(zf, picture), name)


def _check_tone_levels(shape: tuple, dtype: np.dtype, g: int, name: str) -> tuple:
    """The levels' declared shape, if a 2-D uint8 matrix of at most MAX_TONE_PIXELS."""
    if dtype != np.uint8 or len(shape) != 2 or 0 in shape:
        raise FormatError(_bad_levels(g, name))
    if math.prod(shape) > MAX_TONE_PIXELS:
        raise FormatError(f"{name}: tone levels of {shape[1]}x{shape[0]} points, more than "
                          f"the limit of {MAX_TONE_PIXELS} points")
    return shape


def _bad_levels(g: int, name: str) -> str:
    return f"{name}: tone levels must be a 2-D uint8 matrix of levels below {g}"


def _npy_header(zf: zipfile.ZipFile, member: str) -> tuple[tuple, np.dtype]:
    """(shape, dtype) from a member's .npy header alone, nothing inflated past it."""
    with zf.open(member) as f:
        read = _NPY_HEADERS[np.lib.format.read_magic(f)]    # versions check_npy_headers took
        shape, _, dtype = read(f, max_header_size=10_000)
    return shape, dtype


def _npy_array(zf: zipfile.ZipFile, member: str) -> np.ndarray:
    """A member's array, once its header is checked (no pickle)."""
    with zf.open(member) as f:
        return np.lib.format.read_array(f, allow_pickle=False, max_header_size=10_000)


def _check_picture(levels_shape: tuple, shape: tuple, dtype: np.dtype, name: str) -> None:
    """The tone's photo: uint8 grey or colour of the levels' shape."""
    if dtype != np.uint8 or tuple(shape) not in (levels_shape, levels_shape + (3,)):
        raise FormatError(f"{name}: the tone's photo must be uint8 grey or colour of the "
                          f"levels' shape {levels_shape}, got {dtype} {tuple(shape)}")


def tone_of_pictures(levels: np.ndarray, picture: np.ndarray, name: str = "tone") -> Tone:
    """A tone from the photo's finest levels and its picture (uint8 grey, or colour whose greys
    are computed as on acquisition): how a `.dpj` and a document store it."""
    _check_picture(levels.shape, picture.shape, picture.dtype, name)
    if picture.ndim == 2:
        return Tone(levels, picture, None)
    return Tone(levels, np.round(to_grey(picture) * 255).astype(np.uint8), picture)
