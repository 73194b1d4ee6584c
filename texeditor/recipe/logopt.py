"""Log optimisation (thesis §5.4.2, digest §10: the action list "simplifiée et réorganisée"): a
shorter action log that replays to the same texture, and notes that say what was done.

It sits between a History (or a `.texture` file) and storage: the bank, `texeditor log
--optimise` and the History dock's Optimise command keep the optimised recipe. Every rule here
keeps the levels and the palette identical. Besides dropping and merging steps, it reorders
steps that commute (`commute`) so that steps which merge become neighbours.
"""

from __future__ import annotations

from bisect import bisect_left
from dataclasses import dataclass

from .actions import (Action, CropCanvas, NewCanvas, ResizeCanvas, SetLevels, SetPalette,
                      Synthesize, clip_rect)
from .document import EMPTY_LEVELS
from ..errors import InputError
from ..markov.dpj import grey_ramp

LOOKAHEAD = 256                        # how far a covering SetLevels is looked for
REACH = 64                             # how far back a step looks for a step it merges with
_MERGING = (SetLevels, CropCanvas, ResizeCanvas)     # the types `_merge` merges, two of a kind


@dataclass(frozen=True)
class Known:
    """What the optimiser knows of the document before a step (None = unknown)."""

    shape: tuple[int, int] | None
    palette: tuple | None


@dataclass(frozen=True)
class Optimised:
    """An optimised log and, in the order they were done, what was done to get it."""

    actions: tuple[Action, ...]
    notes: tuple[str, ...]


@dataclass(frozen=True)
class _Step:
    """A step of the log being optimised and the steps of the original log it stands for."""

    action: Action
    origin: tuple[int, ...]            # 0-based indices in the log given to optimize()


def optimize(actions, dpjs: dict | None = None) -> list[Action]:
    """Drop no-ops, merge runs of the same change, drop what a later step overwrites, and bring
    together steps that merge once they are neighbours.

    ``dpjs`` (ref → DPJ) lets the optimiser know the palette a Synthesize sets. The result is
    never longer and replays to the same levels and palette (the current DPJ may differ).
    """
    return list(optimize_with_notes(actions, dpjs).actions)


def optimize_with_notes(actions, dpjs: dict | None = None) -> Optimised:
    """`optimize`, saying what it did: one note per step dropped, moved or merged, naming steps
    by their number (1 = first) in the log given."""
    steps = [_Step(a, (k,)) for k, a in enumerate(actions)]
    notes: list[str] = []
    while True:
        before = len(steps)
        for rules in (_DROPS, _MERGES):        # drops first: a merged fill is harder to cover
            steps = _until_stable(rules, steps, dpjs, notes)
        if len(steps) == before:
            return Optimised(tuple(s.action for s in steps), tuple(notes))


def _until_stable(rules, steps, dpjs, notes):
    while True:
        before = len(steps)
        for rule in rules:
            steps = rule(steps, trace([s.action for s in steps], dpjs), notes)
        if len(steps) == before:
            return steps


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


def commute(first: Action, second: Action, shape) -> bool:
    """True when ``first`` then ``second``, on a canvas of ``shape`` (None: unknown), leave the
    document as ``second`` then ``first`` do.

    Both must say what they read and write (`Action.access`), the same whichever runs first,
    and at most one may change the canvas's extent; then they commute when neither writes a
    point (or the palette) the other reads or writes. A step that cannot say never commutes.
    """
    a, b = first.access(shape), second.access(shape)
    if a is None or b is None or (first.EFFECT == second.EFFECT == "canvas"):
        return False
    if first.access(_after(second, shape)) != a or second.access(_after(first, shape)) != b:
        return False
    return not (_overlap(a.writes, b.writes + b.reads) or _overlap(a.reads, b.writes)
                or (a.writes_palette and (b.reads_palette or b.writes_palette))
                or (b.writes_palette and a.reads_palette))


def _after(action: Action, shape):
    if shape is None or action.EFFECT not in ("canvas", "reset"):
        return shape
    return action.canvas_shape(shape)


def _overlap(rects, others) -> bool:
    return any(t < T + H and T < t + h and l < L + W and L < l + w
               for t, l, h, w in rects for T, L, H, W in others)


def _palette_of(array) -> tuple:
    return tuple(tuple(int(c) for c in colour) for colour in array)


