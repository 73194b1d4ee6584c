"""Levels & palettes: turn a photo into a matrix of G levels and a palette (thesis §5.2.1).

It sits at the start of the data flow, photo → levels → DPJ: acquisition counts the windows of the
level matrix made here, and synthesis paints its levels with the palette made here.
"""

from __future__ import annotations

import lzma
import math
import struct
import warnings
import zlib
from pathlib import Path
from typing import NamedTuple

import imageio.v3 as iio
import numpy as np
import scipy.cluster.vq
from numba import njit
from PIL import Image
import skimage as ski     # its subpackages load on first use, not at start-up

from ..errors import ImageError, InputError
from .dpj import whole
from ..fileio import as_path, check_regular

MIN_LEVELS = 2
MAX_LEVELS = 16
MAX_PIXELS = 64 * 2**20
# Decoded, at most a 64-megapixel RGBA photo of 8 bits: acquiring one peaks at 1.9 GB (measured,
# benchmarks/bench_limits.py); 16-bit or float colour pictures that large would pass 2 GiB.
MAX_IMAGE_BYTES = 256 * 2**20
MAX_TIFF_PAGES = 1024     # a multi-page TIFF gives its first page; every page's header is read
BAND = (5.0, 95.0)
MAX_LLOYD_ITERATIONS = 100
METHODS = ("band", "lloyd", "lab")
# "lab" fits its classes on the photo's colours binned to this many bits a channel (at most 2^15
# bins, each at the mean CIELAB of its pixels), then sends each exact colour to the nearest class.
_FIT_BITS = 5
COUNTED_COLOURS = 2**21   # photos of this many pixels on find their colours by counting codes
LAB_CHUNK = 2**20         # colours converted to CIELAB at a time
# Greys and thresholds are rounded to 1e-6, finer than a 16-bit step (1.5e-5) but coarser than the
# noise between the same photo stored as uint8, uint16, float32 or float64 (at most 6e-8), so that
# noise cannot move a pixel lying on a threshold across it.
_DECIMALS = 6


class Quantization(NamedTuple):
    """A quantised photo: what acquisition (levels) and synthesis (palette) need."""

    levels: np.ndarray      # (H, W) uint8, every value < G
    palette: np.ndarray     # (G, 3) uint8 RGB: the photo's mean colour in each level
    thresholds: np.ndarray  # (G-1,) float64 on the [0, 1] grey scale; a grey equal to one goes up
    #                         (empty for "lab" on a colour photo: its classes are not grey bands)


