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
    canvas = ski.transform.resize(grid / 255.0, shape, order=1, anti_aliasing=False)
    q = quantize(np.round(canvas * 255).astype(np.uint8), count, "lab")
    return q.levels, q.palette
