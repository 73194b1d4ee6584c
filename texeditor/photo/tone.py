"""Photographic tone: a level matrix shown with the photo's own greys and colours.

The document stays levels; this renders them. Each output point takes the pixel of a photo
point whose level context (the 3×3 levels around it) is the same, chosen in scan order among
a few candidates — those continuing the photo pixels of its left and upper neighbours (so tone
runs on smoothly across a level region) and a few drawn at random from the photo points with
that context (so no region is one long copy) — by the best match with the greys already
rendered around it. A context the photo never showed backs off to the 4 edge neighbours, then
to the point's own level. Seeded and exact: the same levels, tone and seed give the same image.

A tiling picture (``wrap``) reads its neighbours across the seams. It is drawn one of two ways,
kept apart so older recipes show the same picture (the synthesis's seam closure says which):
TILED scans from row 0 and reads the end of the row above at each row's start, so every point
waits for the one before it: one core, once the levels are closed. TILED_LANES scans a torus
turned one row and one column (so its first row and column have final contexts first) and
leaves its last EDGE_COLUMNS columns, which hold the side seam, for the end: the rest runs on two
lanes beside the synthesis as a plain picture does, and the seam columns then match the points
on both sides of them. (A torus's closure redraws the side seam's columns from top to bottom
and the last rows, after every row is drawn: rows drawn before from levels that changed are
drawn again.)
"""

from __future__ import annotations

import threading
from typing import NamedTuple

import numpy as np
from numba import njit

from ..errors import Cancelled, InputError
from ..markov.synthesis import uniform
from .finish import finished, radial_power

RANDOM_CANDIDATES = 8      # drawn from the photo points sharing the context
FRESH_START = 1 / 64       # chance that a point considers only fresh candidates (no long copies)
COHERENCE = 0.5           # a continuing candidate's mismatch counts this much (Ashikhmin)
HALF = 2                   # the causal neighbourhood compared: rows above and left, ±HALF
DRAWS = 1 + RANDOM_CANDIDATES   # random numbers per point, so point n starts at draw DRAWS·n
GAMMA = 0x9E3779B97F4A7C15  # SplitMix64's step (markov.synthesis.uniform)
PLAIN, TILED, TILED_LANES = 0, 1, 2   # ``wrap``: how (and whether) a picture tiles
BALANCED = 4               # or'ed into ``wrap``: each level's greys keep the photo's histogram of
                           # that level's greys (_penalties); pictures before it were drawn without
FINISHED = 8               # or'ed into ``wrap``: the picture's pixel-scale power is brought to the
                           # photo's (photo.finish; since SynthesizeScales 11)
GREY_BINS = 32             # ... counted in bins of 8 greys
BALANCE = 2.0              # ... a bin drawn x times its photo share too often (counted over the
                           # strips drawn two strips above) weighs its match exp(BALANCE · x)
BALANCE_ROWS = 8           # ... strips of this many rows. Two lanes must cut strips of LANE_ROWS
                           # equal to it or at most (BALANCE_ROWS + 1) // 2: then every row a
                           # strip's weights count is drawn before any row of the strip is
EDGE_COLUMNS = 12          # TILED_LANES: the columns drawn last (a torus's closure redraws the
                           # last 6 from top to bottom; one more is read by the first's context)
LANE_ROWS = 8              # the two-lane wavefront: strips of this many rows,
LANE_COLUMNS = 128         # cut in chunks this wide at most (each row's chunk HALF columns left
                           # of the row above's: a point reads the row above up to HALF on)
LANE_CHUNKS = 4            # ... and in this many at least: the lane below starts two chunks
                           # behind, so with two chunks a strip the lanes would take turns
LANE_WIDTH = 128           # narrower rows are drawn on one lane (chunks too small to share)
ONE_LANE_ROWS = 32         # beside a synthesis: rows drawn at a time on one lane (_rows)
GROUPED_SPACE = 2**22      # context codes below this are grouped by counting (tone_index)
DIRECT_SPACE = 2**21       # 3×3 context codes below this (G ≤ 5) find their photo points in a
                           # look-up table (ToneIndex.direct), not by a binary search
NEIGHBOURS = 2 * HALF * (HALF + 1)   # the causal neighbourhood's points (_gather)


