"""Photographic tone: a level matrix shown with the photo's own greys and colours.

The document stays levels; this renders them. Each output point takes the pixel of a photo
point whose level context (the 3×3 levels around it) is the same, chosen in scan order among
a few candidates — those continuing the photo pixels of its left and upper neighbours (so tone
runs on smoothly across a level region) and a few drawn at random from the photo points with
that context (so no region is one long copy) — by the best match with the greys already
rendered around it. A context the photo never showed backs off to the 4 edge neighbours, then
to the point's own level. Seeded and exact: the same levels, tone and seed give the same image.
"""

from __future__ import annotations

import threading
from typing import NamedTuple

import numpy as np
from numba import njit

from ..errors import InputError
from ..markov.synthesis import uniform

RANDOM_CANDIDATES = 8      # drawn from the photo points sharing the context
FRESH_START = 1 / 64       # chance that a point considers only fresh candidates (no long copies)
COHERENCE = 0.5           # a continuing candidate's mismatch counts this much (Ashikhmin)
HALF = 2                   # the causal neighbourhood compared: rows above and left, ±HALF
DRAWS = 1 + RANDOM_CANDIDATES   # random numbers per point, so point n starts at draw DRAWS·n
GAMMA = 0x9E3779B97F4A7C15  # SplitMix64's step (markov.synthesis.uniform)
LANE_ROWS = 8              # the two-lane wavefront: strips of this many rows,
LANE_COLUMNS = 128         # cut in chunks this wide (each row's chunk HALF columns left of
                           # the row above's: a point reads the row above up to HALF columns on)


class ToneIndex(NamedTuple):
    """The photo's points grouped by level context, three ways (3×3, 4 neighbours, own level)."""

    codes: tuple         # per back-off: every photo point's context code (row-major)
    keys: tuple          # per back-off: sorted unique context codes
    starts: tuple        # per back-off: first index of each code's points in ``points``, + end
    points: tuple        # per back-off: photo point indices sorted by context


def context_codes(levels: np.ndarray, num_levels: int, wrap: bool = False) -> tuple:
    """The three context codes of every point, row-major: beyond the border the border point
    repeats, or (``wrap``) the opposite side continues."""
    lv = np.ascontiguousarray(levels, dtype=np.uint8)
    codes = np.empty((3, lv.size), np.int64)
    _context_codes(lv, np.int64(num_levels), codes, bool(wrap))
    return tuple(codes)


@njit(cache=True, nogil=True, inline="always")
def _at(k, n, wrap):
    """Index k of an axis of length n, off the axis: clamped, or wrapped."""
    return k % n if wrap else min(max(k, 0), n - 1)


@njit(cache=True, nogil=True)
def _context_codes(lv, g, codes, wrap):
    h, w = lv.shape
    for i in range(h):
        for j in range(w):
            nine = np.int64(0)
            for di in range(-1, 2):
                y = _at(i + di, h, wrap)
                for dj in range(-1, 2):
                    nine = nine * g + lv[y, _at(j + dj, w, wrap)]
            five = np.int64(lv[_at(i - 1, h, wrap), j])
            five = five * g + lv[i, _at(j - 1, w, wrap)]
            five = five * g + lv[i, j]
            five = five * g + lv[i, _at(j + 1, w, wrap)]
            five = five * g + lv[_at(i + 1, h, wrap), j]
            n = i * w + j
            codes[0, n], codes[1, n], codes[2, n] = nine, five, lv[i, j]


def tone_index(levels: np.ndarray, num_levels: int) -> ToneIndex:
    """Group the photo's points by their level contexts (sorted, for binary search)."""
    codes = context_codes(levels, num_levels)
    keys, starts, points = [], [], []
    for code in codes:
        order = np.argsort(code, kind="stable")
        unique, first = np.unique(code[order], return_index=True)
        keys.append(unique)
        starts.append(np.append(first, len(order)).astype(np.int64))
        points.append(order.astype(np.int64))
    return ToneIndex(codes, tuple(keys), tuple(starts), tuple(points))


