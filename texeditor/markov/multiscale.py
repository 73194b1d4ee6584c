"""Multi-scale DPJ (the thesis's window law, extended across scales): structure larger than the
window.

A photo is reduced by 2, 4, … (area mean); the coarsest reduction gets a plain DPJ, and every
finer scale a *conditional* DPJ, the law of its window given the coarser levels under it. Such a
DPJ is an ordinary DPJ over composite levels, parent · G + level (parent: the level of the
coarser scale at the point's place), estimated by counting as in §5.2.1. Synthesis draws the
coarsest scale as in ch. 4, then each finer scale row by row exactly given its parents
(markov.synthesis.synthesize_given). Grey-level doubling (§4.5) is the same idea along the grey
axis.
"""

from __future__ import annotations

import math
import threading
from concurrent.futures import ThreadPoolExecutor
from contextlib import closing
from dataclasses import dataclass
from typing import Callable

import numpy as np
import skimage as ski

from ..errors import Cancelled, InputError
from ..wording import counted
from .balance import (FORCED_PASSES, FORCED_TRIGGER, FREE_PASSES, MAX_POINTS, TRIGGER,
                      rebalance)
from .dpj import DPJ, MAX_LEVELS, check_window, encode, whole
from .estimation import estimate_dpj
from .levels import check_levels, has_colour, quantize, to_grey
from .particles import PARTICLES, Shares, check_particles, drafts_for
from .synthesis import (NO_ROW_LIMIT, SynthesisResult, build_tables, check_row_redraws,
                        check_seed, check_size, derived, past_budget, synthesize,
                        synthesize_given)

COARSEST_SIDE = 64          # the photo's coarsest reduction keeps about this many points a side
PYRAMID_ROWS = 256          # the first halving converts the photo this many rows at a time
MAX_SCALES = 6
COARSE_WINDOW = (5, 5)      # the coarsest scale: a wide window over few levels (the layout)
COARSE_LEVELS = 2
WINDOW = (3, 2)             # finer scales: the parents carry the layout, a small window the edges
LEVELS = 4
PARENTS_UNDER = "parents_under"   # a conditional DPJ's meta: True, its parents are read under
                                  # each point (upsample), else one row ahead
PARENT_PHASE = "parent_phase"     # ... True: read under, each point's parent code also says
                                  # whether it is the first or the second finer row over its
                                  # parent (parent_codes). A 2-row window could not tell them
                                  # apart: it drew a parent row's edge as a 1-row stripe every
                                  # other row, "combs" beside brick's mortar (its 256² sample:
                                  # 1-row features 0.059 of the 128² scale, the photo's 0.0095)
FREQUENCY_TOLERANCE = 0.01  # a coarse scale is drawn again while a level's share is further off
PLAIN_TRIES = 2             # plain draws of a scale (side by side) before it is drafted
DRAFT_TRIGGER = 0.03        # ... when a level's share in both is further off than this (as far
                            # as a texture's may stray from its photo's; drafts aim at 0.01)
LEAN_DRAFTS = True          # ... beyond the error of its parents' shares: a scale inherits
                            # about the error its parents hold, and drafts cannot take it
                            # closer (camera at 256², 4 seeds: parents 0.033–0.042 off, the
                            # plain draws 0.035–0.041, the 16 drafts 0.032–0.041, 80–115 ms of
                            # the texture's 240; tileable at 256², camera, cell, moon: 1.14–
                            # 1.24 × the plain time instead of 1.41–1.71, the finest shares as
                            # close). Recipes before it drafted past DRAFT_TRIGGER alone
MAX_DRAFTED_POINTS = 2**18  # a larger scale is only drawn plainly: its drafts would take about
                            # a second (a 1024² scale of a 2048² texture)
COARSE_TRIES = 8            # recipes before particles: draws of a coarse scale (the
                            # next-to-finest: 2; the finest: 1)
TORUS_TOLERANCE = 0.01      # a tileable coarsest draw may leave this share of windows off its DPJ
TORUS_BUDGET = 0.5          # closure 3: a trial coarsest draw redrawing rows more often than this
                            # per point will not close (those that close: ≤ 0.22; the others
                            # 1.5–11 on stochastic photos), so it is stopped there
COARSE_REDRAWS = 4          # a dead end of the coarsest scale: tries redrawing the rows above before
                            # it backs off. Its wide window over a small reduction is nearly
                            # deterministic and later tries seldom get through (brick at 1024²:
                            # 20–34 thousand redraws, most in runs of 16 that end in a back-off,
                            # 90 % of the scale's time); recipes before it kept 16 (OLD_REDRAWS)
OLD_REDRAWS = 16
COARSE_ROW_REDRAWS = 0.5    # ... and once a row of it has redrawn this many times per point of
                            # its width, its further dead ends back off at once. Where the 5×5
                            # DPJ of a small reduction is nearly a copy of it, most positions
                            # dead-end and hardly any try gets through (gravel's 256² crop, its
                            # coarsest scale of a 512² texture: 3 redraws a point, 74 % of the
                            # points backing off either way, 1.8 s of a 2048² texture's 4.5 s);
                            # where tries do get through, rows stay far below it (moon, camera:
                            # 0–0.15 a point). Recipes before it had no limit (NO_ROW_LIMIT)
