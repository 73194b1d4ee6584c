"""Synthesis from a DPJ (thesis ch. 4, digest §6): the 2-D Markov process, top-down.

DPJ → normalised level matrix. The first v rows follow the horizontal chain of column states;
every later row is drawn exactly given the v-1 rows above it, by forward filtering and backward
sampling over the row. The numba kernels release the GIL, so a worker thread leaves a GUI live.

Dead ends (a window position that no configuration of the DPJ can continue, given the rows
above and the points already chosen to its left) never raise and never hang:
1. a segment of the rows above around the dead end is redrawn from its exact law given
   everything around it, and the row's forward pass resumes just before it — wider and deeper
   segments as tries fail, up to ``max_redraws`` tries; every window stays a DPJ entry, and
   the cost stays local, so time grows linearly with the number of points;
2. failing that, the position *backs off* to the DPJ marginal with one context row fewer, down
   to the plain horizontal chain of the bottom row (at worst a restart of it); each such
   position counts as one repair."""

from __future__ import annotations

import math
import threading
import weakref
from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np
from numba import njit

from . import particles, steering
from .dpj import DPJ, decode, encode
from ..errors import Cancelled, InputError

MAX_PIXELS = 2**28
NO_BUDGET = 2**62              # redraws: no limit
NO_ROW_LIMIT = 16.0            # redraws a point of a row: a dead end tries at most 16
                               # times, so a row never reaches it (no limit)
ROWS_PER_CALL_PIXELS = 2**16   # work per kernel call: how often progress and cancel are checked
FINAL_BANDS = 8                # with rows_final, at least this many calls (later work, such as a
                               # tone, starts on the first rows while the others are drawn)
DIRECT_INDEX_MAX = 2**20       # context spaces up to this size get a direct look-up table
MAX_REDRAW_DEPTH = 4           # rows above a dead end that may be redrawn together
CLOSE_TRIES = 8                # closure 2 of a seam: tries, redrawing the rows above, before it
                               # falls back on closure 1's widening and back-off
SPAN_TRIES = 4                 # ... and tries at one stretch before it doubles
CLOSE_SPAN = 4                 # closure 2: the shortest stretch redrawn, in windows
CLOSE_TRIES_3 = 2              # closure 3: as 2, but a scale drawn given its parents has this
                               # many tries (its tries, redrawing ever wider, cascade from
                               # column to column)
CLOSE_SPAN_4 = 1               # closure 4: as 3, the shortest stretch one window (a seam then
                               # redraws a quarter as many points per row and column; its
                               # windows still close: ≤ 0.03 % of a 3×3 photo DPJ's off it)
RING_LEAD = 2                  # closure 6: window positions either side of the side seam drawn
                               # first to choose a row's first points (4 and 8 gave the same
                               # seams within the spread of 12-24 seeds on six photos, and cost
                               # more: 8, about +0.1× a plain draw at 128²)
PULL_ROWS = 32                 # closure 7: the last rows of a torus weighed towards its first row
PULL_SHARE = 8                 # ... at most this share of its height (1/8: at 128², 16 rows)
PULL_POWER = 0.25              # ... each point by P^d(level, first row's level)^0.25 (see _pull)
PULL_POWER_8 = 1.0             # closure 8: by P^d itself, each column's own h-transform (its
                               # bottom seam is redrawn only where the pulled rows did not close
                               # it; 3×3 G=4, 256², 16 seeds: the seam band's TV from the inside
                               # was at 1 the lowest, or within 0.001 of it, of 0.35, 0.5, 0.7
                               # and 1 on seven photos)
PULL_POWER_GIVEN = 0.5         # ... and a scale drawn given its parents by its own chain given
                               # them, ^0.5 (_pull_given; photo models, 256², 32 seeds: 0.5 and 1
                               # alike but for cell, whose bottom seam 0.5 helped more)
NO_PULL = np.zeros((0, 1, 1))  # no row pulled
CLOSURE = 8                    # the seam closure tileable synthesis uses: 8 is 7 with the pull
                               # at its full strength (PULL_POWER_8) and the bottom seam redrawn
                               # only near the columns whose windows across it the DPJ lacks
                               # (_close_columns: a redraw of every column's last points, given
                               # the columns before it but not those after, left brick's last 5
                               # rows of windows 0.33-0.38 TV from the inside against 0.11-0.12
                               # for rows in the middle, 16 seeds; 0.18-0.20 now). 7 is 6 with
                               # the last rows pulled towards the first (_pull; a photo model's
                               # coarsest scale keeps 6: pulled, coffee's finest levels changed
                               # across the bottom seam 3.1× as often as inside, 2.0× unpulled,
                               # 8 seeds; its finer scales are pulled given their parents,
                               # _pull_given). 6 draws each row on its ring (_ring_start,
                               # _draw_row): the side seam's level changes are about as often as
                               # inside (3×3 G=4, 256², 12 seeds: cell 4.59 → 1.04×, brick 1.82
                               # → 0.93×) instead of gathering in a short bridge; the bottom seam
                               # is closed as 5 does. 5 is 4 but for the last column, which
                               # mends only windows across the bottom seam, no longer a row's
                               # failed side closure far up the column (a redraw of most of the
                               # column that seldom closed and cost up to a fifth of the plain
                               # draw); 1 to 7: earlier ways, kept so older recipes replay the
                               # same; 3 differs from 2 only in a scale drawn given its parents,
                               # markov.multiscale


@dataclass(frozen=True)
class SynthesisResult:
    levels: np.ndarray    # (H, W) uint8
    repairs: int          # window positions drawn from a backed-off (smaller) context
    redraws: int          # rows redrawn to get past a dead end
    seed: int
    moved: int = 0        # moves of points bringing the level shares back (markov.balance)


def synthesize(dpj: DPJ, shape: tuple[int, int], *, seed: int = 0,
               progress: Callable[[float], None] | None = None,
               cancel: Callable[[], bool] | None = None, max_redraws: int = 16,
               rows_final: Callable[[np.ndarray, int], None] | None = None,
               tileable: bool = False, closure: int = CLOSURE,
               redraw_budget: int | None = None, repair_budget: int | None = None,
               shares: particles.Shares | None = None, steer=None,
               row_redraws: float | None = None) -> SynthesisResult:
    """Draw an (H, W) level matrix from ``dpj``; same DPJ and seed → same matrix.

    ``progress(fraction)`` is called between bands of rows; ``cancel()`` returning True stops the
    work with :class:`Cancelled`. ``shape`` is (height, width). ``rows_final(levels, n)``, called
    between bands too, says that rows 0..n-1 of ``levels`` will not change any more (a dead end
    may redraw up to MAX_REDRAW_DEPTH rows above it), so later work can start on them.

    ``tileable``: drawn on the torus, so the texture repeats without a seam: each row's last
    points are redrawn from their law given its first ones, then each column's last points
    given its first ones (the same with the DPJ transposed); nothing is blended. Its rows are
    final only once the columns are closed, which may change any row: ``rows_final`` is told
    of the rows as the rows' pass leaves them, and its last call (n = H) gives the closed
    torus, to be compared with what it was told before. ``closure``
    picks the seam closure: 8 (the current one: as 7 at the pull's full strength, and the
    bottom seam redrawn only in the columns whose windows across it the DPJ lacks), 7 (as 6,
    the last rows weighed towards the first row's levels, _pull), 6 (each row drawn on its
    ring, its first points chosen given both sides of the seam, then the rest given them at
    both ends; the bottom seam as 5), 5 (each
    row's end redrawn over a stretch from one window), 4 (as 5, but its last column also
    redraws from any window across the side seam a row's closure left outside the DPJ), 2 (as
    4 over longer stretches; 3 is the same here, see synthesize_given) or 1 (the first, which left a
    few windows across the seams outside the DPJ); older ones are kept so older recipes
    replay the same.

    ``redraw_budget``: give up once the rows have been redrawn more often than this (the
    result then has ``redraws`` above it and is not a texture): a quick "will it close?";
    ``repair_budget`` the same for the positions that backed off (``repairs``).

    ``shares``: the field is drawn given its level shares (markov.particles: several drafts
    side by side, those off course dropped between bands of rows; not with ``rows_final`` or
    a budget).

    ``steer``: level shares the rows are steered towards as they are drawn (markov.steering:
    the law tilted band by band; not with ``shares``).

    ``row_redraws``: a row redraws the rows above at most this many times per point of its
    width (then every further dead end of the row backs off at once); None: no limit.
    """
    h, w = _check_request(dpj, shape)
    out = np.zeros((h, w), dtype=np.uint8)
    across = _tables(_transposed(dpj)) if tileable else None
    closure = check_closure(closure)
    return _draw(out, _tables(dpj), seed, progress, cancel,
                 (max_redraws, _row_cap(row_redraws, w)), rows_final, across,
                 closure, (redraw_budget, repair_budget), shares, steer,
                 pull=_pull(dpj, h, closure) if tileable and closure >= 7 else NO_PULL)


