"""Log optimisation (thesis §5.4, digest §10): a shorter action log that replays to the same texture.

It sits between a History (or a `.texture` file) and storage: the bank and `texeditor log
--optimize` keep the optimised recipe. Every rule here keeps the levels and the palette identical.
"""

from __future__ import annotations

from dataclasses import dataclass

from .actions import (Action, CropCanvas, NewCanvas, ResizeCanvas, SetLevels, SetPalette,
                      Synthesize, clip_rect)
from ..markov.dpj import grey_ramp
from .document import EMPTY_LEVELS

LOOKAHEAD = 256                        # how far a covering SetLevels is looked for
_PURE = (SetLevels, SetPalette, CropCanvas, ResizeCanvas)   # known not to read the palette


@dataclass(frozen=True)
class Known:
    """What the optimiser knows of the document before a step (None = unknown)."""

    shape: tuple[int, int] | None
    palette: tuple | None


def optimize(actions, dpjs: dict | None = None) -> list[Action]:
    """Drop no-ops, collapse runs of the same change, drop what a later step overwrites.

    ``dpjs`` (ref → DPJ) lets the optimiser know the palette a Synthesize sets. The result is
    never longer and replays to the same levels and palette (the current DPJ may differ).
    """
    actions = list(actions)
    while True:
        before = len(actions)
        for rule in (_drop_before_reset, _drop_covered_by_full, _drop_covered_rects,
                     _drop_noops, _collapse_palettes, _collapse_canvas):
            actions = rule(actions, trace(actions, dpjs))
        if len(actions) == before:
            return actions


def trace(actions, dpjs: dict | None = None) -> list[Known]:
    """The known shape and palette before each step, and after the last (len + 1 entries)."""
    known = [Known((0, 0), _palette_of(grey_ramp(EMPTY_LEVELS)))]
    for a in actions:
        shape, palette = known[-1].shape, known[-1].palette
        if a.EFFECT == "other":
            shape = palette = None
        elif a.EFFECT in ("reset", "canvas"):
            shape = a.canvas_shape(shape) if shape is not None or a.EFFECT == "reset" else None
        if isinstance(a, NewCanvas):
            palette = a.palette or _palette_of(grey_ramp(a.levels))
        elif isinstance(a, Synthesize):
            dpj = (dpjs or {}).get(a.dpj)
            palette = None if dpj is None else _palette_of(dpj.palette)
        elif isinstance(a, SetPalette):
            palette = a.palette
        elif a.EFFECT in ("reset", "palette"):
            palette = None
        known.append(Known(shape, palette))
    return known


def _palette_of(array) -> tuple:
    return tuple(tuple(int(c) for c in colour) for colour in array)


# -- rules: each takes the log and its trace and returns a log no longer than it ----------------

def _drop_before_reset(actions, known):
    """A reset (NewCanvas, Synthesize) makes the known steps since the last barrier useless."""
    keep = [True] * len(actions)
    for j, a in enumerate(actions):
        if a.EFFECT == "reset":
            i = j - 1
            while i >= 0 and actions[i].EFFECT != "other":
                keep[i] = False
                i -= 1
    return [a for a, k in zip(actions, keep) if k]


def _drop_covered_by_full(actions, known):
    """A level edit covering the whole canvas makes earlier level edits useless.

    Canvas and palette steps in between stay: they do not read the levels they would lose.
    """
    keep = [True] * len(actions)
    for j, a in enumerate(actions):
        if a.EFFECT == "levels" and known[j].shape is not None and a.covers(known[j].shape):
            i = j - 1
            while i >= 0 and actions[i].EFFECT in ("levels", "palette", "canvas"):
                if actions[i].EFFECT == "levels":
                    keep[i] = False
                i -= 1
    return [a for a, k in zip(actions, keep) if k]