def render(levels, num_levels: int, photo_levels, photo_grey, photo_pixels=None, *,
           seed: int = 0, index: ToneIndex | None = None, wrap: bool = False):
    """Render ``levels`` (H, W) with the photo: returns (grey (H, W) uint8, pixels or None).

    ``photo_levels`` (h, w) are the photo's levels at the same G, ``photo_grey`` its greys (uint8)
    and ``photo_pixels`` its colours (h, w, 3) uint8, or None for a grey photo. ``wrap``: the
    levels tile, and so does the picture (contexts and matches read across the seams).
    """
    drawn = rendering(levels, num_levels, photo_levels, photo_grey, photo_pixels, seed=seed,
                      index=index, wrap=wrap)
    return drawn.grey, drawn.pixels


class Rendered(NamedTuple):
    """A tone picture and what it was drawn from."""

    grey: np.ndarray
    pixels: np.ndarray | None
    source: np.ndarray       # the photo point (row-major index) each point shows
    levels: np.ndarray       # the levels drawn
    seed: int
    wrap: bool

    @property
    def picture(self) -> np.ndarray:
        """The colours when the photo has them, else the greys."""
        return self.grey if self.pixels is None else self.pixels


def rendering(levels, num_levels: int, photo_levels, photo_grey, photo_pixels=None, *,
              seed: int = 0, index: ToneIndex | None = None, wrap: bool = False,
              before: Rendered | None = None) -> Rendered:
    """:func:`render`, keeping what the next rendering can start from. ``before``: the same
    photo's rendering of levels that differ from these only from some row on (an edit): the
    rows above it come out the same (a point reads only the points before it in scan order,
    and its random numbers are fixed by its place), so they are copied, not drawn again."""
    levels = np.ascontiguousarray(levels, dtype=np.uint8)
    start = first_row_to_draw(before, levels, seed, wrap)
    if start == len(levels):
        return before
    renderer = Renderer(levels.shape, num_levels, photo_levels, photo_grey, photo_pixels,
                        seed=seed, index=index, wrap=wrap)
    if start:
        renderer.resume(before, start)
    renderer.advance(levels, len(levels))
    grey, pixels = renderer.result()
    return Rendered(grey, pixels, renderer.source, levels.copy(), int(seed), bool(wrap))


def first_row_to_draw(before: Rendered | None, levels: np.ndarray, seed: int,
                      wrap: bool) -> int:
    """The first row whose picture a change of levels since ``before`` can alter: the row
    above the first changed one (its 3×3 context reads it); on a tiling picture, the first
    row when the change reaches the first or last row (each is the other's context). The
    height: nothing changed."""
    if (before is None or before.levels.shape != levels.shape or before.seed != int(seed)
            or before.wrap != bool(wrap)):
        return 0
    rows = np.flatnonzero((before.levels != levels).any(axis=1))
    if rows.size == 0:
        return len(levels)
    if wrap and (rows[0] == 0 or rows[-1] == len(levels) - 1):
        return 0
    return max(0, int(rows[0]) - 1)


