"""A field's level shares brought back to its DPJ's by moving the borders of its regions.

Drawn given coarser parents, the finest scale of a scene photo's model comes out with level
shares a few hundredths off its DPJ's, the same way seed after seed (chelsea: one level
+0.046 on average, page +0.20): the synthetic parents are not the photo's, and the rows'
exact law given them favours some levels. Drafts (markov.particles) choose among draws and
cannot remove such a bias. Here, once the field is drawn, points on the border of a level
with too large a share take the level of a neighbouring region with too small a share, most
plausible moves first, until every pair of neighbouring levels is within SLACK of its aim:

- a move keeps every window through the point a DPJ entry (no window leaves the DPJ, on the
  torus too), and takes a level that at least LEAST of its 8 neighbours have (a border grows
  by a point; no lone speckle);
- moves are tried in passes over the border points (in RUNS runs of points drawn at random,
  each run in row-major order), each pass accepting moves that lower the sum of the
  log-probabilities of the point's windows by at most THETAS[pass]; a moved point's
  neighbours join the next pass, so a region can grow by a few points' width.

On 16 photos at 512² (4 seeds each) it brought the worst share of 7 scene photos from 0.04–0.07
off to 0.010–0.023 (cell to 0.033, clock from 0.13 to 0.035); page, retina and logo stayed
0.11–0.20 off (their parents rule out the moves). It moves 2–15 % of the points; the GLCM and 3×3
window distances to the photo fell on 12 and 11 of the 12 photos it moved (bench_quality.py's
drift line measures the shares). When the parents rule the moves out, markov.multiscale moves
again on the finest windows' own law for FREE_PASSES passes (``passes``): small textures from
photos of a few large regions then come within 0.03 (benchmarks/bench_shares.py: 228 → 105 of
1280 draws beyond it); a level held by one or two large regions of the photo, absent from the
texture, has no border to grow from and stays off. Forced moves (``forced``, the last resort
markov.multiscale takes after those) close that gap: a window may then leave the DPJ at a cost,
and a level the field lacks starts from its most plausible point and grows round from it
(bench_shares.py: 105 → 0 of 1280 draws beyond 0.03; a photo drawn at 512² never needs them).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..errors import InputError
from .dpj import DPJ
from .synthesis import derived, uniform

TRIGGER = 0.025     # a field is rebalanced when a level's share is further off its aim than this
SLACK = 0.01        # ... until no two neighbouring levels are further apart than this, aim aside
LEAST = 2           # a point takes a level at least this many of its 8 neighbours have
# the log-probability a move may cost, pass by pass (the last passes let a region grow further)
THETAS = (-1.0, -3.0, -6.0, -12.0, -30.0, -30.0, -30.0)
FREE_PASSES = 64    # passes of moves free of the parents (markov.multiscale): a region may grow
                    # by tens of points, as a small field far off its shares needs
FORCED_PASSES = 254  # forced moves (the last resort, markov.multiscale): passes, the first
                     # len(THETAS) as above, the others taking a wanted move at any cost
FORCED_TRIGGER = 0.03  # ... made when a share is further off than this (as far as a texture's
FORCED_SLACK = 0.02    # may stray), until no two neighbouring levels are further apart than this
FORCED_LEAST = 1    # ... a point takes a level one neighbour has (a level the field lacks: from
                    # any point, its first one)
OFF_WINDOW = 10.0   # ... a window left outside the DPJ costs this far below the rarest entry
FORCED_TAKE = 4     # ... and a move is made in a pass with the chance of the point's neighbours
                    # of that level over this: a region grows round and smooth (as in Eden's
                    # model), not as a square nor ragged
MAX_PASSES = 254    # a point's pass is kept in a byte
RUNS = 16           # a pass tries the border points in this many runs (see _in_runs)
MAX_POINTS = 2**21  # a larger field keeps its shares: its moves would take about a second
                    # (chelsea: 0.03 s at 512², 0.15 s at 1024², 0.9 s at 2048²)
_EMPTY = -1


def rebalance(levels: np.ndarray, dpj: DPJ, aim, *, parents: np.ndarray | None = None,
              parent_levels: int = 1, seed: int = 0, wrap: bool = False,
              passes: int = len(THETAS), forced: bool = False) -> int:
    """Move border points of ``levels`` (H, W) uint8, in place, towards the shares ``aim``
    (one a level) without a window leaving ``dpj`` (composite levels parent · G + level when
    ``parents`` are given, as markov.multiscale draws them). ``wrap``: the field is a torus.
    ``passes``: the passes over the border points (THETAS, the last one repeated past them;
    at most 254). ``forced``: the last resort, made beyond FORCED_TRIGGER and until
    FORCED_SLACK (it leaves windows off the DPJ) — a window may leave the DPJ (costing
    OFF_WINDOW below its rarest entry), moves at any cost after the THETAS passes, a point
    takes a level FORCED_LEAST neighbours have, or any level the field lacks, and the border
    points are all tried again when a pass leaves none to try.
    Returns how many moves were made (a point may move twice; 0 when no share is off by more
    than TRIGGER, FORCED_TRIGGER when forced, or the field has more than MAX_POINTS points)."""
    aim = np.asarray(aim, float)
    g = len(aim)
    if dpj.levels != g * (parent_levels if parents is not None else 1):
        raise InputError(f"a DPJ of {dpj.levels} levels does not hold {g} levels"
                         + (f" over {parent_levels} parent levels" if parents is not None else ""))
    if isinstance(passes, bool) or not isinstance(passes, (int, np.integer)) \
            or not 1 <= passes <= MAX_PASSES:
        raise InputError(f"the passes of a rebalance are a whole number from 1 to {MAX_PASSES}, "
                         f"got {passes!r}")
    h, w = levels.shape
    target = np.round(aim * h * w).astype(np.int64)
    counts = np.bincount(levels.ravel(), minlength=g)[:g]
    trigger, slack = (FORCED_TRIGGER, FORCED_SLACK) if forced else (TRIGGER, SLACK)
    if np.abs(counts - target).max() <= trigger * h * w or h * w > MAX_POINTS:
        return 0
    composite = levels.astype(np.uint8, copy=True)
    if parents is not None:
        composite += parents.astype(np.uint8) * np.uint8(g)
    keys, table, bits = derived(dpj, "window log-probabilities", _window_table)
    state = np.random.SeedSequence([int(seed), 0xBA1]).generate_state(1, np.uint64)
    return int(_rebalance(composite, levels, g, dpj.window[0], dpj.window[1], dpj.levels, keys,
                          table, bits, target, counts.astype(np.int64), int(slack * h * w),
                          state, _thetas(int(passes), forced), FORCED_LEAST if forced else LEAST,
                          _off_window(dpj) if forced else -np.inf, bool(wrap)))


def _thetas(passes: int, forced: bool = False) -> np.ndarray:
    """The log-probability each of ``passes`` passes lets a move cost (THETAS, then its last;
    ``forced``: any cost in the last passes)."""
    thetas = np.array(THETAS[:passes] + THETAS[-1:] * max(0, passes - len(THETAS)))
    if forced:
        thetas[len(THETAS):] = -np.inf
    return thetas


def _off_window(dpj: DPJ) -> float:
    """What a window outside the DPJ costs a forced move: OFF_WINDOW below the rarest entry."""
    return float(np.log(dpj.probs[dpj.probs > 0].min())) - OFF_WINDOW


def _window_table(dpj: DPJ):
    """An open-addressing hash table: window code → log-probability (absent: not an entry)."""
    probs = dpj.probs
    live = probs > 0
    return _hash_table(dpj.codes[live].astype(np.int64), np.log(probs[live]))


_GOLDEN = np.uint64(0x9E3779B97F4A7C15)


@njit(cache=True, nogil=True)
def _hash_table(codes, values):
    bits = 1
    while (1 << bits) < 2 * len(codes):
        bits += 1
    keys = np.full(1 << bits, _EMPTY, np.int64)
    table = np.zeros(1 << bits)
    for i in range(len(codes)):
        slot = _slot(codes[i], bits)
        while keys[slot] != _EMPTY:
            slot = (slot + 1) & (len(keys) - 1)
        keys[slot], table[slot] = codes[i], values[i]
    return keys, table, bits


@njit(cache=True, nogil=True, inline="always")
def _slot(key, bits):
    """Fibonacci hashing: the top ``bits`` of key · 2^64/φ."""
    return np.int64((np.uint64(key) * _GOLDEN) >> np.uint64(64 - bits))


@njit(cache=True, nogil=True)
def _log_p(keys, table, bits, key):
    slot = _slot(key, bits)
    while True:
        k = keys[slot]
        if k == key:
            return table[slot]
        if k == _EMPTY:
            return -np.inf
        slot = (slot + 1) & (len(keys) - 1)


@njit(cache=True, nogil=True)
def _windows_through(comp, y, x, u, v, g, wrap, codes, powers):
    """The codes of the windows through point (y, x) (those inside the field, or all on a
    torus) and the weight of the point's digit in each; how many there are."""
    h, w = comp.shape
    n = 0
    for i in range(y - v + 1, y + 1):
        if not wrap and (i < 0 or i > h - v):
            continue
        for j in range(x - u + 1, x + 1):
            if not wrap and (j < 0 or j > w - u):
                continue
            key, weight = 0, 0
            for a in range(v):
                row = _on_torus(i + a, h)
                for b in range(u):
                    key = key * g + comp[row, _on_torus(j + b, w)]
                    weight = 1 if (a == y - i and b == x - j) else weight * g
            codes[n], powers[n] = key, weight
            n += 1
    return n