GIVEN_REDRAWS = 8           # ... and of a scale drawn given its parents. Its tries redraw more
                            # rows, wider, every fourth try, and a dead end that four did not get
                            # past seldom gets past at all: brick at 2048², its 1024² scale, 16
                            # tries: 50 thousand redraws, 0.78 s, 6164 back-offs; 8: 33 thousand,
                            # 0.42 s, 6715 (the finest 1.41 -> 0.96 s); brick, grass, gravel at
                            # 512² and 1024² keep their GLCM, spectrum and TV figures within
                            # ±0.002 (4 seeds). Recipes before it kept OLD_REDRAWS
TORUS_REPAIRS = 0.02        # closure 5: ... or backing off at more than this share of its points
                            # (a back-off leaves about one window off the DPJ: the draws that
                            # closed in our trials backed off at ≤ 0.012 of their points; most
                            # 5×5 draws that do not close, at 0.02–0.16, are stopped part way)
SCALES_CLOSURE = 8          # the seam closure of a tileable multi-scale synthesis: 3 closes every
                            # scale with fewer tries than 2 (synthesis.CLOSE_TRIES_3), stops the
                            # coarsest law's failing trial draws early (TORUS_BUDGET) and has its
                            # tone drawn beside the levels (photo.tone.TILED_LANES); 4 is 3 over
                            # shorter stretches (synthesis.CLOSE_SPAN_4); 5 is 4 with the trial
                            # draws stopped earlier still (TORUS_REPAIRS); 6 is 5 with every
                            # scale's rows drawn on their ring (seam closure 6); 7 is 6 with the
                            # last rows of every scale drawn given its parents pulled towards the
                            # first row (seam closure 7: their finest levels change across the
                            # bottom seam less often, 256², 32 seeds: coffee 2.10 -> 1.67× as
                            # often as inside, camera 2.10 -> 1.76, cell 7.8 -> 5.4, moon 4.3
                            # -> 3.9, brick 2.13 -> 2.00; the coarsest scale is not pulled, see
                            # COARSEST_SEAM); 8 is 7 with those scales closed by seam closure 8
                            # (pulled at full strength, their bottom seam redrawn only near the
                            # columns that do not close: 16 seeds, 256², 7 -> 8: brick 1.98 ->
                            # 1.47, camera 2.06 -> 1.35, coffee 1.70 -> 1.29, moon 3.47 -> 2.03,
                            # gravel 1.60 -> 1.23, grass 1.39 -> 1.13, but cell 5.4 -> 6.3);
                            # 7 to 1 are kept for older recipes
COARSEST_SEAM = 6           # the coarsest scale's seam closure at most (pulled, it made coffee's
                            # finest bottom seam worse: 2.0 -> 3.1× as inside, 8 seeds)
SEAMS = (1, 2, 3, 4, 4, 6, 7, 8)  # the seam closure (synthesis.CLOSURE) of each closure of the scales:
                            # not synthesis closure 5, whose last column leaves a row's failed
                            # side closure far up as it is — a photo model's scales fail more
                            # (2 tries a seam), and its tone then jumped more across the side
                            # seam (6 of 6 photos at 256², 10 seeds: brick 2.21 -> 2.59). Seam
                            # closure 6 mends the same way, but its rows drawn on their ring
                            # have their finest levels change across the side seam 1.4-2.7× as
                            # often as inside (moon, coffee, cell, camera, 256², 24 seeds)
                            # against 2.3-4.6× with seam closure 4


@dataclass(frozen=True)
class MultiScaleDPJ:
    """One DPJ per scale, coarsest first; every one after the first is conditional."""

    dpjs: tuple

    def __post_init__(self):
        check_scales(self.dpjs)

    @property
    def scales(self) -> int:
        return len(self.dpjs)

    def levels_at(self, k: int) -> int:
        """G of scale k (a conditional DPJ's composite levels divided by its parents')."""
        return self.dpjs[k].levels // parent_levels(self.dpjs, k)

    @property
    def levels(self) -> int:
        return self.levels_at(self.scales - 1)

    @property
    def palette(self) -> np.ndarray:
        """The finest scale's G colours."""
        return self.dpjs[-1].palette[: self.levels]

    def frequencies(self, k: int) -> np.ndarray:
        """Each level's share at scale k, by the DPJ (its windows' bottom-right point)."""
        dpj, g = self.dpjs[k], self.levels_at(k)
        return np.bincount(dpj.configs[:, -1, -1] % g, weights=dpj.probs,
                           minlength=g) / dpj.probs.sum()


def parent_levels(dpjs, k: int) -> int:
    """The parent codes of scale k: the levels of scale k - 1 (twice as many with
    PARENT_PHASE)."""
    if k == 0:
        return 1
    value = dpjs[k].meta.get("parent_levels", 0)      # a file's meta: any JSON value
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(f"scale {k}: its DPJ's parent_levels is {value!r:.40}, not a whole "
                         "number of levels")
    return value


def has_phase(dpj: DPJ) -> bool:
    """Whether a conditional DPJ's parent codes hold the row's phase (PARENT_PHASE)."""
    return bool(dpj.meta.get(PARENT_PHASE, False))