class ToneIndex(NamedTuple):
    """The photo's points grouped by level context, three ways (3×3, 4 neighbours, own level)."""

    codes: tuple         # per back-off: every photo point's context code (row-major)
    keys: tuple          # per back-off: sorted unique context codes
    starts: tuple        # per back-off: first index of each code's points in ``points``, + end
    points: tuple        # per back-off: photo point indices sorted by context
    shares: np.ndarray | None = None   # each level's grey histogram (_grey_shares), if the
    #                                    photo's greys were given
    direct: np.ndarray = np.empty(0, np.int32)   # 3×3 code → its place in keys[0] (-1: none),
    #                                              when the codes are below DIRECT_SPACE
    power: np.ndarray | None = None    # the photo's greys' radial power (finish.radial_power),
    #                                    if they were given


def context_codes(levels: np.ndarray, num_levels: int, wrap: bool = False) -> tuple:
    """The three context codes of every point, row-major: beyond the border the border point
    repeats, or (``wrap``) the opposite side continues."""
    lv = np.ascontiguousarray(levels, dtype=np.uint8)
    codes = np.empty((3, lv.size), _code_type(num_levels))
    _context_codes(lv, np.int64(num_levels), codes, bool(wrap))
    return tuple(codes)


def _code_type(num_levels: int):
    """int32 for the context codes when the 3×3 code fits it (up to 10 levels): the tone reads
    them, and the photo points grouped by them, at random, so half the bytes is a tenth or
    more off its time."""
    return np.int32 if num_levels ** 9 < 2**31 else np.int64


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


def tone_index(levels: np.ndarray, num_levels: int, grey=None) -> ToneIndex:
    """Group the photo's points by their level contexts (sorted, for binary search); with the
    photo's ``grey``, keep each level's grey histogram too (a balanced tone reads it)."""
    codes = context_codes(levels, num_levels)
    keys, starts, points = [], [], []
    for code, space in zip(codes, (num_levels ** 9, num_levels ** 5, num_levels)):
        unique, first, order = _grouped(code, space)
        keys.append(unique.astype(code.dtype, copy=False))
        starts.append(np.append(first, len(order)).astype(np.int64))
        points.append(order.astype(np.int32 if code.size < 2**31 else np.int64))
    shares = None if grey is None else _grey_shares(levels, np.asarray(grey, np.uint8),
                                                    num_levels)
    direct = np.empty(0, np.int32)
    if num_levels ** 9 <= DIRECT_SPACE:
        direct = np.full(num_levels ** 9, -1, np.int32)
        direct[keys[0]] = np.arange(len(keys[0]), dtype=np.int32)
    power = None if grey is None else radial_power(grey)
    return ToneIndex(codes, tuple(keys), tuple(starts), tuple(points), shares, direct, power)


def _grouped(code: np.ndarray, space: int):
    """(the codes present, sorted; where each starts in the order; the point indices sorted by
    code, stably): a counting sort when the codes are below a small ``space`` (O(points), where
    a sort of a 12-megapixel photo's codes takes a second), else a stable argsort."""
    if space > GROUPED_SPACE:
        order = np.argsort(code, kind="stable")
        unique, first = np.unique(code[order], return_index=True)
        return unique, first, order
    counts = np.bincount(code, minlength=space)
    slots = np.cumsum(counts) - counts          # where each code's points start
    unique = np.flatnonzero(counts)
    return unique, slots[unique], _stable_scatter(code, slots.copy())


@njit(cache=True, nogil=True)
def _stable_scatter(code, slots):
    """Point indices in order of code, in index order within a code (``slots``: each code's
    first place, moved on as it fills)."""
    order = np.empty(len(code), np.int64)
    for i in range(len(code)):
        order[slots[code[i]]] = i
        slots[code[i]] += 1
    return order


def render(levels, num_levels: int, photo_levels, photo_grey, photo_pixels=None, *,
           seed: int = 0, index: ToneIndex | None = None, wrap: bool = False):
    """Render ``levels`` (H, W) with the photo: returns (grey (H, W) uint8, pixels or None).

    ``photo_levels`` (h, w) are the photo's levels at the same G, ``photo_grey`` its greys (uint8)
    and ``photo_pixels`` its colours (h, w, 3) uint8, or None for a grey photo. ``wrap``: the
    levels tile, and so does the picture (contexts and matches read across the seams; TILED or
    TILED_LANES say which way, True is TILED); with BALANCED or'ed in, each level's greys keep
    the photo's histogram of them (the way pictures are drawn since SynthesizeScales 4); with
    FINISHED, the picture's pixel-scale power is the photo's (since SynthesizeScales 11).
    """
    drawn = rendering(levels, num_levels, photo_levels, photo_grey, photo_pixels, seed=seed,
                      index=index, wrap=wrap)
    return drawn.finished or (drawn.grey, drawn.pixels)


