"""Colour plates (thesis §1.2.3–1.2.4): a colour texture is a grey texture laid on a map of
coloured plates, I = I_plates + I_texture.

It sits at the very end of the data flow, between a document (its levels, palette and plates
layer, `recipe.document`) and the picture shown or exported, and at the start of a plates layer
made from a photo (blurred, reduced to a small grid a step records, then cut into plates).
"""

from __future__ import annotations

import re

import numpy as np
import skimage as ski

from ..errors import InputError
from ..markov.levels import quantize, to_rgb

MAX_GRID = 64           # the photo grid a step records: at most this many points a side
MAX_BLUR_SIDE = 1024    # a larger photo is first taken one point in k (the blur hides it)
MAX_GRID_CHARS = MAX_GRID * (6 * MAX_GRID + 1)
_GRID_ROW = re.compile(r"^(?:[0-9a-f]{6})+$")
_BAND_ROWS = 256        # rows laid on plates at once (bounds the float temporaries)
_STRETCH_POINTS = 2**20     # canvas points a photo grid is stretched over at once (24 MiB)
_GREY = np.array([0.2125, 0.7154, 0.0721])      # skimage's rgb2gray weights, as `to_grey`


# -- the picture: texture on plates ---------------------------------------------------------------
def laid_on_plates(picture: np.ndarray, plates: np.ndarray, colours) -> np.ndarray:
    """I = plate colour + (grey of the texture − its mean grey), rounded and clipped to 0..255.

    The texture (an (H, W, 3) uint8 picture: its levels in their palette, or the photo's tone)
    keeps only its grey variations around its mean, so each plate shows its own colour on
    average and the texture's grain on top (§1.2.4's sum of the two images).

    >>> texture = np.array([[[0, 0, 0], [200, 200, 200]]], np.uint8)     # mean grey 100
    >>> laid_on_plates(texture, np.array([[0, 1]], np.uint8), [[200, 50, 50], [0, 0, 250]])
    array([[[100,   0,   0],
            [100, 100, 255]]], dtype=uint8)
    """
    picture = np.asarray(picture)
    colours = np.asarray(colours, np.float64)
    mean = sum(float((band @ _GREY).sum()) for band in _bands(picture)) / max(plates.size, 1)
    out = np.empty(picture.shape, np.uint8)
    for top, band in zip(range(0, picture.shape[0], _BAND_ROWS), _bands(picture)):
        offset = band @ _GREY - mean
        rows = colours[plates[top:top + _BAND_ROWS]] + offset[..., None]
        out[top:top + _BAND_ROWS] = np.clip(np.rint(rows), 0, 255)
    return out


def levels_on_plates(levels: np.ndarray, palette, plates: np.ndarray, colours) -> np.ndarray:
    """`laid_on_plates` of a texture seen through its palette, by a table of the P × G colours a
    point can take (one look-up per point: 0.12 s for 2048² points, against 0.6 s).

    >>> levels_on_plates(np.array([[0, 1]], np.uint8), [[0, 0, 0], [200, 200, 200]],
    ...                  np.array([[0, 1]], np.uint8), [[200, 50, 50], [0, 0, 250]])
    array([[[100,   0,   0],
            [100, 100, 255]]], dtype=uint8)
    """
    grey = np.asarray(palette, np.float64) @ _GREY
    counts = np.bincount(levels.ravel(), minlength=len(grey))
    offset = grey - counts @ grey / max(levels.size, 1)
    table = np.asarray(colours, np.float64)[:, None, :] + offset[None, :, None]
    table = np.clip(np.rint(table), 0, 255).astype(np.uint8)
    return table[plates, levels]


def _bands(picture: np.ndarray):
    for top in range(0, picture.shape[0], _BAND_ROWS):
        yield picture[top:top + _BAND_ROWS].astype(np.float64)


def document_picture(doc, tone: np.ndarray | None = None, *, plates: bool = True) -> np.ndarray:
    """What the document looks like, (H, W, 3) uint8: its levels in their palette (or ``tone``,
    the photo's own colours), laid on its plates when it has some and ``plates`` is on."""
    if not plates or doc.plates is None:
        return np.asarray(doc.palette, np.uint8)[doc.levels] if tone is None else tone
    if tone is None:
        return levels_on_plates(doc.levels, doc.palette, doc.plates, doc.plate_colours)
    return laid_on_plates(tone, doc.plates, doc.plate_colours)