class Renderer:
    """The tone drawn band by band, as a synthesis makes rows final: the picture is the same
    as one :func:`render` of the finished levels, and the work can run beside the synthesis."""

    def __init__(self, shape, num_levels: int, photo_levels, photo_grey, photo_pixels=None, *,
                 seed: int = 0, index: ToneIndex | None = None, wrap: bool = False):
        shape = tuple(shape)
        if len(shape) != 2 or 0 in shape:
            raise InputError(f"tone needs a non-empty matrix of levels 0..{num_levels - 1}")
        self.num_levels = num_levels
        self.photo_grey = np.ascontiguousarray(photo_grey, dtype=np.uint8)
        self.photo_pixels = photo_pixels
        self.index = index or tone_index(photo_levels, num_levels)
        self.state0 = np.random.SeedSequence([int(seed), 0x70E]).generate_state(1, np.uint64)[0]
        self.source = np.empty(shape, np.int64)
        self.grey = np.empty(shape, np.uint8)
        self.done = 0
        self.wrap = bool(wrap)

    def resume(self, before: Rendered, start: int) -> None:
        """Take rows 0..start-1 as ``before`` drew them (see :func:`rendering`)."""
        self.source[:start] = before.source[:start]
        self.grey[:start] = before.grey[:start]
        self.done = start

    def advance(self, levels, final: int) -> None:
        """Render the rows whose 3×3 context lies in ``levels``' rows 0..final-1 (all of them
        once ``final`` is the height; a tiling picture waits for that: its first row's context
        holds the last row)."""
        h = len(self.grey)
        stop = h if final >= h else self.done if self.wrap else max(self.done, final - 1)
        if stop <= self.done:
            return
        a, b = (0, h) if self.wrap else (max(0, self.done - 1), min(h, stop + 1))
        band = np.ascontiguousarray(levels[a:b], dtype=np.uint8)
        if band.max() >= self.num_levels:
            raise InputError(f"tone needs a matrix of levels 0..{self.num_levels - 1}")
        w = band.shape[1]
        first, last = (self.done - a) * w, (stop - a) * w
        codes = tuple(c[first:last] for c in context_codes(band, self.num_levels, self.wrap))
        rows, base = (self.done, stop), self.done
        if self.wrap or stop - self.done < 2 * LANE_ROWS or w < 2 * LANE_COLUMNS:
            self._chunk(codes, base, rows, (0, w), 0)
        else:
            _two_lanes(lambda r, c: self._chunk(codes, base, r, c, HALF), rows, w)
        self.done = stop

    def _chunk(self, codes, base, rows, columns, skew) -> None:
        """Render rows (i0, i1), row i0 + k over columns (j0, j1) moved ``skew``·k left
        (``codes``: the contexts from row ``base`` on)."""
        ix = self.index
        _render(codes, ix.codes, ix.keys, ix.starts, ix.points, self.photo_grey, self.source,
                self.grey, self.state0, base, rows[0], rows[1], columns[0], columns[1], skew,
                self.wrap)

    def result(self):
        """(grey, pixels or None) of the rows rendered so far (all, after the last advance)."""
        pixels = None
        if self.photo_pixels is not None:
            flat = np.asarray(self.photo_pixels).reshape(-1, self.photo_pixels.shape[-1])
            pixels = flat[self.source.ravel()].reshape(*self.grey.shape, flat.shape[-1])
        return self.grey, pixels