@njit(cache=True, nogil=True)
def _log_p_sum(keys, table, bits, codes, powers, n, change, off):
    """The sum of the windows' log-probabilities once the point's digit changes by
    ``change``, a window that is not a DPJ entry counted as ``off`` (-inf: the move is
    ruled out)."""
    total = 0.0
    for k in range(n):
        p = _log_p(keys, table, bits, codes[k] + change * powers[k])
        if p == -np.inf:
            if off == -np.inf:
                return p
            p = off
        total += p
    return total


@njit(cache=True, nogil=True, inline="always")
def _on_torus(i, n):
    """i mod n for -n <= i < 2n, without a division."""
    return i + n if i < 0 else i - n if i >= n else i


@njit(cache=True, nogil=True, inline="always")
def _wanted(counts, target, a, b, slack):
    """A point of level a should take level b: a is further above its aim than b, by SLACK."""
    return (counts[a] - target[a]) - (counts[b] - target[b]) > slack


@njit(cache=True, nogil=True)
def _neighbours(own, y, x, wrap, tally):
    """How many of point (y, x)'s 8 neighbours have each level."""
    h, w = own.shape
    for k in range(len(tally)):
        tally[k] = 0
    for dy in range(-1, 2):
        i = _on_torus(y + dy, h)
        if not wrap and i != y + dy:
            continue
        for dx in range(-1, 2):
            j = _on_torus(x + dx, w)
            if (dy != 0 or dx != 0) and (wrap or j == x + dx):
                tally[own[i, j]] += 1