def _row_cap(row_redraws, width: int) -> int:
    """The redraws a row of ``width`` points may make (synthesize's ``row_redraws``)."""
    if row_redraws is None:
        return NO_BUDGET
    return int(math.ceil(check_row_redraws(row_redraws) * width))


def check_row_redraws(row_redraws) -> float:
    """A number of redraws a point of a row, 0 to NO_ROW_LIMIT."""
    if isinstance(row_redraws, bool) or not isinstance(row_redraws, (int, float, np.integer,
                                                                     np.floating)) \
            or not 0 <= row_redraws <= NO_ROW_LIMIT:
        raise InputError(f"{row_redraws!r} redraws a point of a row: choose 0 to "
                         f"{NO_ROW_LIMIT:g}")
    return float(row_redraws)


def synthesize_given(dpj: DPJ, parents: np.ndarray, parent_levels: int, *, seed: int = 0,
                     progress: Callable[[float], None] | None = None,
                     cancel: Callable[[], bool] | None = None,
                     max_redraws: int = 16,
                     rows_final: Callable[[np.ndarray, int], None] | None = None,
                     tileable: bool = False, closure: int = CLOSURE,
                     shares: particles.Shares | None = None, steer=None) -> SynthesisResult:
    """Draw a level matrix given a parent level at every point (a finer scale given the coarser
    one under it, markov.multiscale): ``dpj``'s levels are composite, parent · G + level, with
    G = dpj.levels // parent_levels. Row by row and exactly given the rows above and the
    parents, as :func:`synthesize`; the result holds the G-levels alone (so do the rows
    ``rows_final`` is told of). ``tileable``: on the torus, the parents tiling too
    (``closure`` 3 to 8: as 2 with CLOSE_TRIES_3 tries a seam, what multi-scale synthesis
    uses; 4 and 5 over stretches from CLOSE_SPAN_4 windows; 6 each row on its ring; 7 the
    last rows weighed towards the first by the chain given their parents, _pull_given; 8 as 7,
    the bottom seam redrawn only where its windows leave the DPJ);
    ``shares``: the own levels' shares
    it is drawn given; ``steer``: the own levels' shares it is steered towards, given these
    parents (see synthesize)."""
    gp = int(parent_levels)
    if gp < 2 or dpj.levels % gp:
        raise InputError(f"a DPJ of {dpj.levels} composite levels cannot have {gp} parent levels")
    closure = check_closure(closure)
    parents = np.asarray(parents)
    if parents.ndim != 2 or parents.dtype.kind not in "ui" or parents.size == 0:
        raise InputError("the parents must be a non-empty 2-D matrix of levels")
    if parents.max() >= gp:
        raise InputError(f"the parents hold a level above {gp - 1}")
    h, w = _check_request(dpj, parents.shape)
    gx = dpj.levels // gp
    out = (parents.astype(np.uint8) * np.uint8(gx))
    across = _tables(_transposed(dpj), gp) if tileable else None
    result = _draw(out, _tables(dpj, gp), seed, progress, cancel, (max_redraws, NO_BUDGET),
                   rows_final and _own_levels(out, gx, rows_final, tileable), across, closure,
                   (None, None), shares, steer, parents,
                   pull=_pull_given(dpj, gp, h) if tileable and closure >= 7 else NO_PULL)
    np.remainder(result.levels, gx, out=result.levels)
    return result


def _own_levels(out, gx, rows_final, tileable):
    """A rows_final callback that passes on the G-levels of the composite rows (all of them
    at the end of a torus: its closure may change any)."""
    levels, done = np.empty_like(out), [0]     # out: the shape

    def report(composite, n):
        first = 0 if tileable and n == len(out) else done[0]
        np.remainder(composite[first:n], gx, out=levels[first:n])
        done[0] = max(done[0], n)
        rows_final(levels, n)
    return report


def _draw(out, t, seed, progress, cancel, redraws_at, rows_final=None,
          across=None, closure=CLOSURE, budget=(None, None), shares=None, steer=None,
          parents=None, pull=NO_PULL) -> SynthesisResult:
    """Fill ``out`` band by band (progress, cancel and the rows now final between bands;
    ``redraws_at``: (tries at a dead end, redraws a row may make); ``steer``: the level shares
    the bands are steered towards, given ``parents``; ``pull``: see _pull, _pull_given).

    Tileable (``across``: the tables of the DPJ transposed): drawn on the torus — in a copy of
    ``out`` whose first v-1 rows and u-1 columns are repeated after its last, so every window
    across a seam is an ordinary window; the rows are final only once the columns are closed
    (``rows_final`` hears of them before, see synthesize)."""
    h, w = out.shape
    tileable = across is not None
    state = np.random.SeedSequence(check_seed(seed)).generate_state(1, np.uint64)
    work = _torus(out, t.v - 1, t.u - 1) if tileable else out
    tile_h, tile_w = (np.int64(h), np.int64(w)) if tileable else (np.int64(0), np.int64(0))
    if shares is not None:
        if rows_final is not None or budget != (None, None) or steer is not None:
            raise InputError("a synthesis given its level shares has no rows_final, budget or "
                             "steering")
        work, repairs, redraws = _draw_given_shares(work, (h, w), t, seed, progress, cancel,
                                                    redraws_at, tile_h, tile_w, closure, shares,
                                                    pull)
        if not tileable:
            out[:] = work
    else:
        steered = None if steer is None else steering.steering(t, _check_shares(steer, t.gx),
                                                               parents)
        work, repairs, redraws = _draw_bands(out, work, t, state, progress, cancel, redraws_at,
                                             rows_final, tile_h, tile_w, closure, budget,
                                             steered, pull)
        if past_budget(budget, redraws, repairs):
            return SynthesisResult(out, int(repairs), int(redraws), int(seed))
    if tileable:
        turned = np.ascontiguousarray(work.T)
        repairs += _close_columns(turned, across, state, tile_w, tile_h, np.int64(closure))
        out[:] = turned.T[:h, :w]
        if rows_final is not None:
            rows_final(out, h)
    return SynthesisResult(out, int(repairs), int(redraws), int(seed))


def _torus(out: np.ndarray, rows: int, columns: int) -> np.ndarray:
    """``out`` with its first ``rows`` rows and ``columns`` columns repeated after its last:
    np.pad's wrap, ~20 µs sooner (a few per cent of a small torus's seams)."""
    h, w = out.shape
    if rows > h or columns > w:
        return np.pad(out, ((0, rows), (0, columns)), mode="wrap")
    work = np.empty((h + rows, w + columns), out.dtype)
    work[:h, :w] = out
    work[:h, w:] = out[:, :columns]
    work[h:] = work[:rows]
    return work


def _draw_given_shares(work, shape, t, seed, progress, cancel, redraws_at, tile_h, tile_w,
                       closure, shares, pull):
    """The rows of ``work`` drafted given ``shares`` (markov.particles): the draft chosen, what
    it cost."""
    def extend(draft, r0, r1):
        return _sample_rows(draft.rows, r0, r1, t, draft.state, *redraws_at, tile_h, tile_w,
                            np.int64(closure), np.int64(NO_BUDGET), np.int64(NO_BUDGET), pull)
    chosen = particles.draw(work, shape, t.v, t.levels, t.gx, extend, shares, check_seed(seed),
                            MAX_REDRAW_DEPTH, cancel, progress)
    return chosen.rows, chosen.repairs, chosen.redraws