def _two_lanes(run, rows, width: int) -> None:
    """``run((i0, i1), (j0, j1))`` over strips of LANE_ROWS rows and chunks of LANE_COLUMNS
    columns, even strips here and odd ones on a second thread. A strip's chunk waits for the
    strip above to be far enough on (its last row reads that strip's last rows up to HALF
    columns past its end, and those rows' chunks lie up to HALF·(LANE_ROWS-1) columns left):
    every point sees what it would see in scan order, so the picture is the same."""
    i0, i1 = rows
    strips = [(r, min(i1, r + LANE_ROWS)) for r in range(i0, i1, LANE_ROWS)]
    chunks = -(-width // LANE_COLUMNS)
    lead = -(-(HALF * (LANE_ROWS - 1) + HALF) // LANE_COLUMNS)
    done = [0] * len(strips)
    failed = []
    ready = threading.Condition()

    def lane(first: int) -> None:
        try:
            for s in range(first, len(strips), 2):
                for c in range(chunks):
                    need = min(chunks, c + 1 + lead)
                    with ready:
                        ready.wait_for(lambda: failed or s == 0 or done[s - 1] >= need)
                    if failed:
                        return
                    last = c == chunks - 1
                    run(strips[s], (c * LANE_COLUMNS,
                                    width + HALF * LANE_ROWS if last else (c + 1) * LANE_COLUMNS))
                    with ready:
                        done[s] = c + 1
                        ready.notify_all()
        except BaseException as error:      # stop the other lane, raise it on this thread
            with ready:
                failed.append(error)
                ready.notify_all()

    helper = threading.Thread(target=lane, args=(1,), name="tone-lane")
    helper.start()
    lane(0)
    helper.join()
    if failed:
        raise failed[0]


@njit(cache=True, nogil=True)
def _bucket(keys, starts, key):
    """(first, end) of the photo points with context ``key``; (0, 0) if the photo has none."""
    a = np.searchsorted(keys, key)
    if a < len(keys) and keys[a] == key:
        return starts[a], starts[a + 1]
    return 0, 0


@njit(cache=True, nogil=True)
def _distance(grey, i, j, photo, pi, pj, best):
    """Squared grey differences over the rendered causal neighbourhood of (i, j), against the
    photo around (pi, pj); stops once past ``best``. Points off either picture are skipped."""
    w = grey.shape[1]
    pw = photo.shape[1]
    total = np.int64(0)
    for di in range(-HALF, 1):
        y, py = i + di, pi + di
        if y < 0 or py < 0:
            continue
        for dj in range(-HALF, HALF + 1 if di < 0 else 0):
            x, px = j + dj, pj + dj
            if 0 <= x < w and 0 <= px < pw:
                d = np.int64(grey[y, x]) - np.int64(photo[py, px])
                total += d * d
        if total > best:
            return total
    return total


@njit(cache=True, nogil=True)
def _distance_wrap(grey, i, j, photo, pi, pj, best):
    """_distance on a tiling picture: every rendered point of the (2·HALF+1)² square around
    (i, j), read across the seams (the last rows and columns meet the first ones). Away from
    the seams the rendered points are the causal half, so _distance gives the same total."""
    h, w = grey.shape
    if HALF <= i < h - HALF and HALF <= j < w - HALF:
        return _distance(grey, i, j, photo, pi, pj, best)
    ph, pw = photo.shape
    here = i * w + j
    total = np.int64(0)
    for di in range(-HALF, HALF + 1):
        py = pi + di
        if py < 0 or py >= ph:
            continue
        y = (i + di) % h
        for dj in range(-HALF, HALF + 1):
            px = pj + dj
            x = (j + dj) % w
            if 0 <= px < pw and y * w + x < here:
                d = np.int64(grey[y, x]) - np.int64(photo[py, px])
                total += d * d
        if total > best:
            return total
    return total


@njit(cache=True, nogil=True)
def _render(out_codes, photo_codes, keys, starts, points, photo, source, grey, state0, base,
            i0, i1, j0, j1, skew, wrap):
    """Rows i0..i1-1, row i0 + k over columns j0..j1-1 moved skew·k left (clipped to the
    picture), in scan order: coherent and fresh candidates of the right context, the best
    match wins. ``out_codes`` hold the contexts from row ``base`` on. Point n = i·w + j draws
    from SplitMix64 at state0 + DRAWS·n·GAMMA, whichever order the chunks run in. ``wrap``:
    neighbours across the seams count once rendered."""
    h, w = grey.shape
    ph, pw = photo.shape
    cand = np.empty(4 + RANDOM_CANDIDATES, np.int64)
    state = np.empty(1, np.uint64)
    for i in range(i0, i1):
        ja, jb = max(0, j0 - skew * (i - i0)), min(w, j1 - skew * (i - i0))
        state[0] = state0 + np.uint64(DRAWS) * np.uint64(i * w + ja) * np.uint64(GAMMA)
        for j in range(ja, jb):
            n = (i - base) * w + j
            level, a, b = 0, 0, 0
            while level < 3:
                a, b = _bucket(keys[level], starts[level], out_codes[level][n])
                if a < b:
                    break
                level += 1
            count = 0
            if uniform(state) >= FRESH_START:       # continue the neighbours' photo pixels
                for di, dj in ((0, -1), (-1, 0), (-1, -1), (-1, 1)):
                    y, x = i + di, j + dj
                    if wrap:
                        y, x = y % h, x % w
                    if 0 <= y and 0 <= x < w and y * w + x < i * w + j:
                        py, px = source[y, x] // pw - di, source[y, x] % pw - dj
                        if 0 <= py < ph and 0 <= px < pw:
                            s = py * pw + px
                            if level == 3 or photo_codes[level][s] == out_codes[level][n]:
                                cand[count] = s
                                count += 1
            coherent = count
            for _ in range(RANDOM_CANDIDATES):     # fresh ones (anywhere: a level unseen)
                if level == 3:
                    cand[count] = min(np.int64(uniform(state) * ph * pw), ph * pw - 1)
                else:
                    cand[count] = points[level][min(a + np.int64(uniform(state) * (b - a)), b - 1)]
                count += 1
            best, chosen = np.inf, cand[0]
            for k in range(count):
                weight = COHERENCE if k < coherent else 1.0
                if wrap:
                    d = weight * _distance_wrap(grey, i, j, photo, cand[k] // pw, cand[k] % pw,
                                                best / weight)
                else:
                    d = weight * _distance(grey, i, j, photo, cand[k] // pw, cand[k] % pw,
                                           best / weight)
                if d < best:
                    best, chosen = d, cand[k]
            source[i, j] = chosen
            grey[i, j] = photo[chosen // pw, chosen % pw]
