"""A field drawn given its level shares: sequential Monte Carlo over bands of rows.

A coarse scale's field has long-range correlations: one draw of it can hold a level's share a
tenth off its DPJ's (a scene photo: a blob as large as the texture), and every finer scale
inherits it. Drawing again until the shares fit (markov.multiscale before SynthesizeScales 6)
seldom succeeds on such photos (a try lands within 0.01 one time in five to ten). Here PARTICLES
drafts are drawn side by side, band by band, each row exactly given the rows above it by the
ordinary kernel. After each band every draft is weighed by how likely its shares so far are to
end near the aim; when the weights grow uneven, the drafts are resampled (those off course
dropped, those on course copied, each copy drawn on with its own random stream). No row is ever
changed or tilted, only which drafts go on, so the field keeps the DPJ's windows everywhere (a
law tilted row by row towards the shares draws stripes). The draft closest to the aim at the end
is the result: in effect the field conditioned on its level histogram.

The weight of a draft whose first fraction f of the rows hold shares s, aiming at e:
exp(-f² |s - e|² / 2((1 - f) SPREAD² + TOLERANCE²)): the rest of the field, with shares off by
about SPREAD over the whole, can still bring s back to e (the weight of each band is the ratio
of the weights after and before it, so they multiply out to the last one).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import Callable, NamedTuple

import numpy as np

from ..errors import Cancelled, InputError

PARTICLES = 6        # drafts drawn side by side (two lanes: one per core; 8 held the shares
                     # no closer on six scene photos, and took longer)
MAX_PARTICLES = 64
DRAFT_POINTS = 2**18  # more drafts: a small scale is drawn as as many drafts as fit in this
MORE_PARTICLES = 32   # many points, up to this many (a 64² scale: 32, 128²: 16, 256²: 6)
BANDS = 16           # weighed and perhaps resampled after each of this many bands of rows
SPREAD = 0.04        # how far a level's share may still move over the rest of a field
TOLERANCE = 0.01     # how close to its aim a level's share should end


class Shares(NamedTuple):
    """What a field is drawn given: each level's share to aim at, and how many drafts."""

    aim: np.ndarray
    particles: int = PARTICLES