# -- reading a photo ---------------------------------------------------------------------------
def load_image(path) -> np.ndarray:
    """Read an image file as stored: (H, W) grey or (H, W, C) with C = 1..4, dtype preserved.

    Palette images come back as RGB(A). A multi-page file (animated GIF, TIFF stack) gives its
    first page, and only that page is decoded. The declared size is checked against MAX_PIXELS
    and MAX_IMAGE_BYTES before decoding (Pillow's header; a TIFF's through tifffile), so a
    decompression bomb is refused without allocating it; a file neither can read is not a
    picture (an .npz, which imageio would decode unchecked). Every failure is an ImageError
    naming the file, and no reader warning escapes. Samples that have no 0..1 scale of their
    own come back as float32 in 0..1 by their own range (see _own_range).
    """
    path = as_path(path)
    _check_file(path)
    tiff = _is_tiff(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        warnings.simplefilter("error", Image.DecompressionBombWarning)
        if tiff:
            _check_tiff_pages(path)         # before Pillow counts them
        size, pages, mode = _declared_size(path)
        if tiff and mode != "CMYK":
            return _own_range(_check_decoded(_decode_tiff(path), path))
        if size is None:
            raise ImageError(f"{path}: cannot read it as an image (unknown format, or a "
                             "damaged or truncated file)")
        image = _decode_cmyk(path) if mode == "CMYK" else _decode(path)
    if pages > 1 and image.ndim >= 3 and image.shape[1:3] == size:
        image = image[0]
    image = _interleaved(image, size, mode)
    return _own_range(_check_decoded(image, path))


def _own_range(image: np.ndarray) -> np.ndarray:
    """A float picture whose samples leave 0..1 (a height map in metres), a 32- or 64-bit
    integer one, or a signed one with negative samples has no usual white: its colour (or grey)
    is scaled by its own range, min → 0 and max → 1, and so is its alpha, as float32 —
    instead of clipped to one grey or divided down to black. Any other picture is returned as
    it is (one holding NaN too: it is refused where it is used, naming the NaN)."""
    kind = image.dtype.kind
    if kind == "f":
        if not np.isfinite(image).all() or (image.min() >= 0 and image.max() <= 1):
            return image
    elif not (kind in "iu" and (image.dtype.itemsize >= 4 or image.min() < 0)):
        return image
    planes = image[..., None] if image.ndim == 2 else image
    c = planes.shape[2]
    out = np.empty(planes.shape, np.float32)
    for part, flat in ((slice(0, 3 if c >= 3 else 1), 0.0), (slice(1 if c == 2 else 3, c), 1.0)):
        if part.start >= c:
            continue                                # no alpha
        lo, hi = float(planes[..., part].min()), float(planes[..., part].max())
        if kind == "f" and 0 <= lo and hi <= 1:
            lo, hi = 0.0, 1.0                       # this part is within 0..1 already
        for top in range(0, len(planes), _BAND_ROWS):
            band = planes[top:top + _BAND_ROWS, :, part].astype(np.float64)
            out[top:top + _BAND_ROWS, :, part] = (band - lo) / (hi - lo) if hi > lo else flat
    return out[..., 0] if image.ndim == 2 else out


def _interleaved(image: np.ndarray, size, mode) -> np.ndarray:
    """A planar-configuration TIFF (one plane per channel) comes back from tifffile as
    (C, H, W); the header's size and mode say so: make it (H, W, C) like every other picture."""
    if image.ndim != 3 or size is None or mode is None:
        return image
    try:
        bands = Image.getmodebands(mode)
    except (KeyError, ValueError):
        return image
    if image.shape == (bands, *size) and image.shape != (*size, bands):
        return np.moveaxis(image, 0, -1)
    return image


def _check_file(path: Path) -> None:
    """A regular file with something in it: a FIFO would block the decoder forever and a
    device (``/dev/zero``) never ends; both say 0 bytes, which is not what they are."""
    st = check_regular(path, "image", error=ImageError)
    if st.st_size == 0:
        raise ImageError(f"{path}: the file is empty (0 bytes), not an image")


def _declared_size(path: Path) -> tuple[tuple[int, int] | None, int, str | None]:
    """(height, width), page count and Pillow's mode from the header, or (None, 1, None) if
    Pillow does not know the format."""
    try:
        with Image.open(path) as im:
            width, height = im.size
            pages = int(getattr(im, "n_frames", 1) or 1)
            mode = im.mode
    except (Image.DecompressionBombWarning, Image.DecompressionBombError):
        raise ImageError(f"{path}: the image is too large to open safely "
                         f"(more than {MAX_PIXELS // 2**20} megapixels)") from None
    except (Image.UnidentifiedImageError, SyntaxError, ValueError):
        return None, 1, None  # maybe a format only imageio's other plugins can read
    except OSError as exc:
        raise ImageError(f"{path}: cannot read ({exc.strerror or exc})") from None
    _check_pixels(height, width, path)
    return (height, width), pages, mode


def _decode_cmyk(path: Path) -> np.ndarray:
    """A CMYK picture (print JPEGs, TIFFs) as RGB: its four channels are not RGBA."""
    try:
        with Image.open(path) as im:
            return np.asarray(im.convert("RGB"))
    except Exception as exc:  # as in _decode: one message for every way a reader fails
        raise ImageError(f"{path}: cannot read it as an image "
                         "(a damaged or truncated CMYK file)") from exc


def _decode(path: Path) -> np.ndarray:
    """A picture Pillow has identified (its size checked), decoded by Pillow alone."""
    try:
        return np.asarray(iio.imread(path, index=0, plugin="pillow"))
    except (Image.DecompressionBombWarning, Image.DecompressionBombError):
        raise ImageError(f"{path}: the image is too large to open safely") from None
    except MemoryError:
        raise ImageError(f"{path}: not enough memory to decode this image") from None
    except Exception as exc:  # every reader fails differently; the user needs one message
        raise ImageError(f"{path}: cannot read it as an image "
                         "(unknown format, or a damaged or truncated file)") from exc


# -- TIFF ---------------------------------------------------------------------------------------
_TIFF_MAGIC = (b"II*\0", b"MM\0*", b"II+\0", b"MM\0+")     # classic and BigTIFF
_INFLATE = {8: zlib.decompressobj, 32946: zlib.decompressobj, 50013: zlib.decompressobj,
            34925: lzma.LZMADecompressor}      # what tifffile decodes without imagecodecs


def _is_tiff(path: Path) -> bool:
    try:
        with open(path, "rb") as f:
            return f.read(4) in _TIFF_MAGIC
    except OSError as exc:
        raise ImageError(f"{path}: cannot read ({exc.strerror or exc})") from None


def _tifffile():
    """tifffile (imageio's TIFF reader), loaded when a TIFF is read; what it logs about a
    damaged file is not printed (the ImageError says it)."""
    import logging
    import tifffile
    logger = logging.getLogger("tifffile")
    if not logger.handlers:
        logger.addHandler(logging.NullHandler())
    return tifffile


def _check_tiff_pages(path: Path) -> None:
    """At most MAX_TIFF_PAGES pages: Pillow and tifffile walk every page's header (4096 pages
    of 1x1 took 3 s, 100,000 several minutes), though only the first is read. The chain of
    page headers (IFDs) is followed here, MAX_TIFF_PAGES + 1 links at most, a loop ending it."""
    seen = set()
    try:
        with open(path, "rb") as f:
            head = f.read(16)
            order, big = ("<" if head[:2] == b"II" else ">"), head[2:4] in (b"\0+", b"+\0")
            count, entry, link = ("Q", 20, "Q") if big else ("H", 12, "I")
            offset = struct.unpack_from(order + link, head, 8 if big else 4)[0]
            while offset and offset not in seen and len(seen) <= MAX_TIFF_PAGES:
                seen.add(offset)
                f.seek(offset)
                entries = _unpack(f, order + count)
                f.seek(offset + struct.calcsize(count) + (entries or 0) * entry)
                offset = None if entries is None else _unpack(f, order + link)
    except (OSError, ValueError, struct.error):
        return                          # a damaged header: _decode_tiff says so
    if len(seen) > MAX_TIFF_PAGES:
        raise ImageError(f"{path}: the TIFF has more than {MAX_TIFF_PAGES} pages; only its "
                         "first page is read: save it alone")


def _unpack(f, fmt: str) -> int | None:
    """One integer read at the file's position, or None past its end."""
    raw = f.read(struct.calcsize(fmt))
    return struct.unpack(fmt, raw)[0] if len(raw) == struct.calcsize(fmt) else None


def _decode_tiff(path: Path) -> np.ndarray:
    """The first page of a TIFF's first series, its shape, dtype and strips or tiles checked
    before it is decoded: a stack of pages decodes one page only (imageio decoded the whole
    series), and a float or 64-bit page Pillow cannot open is checked too."""
    try:
        with _tifffile().TiffFile(path) as tif:
            series = tif.series[0]
            first = series.pages[0]
            page = first.keyframe
            whole = series.size == page.size          # one page: its series' own shape
            shape = series.shape if whole else _page_shape(series, page)
            _check_decoded_size(_planes_last(shape, page), page.dtype, path)
            _check_segments(tif, first, page, path)
            image = tif.asarray(series=0) if whole else tif.asarray(series=0, key=0)
    except ImageError:
        raise
    except MemoryError:
        raise ImageError(f"{path}: not enough memory to decode this image") from None
    except Exception as exc:  # tifffile fails in many ways on damaged files
        raise ImageError(f"{path}: cannot read it as an image "
                         "(unknown format, or a damaged or truncated file)") from exc
    if not whole:
        image = image.reshape(shape)
    return np.moveaxis(image, 0, -1) if _planes_last(image.shape, page) != image.shape else image


def _page_shape(series, page) -> tuple:
    """A stack's first page as indexing the series would give it: (n, ...) → (...)."""
    rest = tuple(series.shape[1:])
    if series.shape[0] == len(series.pages) and math.prod(rest) == page.size:
        return rest
    return tuple(page.shape)


def _planes_last(shape, page) -> tuple:
    """A planar page (one plane per channel, (C, H, W)) as (H, W, C), like every picture."""
    shape = tuple(shape)
    if page.planarconfig == 2 and len(shape) == 3 and shape[0] == page.samplesperpixel > 1:
        return shape[1:] + shape[:1]
    return shape


def _check_segments(tif, first, page, path: Path) -> None:
    """Refuse a deflated or LZMA strip or tile that inflates past its declared size (tifffile
    would inflate it whole): inflated here a bounded piece at a time, never kept."""
    inflater = _INFLATE.get(int(page.compression))
    if inflater is None:
        return
    limit = math.prod(page.chunks) * page.dtype.itemsize
    end = tif.filehandle.size
    for offset, count in zip(first.dataoffsets, first.databytecounts):
        offset, count = int(offset), int(count)
        tif.filehandle.seek(offset)
        data = tif.filehandle.read(max(0, min(count, end - offset)))
        if len(inflater().decompress(data, limit + 1)) > limit:
            raise ImageError(f"{path}: a strip or tile of the TIFF inflates past its "
                             f"declared {limit} bytes: a damaged file or a decompression bomb")


def _check_pixels(height: int, width: int, path: Path) -> None:
    if height * width == 0:
        raise ImageError(f"{path}: the image has no pixels ({width}x{height})")
    if height * width > MAX_PIXELS:
        raise ImageError(f"{path}: the image is {width}x{height}, more than "
                         f"{MAX_PIXELS // 2**20} megapixels: reduce it first")


def _check_decoded(image: np.ndarray, path: Path) -> np.ndarray:
    _check_decoded_size(image.shape, image.dtype, path)
    return image


def _check_decoded_size(shape: tuple, dtype: np.dtype, path: Path) -> None:
    """What a decoded picture must be (layout, pixels, bytes), checked from a header's shape
    and dtype before decoding as well as on the decoded array."""
    try:
        _check_layout(shape, dtype)
    except ImageError as exc:
        raise ImageError(f"{path}: {exc}") from None
    _check_pixels(shape[0], shape[1], path)
    nbytes = math.prod(shape) * dtype.itemsize
    if nbytes > MAX_IMAGE_BYTES:
        h, w = shape[:2]
        channels = 1 if len(shape) == 2 else shape[2]
        kind = "floats" if dtype.kind == "f" else "integers"
        raise ImageError(f"{path}: the image is {w}x{h} with {channels} channel(s) of "
                         f"{dtype.itemsize * 8}-bit {kind}: "
                         f"{nbytes / 2**20:.0f} MiB decoded, more than "
                         f"{MAX_IMAGE_BYTES // 2**20} MiB; reduce it or save it with 8 bits "
                         "per channel")


def _check_shape(image: np.ndarray) -> None:
    _check_layout(image.shape, image.dtype)


def _check_layout(shape: tuple, dtype: np.dtype) -> None:
    """Grey (H, W) or (H, W, C) with C = 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA; numbers only."""
    if not (len(shape) == 2 or (len(shape) == 3 and 1 <= shape[2] <= 4)):
        raise ImageError(f"an image of shape {tuple(shape)} is not supported: expected grey, "
                         "grey + alpha, RGB or RGBA pixels")
    if dtype.kind not in "biuf":
        raise ImageError(f"pixels of type {dtype} are not supported: expected bool, "
                         "integer or float")


# -- grey -------------------------------------------------------------------------------------
def to_grey(image) -> np.ndarray:
    """Grey (H, W) float64 in [0, 1] of any supported image; RGBA is laid on white first.

    Integer types are scaled by their range (uint16 65535 → 1), 32/64-bit and negative ones by
    their own (as_read); floats are read on 0..1, a little below 0 or above 1 clipped, well
    outside it (FLOAT_RANGE) refused.
    Converted by bands of rows: a 64-megapixel RGBA photo as float64 would take 2 GB at once
    (every step is per pixel, so the result is the same as in one go).
    """
    image = as_read(image)
    grey = np.empty(image.shape[:2], np.float64)
    for top, band in zip(range(0, image.shape[0], _BAND_ROWS), _bands(image)):
        grey[top:top + _BAND_ROWS] = _grey_band(band)
    return grey


_BAND_ROWS = 256


def as_read(image) -> np.ndarray:
    """An array as load_image reads the same samples from a file: 32- or 64-bit integers, and
    signed ones with negative samples, by their own range (_own_range: an int64 photo of 0..255,
    numpy's default integers, would be ~0 on its type's scale, "constant"). The whole array at
    once, so that its bands are scaled alike; floats and other integers are kept as they are."""
    image = np.asarray(image)
    _check_shape(image)
    return _own_range(image) if image.dtype.kind in "iu" and image.size else image


def to_rgb(image) -> np.ndarray:
    """RGB (H, W, 3) float64 in [0, 1] of any supported image: RGBA laid on white (as in
    `to_grey`), a grey one repeated in the three channels."""
    image = as_read(image)
    if image.ndim == 2 or image.shape[2] < 3:
        return np.repeat(to_grey(image)[..., None], 3, axis=2)
    rgb = _as_unit_float(image)
    return ski.color.rgba2rgb(rgb) if rgb.shape[2] == 4 else rgb


def _grey_band(image: np.ndarray) -> np.ndarray:
    img = _as_unit_float(image)
    if img.ndim == 2:
        return img
    if img.shape[2] <= 2:
        return img[..., 0]
    if img.shape[2] == 4:
        img = ski.color.rgba2rgb(img)
    return ski.color.rgb2gray(img)


def _as_unit_float(image) -> np.ndarray:
    image = np.asarray(image)
    _check_shape(image)
    img = ski.util.img_as_float64(image)
    if img.dtype.kind == "f" and image.dtype.kind == "f":
        if not np.all(np.isfinite(img)):
            raise ImageError("the image holds NaN or infinite values")
        _check_float_range(img)
    if np.shares_memory(img, image):
        return np.clip(img, 0.0, 1.0)
    return np.clip(img, 0.0, 1.0, out=img)     # a converted copy: clipped where it is


FLOAT_RANGE = (-1.0, 2.0)   # float pixels are read on 0..1 (scikit-image's convention) and
                            # clipped; beyond these they are on another scale (0..255 after an
                            # .astype(float)), which clipping would turn into a black-and-white
                            # picture without a word


def _check_float_range(img: np.ndarray) -> None:
    lo, hi = float(img.min()), float(img.max())
    if lo < FLOAT_RANGE[0] or hi > FLOAT_RANGE[1]:
        seen = f"reach {hi:.4g}" if hi > FLOAT_RANGE[1] else f"go down to {lo:.4g}"
        raise ImageError(f"the image's float pixels {seen}, but float pixels are read on 0..1: "
                         "divide them by their maximum (by 255 for 0..255 values), or pass 8- "
                         "or 16-bit integers")


# -- quantisation -----------------------------------------------------------------------------
def quantize(image, levels: int, method: str = "band") -> Quantization:
    """Cut a photo into G levels ("band": the thesis's; "lloyd": minimum mean-square error;
    "lab": G colour classes in CIELAB, see `_lab_quantize`, which is "lloyd" on a grey photo)."""
    levels = check_levels(levels)
    if method not in METHODS:
        raise InputError(f"unknown quantisation method {method!r}: choose one of {', '.join(METHODS)}")
    image = as_read(image)
    if method == "lab" and has_colour(image):
        return _lab_quantize(image, levels)
    grey = to_grey(image)
    np.round(grey, _DECIMALS, out=grey)
    _check_contrast(grey)
    find = _band_thresholds if method == "band" else _lloyd_thresholds
    thresholds = np.round(find(grey, levels), _DECIMALS)
    index = np.searchsorted(thresholds, grey, side="right").astype(np.uint8)
    edges = np.concatenate([[0.0], thresholds, [1.0]])
    centres = np.repeat(((edges[:-1] + edges[1:]) / 2)[:, None], 3, axis=1)
    return Quantization(index, _palette(image, grey, index, centres), thresholds)


def has_colour(image) -> bool:
    """True when some pixel's red, green and blue differ (alpha aside): a photo with colour."""
    image = np.asarray(image)
    _check_shape(image)
    if image.ndim == 2 or image.shape[2] < 3:
        return False
    return any(np.any(band[..., 0] != band[..., 1]) or np.any(band[..., 1] != band[..., 2])
               for band in _bands(image))


def _bands(image: np.ndarray):
    for top in range(0, image.shape[0], _BAND_ROWS):
        yield image[top:top + _BAND_ROWS]


def check_levels(levels) -> int:
    """G as an int in MIN_LEVELS..MAX_LEVELS (the DPJ's codes and the palette depend on it)."""
    g = whole(levels, "the number of levels")
    if not MIN_LEVELS <= g <= MAX_LEVELS:
        raise InputError(f"G = {g} levels is out of range: choose {MIN_LEVELS}..{MAX_LEVELS}")
    return g


def _check_contrast(grey: np.ndarray) -> None:
    if grey.size == 0:
        raise ImageError("the image is empty (0 pixels): nothing to quantise")
    if grey.min() == grey.max():
        raise ImageError(f"the image is constant: it has a single grey ({grey.flat[0]:.3g}), "
                         "nothing to quantise; choose a photo with some contrast")


def _band_thresholds(grey: np.ndarray, levels: int) -> np.ndarray:
    """Thesis §5.2.1: G equal intervals across the central band holding 90% of the pixels.

    When that band is a single grey (a mostly flat image with a few outliers), the whole range
    min..max is cut instead, so the outliers still get levels of their own.
    """
    lo, hi = np.percentile(grey, BAND)
    if hi <= lo:
        lo, hi = grey.min(), grey.max()
    return lo + (hi - lo) * np.arange(1, levels) / levels


def _lloyd_thresholds(grey: np.ndarray, levels: int) -> np.ndarray:
    """Lloyd–Max: alternate cell centroids and mid-point thresholds until the cells stop changing.

    Starts from the band thresholds. The values are sorted once, so each iteration is G binary
    searches and G differences of a cumulative sum; an empty cell keeps its previous centroid.
    """
    thresholds = _band_thresholds(grey, levels)    # first: its percentile copy is gone by now
    values = np.sort(grey, axis=None)
    sums = np.empty(values.size + 1)           # [0, cumsum]: no second copy of a large photo
    sums[0] = 0.0
    np.cumsum(values, out=sums[1:])
    edges = np.concatenate([[values[0]], thresholds, [values[-1]]])
    centroids = (edges[:-1] + edges[1:]) / 2
    bounds = None
    for _ in range(MAX_LLOYD_ITERATIONS):
        cuts = np.searchsorted(values, thresholds, side="left")
        if bounds is not None and np.array_equal(cuts, bounds):
            break
        bounds = cuts
        cuts = np.concatenate([[0], cuts, [values.size]])
        counts = np.diff(cuts)
        totals = np.diff(sums[cuts])
        centroids = np.where(counts > 0, totals / np.maximum(counts, 1), centroids)
        thresholds = np.round((centroids[:-1] + centroids[1:]) / 2, _DECIMALS)
    return thresholds


def _palette(image, grey, index: np.ndarray, empty: np.ndarray) -> np.ndarray:
    """Each level's mean colour in the photo (alpha ignored), so a texture looks like the photo.

    A level no pixel falls in takes its ``empty`` colour (G, 3) in [0, 1]: the grey at the
    centre of its interval of the grey scale, or its class's centre in CIELAB.
    """
    levels = len(empty)
    image = np.asarray(image)
    colour = image.ndim == 3 and image.shape[2] >= 3
    if colour and image.dtype == np.uint8:
        counts, sums = _level_sums_u8(index, image, levels)
    else:
        flat = index.ravel()
        counts = np.bincount(flat, minlength=levels)
        sums = np.stack([np.bincount(flat, minlength=levels, weights=(   # a channel at a time
            _as_unit_float(image[..., c]).ravel() if colour else grey.ravel()))
            for c in range(3)], axis=1)
    means = np.array(empty, np.float64)
    seen = counts > 0
    means[seen] = sums[seen] / counts[seen][:, None]
    return np.round(means * 255).astype(np.uint8)


@njit(cache=True, nogil=True)
def _level_sums_u8(index, image, levels):
    """Each level's pixel count and sums of red, green and blue in [0, 1], added in the order
    np.bincount adds them (row-major), with the same x · (1/255) as img_as_float: the same
    means, without a float64 copy and an intp copy of a large photo."""
    counts = np.zeros(levels, np.int64)
    sums = np.zeros((levels, 3))
    scale = 1.0 / 255
    for y in range(index.shape[0]):
        for x in range(index.shape[1]):
            counts[index[y, x]] += 1
    for c in range(3):
        for y in range(index.shape[0]):
            for x in range(index.shape[1]):
                sums[index[y, x], c] += image[y, x, c] * scale
    return counts, sums


# -- colour classes in CIELAB -------------------------------------------------------------------
def _lab_quantize(image: np.ndarray, levels: int) -> Quantization:
    """G colour classes: Lloyd's iterations (k-means) in CIELAB, where distances follow what the
    eye sees, ordered by lightness L* (level 0 the darkest, as with greys); palette = each
    class's mean colour in the photo.

    Each pixel is taken as its 8-bit colour laid on white (as `to_grey` lays RGBA): the classes
    are fitted on those colours binned to _FIT_BITS a channel (weighted by their pixels), then
    every exact colour goes to the nearest class, so the cost hardly grows with the photo. The
    first centres are drawn by k-means++ from a fixed seed: the same photo gives the same
    levels on every machine.
    """
    codes = _colour_codes(image)
    colours, inverse, counts = _unique_colours(codes.ravel())
    if colours.size == 1:
        raise ImageError("the image is one flat colour, nothing to quantise; choose a photo "
                         "with some contrast")
    if colours.size < levels:
        raise ImageError(f"the photo has only {colours.size} colours: choose G ≤ {colours.size} "
                         "colour classes")
    lab, weights = _lab_of_codes(colours), counts.astype(np.float64)
    points, mass = _fit_bins(colours, lab, weights)
    if len(points) < levels:        # a few close colours: fit on the colours themselves
        points, mass = lab, weights
    centres = _lab_centres(points, mass, levels)
    index = _nearest(lab, centres).astype(np.uint8)[inverse].reshape(codes.shape)
    empty = ski.color.lab2rgb(centres[None])[0]
    return Quantization(index, _palette(image, None, index, empty), np.empty(0))


def _unique_colours(codes: np.ndarray):
    """np.unique(codes, return_inverse=True, return_counts=True) of 24-bit colour codes, in
    O(pixels): a radix sort below COUNTED_COLOURS pixels (5× sooner than np.unique's sort on a
    512² photo), else every code counted, with the places as int32 (sorting a 12-megapixel
    photo's codes takes seconds)."""
    if codes.size < COUNTED_COLOURS:
        return _radix_unique(codes)
    counts = _count_codes(codes)
    colours = np.flatnonzero(counts)
    rank = np.cumsum(counts > 0, dtype=np.int32) - 1     # a present code's place in colours
    return colours.astype(codes.dtype), rank[codes], counts[colours]


@njit(cache=True, nogil=True)
def _radix_unique(codes):
    """Sorted distinct codes, each code's place among them and their counts: the codes' order
    found by three stable passes of 8 bits (a least-significant-digit radix sort)."""
    n = codes.size
    order, spare = np.arange(n, dtype=np.int32), np.empty(n, np.int32)
    for shift in (0, 8, 16):
        starts = np.zeros(257, np.int64)
        for i in range(n):
            starts[((codes[i] >> shift) & 255) + 1] += 1
        for b in range(256):
            starts[b + 1] += starts[b]
        for i in range(n):
            b = (codes[order[i]] >> shift) & 255
            spare[starts[b]] = order[i]
            starts[b] += 1
        order, spare = spare, order
    inverse = np.empty(n, np.intp)
    m = 0
    for i in range(n):
        if i == 0 or codes[order[i]] != codes[order[i - 1]]:
            m += 1
        inverse[order[i]] = m - 1
    colours, counts = np.empty(m, codes.dtype), np.zeros(m, np.intp)
    for i in range(n):
        colours[inverse[i]] = codes[i]
        counts[inverse[i]] += 1
    return colours, inverse, counts


@njit(cache=True, nogil=True)
def _count_codes(codes):
    """The number of pixels of each 24-bit code (np.bincount would copy the codes as intp)."""
    counts = np.zeros(1 << 24, np.int64)
    for code in codes:
        counts[code] += 1
    return counts


def _colour_codes(image: np.ndarray) -> np.ndarray:
    """(H, W) uint32: each pixel's 8-bit colour (RGBA laid on white) as 0xRRGGBB."""
    codes = np.empty(image.shape[:2], np.uint32)
    for top, band in zip(range(0, image.shape[0], _BAND_ROWS), _bands(image)):
        rgb8 = band.astype(np.uint32) if band.dtype == np.uint8 and band.shape[2] == 3 else (
            _rgb8_on_white(band))           # the same codes: round(x / 255 · 255) is x
        codes[top:top + _BAND_ROWS] = (rgb8[..., 0] << 16) | (rgb8[..., 1] << 8) | rgb8[..., 2]
    return codes


def _rgb8_on_white(band: np.ndarray) -> np.ndarray:
    rgb = _as_unit_float(band)
    if rgb.shape[2] == 4:
        rgb = ski.color.rgba2rgb(rgb)
    return np.round(rgb * 255).astype(np.uint32)


def _lab_of_codes(codes: np.ndarray) -> np.ndarray:
    """CIELAB of 0xRRGGBB codes, LAB_CHUNK at a time (each colour on its own: the conversion's
    float64 temporaries of a noisy 64-megapixel photo's 13 million colours took 1.5 GB)."""
    lab = np.empty((codes.size, 3))
    for a in range(0, codes.size, LAB_CHUNK):
        part = codes[a:a + LAB_CHUNK]
        rgb = np.stack([(part >> 16) & 255, (part >> 8) & 255, part & 255], axis=-1) / 255.0
        lab[a:a + LAB_CHUNK] = np.round(ski.color.rgb2lab(rgb[None])[0], _DECIMALS)
    return lab


def _fit_bins(colours: np.ndarray, lab: np.ndarray, counts: np.ndarray):
    """The colours binned to _FIT_BITS a channel: each bin's mean CIELAB and its pixels."""
    drop = 8 - _FIT_BITS
    mask = (1 << _FIT_BITS) - 1
    key = (((colours >> (16 + drop)) & mask) << (2 * _FIT_BITS)
           | ((colours >> (8 + drop)) & mask) << _FIT_BITS | ((colours >> drop) & mask))
    present = np.bincount(key, minlength=1 << (3 * _FIT_BITS)) > 0   # np.unique, in O(colours)
    inverse = (np.cumsum(present) - 1)[key]
    bins = np.flatnonzero(present)
    weights = np.bincount(inverse, weights=counts, minlength=bins.size)
    means = np.stack([np.bincount(inverse, weights=counts * lab[:, c], minlength=bins.size)
                      for c in range(3)], axis=-1) / weights[:, None]
    return np.round(means, _DECIMALS), weights


def _lab_centres(points: np.ndarray, weights: np.ndarray, levels: int) -> np.ndarray:
    """Weighted Lloyd iterations from k-means++ centres until no point changes class; an empty
    class keeps its centre. The centres come back sorted by L* (then a*, b*)."""
    centres = _plus_plus(points, weights, levels, np.random.default_rng(0))
    labels = None
    for _ in range(MAX_LLOYD_ITERATIONS):
        new = _nearest(points, centres)
        if labels is not None and np.array_equal(new, labels):
            break
        labels = new
        mass = np.bincount(labels, weights=weights, minlength=levels)
        for c in range(3):
            sums = np.bincount(labels, weights=weights * points[:, c], minlength=levels)
            centres[mass > 0, c] = np.round(sums[mass > 0] / mass[mass > 0], _DECIMALS)
    return centres[np.lexsort(centres.T[::-1])]


def _plus_plus(points, weights, k: int, rng) -> np.ndarray:
    """k-means++ (Arthur & Vassilvitskii): each next centre drawn with probability ∝ pixels ×
    squared distance to the nearest centre so far, so the first centres are far apart."""
    chosen = [rng.choice(len(points), p=weights / weights.sum())]
    nearest = ((points - points[chosen[0]]) ** 2).sum(axis=1)
    for _ in range(1, k):       # the points are distinct and k ≤ their number: mass > 0
        mass = weights * nearest
        chosen.append(rng.choice(len(points), p=mass / mass.sum()))
        nearest = np.minimum(nearest, ((points - points[chosen[-1]]) ** 2).sum(axis=1))
    return points[chosen].copy()


def _nearest(points: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """The index of each point's nearest centre (scipy's vector quantisation, in C)."""
    return scipy.cluster.vq.vq(points, centres, check_finite=False)[0].astype(np.uint8)