@njit(cache=True, nogil=True)
def _borders(own, found):
    """Write the points with a neighbour of another level into ``found`` (row-major order);
    how many there are."""
    h, w = own.shape
    n = 0
    for y in range(h):
        for x in range(w):
            a, edge = own[y, x], False
            for i in (y - 1 if y > 0 else h - 1, y, y + 1 if y < h - 1 else 0):
                for j in (x - 1 if x > 0 else w - 1, x, x + 1 if x < w - 1 else 0):
                    edge |= own[i, j] != a
            if edge:
                found[n] = y * w + x
                n += 1
    return n


@njit(cache=True, nogil=True)
def _in_runs(items, n, state, out):
    """items[:n] (row-major) into ``out`` as RUNS runs, each point in a run drawn at random,
    each run in row-major order: wherever a pass stops, the points it tried are a random share
    of the field (no side favoured, but in the last run), and each run reads the field
    forwards (a 2048² field read in a random order costs twice as much a point)."""
    runs = np.empty(n, np.uint8)
    starts = np.zeros(RUNS + 1, np.int64)
    for i in range(n):
        runs[i] = min(RUNS - 1, np.int64(uniform(state) * RUNS))
        starts[runs[i] + 1] += 1
    for r in range(RUNS):
        starts[r + 1] += starts[r]
    for i in range(n):
        out[starts[runs[i]]] = items[i]
        starts[runs[i]] += 1