def drafts_for(points: int, particles: int, more: bool) -> int:
    """How many drafts a scale of ``points`` is drawn as: ``particles``, or with ``more`` as many
    as fit in DRAFT_POINTS, up to MORE_PARTICLES and never fewer. A small scale's drafts cost
    little, and a photo of large regions needs many to find its shares: on 23 photos at 512²
    (6 seeds) the 7 whose coarse scales were drafted all came closer (a retina's worst share
    0.130 → 0.025, a clock's 0.025 → 0.011), in 4 % more time over all 23; twice the points
    held one more photo within 0.03 but took a fifth more time. (Tilting small scales closer
    instead drew them in bands: markov.steering.)"""
    if not more:
        return particles
    return max(particles, min(MORE_PARTICLES, DRAFT_POINTS // max(1, points)))


def check_particles(particles) -> int:
    if particles not in range(MAX_PARTICLES + 1) or isinstance(particles, bool):
        raise InputError(f"{particles!r} drafts: choose 0 to {MAX_PARTICLES}")
    return int(particles)


class Draft:
    """One particle: the rows drawn so far, its random stream, what it cost, and the counts of
    its levels in rows that can no longer change."""

    __slots__ = ("rows", "state", "repairs", "redraws", "fixed", "fixed_to")

    def __init__(self, rows, state, levels: int):
        self.rows, self.state = rows, state
        self.repairs = self.redraws = 0
        self.fixed, self.fixed_to = np.zeros(levels, np.int64), 0

    def copy(self, state) -> Draft:
        twin = Draft(self.rows.copy(), state, len(self.fixed))
        twin.repairs, twin.redraws = self.repairs, self.redraws
        twin.fixed, twin.fixed_to = self.fixed.copy(), self.fixed_to
        return twin


def draw(start: np.ndarray, shape, window_rows: int, levels: int, own: int, extend: Callable,
         shares: Shares, seed: int, settled: int, cancel=None, progress=None) -> Draft:
    """Draft the rows of ``start`` given ``shares``: ``start`` is the matrix the kernel fills
    (a torus copy may be wider and taller than ``shape``), of ``levels`` composite levels
    whose own level is the value % ``own``. ``extend(draft, r0, r1)`` draws rows r0..r1-1 of
    a draft and returns (repairs, redraws); ``settled``: rows above a band that drawing it may
    still change (dead-end redraws)."""
    h, w = shape
    aim = np.asarray(shares.aim, float)
    count = check_particles(shares.particles)
    if count < 1 or len(aim) != own:
        raise InputError(f"{count} drafts aiming at {len(aim)} shares of {own} levels")
    drafts = [Draft(start.copy(), _state(seed, 0, i), levels) for i in range(count)]
    log_w, log_psi = np.zeros(count), np.zeros(count)
    edges = band_edges(h, window_rows)
    with ThreadPoolExecutor(1, thread_name_prefix="drafts") as lane:
        for b, (r0, r1) in enumerate(zip(edges[:-1], edges[1:])):
            if cancel is not None and cancel():
                raise Cancelled("synthesis cancelled")
            _extend_all(lane, drafts, extend, r0, r1)
            psi = np.array([_log_psi(_shares(d, r1, w, own, settled), aim, r1 / h)
                            for d in drafts])
            log_w += psi - log_psi
            log_psi = psi
            if progress is not None:
                progress(r1 / h)
            if r1 < h and _uneven(log_w):
                picks = _resample(log_w, _uniform(seed, b + 1))
                drafts = [drafts[j].copy(_state(seed, b + 1, i)) for i, j in enumerate(picks)]
                log_psi, log_w = log_psi[picks], np.zeros(count)
    off = [np.abs(_shares(d, h, w, own, settled) - aim).max() for d in drafts]
    return drafts[int(np.argmin(off))]


def band_edges(h: int, window_rows: int) -> list[int]:
    """Row bounds of the BANDS bands; the first band holds at least the window's rows (the
    first rows of a field are drawn together)."""
    edges = sorted({round(h * i / BANDS) for i in range(BANDS + 1)})
    return [0] + [e for e in edges if e >= min(window_rows, h)]


def _extend_all(lane, drafts, extend, r0, r1) -> None:
    """Every draft one band further: the second half on the other lane."""
    half = len(drafts) // 2

    def run(part):
        for d in part:
            rep, red = extend(d, r0, r1)
            d.repairs, d.redraws = d.repairs + rep, d.redraws + red
    other = lane.submit(run, drafts[half:]) if half else None
    run(drafts[:half] if half else drafts)
    if other is not None:
        other.result()


def _shares(d: Draft, r1: int, w: int, own: int, settled: int) -> np.ndarray:
    """The level shares of rows 0..r1-1 (counted once for rows no later band can change)."""
    to = max(d.fixed_to, r1 - settled)
    if to > d.fixed_to:
        d.fixed += _counts(d.rows[d.fixed_to:to, :w], len(d.fixed))
        d.fixed_to = to
    counts = d.fixed + _counts(d.rows[d.fixed_to:r1, :w], len(d.fixed))
    counts = counts.reshape(-1, own).sum(axis=0)
    return counts / (r1 * w)


def _counts(rows: np.ndarray, levels: int) -> np.ndarray:
    return np.bincount(rows.ravel(), minlength=levels)[:levels]


def _log_psi(s: np.ndarray, aim: np.ndarray, f: float) -> float:
    return -float(((f * (s - aim)) ** 2).sum()) / (2 * ((1 - f) * SPREAD ** 2 + TOLERANCE ** 2))


def _uneven(log_w: np.ndarray) -> bool:
    """The weights' effective number of drafts below half of them."""
    p = np.exp(log_w - log_w.max())
    return p.sum() ** 2 / (p ** 2).sum() < len(p) / 2


def _resample(log_w: np.ndarray, u: float) -> np.ndarray:
    """Systematic resampling: draft j is copied about count · weight_j times."""
    p = np.exp(log_w - log_w.max())
    cum = np.cumsum(p / p.sum())
    return np.minimum(np.searchsorted(cum, (u + np.arange(len(p))) / len(p)), len(p) - 1)


def _state(seed: int, band: int, i: int) -> np.ndarray:
    return np.random.SeedSequence([int(seed), band, i]).generate_state(1, np.uint64)


def _uniform(seed: int, band: int) -> float:
    word = np.random.SeedSequence([int(seed), band]).generate_state(1, np.uint64)[0]
    return float(word >> np.uint64(11)) / 2.0 ** 53