# -- plates from a photo ----------------------------------------------------------------------------
def photo_grid(image, sigma: float, side: int = MAX_GRID) -> np.ndarray:
    """A photo blurred by a Gaussian of ``sigma`` of its width (0.02: 2 %), reduced to at most
    ``side`` points a side, (h, w, 3) uint8: all a plates layer needs of it, small enough for
    a step to record (the blur leaves nothing finer than the grid keeps)."""
    if not 0 < sigma <= 1:
        raise InputError(f"the blur is a fraction of the photo's width in (0, 1], got {sigma}")
    image = np.asarray(image)
    step = -(-max(image.shape[:2]) // MAX_BLUR_SIDE)
    rgb = to_rgb(image[::step, ::step])
    h, w = rgb.shape[:2]
    blurred = ski.filters.gaussian(rgb, sigma=sigma * w, channel_axis=-1, mode="nearest")
    scale = min(1.0, side / max(h, w))
    shape = (max(1, round(h * scale)), max(1, round(w * scale)))
    small = ski.transform.resize(blurred, shape, order=1, anti_aliasing=scale < 1)
    return np.round(np.clip(small, 0, 1) * 255).astype(np.uint8)


def grid_text(grid: np.ndarray) -> str:
    """A grid as a step's text: each row its points' rrggbb in hex, rows joined by "/"."""
    return "/".join("".join(f"{r:02x}{g:02x}{b:02x}" for r, g, b in row) for row in grid)


def grid_of_text(text: str) -> np.ndarray:
    """The grid a step's text holds; InputError if it is not rows of equal length of
    rrggbb (at most MAX_GRID a side)."""
    rows = text.split("/")
    if not 1 <= len(rows) <= MAX_GRID or not all(_GRID_ROW.match(r) for r in rows) \
            or len({len(r) for r in rows}) != 1 or len(rows[0]) > 6 * MAX_GRID:
        raise InputError(f"a photo grid is 1..{MAX_GRID} rows of 1..{MAX_GRID} colours rrggbb "
                         "(lower-case hex), all rows as long, joined by /")
    flat = bytes.fromhex("".join(rows))
    return np.frombuffer(flat, np.uint8).reshape(len(rows), -1, 3)


def grid_plates(grid: np.ndarray, shape: tuple[int, int], count: int):
    """(plates, colours): the grid stretched over a canvas of ``shape`` (bilinear) and cut
    into ``count`` colour classes in CIELAB (`markov.levels`, "lab"): the plates and their
    mean colours, darkest first."""
    q = quantize(stretched_grid(grid, shape), count, "lab")
    return q.levels, q.palette


def stretched_grid(grid: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """The grid stretched over a canvas of ``shape``, (H, W, 3) uint8: bit for bit
    ``round(255 · skimage.transform.resize(grid / 255, shape, order=1, anti_aliasing=False))``,
    the colours every release has cut into plates, made _STRETCH_POINTS canvas points at a time.

    The whole canvas in float64 took 1.5 GiB for 2^26 points, and as much again for each
    temporary (4.9 GB for a 707-byte recipe). ``resize`` ends in SciPy's ``zoom_shift`` (its
    bilinear zoom, here in "mirror" mode and grid mode), which can also shift: a band of rows is
    that same routine with the same zoom, shifted by the band's first row. Each output point's
    arithmetic depends only on its own row and column, so the bands hold the whole zoom's rows
    bit for bit on every machine (a zoom written again here could round differently where a
    compiler fuses a multiply and an add). ``zoom_shift`` is not public SciPy: where it cannot
    be imported or called as here, the canvas is stretched whole, as before (the plates tests
    compare the two).
    """
    image = np.asarray(grid) / 255.0
    out_shape = tuple(int(n) for n in shape) + image.shape[2:]
    zoom_shift = _zoom_shift()
    if zoom_shift is not None and all(out_shape):
        # resize's zoom factors, then the output shape and zoom scipy.ndimage.zoom makes of them
        zooms = [1 / f for f in np.divide(image.shape, out_shape)]
        if not all(z == 1 for z in zooms) and tuple(
                int(round(n * z)) for n, z in zip(image.shape, zooms)) == out_shape:
            zoom = np.ascontiguousarray(np.divide(np.array(image.shape), np.array(out_shape)))
            try:
                return _stretched_bands(image, out_shape, zoom, *zoom_shift)
            except TypeError:           # another signature: not the routine this was made for
                pass
    canvas = ski.transform.resize(image, shape, order=1, anti_aliasing=False)
    return np.round(canvas * 255).astype(np.uint8)


def _stretched_bands(image, out_shape, zoom, zoom_shift, mirror) -> np.ndarray:
    lo, hi = np.asarray(image.min()), np.asarray(image.max())   # resize clips to the input's
    out = np.empty(out_shape, np.uint8)
    step = max(1, _STRETCH_POINTS // out_shape[1])
    band = np.empty((min(step, out_shape[0]),) + out_shape[1:])
    shift = np.zeros(len(out_shape))
    for top in range(0, out_shape[0], step):
        rows = band[:min(step, out_shape[0] - top)]
        shift[0] = top                  # output row k of the band is row top + k of the zoom
        zoom_shift(image, zoom, shift, rows, 1, mirror, 0.0, 0, True)
        np.clip(rows, lo, hi, out=rows)
        np.multiply(rows, 255, out=rows)
        out[top:top + len(rows)] = np.round(rows, out=rows)
    return out


def _zoom_shift():
    """(scipy.ndimage's zoom_shift, the code of its "mirror" mode), or None."""
    try:
        from scipy.ndimage._nd_image import zoom_shift
        from scipy.ndimage._ni_support import _extend_mode_to_code
        return zoom_shift, _extend_mode_to_code("mirror")
    except (ImportError, RuntimeError):
        return None