def _draw_bands(out, work, t, state, progress, cancel, redraws_at, rows_final, tile_h, tile_w,
                closure, budget, steered, pull):
    """The rows of ``work`` drawn band by band; stops once past ``budget`` (redraws,
    repairs; None: no limit). ``steered``: a markov.steering.Steering or None; the rows are
    then drawn in shorter bands (steering.band_rows), each after the first from the law it
    tilts, and each moving it. ``pull``: see _pull, _pull_given (NO_PULL: none)."""
    h, w = out.shape
    tileable = tile_h > 0
    bands = 1 if rows_final is None else FINAL_BANDS
    band = max(t.v, min(ROWS_PER_CALL_PIXELS // w, -(-h // bands)))   # rows_final's
    step = band if steered is None else max(t.v, steering.band_rows(w))    # the same bands
    #                                                                    with rows_final or not
    repairs = redraws = 0
    law, told = t, band
    for r0 in range(0, h, step):
        r1 = min(h, r0 + step)
        if cancel is not None and cancel():
            raise Cancelled("synthesis cancelled")
        if steered is not None and r0 > 0:
            law = t.weighed(steered.tilted(t.fent))
        rep, red = _sample_rows(work, r0, r1, law, state, *redraws_at, tile_h, tile_w,
                                np.int64(closure), _left(budget[0], redraws),
                                _left(budget[1], repairs), pull)
        if steered is not None:
            steered.update(work[r0:r1, :w])
        repairs += rep
        redraws += red
        if past_budget(budget, redraws, repairs):
            break
        if progress is not None:
            progress(r1 / h)
        if rows_final is None or (r1 < told and r1 < h):
            continue
        told = r1 + band
        if r1 < h:
            rows_final(work[:h, :w] if tileable else out, max(0, r1 - MAX_REDRAW_DEPTH))
        elif not tileable:
            rows_final(out, h)
    return work, repairs, redraws


def _check_shares(shares, g: int) -> np.ndarray:
    shares = np.asarray(shares, float)
    if shares.shape != (g,) or not np.all(np.isfinite(shares)) or np.any(shares < 0) \
            or not np.isclose(shares.sum(), 1.0):
        raise InputError(f"level shares to steer towards: {g} non-negative numbers adding up to 1")
    return shares


def _left(budget, used) -> np.int64:
    return np.int64(NO_BUDGET if budget is None else budget - used)


def past_budget(budget, redraws, repairs) -> bool:
    """Past the (redraws, repairs) budget, either of which may be None (no limit)."""
    return any(b is not None and x > b for b, x in zip(budget, (redraws, repairs)))


_derived: dict[tuple[int, str], tuple[weakref.ref, object]] = {}


def derived(dpj: DPJ, name: str, make: Callable[[DPJ], object]):
    """``make(dpj)``, made once and kept while ``dpj`` lives (a DPJ is immutable): a DPJ made
    from it keeps its identity, so the tables built for it are kept too (_tables)."""
    key = (id(dpj), name)
    with _cache_lock:
        hit = _derived.get(key)
        if hit is not None and hit[0]() is dpj:
            return hit[1]
        for k in [k for k, (ref, _) in _derived.items() if ref() is None]:
            del _derived[k]
    made = make(dpj)
    with _cache_lock:
        _derived[key] = (weakref.ref(dpj), made)
    return made


def _transposed(dpj: DPJ) -> DPJ:
    """The DPJ of the texture turned a quarter (windows transposed): closing the bottom seam
    is closing the side seam of the turned texture."""
    return derived(dpj, "transposed", lambda d: DPJ(
        np.ascontiguousarray(d.configs.transpose(0, 2, 1)), d.probs, d.levels))


def _pull(dpj: DPJ, height: int, closure: int = 7) -> np.ndarray:
    """Closure 7: the factors the last rows of a torus of ``height`` rows are weighed by, a row
    d + 1 rows above its first row: (d, level, first row's level) → P^(d+1)(level, that
    level) ** PULL_POWER, P the DPJ's vertical level chain (the left column of its windows, a
    level to the one under it). It is what a column alone would weigh by to end where the
    first row begins (at the power 1, a Doob h-transform); its columns are not alone, hence
    the power, and the rows are weighed only where the chain has not yet forgotten the first
    row (PULL_ROWS). Closure 8 weighs at the power 1 (PULL_POWER_8): its bottom seam is
    redrawn only where the pulled rows did not close it. Closure 5
    closed the bottom seam by the columns' law over one window alone, and the rows drawn apart
    met there: brick 3×3, 256², 12 seeds, 3.6 times as many level changes across it as inside,
    2.8 with the pull; coffee 2.4 → 1.3, cell 5.4 → 2.4, camera 2.6 → 1.5."""
    rows = min(PULL_ROWS, height // PULL_SHARE)
    if dpj.window[1] < 2 or rows == 0:
        return NO_PULL
    if closure >= 8:
        return derived(dpj, "pull 8", lambda d: _pull_factors(d, PULL_POWER_8))[:rows]
    return derived(dpj, "pull", lambda d: _pull_factors(d, PULL_POWER))[:rows]


def _pull_factors(dpj: DPJ, power: float) -> np.ndarray:
    u, v = dpj.window
    g = dpj.levels
    windows = decode(dpj.codes, g, v, u)
    chain = np.zeros((g, g))
    np.add.at(chain, (windows[:, 0, 0], windows[:, 1, 0]), dpj.probs)
    chain /= np.maximum(chain.sum(axis=1, keepdims=True), 1e-300)
    factors, chain_d = np.empty((PULL_ROWS, g, g)), np.eye(g)
    for d in range(PULL_ROWS):
        chain_d = chain_d @ chain
        factors[d] = np.maximum(chain_d, 1e-3) ** power
    return factors


def _pull_given(dpj: DPJ, gp: int, height: int) -> np.ndarray:
    """Closure 7 of a scale drawn given its parents: the law of its own levels down a column
    given the parents of both points, (parent · gp + parent under it, level, level under it)
    → P (the left column of its windows). A column's parents are known before it is drawn, so
    its last rows are weighed by what this chain says of reaching the first row's level
    through them (_pull_along); a chain of the levels alone would pull against the parents."""
    if dpj.window[1] < 2 or height // PULL_SHARE == 0:
        return NO_PULL
    return derived(dpj, "pull given", lambda d: _chain_given(d, gp))


def _chain_given(dpj: DPJ, gp: int) -> np.ndarray:
    u, v = dpj.window
    gx = dpj.levels // gp
    windows = decode(dpj.codes, dpj.levels, v, u).astype(np.int64)
    above, under = windows[:, 0, 0], windows[:, 1, 0]
    chain = np.zeros((gp * gp, gx, gx))
    np.add.at(chain, (above // gx * gp + under // gx, above % gx, under % gx), dpj.probs)
    total = chain.sum(axis=2, keepdims=True)     # parents never seen together: no preference
    return np.where(total > 0, chain / np.maximum(total, 1e-300), 1.0 / gx)


def check_closure(closure) -> int:
    if closure not in range(1, CLOSURE + 1) or isinstance(closure, bool):
        raise InputError(f"seam closure {closure!r} does not exist: choose 1 to {CLOSURE}")
    return int(closure)


MAX_SEED = 2**63 - 1        # a recipe stores a seed as a 63-bit integer: a larger one would
                            # draw a texture no .texture could replay


def check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) \
            or not 0 <= seed <= MAX_SEED:
        raise InputError(f"the seed must be an integer 0..2^63 - 1, got {seed!r:.40}")
    return int(seed)


def check_size(shape) -> tuple[int, int]:
    """(height, width) as two positive integers whose product is at most MAX_PIXELS."""
    try:
        h, w = shape
        if any(isinstance(x, bool) or int(x) != x for x in (h, w)):
            raise TypeError
        h, w = int(h), int(w)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"size must be (height, width), two integers, got {shape!r}") from None
    if h < 1 or w < 1:
        raise InputError(f"a {w}x{h} texture has no points: choose a size of at least 1x1")
    if h * w > MAX_PIXELS:
        raise InputError(f"{w}x{h} is more than {MAX_PIXELS} points: choose a smaller size")
    return h, w


def _check_request(dpj: DPJ, shape) -> tuple[int, int]:
    if not isinstance(dpj, DPJ):
        raise InputError("synthesis needs a DPJ")
    h, w = check_size(shape)
    u, v = dpj.window
    if h < v or w < u:
        raise InputError(f"a {w}x{h} texture is smaller than the DPJ's {u}x{v} window")
    p = dpj.probs
    if len(dpj) == 0 or not np.all(np.isfinite(p)) or np.any(p < 0) or p.sum() <= 0:
        raise InputError("the DPJ has no usable probabilities (empty, negative, NaN or zero sum)")
    return h, w


# -- tables: the DPJ rearranged for the kernels ------------------------------------------------

class _Tables(NamedTuple):
    """The DPJ and its back-off marginals, flattened into a few arrays for numba.

    The entries of every back-off level k (the DPJ marginal over its bottom v-k rows) are
    concatenated, grouped by context (the rows above the bottom row), and within a context by
    their last u-1 points, so backward sampling reads one contiguous block.
    """
    levels: int                # G of the stored configurations (composite: G·Gp with parents)
    u: int
    v: int
    gx: int                    # the levels drawn (G); the bottom-row codes are in base gx
    gp: int                    # parent levels Gp (1: no parent), part of every context key
    amod: int                  # rows above enter a context modulo this (gx: without parents)
    ient: np.ndarray           # (5, entries) int64: HEAD, TAIL, BCODE, ROT, LAST of each entry
    fent: np.ndarray           # (2, entries) float64: Q (probability), M (horizontal transition)
    ctx: np.ndarray            # (3, contexts) int64: CODE (sorted per level), START, END entries
    lvl: np.ndarray            # (2, v) int64: OFF and LEN of each level's contexts in ctx
    direct: np.ndarray         # level-0 context code → index in ctx (-1: unseen), when small
    first_q: np.ndarray        # the full model's q, its cumulative sum and configurations:
    first_cum: np.ndarray      # the first v rows are its horizontal chain
    first_configs: np.ndarray
    pfx: np.ndarray            # (3, states) int64: CODE of the first u-1 columns, START, END
    pfx_entry: np.ndarray      # full-model entries grouped by their first u-1 columns

    def weighed(self, fent: np.ndarray) -> "_Tables":
        """These tables with other entry weights (a tilted law: markov.steering)."""
        return self._replace(fent=fent)


# rows of the packed tables
HEAD, TAIL, BCODE, ROT, LAST = 0, 1, 2, 3, 4
Q, M = 0, 1
CODE, START, END = 0, 1, 2
OFF, LEN = 0, 1
LO, HI, TOFF = 0, 1, 2  # rows of the per-position work array: entries weighed, where T starts


# DPJ id → (weakref, tables, bytes), the latest last. The latest DPJ's tables are always kept;
# older ones only within TABLES_MEMORY (a document with many large DPJs would keep 0.6 GB each).
_cache: dict[int, tuple[weakref.ref, _Tables, int]] = {}
_cache_lock = threading.Lock()       # workers and the GUI thread synthesise at once
TABLES_MEMORY = 256 * 2**20


def _tables(dpj: DPJ, gp: int = 1) -> _Tables:
    """Build (or reuse) the kernel tables of a DPJ; DPJs are immutable so id + weakref is safe.
    ``gp``: the parent levels of a conditional DPJ (see :func:`synthesize_given`)."""
    with _cache_lock:
        hit = _cache.pop(id(dpj), None)
        if hit is not None and hit[0]() is dpj and hit[1].gp == gp:
            _cache[id(dpj)] = hit
            return hit[1]
        for key in [k for k, (ref, _, _) in _cache.items() if ref() is None]:
            del _cache[key]
        _evict(TABLES_MEMORY)     # before building: old tables need not stay during the build
    positive = dpj.probs > 0
    model = DPJ(dpj.configs[positive], dpj.probs[positive], dpj.levels).normalized()
    if gp > 1:
        tables = _build_tables(_above_without_parents(model, gp), gp, dpj.levels // gp)
    else:
        tables = _build_tables(model, gp)
    size = sum(a.nbytes for a in tables if isinstance(a, np.ndarray))
    with _cache_lock:
        _cache[id(dpj)] = (weakref.ref(dpj), tables, size)
        _evict(TABLES_MEMORY, keep=1)
    return tables


def build_tables(dpj: DPJ, parent_levels: int = 1, tileable: bool = False) -> None:
    """Build a DPJ's kernel tables now (those of its transpose too, ``tileable``), so a later
    synthesis from it finds them: a caller can build them on another thread ahead of time."""
    _tables(dpj, parent_levels)
    if tileable:
        _tables(_transposed(dpj), parent_levels)


def _evict(budget: int, keep: int = 0) -> None:
    """Forget the oldest tables until those left take ≤ budget bytes (the newest ``keep``
    stay whatever their size)."""
    while len(_cache) > keep and sum(size for _, _, size in _cache.values()) > budget:
        del _cache[next(iter(_cache))]


def _build_tables(dpj: DPJ, gp: int = 1, amod: int = 256) -> _Tables:
    """``gp`` > 1: the DPJ's levels are composite, parent · G + level (see markov.multiscale);
    a context is then the rows above and the parents of the bottom row, and an entry's bottom
    code holds its G-levels only (its parents are fixed by the context)."""
    u, v = dpj.window
    g = dpj.levels
    gx = g // gp
    gu = g ** u
    bcode, rot, q, m, ctx, start, end, off, length = [], [], [], [], [], [], [], [], []
    base = 0
    for k in range(v):  # level k: the DPJ marginal over its bottom v-k rows
        model = dpj if k == 0 else dpj.marginal(rows=slice(k, v))
        ctx_k, b_k = np.divmod(model.codes, gu)
        if gp > 1:
            ctx_k, b_k = _split_parents(ctx_k, b_k, g, gx, gp, u)
        # within a context, group entries by their last u-1 points: backward sampling
        # then reads one contiguous block instead of filtering the whole context
        probs, trans = model.probs, _transitions(model)
        if gp > 1 and k == v - 1:
            ctx_k, b_k, probs, trans = _every_parent_row(ctx_k, b_k, probs, trans, gx, gp, u)
        order = np.lexsort((_rotated(b_k, gx, u), ctx_k))
        ctx_k, b_k = ctx_k[order], b_k[order]
        bcode.append(b_k)
        rot.append(_rotated(b_k, gx, u))
        q.append(probs[order])
        m.append(trans[order])
        uctx, first = np.unique(ctx_k, return_index=True)
        ctx.append(uctx)
        start.append(first + base)
        end.append(np.append(first[1:], len(ctx_k)) + base)
        off.append(sum(len(c) for c in ctx[:-1]))
        length.append(len(uctx))
        base += len(ctx_k)
    pfx = encode(np.ascontiguousarray(dpj.configs[:, :, : u - 1]), g) if u > 1 else np.zeros(len(dpj), np.int64)
    order = np.argsort(pfx, kind="stable")
    upfx, pfirst = np.unique(pfx[order], return_index=True)
    cat = np.concatenate
    bcode = cat(bcode)
    ient = np.stack([bcode // gx, bcode % gx ** (u - 1), bcode, cat(rot), bcode % gx])
    ctx_table = np.stack([cat(ctx), cat(start), cat(end)]).astype(np.int64)
    return _Tables(
        levels=g, u=u, v=v, gx=gx, gp=gp, amod=amod, ient=ient, fent=np.stack([cat(q), cat(m)]),
        ctx=ctx_table, lvl=np.array([off, length], np.int64),
        direct=_direct_index(ctx[0], g ** (u * (v - 1)) * gp ** u),
        first_q=dpj.probs, first_cum=np.cumsum(dpj.probs), first_configs=dpj.configs,
        pfx=np.stack([upfx, pfirst, np.append(pfirst[1:], len(pfx))]).astype(np.int64),
        pfx_entry=order.astype(np.int64))


def _above_without_parents(dpj: DPJ, gp: int) -> DPJ:
    """A conditional DPJ summed over the parents of its rows above: a row is drawn given the
    levels above it and its own parents (the rows above were drawn given theirs)."""
    gx = dpj.levels // gp
    configs = dpj.configs.copy()
    configs[:, :-1, :] %= gx
    codes, inverse = np.unique(encode(configs, dpj.levels), return_inverse=True)
    probs = np.bincount(inverse.ravel(), weights=dpj.probs, minlength=len(codes))
    return DPJ.from_codes(codes, probs, dpj.levels, dpj.window)


def _split_parents(above, bottom, g, gx, gp, u):
    """Composite bottom-row codes → (context: rows above then the bottom row's parents,
    bottom code of the G-levels alone)."""
    pcode = np.zeros_like(bottom)
    xcode = np.zeros_like(bottom)
    for j in range(u - 1, -1, -1):
        bottom, digit = np.divmod(bottom, g)
        pcode += (digit // gx) * gp ** (u - 1 - j)
        xcode += (digit % gx) * gx ** (u - 1 - j)
    return above * gp ** u + pcode, xcode


def _every_parent_row(ctx, b, probs, trans, gx, gp, u):
    """The bottom-row marginal gets a context for every parent row the photo never showed (its
    law: the levels' own, whatever the parents), so a restart always finds entries."""
    missing = np.setdiff1d(np.arange(gp ** u), ctx)
    if not len(missing):
        return ctx, b, probs, trans
    xs, inverse = np.unique(b, return_inverse=True)
    q = np.bincount(inverse, weights=probs, minlength=len(xs))
    q = q / q.sum()
    heads, hinv = np.unique(xs // gx, return_inverse=True)     # m: q over its first u-1 points
    m = q / np.bincount(hinv, weights=q, minlength=len(heads))[hinv]
    n = len(missing)
    return (np.concatenate([ctx, np.repeat(missing, len(xs))]),
            np.concatenate([b, np.tile(xs, n)]),
            np.concatenate([probs, np.tile(q, n)]),
            np.concatenate([trans, np.tile(m, n)]))


def _direct_index(contexts: np.ndarray, space: int) -> np.ndarray:
    """A look-up table from every possible context code, when they are few (no binary search
    in the hot loop); empty otherwise."""
    if space > DIRECT_INDEX_MAX:
        return np.zeros(0, np.int64)
    table = np.full(space, -1, np.int64)
    table[contexts] = np.arange(len(contexts))
    return table


def _rotated(bcode: np.ndarray, g: int, u: int) -> np.ndarray:
    """Bottom-row code with its first point moved last: (b_1..b_{u-1}, b_0)."""
    head, tail = np.divmod(bcode, g ** (u - 1))
    return tail * g + head


def _transitions(model: DPJ) -> np.ndarray:
    """m(c_1..c_{u-1} → c_u) = q / μ(c_1..c_{u-1}) for every entry of the model."""
    u = model.window[0]
    if u == 1:
        return model.probs / model.probs.sum()
    left = encode(np.ascontiguousarray(model.configs[:, :, :-1]), model.levels)
    states, inverse = np.unique(left, return_inverse=True)
    mu = np.bincount(inverse.ravel(), weights=model.probs, minlength=len(states))
    return model.probs / mu[inverse.ravel()]


# -- kernels --------------------------------------------------------------------------------
# In a row, T_n (the forward filter at window position n) is kept unnormalised in the T buffer
# tb, one block per position; R (T_n summed over its first point, indexed by the code of its
# last u-1 points) is normalised, which keeps the numbers in range along a row of any width.
# Per-position functions take plain arrays, not the _Tables tuple: reading a tuple's field costs
# a reference-count update each time, which would dominate the inner loops.
# Compile time (a first start waits for it): numba compiles a function, and all it calls, once
# more for each literal constant passed to it, so integer arguments are np.int64 except the row
# pass's column bounds (0, folded into the hottest loop); arrays are copied with plain loops, as
# slice assignment compiles numba's broadcasting checks. Both cut the first compile from ~40 s to
# ~20 s on a 2-core machine; the results are unchanged.

@njit(cache=True, nogil=True, inline="always")
def uniform(state):
    """SplitMix64: a tiny, explicit, machine-independent generator (state is one uint64)."""
    state[0] += np.uint64(0x9E3779B97F4A7C15)
    z = state[0]
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return np.float64(z >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@njit(cache=True, nogil=True)
def _lower_bound(codes, a, b, key):
    """First index in the sorted codes[a:b] whose code is >= key."""
    while a < b:
        mid = (a + b) >> 1
        if codes[mid] < key:
            a = mid + 1
        else:
            b = mid
    return a


@njit(cache=True, nogil=True)
def _find(codes, lo, n, key):
    """Index of ``key`` in the sorted codes[lo:lo+n], or -1."""
    a = _lower_bound(codes, lo, lo + n, key)
    return a if a < lo + n and codes[a] == key else -1


@njit(cache=True, nogil=True)
def _draw_first(first_cum, state):
    e = np.searchsorted(first_cum, uniform(state) * first_cum[-1], side="right")
    return min(e, len(first_cum) - 1)


@njit(cache=True, nogil=True)
def _first_rows(out, t, state):
    """Rows 0..v-1: the horizontal chain of whole column states (first window from q)."""
    g, u, v = t.levels, t.u, t.v
    first_q, first_cum, configs, pfx, pfx_entry = (t.first_q, t.first_cum, t.first_configs,
                                                   t.pfx, t.pfx_entry)
    repairs = 0
    e = _draw_first(first_cum, state)
    for i in range(v):
        for j in range(u):
            out[i, j] = configs[e, i, j]
    for c in range(u, out.shape[1]):
        key = 0
        for i in range(v):
            for j in range(c - u + 1, c):
                key = key * g + out[i, j]
        p = _find(pfx[CODE], 0, pfx.shape[1], key)
        if p < 0:  # a state the chain cannot leave (non-stationary DPJ): draw afresh
            repairs += 1
            e = _draw_first(first_cum, state)
        else:
            lo, hi = pfx[START, p], pfx[END, p]
            total = 0.0
            for k in range(lo, hi):
                total += first_q[pfx_entry[k]]
            x = uniform(state) * total
            e = pfx_entry[hi - 1]
            for k in range(lo, hi):
                x -= first_q[pfx_entry[k]]
                if x < 0.0:
                    e = pfx_entry[k]
                    break
        for i in range(v):
            out[i, c] = configs[e, i, u - 1]
    return repairs


@njit(cache=True, nogil=True)
def _context(out, r, n, u, rows, g, gx, gp, amod):
    """Code of the ``rows`` rows just above row r, columns n..n+u-1 (row-major, base G), then,
    with parents (gp > 1), the parents of row r's points there (out holds parent · gx + level)."""
    key = 0
    for i in range(r - rows, r):
        for j in range(n, n + u):
            key = key * g + (out[i, j] if amod == 256 else out[i, j] % amod)
    if gp > 1:
        for j in range(n, n + u):
            key = key * gp + out[r, j] // gx
    return key


@njit(cache=True, nogil=True)
def _reserve(tb, used, extra):
    if used + extra <= len(tb):
        return tb
    grown = np.empty(2 * (used + extra), np.float64)
    for i in range(used):
        grown[i] = tb[i]
    return grown


OK, DEAD_END, GROW = 0, 1, 2


@njit(cache=True, nogil=True)
def _chain_weights(tb, toff, lo, hi, big_r, head, m, pulled, factor, last_level):
    """T_n(e) = R(first u-1 points of e) · m(e), times factor[its last level] when ``pulled``
    (closure 7, _pull: in the same pass, not a second)."""
    total = 0.0
    for e in range(lo, hi):
        x = big_r[head[e]] * m[e]
        if pulled:
            x *= factor[last_level[e]]
        tb[toff + e - lo] = x
        total += x
    return total


@njit(cache=True, nogil=True)
def _plain_weights(tb, toff, lo, hi, weight, pulled, factor, last_level):
    """T_n(e) = q(e) at a row's start or a restart, m(e) after fixed points (``pulled``: as
    _chain_weights)."""
    total = 0.0
    for e in range(lo, hi):
        x = weight[e]
        if pulled:
            x *= factor[last_level[e]]
        tb[toff + e - lo] = x
        total += x
    return total


@njit(cache=True, nogil=True)
def _fixed_weights(out, r, n, c0, c1, g, u, tb, toff, lo, hi, bcode, plain, big_r, head, weight,
                   pulled, factor, last_level):
    """T_n(e) as _plain_weights (``plain``) or _chain_weights give it, but 0 for the entries
    disagreeing with the fixed points (outside [c0, c1)) — one pass, not a second to zero
    them. ``g`` is the base of the bottom codes (a point's parent, if any, is not compared).
    The fixed points are the window's first p and last s: an entry agrees when its code lies
    in the range of its first p digits' and its last s digits are theirs (at most a division,
    not one a point)."""
    p = min(u, max(0, c0 - n))
    s = min(u - p, max(0, n + u - c1))
    first = last = 0
    for j in range(p):
        first = first * g + out[r, n + j] % g
    for j in range(u - s, u):
        last = last * g + out[r, n + j] % g
    cut, tail = g ** (u - p), g ** s
    a, b = first * cut, (first + 1) * cut      # the codes whose first p digits are first's
    total = 0.0
    for e in range(lo, hi):
        code = bcode[e]
        if code < a or code >= b or (s > 0 and code % tail != last):
            x = 0.0
        elif plain:
            x = weight[e]
        else:
            x = big_r[head[e]] * weight[e]
        if pulled:
            x *= factor[last_level[e]]
        tb[toff + e - lo] = x
        total += x
    return total


@njit(cache=True, nogil=True)
def _accumulate(big_r, tail, tb, toff, lo, hi, scale):
    """R(last u-1 points) += T_n(e) / sum T_n: the filter carried to the next position."""
    for e in range(lo, hi):
        big_r[tail[e]] += tb[toff + e - lo] * scale


@njit(cache=True, nogil=True)
def _clear(big_r, tail, lo, hi):
    """Zero what entries lo..hi wrote into R: sparsely, or all of R when that is shorter."""
    if len(big_r) <= hi - lo:
        big_r[:] = 0.0
    else:
        for e in range(lo, hi):
            big_r[tail[e]] = 0.0


@njit(cache=True, nogil=True)
def _forward(out, r, n, n_first, c0, c1, lenient_at, kmin, width, t, work, below, below_to):
    """The forward filter over row r from position n to the last window touching [c0, c1).

    Positions before n must already be in ``work`` (a resumed pass). Returns (status, n,
    repairs): OK, or DEAD_END / GROW at position n. Only at ``lenient_at`` may a position back
    off to the DPJ marginal with fewer rows above, and at worst restart the bottom-row chain.
    ``kmin`` rows of context are left out everywhere (a conditional scale's first rows).
    Windows lie in columns 0..width-1. ``below`` > 0: the rows under row r are fixed too (the
    first rows of a torus, after its last), and so are the windows they end at positions before
    ``below_to`` (but for the position backing off).
    """
    g, u, v, direct, lvl = t.levels, t.u, t.v, t.direct, t.lvl
    gx, gp = t.gx, t.gp
    head, tail, bcode = t.ient[HEAD], t.ient[TAIL], t.ient[BCODE]
    last_level = t.ient[LAST]
    q, m = t.fent[Q], t.fent[M]
    code, start, end = t.ctx[CODE], t.ctx[START], t.ctx[END]
    big_r, pos, inv, tb = work.big_r, work.pos, work.inv, work.tb[0]
    pulled = work.pull[0, gx] > 0.0    # closure 7 (_pull): the rows' pass, so never with
    #                                    ``below`` (the columns' closure), whose factors follow
    n_last = min(width - u, c1 - 1)
    repairs = 0
    while n <= n_last:
        toff = pos[TOFF, n]
        total, lo, hi = 0.0, 0, 0
        levels = v if n == lenient_at else kmin + 1
        for k in range(kmin, levels + (n == lenient_at)):
            restart = k == levels
            key = _context(out, r, n, u, 0 if restart else v - 1 - k, g, gx, gp, t.amod)
            if k == 0 and len(direct):
                ci = direct[key]
            else:
                kk = v - 1 if restart else k
                ci = _find(code, lvl[OFF, kk], lvl[LEN, kk], key)
            if ci < 0:
                continue
            lo, hi = start[ci], end[ci]
            if toff + hi - lo > len(tb):
                pos[HI, n] = toff + hi - lo  # the room needed
                return GROW, n, repairs
            plain = n == 0 or restart or n == n_first
            weight = q if n == 0 or restart else m
            factor = work.pull[n + u - 1]
            if n < c0 or n + u > c1:
                total = _fixed_weights(out, r, n, c0, c1, gx, u, tb, toff, lo, hi, bcode,
                                       plain, big_r, head, weight, pulled, factor, last_level)
            elif plain:
                total = _plain_weights(tb, toff, lo, hi, weight, pulled, factor, last_level)
            else:
                total = _chain_weights(tb, toff, lo, hi, big_r, head, m, pulled, factor,
                                       last_level)
            if below > 0 and n != lenient_at and n < below_to:
                total = _keep_below(out, r, n, below, tb, toff, lo, hi, bcode, t)
            if total > 0.0:
                repairs += k > kmin
                break
        if total == 0.0:
            return DEAD_END, n, repairs
        if n > n_first:
            _clear(big_r, tail, pos[LO, n - 1], pos[HI, n - 1])
        pos[LO, n], pos[HI, n], inv[n] = lo, hi, 1.0 / total
        _accumulate(big_r, tail, tb, toff, lo, hi, 1.0 / total)
        if n + 1 < pos.shape[1]:
            pos[TOFF, n + 1] = toff + hi - lo
        n += 1
    _clear(big_r, tail, pos[LO, n_last], pos[HI, n_last])
    return OK, n_last, repairs


@njit(cache=True, nogil=True)
def _mass(tb, off, count):
    total = 0.0
    for i in range(off, off + count):
        total += tb[i]
    return total


@njit(cache=True, nogil=True)
def _pick(tb, off, lo, hi, state):
    """Draw an entry of [lo, hi) with probability ∝ its weight tb[off + e - lo]."""
    x = uniform(state) * _mass(tb, off, hi - lo)
    last = lo
    for e in range(lo, hi):
        w = tb[off + e - lo]
        if w > 0.0:
            last = e
            x -= w
            if x < 0.0:
                return e
    return last


@njit(cache=True, nogil=True)
def _backward(out, r, n_last, c0, t, work, state):
    """Draw the last window from T, then each earlier new point given the u-1 points after it.

    A point's parent, if any, stays: out holds parent · gx + level."""
    g, u, bcode, rot = t.gx, t.u, t.ient[BCODE], t.ient[ROT]
    parents = g if t.gp > 1 else 256        # out // parents * g: the parent part, or 0
    pos, tb = work.pos, work.tb[0]
    gu1 = g ** (u - 1)
    code = bcode[_pick(tb, pos[TOFF, n_last], pos[LO, n_last], pos[HI, n_last], state)]
    for j in range(u - 1, -1, -1):  # fixed points among these agree: _fixed_weights saw to it
        out[r, n_last + j] = out[r, n_last + j] // parents * g + code % g
        code //= g
    for n in range(n_last - 1, c0 - 1, -1):
        need = 0
        for j in range(n + 1, n + u):
            need = need * g + out[r, j] % g
        lo, hi = pos[LO, n], pos[HI, n]
        a = _lower_bound(rot, lo, hi, need * g)
        b = _lower_bound(rot, a, hi, need * g + g)
        off = pos[TOFF, n] + a - lo
        if a == b or _mass(tb, off, b - a) == 0.0:
            a, b, off = lo, hi, pos[TOFF, n]  # the far side was a restart: any point
        out[r, n] = out[r, n] // parents * g + bcode[_pick(tb, off, a, b, state)] // gu1


class _Work(NamedTuple):
    big_r: np.ndarray     # R, indexed by the code of u-1 points
    pos: np.ndarray       # (3, positions) int64: LO, HI entries weighed, TOFF of their T in tb
    inv: np.ndarray       # per position: 1 / sum T_n
    tb: list              # the T buffer, in a list so it can grow in place
    saved: np.ndarray     # rows above as they were, to restore after a failed redraw
    pull: np.ndarray      # (columns, g + 1): closure 7's factor per column and level of a
                          # pulled row (_pull); pull[0, g] > 0: the row is pulled


@njit(cache=True, nogil=True)
def _new_work(g, u, w, depth):
    npos = w - u + 1
    return _Work(np.zeros(g ** (u - 1), np.float64), np.zeros((3, npos), np.int64),
                 np.zeros(npos, np.float64), [np.empty(npos * 8, np.float64)],
                 np.empty((depth, w), np.uint8), np.zeros((w, g + 1), np.float64))


@njit(cache=True, nogil=True)
def _run(out, r, n, n_first, c0, c1, lenient_at, kmin, width, t, work, below, below_to):
    """_forward, growing the T buffer as often as it asks."""
    while True:
        status, n, repairs = _forward(out, r, n, n_first, c0, c1, lenient_at, kmin, width, t,
                                      work, below, below_to)
        if status != GROW:
            return status, n, repairs
        pos = work.pos
        work.tb[0] = _reserve(work.tb[0], pos[TOFF, n], pos[HI, n] - pos[TOFF, n])


@njit(cache=True, nogil=True)
def _redraw_segment(out, r, c0, c1, kmin, t, work, state, lenient, below, below_to):
    """Redraw row r on columns [c0, c1) from its exact law given everything around it
    (``lenient``: a position that meets a dead end backs off, as _draw_row's last resort;
    ``below``: the rows fixed under it, see _forward).

    Returns -1, or the position of the dead end that left the row untouched.
    """
    n_first = max(0, c0 - t.u + 1)
    work.pos[TOFF, n_first] = 0
    n, lenient_at = n_first, np.int64(-1)
    while True:
        status, n, _ = _run(out, r, n, n_first, c0, c1, lenient_at, kmin,
                            np.int64(out.shape[1]), t, work, below, below_to)
        if status != DEAD_END:
            break
        if not lenient or lenient_at == n:
            if n > n_first:
                _clear(work.big_r, t.ient[TAIL], work.pos[LO, n - 1], work.pos[HI, n - 1])
            return n
        lenient_at = n
    _backward(out, r, n, max(c0, n_first), t, work, state)
    return np.int64(-1)


@njit(cache=True, nogil=True)
def _copy_rows(src, s0, dst, d0, rows, c0, c1):
    """dst[d0:d0+rows, c0:c1] = src[s0:s0+rows, c0:c1] (plain loops: see the kernels' note)."""
    for i in range(rows):
        for j in range(c0, c1):
            dst[d0 + i, j] = src[s0 + i, j]


@njit(cache=True, nogil=True)
def _redraw_above(out, r, n, tries, col0, col1, t, seg, state):
    """A dead end at position n of row r: redraw a segment of the rows above around n, wider
    and deeper as tries fail, within columns [col0, col1). Returns the first column changed,
    or -1 if nothing changed."""
    u = t.u
    depth = min(1 + tries // 4, MAX_REDRAW_DEPTH, r - t.v + 1)
    if depth <= 0:
        return -1
    half = u * (2 + 2 * (tries // 4))
    c0, c1 = max(col0, n - half), min(col1, n + u + half)
    if c0 >= c1:
        return -1
    _copy_rows(out, r - depth, seg.saved, 0, depth, c0, c1)
    for ra in range(r - depth, r):
        if _redraw_segment(out, ra, c0, c1, np.int64(0), t, seg, state, False,
                           np.int64(0), np.int64(0)) >= 0:
            _copy_rows(seg.saved, 0, out, r - depth, depth, c0, c1)
            return -1
    return c0


@njit(cache=True, nogil=True)
def _draw_row(out, r, kmin, col0, col1, ring, t, work, seg, state, max_redraws, row_redraws):
    """Draw row r given the v-1-kmin rows above it. Returns (repairs, redraws, drawn).

    A dead end at position n redraws the rows above around n and resumes the forward pass just
    before the redrawn columns (the filter there is unchanged); after ``max_redraws`` failed
    tries at the same place, once the row has redrawn ``row_redraws`` times, or where no full
    context rows lie above, that position backs off.
    The row is drawn on columns 0..col1-1 (a tileable row's copied columns come after), and
    the rows above are redrawn within [col0, col1). ``ring`` (closure 6): the row's first u-1
    points, already drawn (_ring_start) and copied after col1, stay, and the row is drawn
    given them at both ends; not ``drawn``: a back-off could not meet them (the row is left
    to be drawn again).
    """
    u, w = t.u, col1
    fixed = u - 1 if ring else 0
    width = w + fixed
    tail, pos = t.ient[TAIL], work.pos
    repairs = redraws = tries = np.int64(0)
    n, lenient_at, frontier = np.int64(0), np.int64(-1), np.int64(-1)
    pos[TOFF, 0] = 0
    while True:
        status, n, rep = _run(out, r, n, 0, fixed, w, lenient_at, kmin, width, t, work, 0,
                              0)             # 0: nothing fixed below
        repairs += rep
        if status == OK:
            break
        if n == lenient_at:        # only fixed points stop a back-off
            if n > 0:
                _clear(work.big_r, tail, pos[LO, n - 1], pos[HI, n - 1])
            return repairs, redraws, False
        if n > frontier:  # a dead end further along the row: a fresh budget of tries
            frontier, tries = n, 0
        if tries >= max_redraws or redraws >= row_redraws or t.v == 1 or r < t.v:
            lenient_at = n  # resume at n (R still holds the filter of n - 1), backing off
            continue
        c0 = _redraw_above(out, r, n, tries, col0, col1, t, seg, state)
        tries += 1
        redraws += 1
        resume = n if c0 < 0 else max(0, min(n, c0 - u + 1))
        if n > 0:  # R back to the filter just before the resumed position
            _clear(work.big_r, tail, pos[LO, n - 1], pos[HI, n - 1])
        if resume > 0:
            p = resume - 1
            _accumulate(work.big_r, tail, work.tb[0], pos[TOFF, p], pos[LO, p], pos[HI, p],
                        work.inv[p])
        n = resume
    _backward(out, r, width - u, 0, t, work, state)
    return repairs, redraws, True


@njit(cache=True, nogil=True)
def _ring_start(out, r, tile_w, t, seg, state):
    """Draw the first u-1 points of row r given the rows above on both sides of the side seam:
    a stretch of RING_LEAD window positions either side of it, drawn as a free chain in a
    strip of ``seg.saved`` holding the rows above from column tile_w - RING_LEAD on, across
    the seam (the ring's own start, which the row then meets at its end: drawn from the row's
    first window alone, they often could not be met, and the row's last points changed level
    2-5 times as often as inside). False: it met a dead end (nothing of row r changed)."""
    u, v = t.u, t.v
    lead = min(np.int64(RING_LEAD), (tile_w - u) // 2)
    width = 2 * lead + u - 1 + u - 1
    strip = seg.saved
    for i in range(v):
        for j in range(width):
            c = tile_w - lead + j
            strip[i, j] = out[r - v + 1 + i, c - tile_w if c >= tile_w else c]
    seg.pos[TOFF, 0] = 0
    status, n, _ = _run(strip, v - 1, np.int64(0), 0, 0, width, np.int64(-1), np.int64(0),
                        width, t, seg, 0, 0)
    if status != OK:
        if n > 0:
            _clear(seg.big_r, t.ient[TAIL], seg.pos[LO, n - 1], seg.pos[HI, n - 1])
        return False
    _backward(strip, v - 1, width - u, 0, t, seg, state)
    for j in range(u - 1):
        out[r, j] = strip[v - 1, lead + j]
        out[r, tile_w + j] = strip[v - 1, lead + j]
    return True


@njit(cache=True, nogil=True)
def _sample_rows(out, r0, r1, t, state, max_redraws, row_redraws, tile_h, tile_w, closure,
                 budget, repair_budget, pull):
    """Rows r0..r1-1. Without parents the first call (r0 = 0) draws the first v rows as the
    chain of column states; with parents each of them is drawn with the rows above it. Stops
    after the row that takes the redraws past ``budget`` or the repairs past
    ``repair_budget``.

    Tileable (tile_h > 0): ``out`` is the (tile_h, tile_w) torus with its first v-1 rows and
    u-1 columns copied after its last (see _draw); each row is drawn on its ring (closure 6:
    _ring_start, then _draw_row), or drawn, then closed across the side seam (_close_row, by
    the seam closure of version ``closure``; 6 and 7 too where the ring does not close). The
    last rows are weighed towards the first (closure 7: _pull, _pull_given, _pull_along)."""
    w = out.shape[1]
    work = _new_work(t.gx, t.u, w, np.int64(1))
    seg = _new_work(t.gx, t.u, w, np.int64(max(MAX_REDRAW_DEPTH, t.v)))
    repairs = redraws = 0
    start = r0
    col0, col1 = np.int64(0), np.int64(w)
    if tile_h > 0:                     # dead ends never redraw a seam column above
        col0, col1 = np.int64(t.u - 1), tile_w
    if r0 == 0 and t.gp == 1:
        repairs += _first_rows(out, t, state)
        start = t.v
        if tile_h > 0:                 # close them top down, each end at least as wide
            c0 = tile_w
            for r in range(t.v):
                c0 = _close_row(out, r, np.int64(max(0, t.v - 1 - r)), tile_w, c0, t, seg,
                                state, closure, np.int64(0), np.int64(0))
                repairs += c0 < 0
                c0 = -1 - c0 if c0 < 0 else c0
    along = np.zeros((_pulled_rows(pull, t, tile_h), w, t.gx))
    for r in range(start, r1):
        kmin = np.int64(max(0, t.v - 1 - r))
        d = tile_h - 1 - r             # a pulled row: d < len(along)
        if 0 <= d < len(along):
            if r == start or d == len(along) - 1:   # the first row is final by then
                _pull_along(out, tile_h, pull, t, along, closure >= 8)
            work.pull[:, :t.gx] = along[d]
            work.pull[0, t.gx] = 1.0
        ring = tile_h > 0 and closure >= 6 and kmin == 0 and t.u > 1 and tile_w >= 2 * t.u \
            and _ring_start(out, r, tile_w, t, seg, state)
        rep, red, drawn = _draw_row(out, r, kmin, col0, col1, ring, t, work, seg, state,
                                    max_redraws, row_redraws)
        if not drawn:                  # the ring did not close: drawn and closed as closure 5
            repairs += rep
            redraws += red
            rep, red, drawn = _draw_row(out, r, kmin, col0, col1, False, t, work, seg, state,
                                        max_redraws, row_redraws)
            ring = False
        repairs += rep
        redraws += red
        work.pull[0, t.gx] = 0.0
        if tile_h > 0 and not ring:
            repairs += _close_row(out, r, kmin, tile_w, tile_w, t, seg, state, closure,
                                  np.int64(0), np.int64(0)) < 0
        if redraws > budget or repairs > repair_budget:
            break
    return repairs, redraws


@njit(cache=True, nogil=True)
def _pulled_rows(pull, t, tile_h):
    """How many of the last rows of a torus of ``tile_h`` rows are pulled (closure 7)."""
    if tile_h == 0 or len(pull) == 0:
        return 0
    if t.gp == 1:
        return len(pull)
    return min(PULL_ROWS, tile_h // PULL_SHARE)


@njit(cache=True, nogil=True)
def _pull_along(out, tile_h, pull, t, along, full=False):
    """along[d, c, x]: the pull of level x in column c of the row d + 1 rows above the first
    (closure 7), towards the first row's level in that column. One DPJ: ``pull`` holds the
    factors (_pull). A scale given its parents: ``pull`` is its chain given the parents
    (_pull_given), and each column's factors come from the probability of reaching the first
    row's level through that column's own parents, h_d = P_d h_(d-1) from the seam up (scaled
    to a largest of 1, which a position's weights do not see), ** PULL_POWER_GIVEN (``full``,
    closure 8: ** PULL_POWER_8)."""
    g = t.gx
    w = along.shape[1]
    if t.gp == 1:
        for d in range(len(along)):
            for c in range(w):
                first = out[0, c] % g
                for x in range(g):
                    along[d, c, x] = pull[d, x, first]
        return
    h, step = np.empty(g), np.empty(g)
    for c in range(w):
        first = out[0, c] % g
        for x in range(g):
            h[x] = 1.0 if x == first else 0.0
        under = out[0, c] // g
        for d in range(len(along)):
            parent = out[tile_h - 1 - d, c] // g
            k = parent * t.gp + under
            top = 0.0
            for x in range(g):
                step[x] = 0.0
                for y in range(g):
                    step[x] += pull[k, x, y] * h[y]
                top = max(top, step[x])
            for x in range(g):
                h[x] = step[x] / top if top > 0.0 else 1.0
                if full:
                    along[d, c, x] = max(h[x], 1e-3) ** PULL_POWER_8
                else:
                    along[d, c, x] = max(h[x], 1e-3) ** PULL_POWER_GIVEN
            under = parent


@njit(cache=True, nogil=True)
def _close_columns(across, t, state, tile_w, tile_h, closure):
    """The bottom seam, closed as the side one: ``across`` is the torus transposed (a row of
    it is a column of the texture) and ``t`` the transposed DPJ's tables, so each column's
    last points are redrawn given its first ones and the columns before it.

    Closure 2 also keeps every window whole that an earlier column's redraw changed (a column's
    redrawn stretch reaches back to the first window that left the DPJ), and draws each column
    given the v-1 after it too: the next columns up to where their own closure redraws (so one
    long redraw does not spread to every later column), the first columns whole for the last
    one (the corner, where the two seams cross). Closure 2 to 4 also redraw the last column
    from the first window across the side seam outside the DPJ, however far up (a row whose
    closure backed off left it; that long redraw seldom closes); closure 5 reads the last
    column as the others, from where the columns before it were redrawn. Closure 8 keeps a
    column as drawn where its windows and the next v-1 columns' are the DPJ's, from where the
    columns before it were redrawn to across the seam (_first_bad, _whole_to)."""
    seg = _new_work(t.gx, t.u, across.shape[1], np.int64(MAX_REDRAW_DEPTH))
    u, v = t.u, t.v
    repairs = 0
    recent = np.full(max(v - 1, 1), tile_h, np.int64)   # the last v-1 columns' first change
    whole = np.int64(-1)               # closure 8: the windows ending in the columns up to this
    if closure >= 8:                   # one are the DPJ's near the seam (since the last redraw),
        for j in range(across.shape[0]):   # read across it: each column's first points after
            for i in range(u - 1):         # its last, as _close_row copies them
                across[j, tile_h + i] = across[j, i]
    for j in range(tile_w):
        kmin = np.int64(max(0, v - 1 - j))
        reach, below, below_to = tile_h, np.int64(0), np.int64(0)
        last = j == tile_w - 1
        stretch = tile_h - (_span(closure) + 1) * u + 1       # where later closures may redraw
        if closure > 1 and j >= v - 1:
            below = np.int64(v - 1)
            below_to = np.int64(tile_h if last else stretch)
            n0 = 0 if last and closure < 5 else max(0, recent.min() - u + 1)
            reach = _first_bad(across, j, below if last else 0, n0, stretch, t)
        kept = False
        if closure >= 8 and j >= v - 1 and reach >= tile_h:
            ahead = j + v - 1 if j + v - 1 < tile_w else tile_w + v - 2   # the corner's too
            whole = _whole_to(across, j, ahead, whole, max(0, stretch), tile_h, t)
            kept = whole >= ahead
        if kept:
            c0 = tile_h                # the pulled rows met the first ones: kept as drawn
        else:
            c0 = _close_row(across, j, kmin, tile_h, reach, t, seg, state, closure, below,
                            below_to)
            whole = np.int64(-1)
        repairs += c0 < 0
        recent[j % len(recent)] = -1 - c0 if c0 < 0 else c0
        if j < v - 1:                # a first column, as it is now, after the last
            _copy_rows(across, j, across, tile_w + j, 1, 0, across.shape[1])
    return repairs


@njit(cache=True, nogil=True)
def _close_row(out, r, kmin, tile_w, reach, t, seg, state, closure, below, below_to):
    """Close row r across the side seam: copy its first u-1 points after its last column, then
    redraw its end from the exact law given both sides (and the ``below`` rows under it), from
    column ``reach`` - (u-1) or before (closure 2: ``reach``), over a wider stretch while that
    meets a dead end — closure 2 redraws the rows above around a dead end instead. Returns
    the first column redrawn c0, or -1 - c0 when only a back-off closed the row (-1 - width:
    nothing did; a window across the seam the DPJ lacks)."""
    u = t.u
    for j in range(u - 1):
        out[r, tile_w + j] = out[r, j]
    if u == 1:
        return tile_w
    if closure > 1:
        c0 = _close_bridged(out, r, kmin, tile_w, reach, t, seg, state, below, below_to,
                            CLOSE_TRIES if closure == 2 or t.gp == 1 else CLOSE_TRIES_3,
                            _span(closure))
        if c0 >= 0:
            return c0
        c0 = -1 - c0                   # back off where needed, over what the tries changed
        if _redraw_segment(out, r, c0, tile_w, kmin, t, seg, state, True, below, below_to) < 0:
            return -1 - c0
        return -1 - tile_w
    for lenient in (False, True):      # a back-off at a dead end only when no stretch closes
        span = max(4 * u, tile_w - reach + u - 1)
        while True:
            c0 = max(u - 1, tile_w - span)
            if _redraw_segment(out, r, c0, tile_w, kmin, t, seg, state, lenient, below,
                               below_to) < 0:
                return c0 if not lenient else -1 - c0
            if c0 == u - 1:
                break
            span *= 2
    return -1 - tile_w


@njit(cache=True, nogil=True, inline="always")
def _span(closure):
    """The shortest stretch a seam closure redraws, in windows."""
    return CLOSE_SPAN_4 if closure >= 4 else CLOSE_SPAN


@njit(cache=True, nogil=True)
def _close_bridged(out, r, kmin, tile_w, reach, t, seg, state, below, below_to, most, least):
    """Closure 2 (and 3, 4) of row r: at a dead end, the rows above are redrawn around it too
    (as a dead end inside the texture does, see _redraw_above, but within the stretch), deeper
    and wider as tries fail, then the row's stretch again, longer every fourth try; ``most``
    tries, the first over ``least`` windows at least. Returns the first column redrawn c0, or
    -1 - c0 when no try closed the row (the rows above may have changed from c0 on)."""
    u = t.u
    span = max(least * u, tile_w - reach)
    c0 = max(u - 1, tile_w - span)
    for tries in range(most):
        c0 = max(u - 1, tile_w - span)
        n = _redraw_segment(out, r, c0, tile_w, kmin, t, seg, state, False, below, below_to)
        if n < 0:
            return c0
        depth = min(1 + tries % 3, MAX_REDRAW_DEPTH, r - t.v + 1)
        half = u * (2 + tries // 3)
        a, b = max(c0, n - half), min(tile_w, n + u + half)
        if depth > 0 and a < b:
            _copy_rows(out, r - depth, seg.saved, 0, depth, a, b)
            for ra in range(r - depth, r):
                if _redraw_segment(out, ra, a, b, np.int64(0), t, seg, state, False,
                                   np.int64(0), np.int64(0)) >= 0:
                    _copy_rows(seg.saved, 0, out, r - depth, depth, a, b)
                    break
        if tries % SPAN_TRIES == SPAN_TRIES - 1:
            span *= 2
    return -1 - c0


@njit(cache=True, nogil=True)
def _whole_to(out, r, ahead, known, n0, n1, t):
    """The last of rows r..``ahead`` up to which every window at a position in [n0, n1) ending
    in that row is a DPJ entry (those up to ``known`` are), or r-1. Closure 8 keeps row r as
    drawn only when the next v-1 are whole too (the last rows: up to the corner): a row redrawn
    between rows kept as drawn met dead ends, and backed off over more windows."""
    for rk in range(max(r, known + 1), ahead + 1):
        for n in range(n0, n1):
            if _window_m(out, rk, n, np.int64(-1), np.int64(0), t) == 0.0:
                return np.int64(rk - 1)
    return np.int64(ahead)


@njit(cache=True, nogil=True)
def _first_bad(out, r, below, n0, n1, t):
    """Where a redraw of row r must start to reach the first window position in [n0, n1)
    whose window ending in row r..r+below is not a DPJ entry (its last point), or the torus
    width when there is none."""
    for n in range(n0, n1):
        for k in range(below + 1):
            if _window_m(out, r + k, n, np.int64(-1), np.int64(0), t) == 0.0:
                return np.int64(n + t.u - 1)
    return np.int64(out.shape[1] - t.u + 1)


@njit(cache=True, nogil=True)
def _keep_below(out, r, n, below, tb, toff, lo, hi, bcode, t):
    """Weigh each entry by how the ``below`` fixed rows under row r continue from it: the
    horizontal transition m of each window ending in one of them (0: not in the DPJ). The
    rows below are drawn as chains of such transitions, so this is their likelihood but for
    its normaliser over the row, which depends on the whole row and is left out.
    (Building each row's window key once a position rather than once an entry was 0.1–0.2 ms
    sooner on a 128² torus, but made the first start's compile 5 s longer: not kept.)"""
    total = 0.0
    for e in range(lo, hi):
        x = tb[toff + e - lo]
        for k in range(1, below + 1):
            if x == 0.0:
                break
            x *= _window_m(out, r + k, n, r, bcode[e], t)
        tb[toff + e - lo] = x
        total += x
    return total


@njit(cache=True, nogil=True)
def _window_m(out, r, n, sub, sub_code, t):
    """The horizontal transition m of the window ending in row r at position n (level 0 of the
    tables), 0 when the DPJ lacks it; row ``sub``, if one of its rows, is read as the bottom
    code ``sub_code``."""
    g, gx, gp, u, v = t.levels, t.gx, t.gp, t.u, t.v
    key = 0
    for i in range(r - v + 1, r):
        for j in range(u):
            if i == sub:
                x = sub_code // gx ** (u - 1 - j) % gx
            else:
                x = out[i, n + j] % t.amod
            key = key * g + x
    bottom = 0
    for j in range(u):
        if gp > 1:
            key = key * gp + out[r, n + j] // gx
        bottom = bottom * gx + out[r, n + j] % gx
    if len(t.direct):
        ci = t.direct[key]
    else:
        ci = _find(t.ctx[CODE], t.lvl[OFF, 0], t.lvl[LEN, 0], key)
    if ci < 0:
        return 0.0
    gu1 = gx ** (u - 1)
    lo = t.ctx[START, ci]
    e = _find(t.ient[ROT], lo, t.ctx[END, ci] - lo, bottom % gu1 * gx + bottom // gu1)
    return t.fent[M, e] if e >= 0 else 0.0