def check_scales(dpjs) -> None:
    """Each finer DPJ's composite levels are its parents' G times its own."""
    if not dpjs or len(dpjs) > MAX_SCALES or not all(isinstance(d, DPJ) for d in dpjs):
        raise InputError(f"a multi-scale DPJ has 1..{MAX_SCALES} DPJs")
    below = dpjs[0].levels
    for k in range(1, len(dpjs)):
        for key in (PARENTS_UNDER, PARENT_PHASE):
            if not isinstance(dpjs[k].meta.get(key, False), bool):
                raise InputError(f"scale {k}: {key} says true or false")
        if has_phase(dpjs[k]) and not parents_under(dpjs[k]):
            raise InputError(f"scale {k}: a parent's phase is read under the point only")
        gp = parent_levels(dpjs, k)
        if gp != below * (2 if has_phase(dpjs[k]) else 1) or dpjs[k].levels % gp \
                or dpjs[k].levels // gp < 2:
            raise InputError(f"scale {k}: a conditional DPJ of {dpjs[k].levels} composite levels "
                             f"does not sit on a scale of {below} levels")
        below = dpjs[k].levels // gp


def scales_phrase(n: int) -> str:
    """"1 scale", "3 scales": how messages and labels count scales."""
    return counted(n, "scale")


def default_scales(shape) -> int:
    """Enough halvings to bring the photo's shorter side to about COARSEST_SIDE points."""
    side = min(shape[:2])
    return int(max(1, min(MAX_SCALES, 1 + math.floor(math.log2(max(side, 1) / COARSEST_SIDE)))))


def scales_that_fit(shape, scales: int, window=WINDOW, coarse_window=COARSE_WINDOW) -> int:
    """The most scales, up to ``scales``, that a texture of ``shape`` (H, W) holds, each scale
    at least its window (one scale takes ``window``): what "auto" gives a small texture,
    which the photo's own number of scales would refuse."""
    for n in range(int(scales), 1, -1):
        windows = [tuple(coarse_window)] + [tuple(window)] * (n - 1)
        if all(h >= v and w >= u for (h, w), (u, v) in zip(scale_shapes(shape, n), windows)):
            return n
    return 1


def pyramid(photo: np.ndarray, scales: int, as_float=np.asarray) -> list[np.ndarray]:
    """The photo cropped to a multiple of 2^(scales-1), then halved by area mean; coarsest first.
    ``as_float`` converts the photo's pixels for the first halving, PYRAMID_ROWS rows at a time
    (a 64-megapixel colour photo as float64 would take 1.5 GB at once; each block's mean is the
    same either way). The finest layer is the photo's crop as it is."""
    n = 2 ** (scales - 1)
    h, w = photo.shape[0] // n * n, photo.shape[1] // n * n
    if h < n * 8 or w < n * 8:
        size = f"a {photo.shape[1]}x{photo.shape[0]} photo is too small"
        raise InputError(f"{size}: a photo has at least 8 points a side" if scales == 1 else
                         f"{size} for {scales} scales (its coarsest reduction would have fewer "
                         f"than 8 points a side)")
    out = [photo[:h, :w]]
    block = (2, 2) + (1,) * (photo.ndim - 2)          # a colour photo: each channel
    if scales > 1:
        out.append(np.concatenate([ski.transform.downscale_local_mean(
            as_float(photo[top:min(h, top + PYRAMID_ROWS), :w]), block)
            for top in range(0, h, PYRAMID_ROWS)]))
    for _ in range(scales - 2):
        out.append(ski.transform.downscale_local_mean(out[-1], block))
    return out[::-1]


def upsample(parents: np.ndarray, shape, under: bool = False) -> np.ndarray:
    """The parent of every finer point: the coarse point under the point just below it (the
    last row: its own), or with ``under`` the coarse point under the point itself. A row is
    drawn given the rows above and its parents, never the rows below; reading the parents one
    row ahead lets every odd row see the coarse row it leads into, which keeps the finest
    scale's rare levels (read under the point, a thin mortar joint comes out doubled), but a
    coarse point then leads three finer rows, not two: every scale read so stretches the
    layout by half again down the rows (gravel's pebbles ran down the picture in drips, its
    levels' vertical correlation at 8 points 0.27 against the photo's 0.04). So a photo model
    reads its scales under the point but the finest, which reads ahead (PARENTS_UNDER)."""
    h, w = shape
    if under:
        return np.repeat(np.repeat(parents, 2, axis=0), 2, axis=1)[:h, :w]
    up = np.repeat(np.repeat(parents, 2, axis=0), 2, axis=1)[1: h + 1, :w]
    return up if len(up) == h else np.vstack([up, up[-1:]])