# -- notes -----------------------------------------------------------------------------------------

def _name(step: _Step) -> str:
    numbers = [str(k + 1) for k in sorted(step.origin)]
    if len(numbers) == 1:
        return f"step {numbers[0]}"
    return f"steps {', '.join(numbers[:-1])} and {numbers[-1]}"


def _described(step: _Step) -> str:
    return f"{_name(step)} ({step.action.label()})"


def _without(steps: list[_Step], drops: dict[int, str], notes: list[str]) -> list[_Step]:
    """The log without the steps in ``drops`` (index → why), noting each; a step a later step
    finds by its place in the log (`Action.refers_to`) stays."""
    actions = [s.action for s in steps]
    needed = {k for j, a in enumerate(actions) for k in a.refers_to(actions, j)}
    drops = {k: why for k, why in drops.items() if k not in needed}
    notes += [f"dropped {_described(steps[k])}: {why}" for k, why in sorted(drops.items())]
    return [s for k, s in enumerate(steps) if k not in drops]


# -- rules: each takes the log, its trace and the notes, and returns a log no longer than it ------

def _drop_before_reset(steps, known, notes):
    """A reset (NewCanvas, Synthesize) makes the known steps since the last barrier useless."""
    drops = {}
    for j, s in enumerate(steps):
        if s.action.EFFECT == "reset":
            i = j - 1
            while i >= 0 and steps[i].action.EFFECT != "other":
                drops.setdefault(i, f"{_described(s)} starts afresh")
                i -= 1
    return _without(steps, drops, notes)


def _drop_covered_by_full(steps, known, notes):
    """A level edit covering the whole canvas makes earlier level edits useless.

    Canvas and palette steps in between stay: they do not read the levels they would lose.
    """
    drops = {}
    for j, s in enumerate(steps):
        if s.action.EFFECT == "levels" and known[j].shape is not None \
                and s.action.covers(known[j].shape):
            i = j - 1
            while i >= 0 and steps[i].action.EFFECT in ("levels", "palette", "canvas"):
                if steps[i].action.EFFECT == "levels":
                    drops.setdefault(i, f"{_name(s)} overwrites every point")
                i -= 1
    return _without(steps, drops, notes)


def _drop_covered_rects(steps, known, notes):
    """A SetLevels whose points are all overwritten by later fills, or cut away by later canvas
    changes, goes. Its rectangle is followed through crops (which move it) and resizes."""
    actions = [s.action for s in steps]
    fills = [clip_rect(a.top, a.left, a.height, a.width, k.shape)
             if isinstance(a, SetLevels) and k.shape is not None else None
             for a, k in zip(actions, known)]
    drops = {}
    for i, rect in enumerate(fills):
        if rect is not None and _overwritten(rect, actions, known, fills, i + 1):
            drops[i] = "later fills or canvas changes overwrite or cut away all its points"
    return _without(steps, drops, notes)


def _overwritten(rect, actions, known, fills, start) -> bool:
    """``fills``: each SetLevels's rectangle clipped to the canvas before it."""
    for j in range(start, min(len(actions), start + LOOKAHEAD)):
        if rect[2] == 0 or rect[3] == 0:
            return True
        b, shape = actions[j], known[j].shape
        if isinstance(b, SetLevels):
            if _inside(rect, fills[j]):
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


def _drop_noops(steps, known, notes):
    """Steps that change nothing: an empty fill, a same-size resize, a whole-canvas crop,
    the palette already in place."""
    drops = {k: "it changes nothing here" for k, (s, kn) in enumerate(zip(steps, known))
             if _is_noop(s.action, kn)}
    return _without(steps, drops, notes)


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


def _collapse_palettes(steps, known, notes):
    """Of two SetPalette, the first goes when every step between commutes with it (none reads
    the palette): moved up to the second, it would be overwritten at once."""
    actions = [s.action for s in steps]
    drops = {}
    for i, a in enumerate(actions):
        if isinstance(a, SetPalette):
            shape = known[i].shape
            for j in range(i + 1, len(actions)):
                if isinstance(actions[j], SetPalette):
                    drops[i] = f"{_name(steps[j])} sets the palette again and nothing between " \
                               f"reads it"
                    break
                if not commute(a, actions[j], shape):
                    break
                shape = _after(actions[j], shape)
    return _without(steps, drops, notes)