class Rendered(NamedTuple):
    """A tone picture and what it was drawn from."""

    grey: np.ndarray         # as drawn (a next rendering starts from these)
    pixels: np.ndarray | None
    source: np.ndarray       # the photo point (row-major index) each point shows
    levels: np.ndarray       # the levels drawn
    seed: int
    wrap: int                # PLAIN, TILED or TILED_LANES, maybe | BALANCED | FINISHED
    finished: tuple | None = None    # FINISHED: (grey, pixels) as shown

    @property
    def picture(self) -> np.ndarray:
        """What is shown: the colours when the photo has them, else the greys (finished)."""
        grey, pixels = self.finished or (self.grey, self.pixels)
        return grey if pixels is None else pixels


def rendering(levels, num_levels: int, photo_levels, photo_grey, photo_pixels=None, *,
              seed: int = 0, index: ToneIndex | None = None, wrap: bool = False,
              before: Rendered | None = None) -> Rendered:
    """:func:`render`, keeping what the next rendering can start from. ``before``: the same
    photo's rendering of levels that differ from these only from some row on (an edit): the
    rows above it come out the same (a point reads only the points before it in scan order,
    and its random numbers are fixed by its place), so they are copied, not drawn again."""
    levels = np.ascontiguousarray(levels, dtype=np.uint8)
    start = first_row_to_draw(before, levels, seed, wrap)
    if start == len(levels) and np.array_equal(before.levels, levels):
        return before
    renderer = Renderer(levels.shape, num_levels, photo_levels, photo_grey, photo_pixels,
                        seed=seed, index=index, wrap=wrap)
    if start:
        renderer.resume(before, start)
    renderer.advance(levels, len(levels))
    grey, pixels = renderer.result()
    shown = as_shown(grey, pixels, wrap, renderer.index, photo_grey)
    return Rendered(grey, pixels, renderer.sources(), levels.copy(), int(seed), int(wrap),
                    None if shown[0] is grey else shown)


def as_shown(grey, pixels, wrap, index: ToneIndex | None, photo_grey) -> tuple:
    """(grey, pixels) as shown: finished (photo.finish) when ``wrap`` has FINISHED."""
    if not int(wrap) & FINISHED:
        return grey, pixels
    power = getattr(index, "power", None)          # kept with an index built from the greys
    if power is None:
        power = radial_power(np.asarray(photo_grey, np.uint8))
    return finished(grey, pixels, power, bool(int(wrap) & ~(BALANCED | FINISHED)))


def first_row_to_draw(before: Rendered | None, levels: np.ndarray, seed: int, wrap) -> int:
    """The first row, in drawing order, whose picture a change of levels since ``before``
    can alter: the row above the first changed one (its 3×3 context reads it); on a tiling
    picture, the first row when the change reaches the first or last row drawn (each is the
    other's context). The height: nothing changed. (TILED_LANES: of the points drawn before
    the seam columns, which are drawn again after any change.)"""
    if (before is None or before.levels.shape != levels.shape or before.seed != int(seed)
            or before.wrap != int(wrap)):
        return 0
    way = int(wrap) & ~(BALANCED | FINISHED)
    if way != TILED_LANES:
        return _first_to_redraw((before.levels != levels).any(axis=1), bool(way))
    read = _read_before_seam(levels.shape[1])
    changed = (_turned(before.levels) != _turned(levels))[:, read].any(axis=1)
    return _first_to_redraw(changed, True)


def _first_to_redraw(changed: np.ndarray, wrap: bool) -> int:
    """first_row_to_draw, from which rows (in drawing order) changed."""
    rows = np.flatnonzero(changed)
    if rows.size == 0:
        return len(changed)
    if wrap and (rows[0] == 0 or rows[-1] == len(changed) - 1):
        return 0
    return max(0, int(rows[0]) - 1)


def _seam_start(w: int) -> int:
    """TILED_LANES: the first of the columns drawn last, in drawing order."""
    return max(0, w - EDGE_COLUMNS)


def _read_before_seam(w: int) -> np.ndarray:
    """TILED_LANES: the columns (drawing order) whose levels the points drawn before the seam
    columns read: their own, the next one, and the last (the first column's left neighbour)."""
    return np.unique(np.r_[0:min(w, _seam_start(w) + 1), w - 1])