def _drop_covered_rects(actions, known):
    """A SetLevels whose points are all overwritten by later fills, or cut away by later canvas
    changes, goes. Its rectangle is followed through crops (which move it) and resizes."""
    keep = [True] * len(actions)
    for i, a in enumerate(actions):
        if isinstance(a, SetLevels) and known[i].shape is not None:
            rect = clip_rect(a.top, a.left, a.height, a.width, known[i].shape)
            keep[i] = not _overwritten(rect, actions, known, i + 1)
    return [a for a, k in zip(actions, keep) if k]


def _overwritten(rect, actions, known, start) -> bool:
    for j in range(start, min(len(actions), start + LOOKAHEAD)):
        if rect[2] == 0 or rect[3] == 0:
            return True
        b, shape = actions[j], known[j].shape
        if isinstance(b, SetLevels):
            if _inside(rect, clip_rect(b.top, b.left, b.height, b.width, shape)):
                return True
        elif isinstance(b, ResizeCanvas):
            rect = clip_rect(*rect, (b.height, b.width))
        elif isinstance(b, CropCanvas):
            t, l, h, w = clip_rect(b.top, b.left, b.height, b.width, shape)
            rect = clip_rect(rect[0] - t, rect[1] - l, rect[2], rect[3], (h, w))
        elif not isinstance(b, SetPalette):
            return False
    return rect[2] == 0 or rect[3] == 0


def _inside(inner, outer) -> bool:
    (t, l, h, w), (T, L, H, W) = inner, outer
    return T <= t and L <= l and t + h <= T + H and l + w <= L + W


def _drop_noops(actions, known):
    """Steps that change nothing: an empty fill, a same-size resize, a whole-canvas crop,
    the palette already in place."""
    return [a for a, k in zip(actions, known) if not _is_noop(a, k)]


def _is_noop(a, k: Known) -> bool:
    if isinstance(a, SetPalette):
        return k.palette is not None and a.palette == k.palette
    if k.shape is None:
        return False
    if isinstance(a, SetLevels):
        t, l, h, w = clip_rect(a.top, a.left, a.height, a.width, k.shape)
        return h == 0 or w == 0
    if isinstance(a, ResizeCanvas):
        return (a.height, a.width) == k.shape
    if isinstance(a, CropCanvas):
        return a.canvas_shape(k.shape) == k.shape
    return False


def _collapse_palettes(actions, known):
    """Of several SetPalette with only fills and canvas changes between, the last one counts."""
    keep = [True] * len(actions)
    for i, a in enumerate(actions):
        if isinstance(a, SetPalette):
            for b in actions[i + 1:]:
                if isinstance(b, SetPalette):
                    keep[i] = False
                if not isinstance(b, _PURE) or isinstance(b, SetPalette):
                    break
    return [a for a, k in zip(actions, keep) if k]


def _collapse_canvas(actions, known):
    """Two crops in a row are one crop; two resizes in a row with one fill are one resize
    when the first keeps every point the second keeps."""
    out: list[Action] = []
    k_out: list[Known] = []
    for a, k in zip(actions, known):
        prev = out[-1] if out else None
        merged = _merge(prev, k_out[-1], a) if prev is not None else None
        if merged is not None:
            out[-1] = merged
        else:
            out.append(a)
            k_out.append(k)
    return out


def _merge(first, k: Known, second):
    if k.shape is None:
        return None
    if isinstance(first, CropCanvas) and isinstance(second, CropCanvas):
        t1, l1, h1, w1 = clip_rect(first.top, first.left, first.height, first.width, k.shape)
        if not (h1 and w1):
            return None
        t2, l2, h2, w2 = clip_rect(second.top, second.left, second.height, second.width, (h1, w1))
        if not (h2 and w2):
            return None
        return CropCanvas(t1 + t2, l1 + l2, h2, w2)
    if (isinstance(first, ResizeCanvas) and isinstance(second, ResizeCanvas)
            and first.fill == second.fill):
        (h0, w0), h1, w1 = k.shape, first.height, first.width
        if h1 >= min(h0, second.height) and w1 >= min(w0, second.width):
            return second
    return None