def _bring_together(steps, known, notes):
    """The reorganised log: a step moves back next to an earlier step it merges with, across
    the steps it commutes with, or the earlier step moves forward across the steps between
    (§5.4.2 "réorganisée"). `_merge_neighbours` then merges them."""
    actions = [s.action for s in steps]
    seen: dict[type, list[int]] = {}
    out, settled = list(steps), 0      # steps before ``settled`` have not moved: known holds
    for j, a in enumerate(actions):
        if not isinstance(a, _MERGING):
            continue
        earlier = seen.setdefault(type(a), [])
        move = None if j < settled else _partner(actions, known, earlier, j, settled)
        earlier.append(j)
        if move is None:
            continue
        i, forward = move
        if forward:                    # i goes just before j
            out[i:j] = out[i + 1:j] + [steps[i]]
            notes.append(f"moved {_described(steps[i])} after {_name(steps[j - 1])} so it "
                         f"merges with {_name(steps[j])}")
        else:                          # j goes just after i
            out[i + 1:j + 1] = [steps[j]] + out[i + 1:j]
            notes.append(f"moved {_described(steps[j])} before {_name(steps[i + 1])} so it "
                         f"merges with {_name(steps[i])}")
        settled = j + 1
    return out


def _partner(actions, known, earlier, j, settled):
    """(i, forward) for the nearest earlier step i of the same type that step j merges with
    once they are neighbours, when j can move back to it (forward False) or i forward to j."""
    second = actions[j]
    if not earlier or _merge(actions[j - 1], known[j - 1], second) is not None:
        return None                    # it merges where it is
    for i in reversed(earlier[bisect_left(earlier, max(settled, j - REACH)):]):
        first = actions[i]
        if _merge(first, known[i], second) is None:
            continue
        if i and _merge(actions[i - 1], known[i - 1], first) is not None:
            return None                # i merges with its own neighbour first
        if all(commute(actions[k], second, known[k].shape) for k in range(i + 1, j)):
            return i, False
        shape = known[i].shape
        for k in range(i + 1, j):
            if not commute(first, actions[k], shape):
                return None
            shape = _after(actions[k], shape)
        return (i, True) if _merge(first, Known(shape, None), second) is not None else None
    return None


def _merge_neighbours(steps, known, notes):
    """Two crops in a row are one crop; two resizes in a row with one fill are one resize
    when the first keeps every point the second keeps; two fills of one level whose rectangles
    make a rectangle are one fill."""
    out: list[_Step] = []
    k_out: list[Known] = []
    for s, k in zip(steps, known):
        prev = out[-1] if out else None
        merged = _merge(prev.action, k_out[-1], s.action) if prev is not None else None
        if merged is not None:
            out[-1] = _Step(merged, prev.origin + s.origin)
            notes.append(f"merged {_described(prev)} and {_described(s)} into one step: "
                         f"{merged.label()}")
        else:
            out.append(s)
            k_out.append(k)
    return out


def _merge(first, k: Known, second):
    """The one step that does what ``first`` then ``second`` do (``k``: before first), or None."""
    if isinstance(first, SetLevels) and isinstance(second, SetLevels):
        return _merge_fills(first, second)
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


def _merge_fills(first: SetLevels, second: SetLevels):
    """One fill of the level both write when their rectangles together are one rectangle (side
    by side along a whole side, overlapping or touching, or one inside the other)."""
    if first.value != second.value:
        return None
    a = (first.top, first.left, first.height, first.width)
    b = (second.top, second.left, second.height, second.width)
    for inner, outer in ((a, b), (b, a)):
        if _inside(inner, outer):
            return SetLevels(*outer, first.value)
    (t, l, h, w), (T, L, H, W) = a, b
    if (t, h) == (T, H) and l <= L + W and L <= l + w:
        rect = (t, min(l, L), h, max(l + w, L + W) - min(l, L))
    elif (l, w) == (L, W) and t <= T + H and T <= t + h:
        rect = (min(t, T), l, max(t + h, T + H) - min(t, T), w)
    else:
        return None
    try:
        return SetLevels(*rect, first.value)
    except InputError:                  # wider than a fill may be: two fills stay
        return None


_DROPS = (_drop_before_reset, _drop_covered_by_full, _drop_covered_rects, _drop_noops,
          _collapse_palettes)
_MERGES = (_bring_together, _merge_neighbours)