@njit(cache=True, nogil=True)
def _listed(listed, k, items):
    """The points listed for pass k + 1, row-major, into ``items``; how many."""
    n = 0
    for p in range(len(listed)):
        if listed[p] == k + 1:
            items[n] = p
            n += 1
    return n


@njit(cache=True, nogil=True)
def _best_move(comp, own, y, x, g, u, v, big_g, wrap, keys, table, bits, counts, target,
               slack, least, off, tally, codes, powers):
    """(level, log-probability change) of the most plausible wanted move of (y, x), or
    (-1, -inf)."""
    a = own[y, x]
    best, gain = -1, -np.inf
    if not _gives(counts, target, a, slack):
        return best, gain
    _neighbours(own, y, x, wrap, tally)
    n, before = -1, 0.0
    for b in range(g):
        if b == a or (tally[b] < least and (counts[b] > 0 or off == -np.inf)) \
                or not _wanted(counts, target, a, b, slack):
            continue
        if n < 0:
            n = _windows_through(comp, y, x, u, v, big_g, wrap, codes, powers)
            before = _log_p_sum(keys, table, bits, codes, powers, n, 0, off)
        after = _log_p_sum(keys, table, bits, codes, powers, n, b - a, off)
        if after - before > gain:
            best, gain = b, after - before
    return best, gain


@njit(cache=True, nogil=True)
def _rebalance(comp, own, g, u, v, big_g, keys, table, bits, target, counts, slack, state,
               thetas, least, off, wrap):
    h, w = own.shape
    forced = off != -np.inf
    listed = np.zeros(h * w, np.uint8)      # the pass (+1) a point is listed for
    todo = np.empty(h * w, np.int32)        # points as int32: h · w ≤ MAX_POINTS
    order = np.empty(h * w, np.int32)
    n = _borders(own, todo)
    tally = np.zeros(g, np.int64)
    codes, powers = np.empty(u * v, np.int64), np.empty(u * v, np.int64)
    moved = 0
    for k in range(len(thetas)):
        if not _any_wanted(counts, target, slack):
            break
        _in_runs(todo, n, state, order)
        for i in range(n):
            p = order[i]
            y, x = p // w, p % w
            b, gain = _best_move(comp, own, y, x, g, u, v, big_g, wrap, keys, table, bits,
                                 counts, target, slack, least, off, tally, codes, powers)
            if b < 0:
                continue                       # nothing wanted here now
            if gain < thetas[k] or (forced and uniform(state) * FORCED_TAKE >= max(tally[b], 1)):
                listed[p] = k + 1              # perhaps in a later pass
                continue
            counts[own[y, x]] -= 1
            counts[b] += 1
            comp[y, x] += b - own[y, x]
            own[y, x] = b
            moved += 1
            for dy in range(-1, 2):            # its neighbours may move next
                for dx in range(-1, 2):
                    listed[_on_torus(y + dy, h) * w + _on_torus(x + dx, w)] = k + 1
        n = _listed(listed, k, todo)
        if n == 0 and forced:                  # every border again: the shares have moved
            n = _borders(own, todo)
    return moved


@njit(cache=True, nogil=True)
def _any_wanted(counts, target, slack):
    for a in range(len(counts)):
        if _gives(counts, target, a, slack):
            return True
    return False


@njit(cache=True, nogil=True, inline="always")
def _gives(counts, target, a, slack):
    """Some level is wanted in place of a."""
    for b in range(len(counts)):
        if _wanted(counts, target, a, b, slack):
            return True
    return False