def _turned(a: np.ndarray) -> np.ndarray:
    """TILED_LANES's drawing order: the picture turned one row and one column."""
    return np.roll(a, (-1, -1), axis=(0, 1))


def _unturned(a: np.ndarray) -> np.ndarray:
    return np.roll(a, (1, 1), axis=(0, 1))


class Renderer:
    """The tone drawn band by band, as a synthesis makes rows final: the picture is the same
    as one :func:`render` of the finished levels, and the work can run beside the synthesis.

    Its arrays hold the points in drawing order (TILED_LANES: the picture turned, _turned)."""

    def __init__(self, shape, num_levels: int, photo_levels, photo_grey, photo_pixels=None, *,
                 seed: int = 0, index: ToneIndex | None = None, wrap=False, cancel=None):
        """``cancel()`` returning True stops the rendering between chunks (Cancelled)."""
        shape = tuple(shape)
        if len(shape) != 2 or 0 in shape:
            raise InputError(f"tone needs a non-empty matrix of levels 0..{num_levels - 1}")
        way = int(wrap)
        if way & ~(BALANCED | FINISHED) not in (PLAIN, TILED, TILED_LANES) or way < 0:
            raise InputError(f"a tone tiles in no way {wrap!r}")
        self.num_levels = num_levels
        self.cancel = cancel
        self.beside = None          # beside() True: a synthesis is drawing the levels (one lane)
        self.photo_grey = np.ascontiguousarray(photo_grey, dtype=np.uint8)
        self.photo_pixels = photo_pixels
        self.index = index or tone_index(photo_levels, num_levels)
        self.state0 = np.random.SeedSequence([int(seed), 0x70E]).generate_state(1, np.uint64)[0]
        self.source = np.empty(shape, np.int64)
        self.grey = np.empty(shape, np.uint8)
        self.done = 0
        self.wrap = way & ~(BALANCED | FINISHED)
        self.balanced = bool(way & BALANCED)
        rows = shape[0] if self.balanced else 0
        self.shares = np.zeros((num_levels, GREY_BINS))
        if self.balanced:
            self.shares = (self.index.shares if self.index.shares is not None else
                           _grey_shares(photo_levels, self.photo_grey, num_levels))
        self.row_counts = np.zeros((rows, num_levels, GREY_BINS))    # levels' greys drawn, by row
        self.above = np.zeros((-(-rows // BALANCE_ROWS), num_levels, GREY_BINS))  # before a strip
        self.turned = self.wrap == TILED_LANES
        self.seam = _seam_start(shape[1]) if self.turned else shape[1]
        if self.turned:                              # the levels drawn from (drawing order),
            self.seen = np.zeros(shape, np.uint8)    # checked at the end, and those the seam
            self.seen_rows = np.zeros(shape[0], bool)    # columns were drawn for
            self.closed = None

    def resume(self, before: Rendered, start: int) -> None:
        """Take rows 0..start-1 (drawing order) as ``before`` drew them (see rendering)."""
        source, grey = before.source, before.grey
        if self.turned:
            source, grey = _turned(source), _turned(grey)
            self.seen[:] = _turned(before.levels)
            self.seen_rows[:] = True
        self.source[:start] = source[:start]
        self.grey[:start] = grey[:start]
        self.done = start
        if self.balanced:
            self._recount(self.seen if self.turned else before.levels)

    def _recount(self, levels) -> None:
        """The greys counted for balance (BALANCED) as rows 0..done-1 hold them (drawing
        order; the seam columns drawn last are not counted): after a resume, or rows to be
        drawn again."""
        rows, cols = self.done, self.seam
        self.row_counts[:] = 0
        where = (np.repeat(np.arange(rows), cols), levels[:rows, :cols].ravel(),
                 self.grey[:rows, :cols].ravel() // (256 // GREY_BINS))
        np.add.at(self.row_counts, where, 1)
        strips = np.zeros_like(self.above)
        np.add.at(strips, np.arange(len(self.row_counts)) // BALANCE_ROWS, self.row_counts)
        self.above[1:] = np.cumsum(strips, axis=0)[:-1]

    def advance(self, levels, final: int) -> None:
        """Render the rows whose 3×3 context lies in ``levels``' rows 0..final-1 (all of them
        once ``final`` is the height). TILED waits for that (its first row's context holds the
        last row). TILED_LANES draws on; once ``final`` is the height, the rows drawn from
        levels that changed since are drawn again, then the seam columns."""
        h = len(self.grey)
        if self.turned:
            self._advance_turned(levels, final)
            return
        stop = h if final >= h else self.done if self.wrap else max(self.done, final - 1)
        if stop <= self.done:
            return
        a, b = (0, h) if self.wrap else (max(0, self.done - 1), min(h, stop + 1))
        band = self._checked(levels[a:b])
        w = band.shape[1]
        first, last = (self.done - a) * w, (stop - a) * w
        codes = tuple(c[first:last] for c in context_codes(band, self.num_levels, self.wrap))
        if self.wrap:                               # TILED: one scan
            self._chunk(codes, (self.done, 0, w), (self.done, stop), (0, w), 0)
            self.done = stop
        else:
            self._rows(codes, stop, w)

    def _advance_turned(self, levels, final: int) -> None:
        h, w = self.grey.shape
        if final >= h:
            now = _turned(levels)
            if self.closed is not None and np.array_equal(now, self.closed):
                return                             # drawn from these very levels
            read = _read_before_seam(w)
            changed = self.seen_rows & (now[:, read] != self.seen[:, read]).any(axis=1)
            first = _first_to_redraw(changed, True)
            if first < self.done:
                self.done = first
                if self.balanced:
                    self._recount(self.seen)
        stop = h if final >= h else max(self.done, final - 2)
        if stop > self.done and self.seam > 0:
            order = np.arange(self.done - 1, stop + 1) % h   # the rows drawn, one either side
            band = self._checked(_turned_rows(levels, order))
            self.seen[order], self.seen_rows[order] = band, True
            codes = tuple(c[w:-w] for c in context_codes(band, self.num_levels, True))
            self._rows(codes, stop, self.seam)
        self.done = max(self.done, stop)
        if final >= h:                             # the seam columns, top to bottom
            columns = np.arange(self.seam - 1, w + 1) % w
            band = self._checked(now[:, columns])
            width = w - self.seam
            codes = tuple(c.reshape(h, -1)[:, 1:-1].ravel()
                          for c in context_codes(band, self.num_levels, True))
            self._chunk(codes, (0, self.seam, width), (0, h), (self.seam, w), 0, count=False)
            self.closed = now

    def _checked(self, band) -> np.ndarray:
        band = np.ascontiguousarray(band, dtype=np.uint8)
        if band.max() >= self.num_levels:
            raise InputError(f"tone needs a matrix of levels 0..{self.num_levels - 1}")
        return band

    def _rows(self, codes, stop: int, width: int) -> None:
        """Rows done..stop-1 over columns 0..width-1 (``codes``: their contexts, a full row
        each), on two lanes when they are many — but on one while ``beside()`` says a synthesis
        is drawing the levels: its thread and two lanes on two cores would each get two thirds
        of one, and the synthesis, which the tone waits for, would come out later (2048²,
        medians of 4 seeds in one process: 3–19 % off the whole time, grass within the noise;
        the picture is the same either way)."""
        at = (self.done, 0, len(self.grey[0]))
        while self.beside is not None and self.beside() and self.done < stop:
            piece = (self.done, min(stop, self.done + ONE_LANE_ROWS))
            self._chunk(codes, at, piece, (0, width), 0)
            self.done = piece[1]
        rows = (self.done, stop)
        if stop - self.done < 2 * LANE_ROWS or width < LANE_WIDTH:
            self._chunk(codes, at, rows, (0, width), 0)
        else:
            _two_lanes(lambda r, c: self._chunk(codes, at, r, c, HALF), rows, width)
        self.done = stop

    def _chunk(self, codes, at, rows, columns, skew, count=True) -> None:
        """Render rows (i0, i1), row i0 + k over columns (j0, j1) moved ``skew``·k left and
        clipped to them (``codes``: the contexts of the rows from ``at`` = (row, column,
        width) on); ``count``: their greys count for balance."""
        if self.cancel is not None and self.cancel():
            raise Cancelled("tone cancelled")
        ix = self.index
        _render(codes, ix.codes, ix.keys, ix.starts, ix.points, ix.direct, self.photo_grey,
                self.source, self.grey, self.state0, at[0], at[1], at[2], rows[0], rows[1],
                columns[0], columns[1], skew, self.wrap, self.seam,
                (self.shares, self.row_counts, self.above, self.balanced, count))

    def sources(self) -> np.ndarray:
        """The photo point each picture point shows (row-major index), in picture order."""
        return _unturned(self.source) if self.turned else self.source

    def result(self):
        """(grey, pixels or None) of the rows rendered so far (all, after the last advance),
        in picture order."""
        grey = _unturned(self.grey) if self.turned else self.grey
        pixels = None
        if self.photo_pixels is not None:
            flat = np.asarray(self.photo_pixels).reshape(-1, self.photo_pixels.shape[-1])
            pixels = flat[self.sources().ravel()].reshape(*grey.shape, flat.shape[-1])
        return grey, pixels


def _turned_rows(levels: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Rows ``order`` of the turned levels (_turned), without turning all of them."""
    h = len(levels)
    return np.roll(levels[(order + 1) % h], -1, axis=1)


def _two_lanes(run, rows, width: int) -> None:
    """``run((i0, i1), (j0, j1))`` over strips of LANE_ROWS rows, each cut in LANE_CHUNKS
    chunks or more, LANE_COLUMNS columns wide at most: even strips here and odd ones on a
    second thread. A strip's chunk waits for the strip above to be far enough on (its last
    row reads that strip's last rows up to HALF columns past its end, and those rows' chunks
    lie up to HALF·(LANE_ROWS-1) columns left): every point sees what it would see in scan
    order, so the picture is the same."""
    i0, i1 = rows
    cuts = [i0] + list(range((i0 // LANE_ROWS + 1) * LANE_ROWS, i1, LANE_ROWS)) + [i1]
    strips = list(zip(cuts, cuts[1:]))          # on whole strips of the picture (balance)
    size = max(1, min(LANE_COLUMNS, width // LANE_CHUNKS))
    chunks = -(-width // size)
    lead = -(-(HALF * (LANE_ROWS - 1) + HALF) // size)
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
                    run(strips[s], (c * size, width + HALF * LANE_ROWS if last else (c + 1) * size))
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


@njit(cache=True, nogil=True, inline="always")
def _split(s, pw, inverse):
    """(s // pw, s % pw) of a photo point 0 <= s < 2^40 without an integer division (up to 16
    a point, each slower than a multiplication): the float quotient is off by at most one,
    which the remainder corrects. With the look-up table, 12-20 % off the tone's time."""
    q = np.int64(s * inverse)
    r = s - q * pw
    if r < 0:
        q -= 1
        r += pw
    elif r >= pw:
        q += 1
        r -= pw
    return q, r


@njit(cache=True, nogil=True, inline="always")
def _before(y, x, i, j, w, seam):
    """Whether point (y, x) is drawn before (i, j): the columns from ``seam`` on come after
    all the others (TILED_LANES; else ``seam`` is the width), each part in scan order."""
    late, now_late = x >= seam, j >= seam
    return late < now_late or (late == now_late and y * w + x < i * w + j)


@njit(cache=True, nogil=True)
def _distance(grey, i, j, photo, pi, pj, best, limit):
    """Squared grey differences over the rendered causal neighbourhood of (i, j) (columns
    before ``limit``), against the photo around (pi, pj); stops once past ``best``. Points off
    either picture are skipped (a point and a candidate away from the edges take
    _distance_near)."""
    pw = photo.shape[1]
    total = np.int64(0)
    for di in range(-HALF, 1):
        y, py = i + di, pi + di
        if y < 0 or py < 0:
            continue
        for dj in range(-HALF, HALF + 1 if di < 0 else 0):
            x, px = j + dj, pj + dj
            if 0 <= x < limit and 0 <= px < pw:
                d = np.int64(grey[y, x]) - np.int64(photo[py, px])
                total += d * d
        if total > best:
            return total
    return total


@njit(cache=True, nogil=True, inline="always")
def _gather(grey, i, j, near):
    """The greys of the causal neighbourhood of (i, j), in _distance_near's order."""
    k = 0
    for di in range(-HALF, 1):
        for dj in range(-HALF, HALF + 1 if di < 0 else 0):
            near[k] = grey[i + di, j + dj]
            k += 1


@njit(cache=True, nogil=True, inline="always")
def _distance_near(near, photo, pi, pj):
    """_distance's total where no point is off either picture (most points), from the point's
    gathered greys and in full: a total past the best loses either way, and a sum with no test
    a row or a point is quicker."""
    total = np.int32(0)
    k = 0
    for di in range(-HALF, 1):
        for dj in range(-HALF, HALF + 1 if di < 0 else 0):
            d = near[k] - np.int32(photo[pi + di, pj + dj])
            total += d * d
            k += 1
    return np.int64(total)


@njit(cache=True, nogil=True)
def _penalties(pen, shares, row_counts, above, strip):
    """BALANCED: the weight of each (level, grey bin) on the matches of strip ``strip``
    (BALANCE_ROWS rows), from the greys drawn in the strips above the one above it (complete
    whichever lane draws them, see BALANCE_ROWS): a bin drawn more often than the photo's
    share of that level's greys weighs more (Kopf et al. 2007 keep a solid texture's histogram
    the same way). ``above[s]`` sums the rows' counts before strip s (each row is counted by
    the one lane that draws it)."""
    g, bins = shares.shape
    if strip >= 2:
        r0 = (strip - 2) * BALANCE_ROWS
        for lv in range(g):
            for b in range(bins):
                x = above[strip - 2, lv, b]
                for r in range(r0, r0 + BALANCE_ROWS):
                    x += row_counts[r, lv, b]
                above[strip - 1, lv, b] = x
    for lv in range(g):
        drawn = 0.0
        if strip >= 1:
            for b in range(bins):
                drawn += above[strip - 1, lv, b]
        for b in range(bins):
            pen[lv, b] = 1.0
            if drawn > 0.0:
                p = shares[lv, b]
                x = (above[strip - 1, lv, b] / drawn - p) / max(p, 1e-3)
                pen[lv, b] = np.exp(BALANCE * min(3.0, x))


def _grey_shares(photo_levels, photo_grey, num_levels: int) -> np.ndarray:
    """Each level's greys in the photo: (G, GREY_BINS) shares, a row per level."""
    levels = np.asarray(photo_levels)
    grey = photo_grey[: levels.shape[0], : levels.shape[1]]
    cells = levels.ravel().astype(np.int64) * GREY_BINS + grey.ravel() // (256 // GREY_BINS)
    counts = np.bincount(cells, minlength=num_levels * GREY_BINS).astype(float)
    counts = counts.reshape(num_levels, GREY_BINS)
    return counts / np.maximum(counts.sum(axis=1, keepdims=True), 1)


@njit(cache=True, nogil=True, inline="always")
def _inside(i, j, h, w, wrap, seam):
    """Whether no neighbour of (i, j) that _distance_wrap reads lies across a seam or in
    the seam columns drawn last: _distance over the columns before ``seam`` gives its total."""
    if wrap == TILED_LANES:
        return j < seam and i < h - HALF
    return HALF <= i < h - HALF and HALF <= j < w - HALF


@njit(cache=True, nogil=True)
def _distance_wrap(grey, i, j, photo, pi, pj, best, seam):
    """_distance on a tiling picture: every point of the (2·HALF+1)² square around (i, j)
    drawn before it (_before), read across the seams (the last rows and columns meet the first
    ones). Only needed where _inside is false: elsewhere _distance gives the same total, and
    sooner (this one costs the tone a third more when every point goes through it)."""
    h, w = grey.shape
    ph, pw = photo.shape
    total = np.int64(0)
    for di in range(-HALF, HALF + 1):
        py = pi + di
        if py < 0 or py >= ph:
            continue
        y = (i + di) % h
        for dj in range(-HALF, HALF + 1):
            px = pj + dj
            x = (j + dj) % w
            if 0 <= px < pw and _before(y, x, i, j, w, seam):
                d = np.int64(grey[y, x]) - np.int64(photo[py, px])
                total += d * d
        if total > best:
            return total
    return total


@njit(cache=True, nogil=True, inline="always")
def _unique_first(cand, count):
    """Keep the first of equal candidates (in place); returns how many are left. A repeat
    has the same weight and mismatch as the first, which is compared before it, so it could
    only tie: dropping it leaves the choice as it was."""
    kept = 0
    for k in range(count):
        seen = False
        for m in range(kept):
            seen = seen or cand[m] == cand[k]
        if not seen:
            cand[kept] = cand[k]
            kept += 1
    return kept


@njit(cache=True, nogil=True)
def _render(out_codes, photo_codes, keys, starts, points, direct, photo, source, grey, state0,
            base, base_col, codes_width, i0, i1, j0, j1, skew, wrap, seam, balance):
    """Rows i0..i1-1, row i0 + k over columns j0..j1-1 moved skew·k left (clipped to the
    columns before ``seam`` or, from j0 = seam on, to the last ones), in scan order: coherent
    and fresh candidates of the right context, the best match wins. ``out_codes`` hold the
    contexts of rows ``base`` on and columns ``base_col`` .. ``base_col + codes_width - 1``.
    Point n = i·w + j draws from SplitMix64 at state0 + DRAWS·n·GAMMA, whichever order the
    chunks run in. ``wrap``: neighbours across the seams count once drawn (_before).
    ``balance`` = (shares, row counts, counts above, balanced, count): see _penalties.
    ``direct``: ToneIndex.direct (empty: the 3×3 contexts are searched in ``keys[0]``)."""
    h, w = grey.shape
    ph, pw = photo.shape
    shares, row_counts, above, balanced, count_them = balance
    pen = np.ones(shares.shape)
    bin_width = 256 // GREY_BINS
    lo, hi = (0, seam) if j0 < seam else (seam, w)
    inverse = 1.0 / pw
    cand = np.empty(4 + RANDOM_CANDIDATES, np.int64)
    near = np.empty(NEIGHBOURS, np.int32)               # the point's causal neighbourhood
    state = np.empty(1, np.uint64)
    for i in range(i0, i1):
        if balanced and (i == i0 or i % BALANCE_ROWS == 0):
            _penalties(pen, shares, row_counts, above, i // BALANCE_ROWS)
        ja, jb = max(lo, j0 - skew * (i - i0)), min(hi, j1 - skew * (i - i0))
        state[0] = state0 + np.uint64(DRAWS) * np.uint64(i * w + ja) * np.uint64(GAMMA)
        for j in range(ja, jb):
            n = (i - base) * codes_width + j - base_col
            level, a, b = 0, 0, 0              # the photo points of its context, backing off
            if len(direct):
                slot = direct[out_codes[0][n]]
                if slot >= 0:
                    a, b = starts[0][slot], starts[0][slot + 1]
                else:
                    level = 1
            while level < 3 and a >= b:
                a, b = _bucket(keys[level], starts[level], out_codes[level][n])
                if a < b:
                    break
                level += 1
            count = 0
            if uniform(state) >= FRESH_START:       # continue the neighbours' photo pixels
                for di, dj in ((0, -1), (-1, 0), (-1, -1), (-1, 1)):
                    y, x = i + di, j + dj
                    if wrap and (x < 0 or x >= w or y < 0):    # across a seam
                        y, x = y % h, x % w
                    if 0 <= y and 0 <= x < w and _before(y, x, i, j, w, seam):
                        py, px = _split(source[y, x], pw, inverse)
                        py, px = py - di, px - dj
                        if 0 <= py < ph and 0 <= px < pw:
                            s = py * pw + px
                            if level == 3 or photo_codes[level][s] == out_codes[level][n]:
                                cand[count] = s
                                count += 1
            count = _unique_first(cand, count)  # a repeat could never win: skip it
            coherent = count
            for _ in range(RANDOM_CANDIDATES):     # fresh ones (anywhere: a level unseen)
                if level == 3:
                    cand[count] = min(np.int64(uniform(state) * ph * pw), ph * pw - 1)
                else:
                    cand[count] = points[level][min(a + np.int64(uniform(state) * (b - a)), b - 1)]
                count += 1
            best, chosen = np.inf, cand[0]
            across = wrap and not _inside(i, j, h, w, wrap, seam)
            whole = not across and HALF <= min(i, j) and j + HALF < seam
            if whole:
                _gather(grey, i, j, near)
            own = out_codes[2][n]
            for k in range(count):
                pi, pj = _split(cand[k], pw, inverse)
                weight = COHERENCE if k < coherent else 1.0
                if balanced:
                    weight *= pen[own, photo[pi, pj] // bin_width]
                if whole and HALF <= pi and HALF <= pj < pw - HALF:
                    d = weight * _distance_near(near, photo, pi, pj)
                elif across:
                    d = weight * _distance_wrap(grey, i, j, photo, pi, pj, best / weight, seam)
                else:
                    d = weight * _distance(grey, i, j, photo, pi, pj, best / weight, seam)
                if d < best:
                    best, chosen = d, cand[k]
            source[i, j] = chosen
            grey[i, j] = photo[chosen // pw, chosen % pw]
            if balanced and count_them:
                row_counts[i, own, grey[i, j] // bin_width] += 1.0
