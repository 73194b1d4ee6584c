"""Synthesis from a DPJ (thesis ch. 4, digest §6): the 2-D Markov process, top-down.

DPJ → normalised level matrix. The first v rows follow the horizontal chain of column states;
every later row is drawn exactly given the v-1 rows above it, by forward filtering and backward
sampling over the row. The numba kernels release the GIL, so a worker thread leaves a GUI live.

Dead ends (a row that no configuration of the DPJ can continue) never raise and never hang:
1. the row above is redrawn, up to ``max_redraws`` times (every window stays a DPJ entry);
2. failing that, each window position that cannot continue *backs off* to the DPJ marginal with
   one context row fewer, down to the plain horizontal chain of the bottom row; each such
   position counts as one repair.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np
from numba import njit

from .dpj import DPJ, encode
from .errors import Cancelled, InputError

MAX_PIXELS = 2**28
ROWS_PER_CALL_PIXELS = 2**16
MAX_REDRAW_DEPTH = 4           # rows above a dead end that may be redrawn together   # work per kernel call: how often progress and cancel are checked


@dataclass(frozen=True)
class SynthesisResult:
    levels: np.ndarray    # (H, W) uint8
    repairs: int          # window positions drawn from a backed-off (smaller) context
    redraws: int          # rows redrawn to get past a dead end
    seed: int


def synthesize(dpj: DPJ, shape: tuple[int, int], *, seed: int = 0,
               progress: Callable[[float], None] | None = None,
               cancel: Callable[[], bool] | None = None, max_redraws: int = 16) -> SynthesisResult:
    """Draw an (H, W) level matrix from ``dpj``; same DPJ and seed → same matrix.

    ``progress(fraction)`` is called between bands of rows; ``cancel()`` returning True stops the
    work with :class:`Cancelled`. ``shape`` is (height, width).
    """
    h, w = _check_request(dpj, shape)
    t = _tables(dpj)
    out = np.zeros((h, w), dtype=np.uint8)
    state = np.random.SeedSequence(_check_seed(seed)).generate_state(1, np.uint64)
    band = max(t.v, ROWS_PER_CALL_PIXELS // w)
    repairs = redraws = 0
    for r0 in range(0, h, band):
        if cancel is not None and cancel():
            raise Cancelled("synthesis cancelled")
        rep, red = _sample_rows(out, r0, min(h, r0 + band), t, state, max_redraws)
        repairs += rep
        redraws += red
        if progress is not None:
            progress(min(h, r0 + band) / h)
    return SynthesisResult(out, int(repairs), int(redraws), int(seed))


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"the seed must be a non-negative integer, got {seed!r}")
    return int(seed)


def _check_request(dpj: DPJ, shape) -> tuple[int, int]:
    if not isinstance(dpj, DPJ):
        raise InputError("synthesis needs a DPJ")
    try:
        h, w = (int(x) for x in shape)
    except (TypeError, ValueError):
        raise InputError(f"size must be (height, width), got {shape!r}") from None
    u, v = dpj.window
    if h < v or w < u:
        raise InputError(f"a {w}x{h} texture is smaller than the DPJ's {u}x{v} window")
    if h * w > MAX_PIXELS:
        raise InputError(f"{w}x{h} is more than {MAX_PIXELS} points: choose a smaller size")
    p = dpj.probs
    if len(dpj) == 0 or not np.all(np.isfinite(p)) or np.any(p < 0) or p.sum() <= 0:
        raise InputError("the DPJ has no usable probabilities (empty, negative, NaN or zero sum)")
    return h, w


# -- tables: the DPJ rearranged for the kernels ------------------------------------------------

class _Tables(NamedTuple):
    levels: int
    u: int
    v: int
    first_cum: np.ndarray      # cumulative q over the full model's entries (first window)
    first_q: np.ndarray        # q over the full model's entries
    first_configs: np.ndarray  # (n, v, u) configurations of the full model
    pfx_codes: np.ndarray      # unique codes of the first u-1 columns (horizontal chain states)
    pfx_start: np.ndarray
    pfx_end: np.ndarray
    pfx_entry: np.ndarray      # full-model entries grouped by their first u-1 columns
    bcode: np.ndarray          # per entry of every back-off level: code of the bottom row
    rot: np.ndarray            # the same code read from its second point (last u-1 points first)
    head: np.ndarray           # code of the first u-1 points (the index of R it reads)
    tail: np.ndarray           # code of the last u-1 points (the index of R it feeds)
    q: np.ndarray              # per entry: probability
    m: np.ndarray              # per entry: horizontal transition q / μ(first u-1 columns)
    ctx_codes: np.ndarray      # per level: sorted unique codes of the rows above (the context)
    ctx_start: np.ndarray
    ctx_end: np.ndarray
    level_off: np.ndarray      # per back-off level: offset and length in ctx_*
    level_len: np.ndarray


_cache: dict[int, tuple[weakref.ref, _Tables]] = {}


def _tables(dpj: DPJ) -> _Tables:
    """Build (or reuse) the kernel tables of a DPJ; DPJs are immutable so id + weakref is safe."""
    hit = _cache.get(id(dpj))
    if hit is not None and hit[0]() is dpj:
        return hit[1]
    positive = dpj.probs > 0
    tables = _build_tables(DPJ(dpj.configs[positive], dpj.probs[positive], dpj.levels).normalized())
    for key in [k for k, (ref, _) in _cache.items() if ref() is None]:
        del _cache[key]
    _cache[id(dpj)] = (weakref.ref(dpj), tables)
    return tables


def _build_tables(dpj: DPJ) -> _Tables:
    u, v = dpj.window
    g = dpj.levels
    gu = g ** u
    bcode, rot, q, m, ctx, start, end, off, length = [], [], [], [], [], [], [], [], []
    base = 0
    for k in range(v):  # level k: the DPJ marginal over its bottom v-k rows
        model = dpj if k == 0 else dpj.marginal(rows=slice(k, v))
        ctx_k, b_k = np.divmod(model.codes, gu)
        # within a context, group entries by their last u-1 points: backward sampling
        # then reads one contiguous block instead of filtering the whole context
        order = np.lexsort((_rotated(b_k, g, u), ctx_k))
        ctx_k, b_k = ctx_k[order], b_k[order]
        bcode.append(b_k)
        rot.append(_rotated(b_k, g, u))
        q.append(model.probs[order])
        m.append(_transitions(model)[order])
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
    return _Tables(
        levels=g, u=u, v=v, first_cum=np.cumsum(dpj.probs), first_q=dpj.probs, first_configs=dpj.configs,
        pfx_codes=upfx, pfx_start=pfirst, pfx_end=np.append(pfirst[1:], len(pfx)),
        pfx_entry=order.astype(np.int64), bcode=cat(bcode), rot=cat(rot),
        head=cat(bcode) // g, tail=cat(bcode) % g ** (u - 1), q=cat(q), m=cat(m),
        ctx_codes=cat(ctx), ctx_start=cat(start).astype(np.int64),
        ctx_end=cat(end).astype(np.int64), level_off=np.array(off, np.int64),
        level_len=np.array(length, np.int64))


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
# In the row sampler, T_n (the forward filter at window position n) is kept unnormalised in tbuf,
# one block per position; R (its sum over the first point, indexed by the last u-1 points) is
# normalised, which keeps the numbers in range along a row of any width.

@njit(cache=True, nogil=True)
def _uniform(state):
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
def _draw_first(t, state):
    e = np.searchsorted(t.first_cum, _uniform(state) * t.first_cum[-1], side="right")
    return min(e, len(t.first_cum) - 1)


@njit(cache=True, nogil=True)
def _first_rows(out, t, state):
    """Rows 0..v-1: the horizontal chain of whole column states (first window from q)."""
    g, u, v = t.levels, t.u, t.v
    repairs = 0
    e = _draw_first(t, state)
    for i in range(v):
        for j in range(u):
            out[i, j] = t.first_configs[e, i, j]
    for c in range(u, out.shape[1]):
        key = 0
        for i in range(v):
            for j in range(c - u + 1, c):
                key = key * g + out[i, j]
        p = _find(t.pfx_codes, 0, len(t.pfx_codes), key)
        if p < 0:  # a state the chain cannot leave (non-stationary DPJ): draw afresh
            repairs += 1
            e = _draw_first(t, state)
        else:
            lo, hi = t.pfx_start[p], t.pfx_end[p]
            total = 0.0
            for k in range(lo, hi):
                total += t.first_q[t.pfx_entry[k]]
            x = _uniform(state) * total
            e = t.pfx_entry[hi - 1]
            for k in range(lo, hi):
                x -= t.first_q[t.pfx_entry[k]]
                if x < 0.0:
                    e = t.pfx_entry[k]
                    break
        for i in range(v):
            out[i, c] = t.first_configs[e, i, u - 1]
    return repairs


@njit(cache=True, nogil=True)
def _context(out, r, n, u, rows, g):
    """Code of the ``rows`` rows just above row r, columns n..n+u-1 (row-major, base G)."""
    key = 0
    for i in range(r - rows, r):
        for j in range(n, n + u):
            key = key * g + out[i, j]
    return key


@njit(cache=True, nogil=True)
def _reserve(tbuf, used, extra):
    if used + extra <= len(tbuf):
        return tbuf
    grown = np.empty(2 * (used + extra), np.float64)
    grown[:used] = tbuf[:used]
    return grown


@njit(cache=True, nogil=True)
def _sample_row(out, r, strict, t, state, work):
    """Draw row r given the rows above: forward filtering, backward sampling (digest §6).

    Returns (ok, repairs). With ``strict`` only the full DPJ is used and a dead end returns
    ok = False with row r untouched; otherwise positions back off to smaller contexts.
    """
    g, u, v = t.levels, t.u, t.v
    big_r, pos_lo, pos_hi, pos_off = work.big_r, work.pos_lo, work.pos_hi, work.pos_off
    npos = out.shape[1] - u + 1
    repairs = 0
    toff = 0
    for n in range(npos):
        total = 0.0
        lo = hi = 0
        for k in range(1 if strict else v):
            ci = _find(t.ctx_codes, t.level_off[k], t.level_len[k],
                       _context(out, r, n, u, v - 1 - k, g))
            if ci < 0:
                continue
            lo, hi = t.ctx_start[ci], t.ctx_end[ci]
            work.tbuf[0] = _reserve(work.tbuf[0], toff, hi - lo)
            tb = work.tbuf[0]
            for e in range(lo, hi):
                x = t.q[e] if n == 0 else big_r[t.head[e]] * t.m[e]
                tb[toff + e - lo] = x
                total += x
            if total > 0.0:
                repairs += k > 0
                break
        if total == 0.0:
            if strict:
                if n > 0:
                    _clear(big_r, t.tail, pos_lo[n - 1], pos_hi[n - 1])
                return False, 0
            # nothing continues the row: restart the bottom-row chain here
            ci = t.level_off[v - 1]
            lo, hi = t.ctx_start[ci], t.ctx_end[ci]
            work.tbuf[0] = _reserve(work.tbuf[0], toff, hi - lo)
            tb = work.tbuf[0]
            for e in range(lo, hi):
                tb[toff + e - lo] = t.q[e]
                total += t.q[e]
            repairs += 1
        if n > 0:
            _clear(big_r, t.tail, pos_lo[n - 1], pos_hi[n - 1])
        tb = work.tbuf[0]
        inv = 1.0 / total
        for e in range(lo, hi):
            big_r[t.tail[e]] += tb[toff + e - lo] * inv
        pos_lo[n], pos_hi[n], pos_off[n] = lo, hi, toff
        toff += hi - lo
    _clear(big_r, t.tail, pos_lo[npos - 1], pos_hi[npos - 1])
    _backward(out, r, t, work, npos, state)
    return True, repairs


@njit(cache=True, nogil=True)
def _clear(big_r, tail, lo, hi):
    """Zero what entries lo..hi wrote into R: sparsely, or all of R when that is shorter."""
    if len(big_r) <= hi - lo:
        big_r[:] = 0.0
    else:
        for e in range(lo, hi):
            big_r[tail[e]] = 0.0


@njit(cache=True, nogil=True)
def _backward(out, r, t, work, npos, state):
    """Draw the last window from T, then each earlier point given the u-1 points after it."""
    g, u = t.levels, t.u
    gu1 = g ** (u - 1)
    tb = work.tbuf[0]
    n = npos - 1
    e = _pick(tb, work.pos_off[n], work.pos_lo[n], work.pos_hi[n], state)
    code = t.bcode[e]
    for j in range(u - 1, -1, -1):
        out[r, n + j] = code % g
        code //= g
    for n in range(npos - 2, -1, -1):
        need = 0
        for j in range(n + 1, n + u):
            need = need * g + out[r, j]
        lo, hi = work.pos_lo[n], work.pos_hi[n]
        a = _lower_bound(t.rot, lo, hi, need * g)
        b = _lower_bound(t.rot, a, hi, need * g + g)
        off = work.pos_off[n] + a - lo
        if a == b or _mass(tb, off, b - a) == 0.0:
            a, b, off = lo, hi, work.pos_off[n]  # the far side was a restart: any point
        out[r, n] = t.bcode[_pick(tb, off, a, b, state)] // gu1


@njit(cache=True, nogil=True)
def _mass(tb, off, count):
    total = 0.0
    for i in range(off, off + count):
        total += tb[i]
    return total


@njit(cache=True, nogil=True)
def _pick(tb, off, lo, hi, state):
    """Draw an entry of [lo, hi) with probability ∝ its weight tb[off + e - lo]."""
    x = _uniform(state) * _mass(tb, off, hi - lo)
    last = lo
    for e in range(lo, hi):
        w = tb[off + e - lo]
        if w > 0.0:
            last = e
            x -= w
            if x < 0.0:
                return e
    return last


class _Work(NamedTuple):
    big_r: np.ndarray
    tbuf: list
    pos_lo: np.ndarray
    pos_hi: np.ndarray
    pos_off: np.ndarray


@njit(cache=True, nogil=True)
def _sample_rows(out, r0, r1, t, state, max_redraws):
    """Rows r0..r1-1 (the first call, r0 = 0, also draws the first v rows)."""
    w = out.shape[1]
    npos = w - t.u + 1
    work = _Work(np.zeros(t.levels ** (t.u - 1), np.float64), [np.empty(npos * 8, np.float64)],
                 np.empty(npos, np.int64), np.empty(npos, np.int64), np.empty(npos, np.int64))
    saved = np.empty((MAX_REDRAW_DEPTH, w), np.uint8)
    repairs = redraws = 0
    start = r0
    if r0 == 0:
        repairs += _first_rows(out, t, state)
        start = t.v
    for r in range(start, r1):
        ok, rep = _sample_row(out, r, True, t, state, work)
        tries = 0
        while not ok and tries < max_redraws and t.v > 1:
            # redraw the rows above, going deeper as tries fail (row v-1 is the highest one
            # that has v-1 rows above it)
            depth = min(1 + tries // 4, MAX_REDRAW_DEPTH, r - t.v + 1)
            tries += 1
            redraws += 1
            saved[:depth] = out[r - depth:r]
            ok = True
            for ra in range(r - depth, r):
                ok, rep = _sample_row(out, ra, True, t, state, work)
                if not ok:
                    break
            if not ok:
                out[r - depth:r] = saved[:depth]
                continue
            ok, rep = _sample_row(out, r, True, t, state, work)
        if not ok:
            ok, rep = _sample_row(out, r, False, t, state, work)
            repairs += rep
    return repairs, redraws