def upsample_torus(parents: np.ndarray, shape, under: bool = False) -> np.ndarray:
    """``upsample`` on the torus (``under`` as there): the last row's parent is the first
    row's (one row ahead), and a side of odd length is resampled to the nearest coarse point,
    so the parents tile as the points do."""
    (h, w), (hc, wc) = shape, parents.shape
    rows = (np.arange(h) * hc // h) if under else (np.arange(1, h + 1) * hc // h) % hc
    cols = np.arange(w) * wc // w
    return parents[np.ix_(rows, cols)]


def parent_codes(parents: np.ndarray, shape, *, under: bool, phase: bool,
                 tileable: bool = False) -> np.ndarray:
    """The parent code of every point of a (H, W) scale given the levels ``parents`` of the
    scale under it: the parent's level (upsample, ``under`` as there, on the torus when
    ``tileable``), or with ``phase`` (PARENT_PHASE) 2 · level, + 1 on the second finer row
    over a parent row."""
    up = (upsample_torus if tileable else upsample)(parents, shape, under)
    if not phase:
        return up
    h, hc = shape[0], parents.shape[0]
    rows = np.arange(h) * hc // h if tileable else np.arange(h) // 2    # as upsample reads
    second = np.zeros(h, up.dtype)
    second[1:] = rows[1:] == rows[:-1]
    return up * 2 + second[:, None]


def codes_for(dpj: DPJ, parents: np.ndarray, shape, tileable: bool = False) -> np.ndarray:
    """The parent codes a conditional DPJ draws its scale given (parent_codes)."""
    return parent_codes(parents, shape, under=parents_under(dpj), phase=has_phase(dpj),
                        tileable=tileable)


def parents_under(dpj: DPJ) -> bool:
    """Whether a conditional DPJ reads each point's parent under the point itself (models
    acquired since PARENTS_UNDER; older DPJs read it one row ahead)."""
    return bool(dpj.meta.get(PARENTS_UNDER, False))


def estimate_scales(image, *, scales: int | None = None, levels: int = LEVELS,
                    window=WINDOW, coarse_levels: int = COARSE_LEVELS,
                    coarse_window=COARSE_WINDOW, quantizer: str = "lab",
                    under: bool = True, phase: bool = True):
    """Acquire a multi-scale DPJ from a photo. Returns (model, the photo's levels at each scale,
    coarsest first). Each scale is quantised on its own (a reduced photo has less contrast);
    with the "lab" quantiser a colour photo's levels are colour classes at every scale.
    ``under``: the scales between the coarsest and the finest read their parents under each
    point (upsample; False: one row ahead, as models acquired before PARENTS_UNDER);
    ``phase``: those whose composite levels allow it (2 · parents' G · G ≤ MAX_LEVELS: the
    scale over the coarsest) also by the row's phase (PARENT_PHASE)."""
    colour = quantizer == "lab" and has_colour(image)
    grey = None if colour else to_grey(image)        # a colour photo's grey is not needed
    scales = default_scales(np.shape(image)) if scales is None else whole(scales, "scales")
    if not 1 <= scales <= MAX_SCALES:
        raise InputError(f"{scales} scales: choose 1..{MAX_SCALES}")
    levels, coarse_levels = check_levels(levels), check_levels(coarse_levels)
    if scales == 1:
        coarse_levels, coarse_window = levels, window
    below = [] if scales == 1 else [coarse_levels] + [levels] * (scales > 2)   # the parents'
    for parents in below:
        if levels * parents > MAX_LEVELS:
            most = max(g for g in range(1, MAX_LEVELS + 1)
                       if g * (max(g, coarse_levels) if scales > 2 else coarse_levels)
                       <= MAX_LEVELS)
            if most < 2:                  # no G fits: the coarse levels are the ones to lower
                raise InputError(f"{coarse_levels} levels at the coarsest scale leave no room "
                                 "for the finer ones: a conditional DPJ holds G × its parents' "
                                 f"levels, at most {MAX_LEVELS}; choose at most "
                                 f"{MAX_LEVELS // 2} coarse levels")
            raise InputError(f"G = {levels} on a scale of {parents} levels: a conditional DPJ "
                             f"holds G × its parents' levels ({levels * parents}), at most "
                             f"{MAX_LEVELS}; with {scales} scales choose G ≤ {most}")
    check_window(coarse_window, coarse_levels)
    check_window(window, levels * max(levels, coarse_levels))
    if colour:
        layers = pyramid(np.asarray(image), scales, lambda band: ski.util.img_as_float(
            band[..., :3]))
    else:
        layers = pyramid(grey, scales)
    h, w = layers[-1].shape[:2]
    layers[-1] = np.asarray(image)[:h, :w]          # the finest palette keeps the photo's colours
    per_scale = [coarse_levels] + [levels] * (scales - 1)
    quantized = []
    for k, g in enumerate(per_scale):     # each reduction let go once quantised (a 64 MP photo's
        quantized.append(quantize(layers[k], g, quantizer))     # take 0.5 GB as float64)
        layers[k] = None
    lv = [q.levels for q in quantized]
    dpjs = [estimate_dpj(lv[0], coarse_window, coarse_levels, wrap=True,
                         palette=quantized[0].palette, meta={"scale": 0, "scales": scales})]
    for k in range(1, scales):
        gp, below = per_scale[k - 1], under and k < scales - 1   # the finest reads ahead
        meta = {"scale": k, "scales": scales}
        if below:
            meta[PARENTS_UNDER] = True
            if phase and 2 * gp * per_scale[k] <= MAX_LEVELS:
                meta[PARENT_PHASE], gp = True, 2 * gp
        meta["parent_levels"] = gp
        codes = parent_codes(lv[k - 1], lv[k].shape, under=below,
                             phase=meta.get(PARENT_PHASE, False))
        composite = codes * per_scale[k] + lv[k]   # parent code · G + level shows as its level
        dpjs.append(estimate_dpj(composite, window, gp * per_scale[k], wrap=True,
                                 palette=np.tile(quantized[k].palette, (gp, 1)), meta=meta))
    return MultiScaleDPJ(tuple(dpjs)), lv


def scale_shapes(shape, scales: int) -> list[tuple[int, int]]:
    h, w = shape
    return [(-(-h // 2 ** (scales - 1 - k)), -(-w // 2 ** (scales - 1 - k))) for k in range(scales)]


def synthesize_scales(model: MultiScaleDPJ, shape, *, seed: int = 0,
                      progress: Callable[[float], None] | None = None,
                      cancel: Callable[[], bool] | None = None,
                      rows_final: Callable[[np.ndarray, int], None] | None = None,
                      tileable: bool = False, closure: int = SCALES_CLOSURE,
                      coarse_redraws: int = COARSE_REDRAWS,
                      particles: int = PARTICLES, rebalance: bool = True,
                      steer: bool = True, more_drafts: bool = True,
                      given_redraws: int = GIVEN_REDRAWS,
                      coarse_row_redraws: float = COARSE_ROW_REDRAWS,
                      free_moves: bool = True, forced_moves: bool = True,
                      lean_drafts: bool = LEAN_DRAFTS) -> SynthesisResult:
    """Draw the coarsest scale, then each finer one given the one under it; the finest levels
    (``rows_final`` follows the finest scale's rows as they are drawn, see synthesize).
    ``tileable``: every scale is drawn on the torus (``closure``: which seam closure, 1 to
    SCALES_CLOSURE, see synthesize). ``coarse_redraws``: the coarsest scale's tries at a dead
    end before it backs off (COARSE_REDRAWS; OLD_REDRAWS in older recipes); ``given_redraws``
    the same for the scales drawn given their parents (GIVEN_REDRAWS; OLD_REDRAWS in older
    recipes); ``coarse_row_redraws``: the redraws a row of the coarsest scale may make, per
    point of its width (COARSE_ROW_REDRAWS; NO_ROW_LIMIT in older recipes).

    A coarse scale's field has long-range correlations: one draw of it can hold a level's share
    a tenth off the model's, and every finer scale inherits it. So each scale but the finest is
    drawn given its level shares (its DPJ's): plainly (PLAIN_TRIES draws side by side, the
    first within FREQUENCY_TOLERANCE kept, else the closer), and if that one is still further
    off than DRAFT_TRIGGER, again as ``particles`` drafts (markov.particles), the closer to the
    shares kept (scales up to MAX_DRAFTED_POINTS). ``particles`` = 0, as recipes before it:
    drawn again up to COARSE_TRIES times instead, the first within the tolerance or the
    closest kept. ``rebalance``: the finest scale's level shares, when they come out off,
    are then brought back by moving region borders (markov.balance; ``moved`` counts the
    moves, made after rows_final was told of all rows but the last band, and the last call,
    all rows final, is not made then; False, as recipes before it); ``free_moves``: when the
    moves its parents allow leave a share off, more moves follow, free of them (False, as
    recipes before it); ``forced_moves``: when a share is off even then, forced moves follow,
    which may leave windows outside the DPJ (False, as recipes before it). ``steer``: every plain draw of a scale is steered towards its level
    shares as its rows are drawn (markov.steering; False, as recipes before it), so drafts
    and moves are seldom needed.
    ``more_drafts``: a small scale is drafted as more particles (particles.drafts_for; False,
    as recipes before it). ``lean_drafts``: a scale is drafted only when its plain draw is
    further off than DRAFT_TRIGGER beyond its parents' own error (LEAN_DRAFTS; False: whenever
    further off than DRAFT_TRIGGER, as recipes before it). The same model and seed give the
    same matrix."""
    seed = check_seed(seed)
    shapes = scale_shapes(check_size(shape), model.scales)
    _check_scale_sizes(model, shapes)
    closure = check_scales_closure(closure)
    redraws_at = ((check_redraws(coarse_redraws), check_row_redraws(coarse_row_redraws)),
                  (check_redraws(given_redraws), None))     # the coarsest's, the others'
    particles = check_particles(particles)
    weights = np.array([h * w for h, w in shapes], float)
    done = np.concatenate([[0], np.cumsum(weights)]) / weights.sum()
    repairs = redraws = 0
    levels = parents = None
    told, held = rows_final, []
    if rebalance and rows_final is not None:
        told = _holding_the_last(rows_final, shapes[-1][0], held)
    ahead = ThreadPoolExecutor(1, thread_name_prefix="tables")   # the finer scales' tables are
    try:                                                           # built as the coarse are drawn
        built = [None] + [ahead.submit(build_tables, model.dpjs[k], parent_levels(model.dpjs, k),
                                       bool(tileable)) for k in range(1, model.scales)]
        trial = None
        if tileable and closure >= 2:
            law, trial = _torus_law(model.dpjs[0], shapes[0], seed, closure, redraws_at[0],
                                    model.frequencies(0) if steer else None)
            model = MultiScaleDPJ((law,) + model.dpjs[1:])
        for k in range(model.scales):
            if built[k] is not None:
                built[k].result()
            r = _draw_scale_closest(model, k, shapes, levels, seed, done, progress, cancel,
                                    told, tileable, closure, redraws_at, particles,
                                    trial if k == 0 < model.scales - 1 else None, steer,
                                    more_drafts, _draft_trigger(model, k, levels, lean_drafts))
            parents, levels = levels, r.levels
            repairs, redraws = repairs + r.repairs, redraws + r.redraws
    finally:
        ahead.shutdown(wait=False, cancel_futures=True)
    moved = 0
    if rebalance:
        if cancel is not None and cancel():
            raise Cancelled("synthesis cancelled")
        levels, moved = _rebalanced(model, levels, parents, seed, tileable, free_moves,
                                    forced_moves)
        if held and not moved:
            rows_final(*held[-1])
    return SynthesisResult(levels, repairs, redraws, int(seed), moved)


def _holding_the_last(rows_final, height: int, held: list):
    """rows_final, but for its last call (all rows final), kept in ``held`` until the shares
    are rebalanced: when points move, the levels it would give are not the texture's."""
    def told(levels, n):
        if n >= height:
            held.append((levels, n))
        else:
            rows_final(levels, n)
    return told


def _rebalanced(model: MultiScaleDPJ, levels, parents, seed: int, tileable: bool,
                free_moves: bool = False, forced_moves: bool = False):
    """The finest levels with their shares brought back (a copy, when points moved): first by
    moves its parents allow; then, if ``free_moves`` and a share is still off (a small field
    from a photo of a few large regions: its parents were drawn as few blobs), by moves on the
    law of the finest windows alone (own_law), over FREE_PASSES passes; then, if
    ``forced_moves`` and a share is still beyond FORCED_TRIGGER (a level held by one large region of the photo,
    which the texture lacks or holds too little of), by forced moves (balance.rebalance's
    ``forced``: a window may leave the DPJ, at a cost; a lacking level starts from one point)
    over FORCED_PASSES passes. The finest scale has no scale drawn given it, so its parents
    only say where its levels may go."""
    k = model.scales - 1
    if levels.size > MAX_POINTS:          # rebalance would leave it: skip its set-up (0.1 s)
        return levels, 0
    up = None
    if k > 0:
        up = codes_for(model.dpjs[k], parents, levels.shape, tileable)
    aim, g = model.frequencies(k), model.levels_at(k)
    moved_levels = levels.copy()
    moved = rebalance(moved_levels, model.dpjs[k], aim, parents=up,
                      parent_levels=parent_levels(model.dpjs, k), seed=scale_seed(seed, k),
                      wrap=bool(tileable))
    if free_moves and _frequency_error(moved_levels, aim) > TRIGGER:
        moved += rebalance(moved_levels, own_law(model.dpjs[k], g), aim,
                           seed=scale_seed(seed, k), wrap=bool(tileable), passes=FREE_PASSES)
    if forced_moves and _frequency_error(moved_levels, aim) > FORCED_TRIGGER:
        moved += rebalance(moved_levels, own_law(model.dpjs[k], g), aim,
                           seed=scale_seed(seed, k), wrap=bool(tileable), passes=FORCED_PASSES,
                           forced=True)
    return (moved_levels, moved) if moved else (levels, 0)


def own_law(dpj: DPJ, g: int) -> DPJ:
    """The law of a conditional DPJ's windows of its own ``g`` levels, the parents summed out
    (the photo's windows of that scale, as a plain DPJ counts them); kept while ``dpj`` lives."""
    if g == dpj.levels:
        return dpj

    def summed(d: DPJ) -> DPJ:
        codes, where = np.unique(encode(d.configs % g, g), return_inverse=True)
        return DPJ.from_codes(codes, np.bincount(where, weights=d.probs), g, d.window)
    return derived(dpj, f"own law of {g} levels", summed)


def _check_scale_sizes(model: MultiScaleDPJ, shapes) -> None:
    """Every scale at least its window: else name the smallest size that has it."""
    n = model.scales
    if all(h >= d.window[1] and w >= d.window[0] for (h, w), d in zip(shapes, model.dpjs)):
        return
    low_h = max((d.window[1] - 1) * 2 ** (n - 1 - k) + 1 for k, d in enumerate(model.dpjs))
    low_w = max((d.window[0] - 1) * 2 ** (n - 1 - k) + 1 for k, d in enumerate(model.dpjs))
    (h, w) = shapes[-1]
    fewer = ", or fewer scales" if n > 1 else ""
    raise InputError(f"a {w}x{h} texture is too small for {scales_phrase(n)} (each scale is half "
                     f"the next and holds at least its window): choose at least "
                     f"{low_w}x{low_h}{fewer}")


def _draw_scale_closest(model, k, shapes, parents, seed, done, progress, cancel, rows_final,
                        tileable, closure, redraws_at, particles,
                        first=None, steer=False, more_drafts=False,
                        trigger=DRAFT_TRIGGER) -> SynthesisResult:
    """Scale k drawn as close to its level shares as synthesize_scales says; ``done``: the
    share of the work done before each scale (progress); ``first``: the first try, when it is
    already drawn (the trial draw that chose the coarsest law on the torus); ``redraws_at``:
    how the coarsest scale and the others redraw (_draw_scale's ``redraws``); ``steer``: its
    plain draws steered towards the shares; ``more_drafts``: drafted as more particles when
    it is small; ``trigger``: drafted when the plain draws are further off than this."""
    report = None if progress is None else (
        lambda f: progress(done[k] + f * (done[k + 1] - done[k])))
    final = rows_final if k == model.scales - 1 else None
    expected = model.frequencies(k)

    def draw(t, report, cancel, shares=None):
        if t == 0 and first is not None:
            return first
        return _draw_scale(model, k, shapes[k], parents, _try_seed(seed, k, t), report,
                           cancel, final, bool(tileable), closure, redraws_at[k > 0], shares,
                           expected if steer and shares is None else None)
    if particles == 0 or k == model.scales - 1:
        return _closest_draw(draw, _tries(k, model.scales), expected, report, cancel)
    drafts = shapes[k][0] * shapes[k][1] <= MAX_DRAFTED_POINTS
    plain = _closest_draw(draw, PLAIN_TRIES, expected,
                          report and (lambda f: report(f / 2 if drafts else f)), cancel)
    if _frequency_error(plain.levels, expected) <= trigger or not drafts:
        return plain
    drafted = draw(PLAIN_TRIES, report and (lambda f: report((1 + f) / 2)), cancel,
                   Shares(expected, drafts_for(shapes[k][0] * shapes[k][1], particles,
                                               more_drafts)))
    return min(plain, drafted, key=lambda r: _frequency_error(r.levels, expected))


def _draft_trigger(model, k: int, parents, lean: bool) -> float:
    """How far off a plain draw of scale k may be before it is drafted: DRAFT_TRIGGER, and
    with ``lean`` (LEAN_DRAFTS) that beyond its parents' own error."""
    if not lean or k == 0:
        return DRAFT_TRIGGER
    return DRAFT_TRIGGER + _frequency_error(parents, model.frequencies(k - 1))


def _closest_draw(draw, tries: int, expected, progress, cancel) -> SynthesisResult:
    """The first of ``tries`` draws whose level shares are within FREQUENCY_TOLERANCE of
    ``expected``, else the closest (the draws run two at a time, see _in_order)."""
    if tries == 1:
        return draw(0, progress, cancel)
    best = None
    with closing(_in_order(draw, tries, progress, cancel)) as draws:
        for r in draws:
            off = _frequency_error(r.levels, expected)
            if best is None or off < best[0]:
                best = (off, r)
            if off <= FREQUENCY_TOLERANCE:
                return r
    return best[1]


def _in_order(draw, count: int, progress=None, cancel=None):
    """Yield draw(t, progress, cancel) for t = 0 … count-1 in order, two at a time: draw t + 1
    runs on a second thread (the other core is otherwise idle while the coarse scales are
    drawn). The results are those of one draw after another; once the caller stops reading,
    the draw running ahead is cancelled."""
    with ThreadPoolExecutor(1, thread_name_prefix="coarse-try") as worker:
        for t in range(0, count, 2):
            pair = min(2, count - t)
            report = None if progress is None else _part(progress, t, pair, count)
            with closing(_pair(worker, draw, t, pair, report, cancel)) as draws:
                yield from draws


def _part(progress, t: int, pair: int, tries: int):
    return lambda f: progress((t + f * pair) / tries)


def _pair(worker, draw, t: int, pair: int, progress, cancel):
    """Draw t here and (``pair`` = 2) draw t + 1 on ``worker`` at once; yields them in order.
    Once the caller stops reading, the draw on the worker is cancelled and waited for."""
    stop = threading.Event()
    ahead = None
    if pair == 2:
        ahead = worker.submit(draw, t + 1, None, lambda: stop.is_set() or bool(cancel and cancel()))
    try:
        yield draw(t, progress, cancel)
        if ahead is not None:
            yield ahead.result()
    finally:
        stop.set()
        if ahead is not None:
            _settle(ahead)


def _settle(job) -> None:
    """Wait for a speculative draw to end (finished, failed or cancelled); its result is unused
    unless it was read before."""
    try:
        job.result()
    except Cancelled:
        pass


def _torus_law(dpj: DPJ, shape, seed: int, closure: int,
               redraws=(OLD_REDRAWS, NO_ROW_LIMIT),
               steer=None) -> tuple[DPJ, SynthesisResult | None]:
    """The coarsest scale's law for a tileable draw: its own, or the law of its largest
    sub-window (one row and column fewer at a time) whose draw on the torus closes; and that
    draw (None for the last resort, which is not tried). The draw is the coarsest scale's first
    try: the same law, seed and redraws, and a budget it did not reach.

    A wide window over a small photo reduction is nearly deterministic: its chain follows the
    photo's rows, which close only around the photo's own torus. Drawn on a torus of another
    size, the seams then meet dead ends everywhere (grass, gravel: 50–90 % of the windows
    outside the DPJ, a band the finer scales inherit). A smaller window branches more and
    closes; the first draw that leaves at most TORUS_TOLERANCE of its windows outside says
    which (judged on ``scale_seed(seed, 0)``, so the same seed picks the same window;
    closure 3 stops a draw past TORUS_BUDGET redraws a point: it does not close; closure 5
    also past TORUS_REPAIRS back-offs a point; each draw redraws as ``redraws`` says (the
    tries at a dead end, the redraws a row may make per point), as the coarsest scale's draws
    will, and steered towards ``steer``, the level shares, as
    they will be, when given)."""
    laws = derived(dpj, "torus laws", _sub_windows)
    points = shape[0] * shape[1]
    budget = int(TORUS_BUDGET * points) if closure >= 3 else None
    repairs = int(TORUS_REPAIRS * points) if closure >= 5 else None

    def closes(t, progress, cancel):
        law = laws[t]
        drawn = synthesize(law, shape, seed=scale_seed(seed, 0), tileable=True,
                           closure=_seam(closure, 0), cancel=cancel, redraw_budget=budget,
                           repair_budget=repairs, max_redraws=redraws[0],
                           row_redraws=redraws[1], steer=steer)
        if past_budget((budget, repairs), drawn.redraws, drawn.repairs):
            return None
        seen = estimate_dpj(drawn.levels, law.window, law.levels, wrap=True)
        return drawn if seen.probs[~np.isin(seen.codes, law.codes)].sum() <= TORUS_TOLERANCE \
            else None

    with closing(_in_order(closes, len(laws) - 1)) as tried:   # the last law is the last resort
        for law, drawn in zip(laws, tried):
            if drawn is not None:
                return law, drawn
    return laws[-1], None


def _sub_windows(dpj: DPJ) -> tuple:
    """The DPJ and the laws of its top-left sub-windows, one row and column fewer at a time
    down to 2 (kept with the DPJ, see synthesis.derived: their tables are built once)."""
    laws = [dpj]
    while min(laws[-1].window) > 2:
        (u, v) = laws[-1].window
        laws.append(laws[-1].marginal(rows=slice(0, v - 1), cols=slice(0, u - 1)))
    return tuple(laws)


def check_redraws(redraws) -> int:
    if redraws not in range(OLD_REDRAWS + 1) or isinstance(redraws, bool):
        raise InputError(f"{redraws!r} redraws at a dead end: choose 0 to {OLD_REDRAWS}")
    return int(redraws)


def check_scales_closure(closure) -> int:
    if closure not in range(1, SCALES_CLOSURE + 1) or isinstance(closure, bool):
        raise InputError(f"seam closure {closure!r} does not exist: choose 1 to "
                         f"{SCALES_CLOSURE}")
    return int(closure)


def _seam(closure: int, k: int) -> int:
    """The seam closure (synthesis.CLOSURE) a closure of the scales draws scale k with."""
    return min(SEAMS[closure - 1], COARSEST_SEAM) if k == 0 else SEAMS[closure - 1]


def _tries(k: int, scales: int) -> int:
    """The finest scale is drawn once (it is most of the work, and given its parents its level
    shares come out right), the next one at most twice, the small coarse ones more often."""
    return 1 if k == scales - 1 else 2 if k == scales - 2 else COARSE_TRIES


def _draw_scale(model, k, shape, parents, seed, progress, cancel, rows_final, tileable,
                closure, redraws, shares=None, steer=None):
    """Scale k, given the levels of scale k - 1 (``parents``); ``redraws``: its tries at a
    dead end and (the coarsest) the redraws a row may make per point."""
    dpj = model.dpjs[k]
    if k == 0:
        return synthesize(dpj, shape, seed=seed, progress=progress, cancel=cancel,
                          rows_final=rows_final, tileable=tileable, closure=_seam(closure, 0),
                          max_redraws=redraws[0], row_redraws=redraws[1], shares=shares,
                          steer=steer)
    return synthesize_given(dpj, codes_for(dpj, parents, shape, tileable),
                            parent_levels(model.dpjs, k), seed=seed,
                            progress=progress, cancel=cancel, rows_final=rows_final,
                            tileable=tileable, closure=_seam(closure, k), shares=shares,
                            steer=steer, max_redraws=redraws[0])


def _frequency_error(levels: np.ndarray, expected: np.ndarray) -> float:
    shares = np.bincount(levels.ravel(), minlength=len(expected)) / levels.size
    return float(np.abs(shares - expected).max())


def _try_seed(seed: int, k: int, t: int) -> int:
    """The first draw of scale k uses scale_seed; a redraw, a seed drawn from (seed, k, t)."""
    if t == 0:
        return scale_seed(seed, k)
    state = np.random.SeedSequence([int(seed), k, t]).generate_state(1, np.uint64)[0]
    return int(state >> np.uint64(1))


def scale_seed(seed: int, k: int) -> int:
    """Scale 0 uses the seed itself; finer scales a seed drawn from (seed, k)."""
    if k == 0:
        return int(seed)
    return int(np.random.SeedSequence([int(seed), k]).generate_state(1, np.uint64)[0] >> np.uint64(1))
