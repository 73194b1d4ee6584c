"""Grey-level doubling (thesis §4.5, after Massaloux): learn from a photo how each level splits in
two given its 8 neighbours, then turn a G-level synthetic texture into a 2G-level one.

It sits after synthesis: photo → (G and 2G levels) → a *doubling table* → a G-level texture
becomes 2G levels. The table is stored as a 3×3 DPJ of the photo at 2G levels (its configurations
hold the children; a neighbour's G-level value is its child // 2), so a document keeps it in its
DPJ store and a `.texture` file carries it like any DPJ.

The children of level b are 2b and 2b + 1 (**erratum**: the thesis prints 2b and 2b − 1). So that
every 2G level has one parent, the 2G quantisation *refines* the G one: each level of the photo's
G-level quantisation is cut in two at the mean grey of its pixels (one Lloyd step inside the
cell); a grey strictly above the mean goes to the upper child.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import skimage as ski

from .dpj import DPJ, MAX_LEVELS
from ..errors import InputError
from .estimation import estimate_dpj
from .levels import quantize, to_grey

WINDOW = (3, 3)
CONTEXTS = ("8 neighbours", "4 neighbours", "own level", "none")
# Neighbour positions in a 3×3 configuration (row, col), read row by row; the centre is (1, 1).
_EIGHT = ((0, 0), (0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1), (2, 2))
_FOUR = ((0, 1), (1, 0), (1, 2), (2, 1))


class Refinement(NamedTuple):
    """A photo at G levels and at 2G levels, the second refining the first (child // 2 = parent)."""

    parents: np.ndarray      # (H, W) uint8, 0..G-1
    children: np.ndarray     # (H, W) uint8, 0..2G-1
    palette: np.ndarray      # (2G, 3) uint8: the photo's mean colour in each child level


class Doubling(NamedTuple):
    """A doubled texture and how many points each context decided (see CONTEXTS)."""

    levels: np.ndarray       # (H, W) uint8, 0..2G-1
    contexts: tuple          # points drawn with 8 neighbours, 4 neighbours, own level, none


# -- learning --------------------------------------------------------------------------------------

def refine(image, levels: int, method: str = "band") -> Refinement:
    """Quantise a photo at G levels (``texeditor.levels.quantize``) and split each level in two."""
    if not 2 <= levels <= MAX_LEVELS // 2:
        raise InputError(f"G = {levels}: doubling needs 2..{MAX_LEVELS // 2} levels "
                         f"(2G must stay within {MAX_LEVELS})")
    q = quantize(image, levels, method)
    grey = to_grey(image)
    flat = q.levels.ravel()
    counts = np.bincount(flat, minlength=levels)
    means = np.bincount(flat, weights=grey.ravel(), minlength=levels) / np.maximum(counts, 1)
    upper = grey > means[q.levels]
    children = (2 * q.levels + upper).astype(np.uint8)
    return Refinement(q.levels, children, _palette(image, grey, children, q.palette))


def _palette(image, grey, children, parent_palette) -> np.ndarray:
    """Each child's mean colour in the photo; a child no pixel falls in takes its parent's."""
    image = np.asarray(image)
    colour = image.ndim == 3 and image.shape[2] >= 3
    channels = np.clip(ski.util.img_as_float64(image[..., :3]), 0, 1) if colour else grey[..., None]
    n = 2 * len(parent_palette)
    flat = children.ravel()
    counts = np.bincount(flat, minlength=n)
    out = np.repeat(np.asarray(parent_palette, dtype=np.float64), 2, axis=0) / 255
    for ch in range(3):
        sums = np.bincount(flat, weights=channels[..., min(ch, channels.shape[-1] - 1)].ravel(),
                           minlength=n)
        out[counts > 0, ch] = sums[counts > 0] / counts[counts > 0]
    return np.round(out * 255).astype(np.uint8)


def learn(image, levels: int, method: str = "band", *, name: str = "") -> DPJ:
    """The doubling table of a photo for G-level textures: its 3×3 DPJ at 2G refined levels.

    P(B = b | A1..A8) is read from it by summing configurations (see :func:`split_odds`).
    """
    r = refine(image, levels, method)
    h, w = r.children.shape
    if h < 3 or w < 3:
        raise InputError(f"the photo is {w}x{h}: doubling needs at least 3x3 pixels")
    meta = {"source": "doubling table", "parent_levels": int(levels), "quantizer": method,
            **({"name": f"{name} ×2 levels"} if name else {})}
    return estimate_dpj(r.children, WINDOW, 2 * levels, wrap=False, palette=r.palette,
                        meta=meta)


def check_table(table: DPJ) -> int:
    """The G a doubling table doubles (its 3×3 window and even level count are checked)."""
    if not isinstance(table, DPJ) or table.window != WINDOW or table.levels % 2:
        raise InputError("a doubling table is a 3x3 DPJ with an even number of levels 2G "
                         "(make one with texeditor.doubling.learn)")
    return table.levels // 2


# -- the conditional law, by context ---------------------------------------------------------------

def split_odds(table: DPJ) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """For each context of CONTEXTS but the last: (sorted keys, P(odd child), weight).

    A key is the base-G code of the neighbours' levels (8, then 4, then none) followed by the
    centre's own level b; P(odd child) is P(B = 2b + 1 | context, B ∈ {2b, 2b + 1}).
    """
    g = check_table(table)
    parents = table.configs // 2
    odd = (table.configs[:, 1, 1] % 2).astype(np.float64)
    out = []
    for cells in (_EIGHT, _FOUR, ()):
        keys = _keys([parents[:, r, c] for r, c in cells] + [parents[:, 1, 1]], g)
        unique, inverse = np.unique(keys, return_inverse=True)
        weight = np.bincount(inverse.ravel(), weights=table.probs, minlength=len(unique))
        p_odd = np.bincount(inverse.ravel(), weights=table.probs * odd, minlength=len(unique))
        out.append((unique, p_odd / np.where(weight > 0, weight, 1), weight))
    return out


def _keys(digits, g: int) -> np.ndarray:
    keys = np.zeros(np.shape(digits[0]), dtype=np.int64)
    for d in digits:
        keys = keys * g + d
    return keys


# -- doubling a texture ----------------------------------------------------------------------------

def double_levels(levels, table: DPJ, seed: int = 0) -> Doubling:
    """Rewrite each point b of a G-level texture as 2b or 2b + 1, drawn from the table.

    The law of a point uses its 8 neighbours when the photo showed that neighbourhood around a
    point of its level; otherwise its 4 edge neighbours; otherwise its level alone; a level the
    photo never had splits evenly. Points on the border see the border repeated outwards. The
    draws are independent given the G-level texture, from ``numpy.random.default_rng(seed)``.
    """
    g = check_table(table)
    levels = np.asarray(levels)
    if levels.ndim != 2 or levels.size == 0 or levels.dtype.kind not in "ui":
        raise InputError("doubling needs a non-empty 2-D matrix of levels")
    if levels.max() >= g:
        raise InputError(f"this table doubles textures of G = {g} levels; the texture uses "
                         f"level {int(levels.max())}")
    padded = np.pad(levels.astype(np.int64), 1, mode="edge")
    h, w = levels.shape
    view = {(r, c): padded[r:r + h, c:c + w] for r in range(3) for c in range(3)}
    p_odd = np.full(levels.shape, 0.5)
    decided = np.zeros(levels.shape, dtype=bool)
    counts = []
    for cells, (keys, odds, weight) in zip((_EIGHT, _FOUR, ()), split_odds(table)):
        if not len(keys):
            counts.append(0)
            continue
        query = _keys([view[cell] for cell in cells] + [view[(1, 1)]], g)
        i = np.minimum(np.searchsorted(keys, query), len(keys) - 1)
        found = ~decided & (keys[i] == query) & (weight[i] > 0)
        p_odd[found] = odds[i[found]]
        decided |= found
        counts.append(int(found.sum()))
    counts.append(int((~decided).sum()))
    upper = np.random.default_rng(seed).random(levels.shape) < p_odd
    return Doubling((2 * levels + upper).astype(np.uint8), tuple(counts))
