"""Editing a DPJ by hand (thesis §5.2.2, §4.5; digest §5, §7, §8, §11): pure functions, new DPJs.

It sits between the manual DPJ editor (app/dpj_editor) and synthesis: set or remove entries, the
checks' remedies (normalise, make stationary, restrict), the generators (from a seed, the empty
and all-maximum weights, merging levels) and the small views the editor's charts draw.
"""

from __future__ import annotations

import numpy as np
import scipy        # scipy.sparse loads on first use, not at start-up

from .chain import MAIN
from .dpj import DPJ, check_palette, check_window, decode, encode, grey_ramp
from ..errors import Cancelled, InputError

MAX_RANDOM_CONFIGS = 2**22     # a seeded DPJ draws every configuration: G^(u·v) must stay small
STATIONARY_TOL = 1e-11         # L1 residual make_stationary aims below (the checks want 1e-9)
FADED = 1e-8                   # an entry make_stationary shrinks by more is fading to 0: dropped
MAX_PRUNINGS = 16              # rounds dropping entries no stationary law keeps
STATIONARY_CHECK = 1e-10       # ... until the law's residual is below this (the checks want 1e-9)



# -- entries ---------------------------------------------------------------------------------------

def set_entries(dpj: DPJ, configs, probs) -> DPJ:
    """The DPJ with these configurations set to these probabilities (added or replaced).

    A probability of 0 removes the configuration: only non-zero entries are stored (§5).
    """
    u, v = dpj.window
    configs = np.asarray(configs)
    if configs.ndim == 2:
        configs = configs[None]
    probs = np.atleast_1d(np.asarray(probs, dtype=np.float64))
    if configs.shape[1:] != (v, u) or len(probs) != len(configs):
        raise InputError(f"a configuration of this DPJ is {v} rows × {u} columns, one "
                         "probability each")
    _check_probabilities(probs)
    if len(configs) and (configs.min() < 0 or configs.max() >= dpj.levels):
        raise InputError(f"a configuration uses a level outside 0..{dpj.levels - 1}")
    codes = encode(configs.astype(np.uint8), dpj.levels)
    codes, last = np.unique(codes[::-1], return_index=True)      # the last value given wins
    probs = probs[::-1][last]
    keep = ~np.isin(dpj.codes, codes)
    new = probs != 0
    return _rebuild(dpj, np.concatenate([dpj.codes[keep], codes[new]]),
                    np.concatenate([dpj.probs[keep], probs[new]]))


def set_entry(dpj: DPJ, config, prob: float) -> DPJ:
    """One configuration (v, u) set to ``prob`` (0 removes it): the "Add/Set" of the painter."""
    return set_entries(dpj, np.asarray(config)[None], [prob])


def remove_entries(dpj: DPJ, codes) -> DPJ:
    """The DPJ without the configurations of these codes (unknown codes are ignored)."""
    keep = ~np.isin(dpj.codes, np.asarray(codes, dtype=np.int64))
    return _rebuild(dpj, dpj.codes[keep], dpj.probs[keep])


def normalize(dpj: DPJ) -> DPJ:
    """Divide every probability by the sum, so they sum to 1 (the check's one-click remedy)."""
    return dpj.normalized()


def _rebuild(dpj: DPJ, codes, probs, **kw) -> DPJ:
    kw = {"palette": dpj.palette, "meta": dpj.meta, **kw}
    return DPJ.from_codes(codes, probs, dpj.levels, dpj.window, **kw)


def _check_probabilities(probs: np.ndarray) -> None:
    if not np.all(np.isfinite(probs)) or np.any(probs < 0) or np.any(probs > 1):
        raise InputError("a probability is a number between 0 and 1")


# -- stationarity (§5.2.2: the connectivity rules, Fig. 4.4) ---------------------------------------

def residuals(dpj: DPJ) -> tuple[float, float]:
    """(horizontal, vertical) stationarity residuals: the L1 distance between the laws of the
    left and right (u-1)-column sub-windows, and of the top and bottom (v-1)-row ones."""
    u, v = dpj.window
    found = iter(_sub_windows(dpj))
    out = []
    for present in (u > 1, v > 1):
        if not present or not len(dpj):
            out.append(0.0)
            continue
        a, b = next(found)
        _, ids = np.unique(np.concatenate([a, b]), return_inverse=True)
        ids = ids.ravel()
        m = int(ids.max()) + 1
        diff = (np.bincount(ids[:len(a)], dpj.probs, m) - np.bincount(ids[len(a):], dpj.probs, m))
        out.append(float(np.abs(diff).sum()))
    return out[0], out[1]


def make_stationary(dpj: DPJ, *, tol: float = STATIONARY_TOL, max_steps: int = 100,
                    cancel=None) -> DPJ:
    """The stationary DPJ closest to this one: residuals below ``tol``, same total mass.

    What is chosen: the *I-projection*, the law p' that minimises the divergence KL(p' ‖ p) among
    the laws on the same configurations whose left/right and top/bottom marginals agree. It has
    the form of iterative proportional fitting, p'(c) ∝ p(c)·x(L)/x(R)·y(T)/y(B) with one factor
    per sub-window (L, R the left and right (u-1)-column ones, T, B the top and bottom (v-1)-row
    ones); the factors are found by Newton's method on the convex dual rather than by alternating
    sweeps, which crawl when classes of the chain are weakly linked. No configuration is added,
    so the texture keeps its character. A configuration no stationary law can keep is dropped:
    first every transition that never comes back (in either direction); then, since the two
    directions constrain each other, any entry the projection shrinks by more than ``1/FADED``
    (it is fading to 0), after which the rest is balanced again. A stationary DPJ comes back
    unchanged. ``cancel()`` returning True stops the work with :class:`Cancelled`.
    """
    _check_usable(dpj)
    if _worst_residual(dpj) <= tol:
        return dpj
    keep = dpj.probs > 0
    for _ in range(MAX_PRUNINGS):
        keep = _recurrent_support(dpj, keep)
        if not keep.any():
            break
        logw = _balance(dpj, keep, tol, max_steps, cancel)
        logq = logw - logw.max()
        logq -= np.log(np.exp(logq).sum())
        shrink = logq - np.log(dpj.probs[keep] / dpj.total)
        fading = shrink < np.log(FADED)
        if not fading.any():
            balanced = _rebuild(dpj, dpj.codes[keep], np.exp(logq) * dpj.total)
            if _worst_residual(balanced) <= STATIONARY_CHECK:
                return balanced
            fading = shrink == shrink.min()   # the projection stalled on its way to dropping it
        keep[np.flatnonzero(keep)[fading]] = False
    raise InputError("no stationary DPJ uses only these configurations: each of them "
                     "leads to a sub-window that never comes back; add configurations "
                     "that close the cycles")


def _check_usable(dpj: DPJ) -> None:
    p = dpj.probs
    if not len(dpj) or not np.all(np.isfinite(p)) or np.any(p < 0) or p.sum() <= 0:
        raise InputError("the DPJ needs at least one configuration of positive probability")


def _worst_residual(dpj: DPJ) -> float:
    return max(residuals(dpj)) / dpj.total


def _sub_windows(dpj: DPJ) -> list[tuple[np.ndarray, np.ndarray]]:
    """(from, to) codes of each entry for each direction that has a constraint."""
    u, v = dpj.window
    pairs = []
    if u > 1:
        pairs.append(dpj.horizontal_states())
    if v > 1:
        pairs.append(dpj.vertical_states())
    return pairs


def _constraints(dpj: DPJ, keep: np.ndarray):
    """The (entries × sub-windows) matrix A of +1 (leaves) / -1 (enters): Aᵀp = 0 is stationarity.

    Returns A (CSR) and the number of columns of each direction.
    """
    rows, cols, vals, sizes, offset = [], [], [], [], 0
    idx = np.flatnonzero(keep)
    for a, b in _sub_windows(dpj):
        _, ids = np.unique(np.concatenate([a[keep], b[keep]]), return_inverse=True)
        ids = ids.ravel()
        m = int(ids.max()) + 1 if len(ids) else 0
        k = len(idx)
        rows += [np.arange(k), np.arange(k)]
        cols += [ids[:k] + offset, ids[k:] + offset]
        vals += [np.ones(k), -np.ones(k)]
        sizes.append(m)
        offset += m
    if not rows:
        return scipy.sparse.coo_matrix((len(idx), 0)).tocsr(), sizes
    a = scipy.sparse.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                   shape=(len(idx), offset)).tocsr()     # a self-loop's +1 and -1 cancel
    a.eliminate_zeros()
    return a, sizes


def _recurrent_support(dpj: DPJ, keep: np.ndarray) -> np.ndarray:
    """Entries that can carry mass in a stationary law: drop, until none is left to drop, every
    transition between two strongly connected classes of the horizontal or the vertical graph
    of sub-windows (a flow that conserves mass cannot use an edge that is on no cycle)."""
    keep = keep.copy()
    pairs = _sub_windows(dpj)
    changed = True
    while changed and keep.any():
        changed = False
        for a, b in pairs:
            crossing = _crossing_edges(a[keep], b[keep])
            if crossing.any():
                idx = np.flatnonzero(keep)
                keep[idx[crossing]] = False
                changed = True
    return keep


def _crossing_edges(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    states, ids = np.unique(np.concatenate([a, b]), return_inverse=True)
    ids = ids.ravel()
    k = len(a)
    graph = scipy.sparse.coo_matrix((np.ones(k), (ids[:k], ids[k:])), shape=(len(states), len(states)))
    _, label = scipy.sparse.csgraph.connected_components(graph.tocsr(), directed=True, connection="strong")
    return label[ids[:k]] != label[ids[k:]]


def _balance(dpj: DPJ, keep: np.ndarray, tol: float, max_steps: int, cancel=None) -> np.ndarray:
    """log p'(c) up to a constant: minimise f(θ) = log Σ p·exp(Aθ) by damped Newton steps.

    ∇f = Aᵀp'/Σp' is the vector of marginal differences, so its L1 norm is the residual.
    """
    a, _ = _constraints(dpj, keep)
    logp = np.log(dpj.probs[keep])
    if a.shape[1] == 0:
        return logp
    theta = np.zeros(a.shape[1])
    f, w, g = _objective(a, logp, theta)
    for _ in range(max_steps):
        if np.abs(g).sum() <= tol:
            break
        if cancel is not None and cancel():
            raise Cancelled("make stationary cancelled")
        step = _newton_step(a, w, g)
        slope = float(g @ step)
        if not np.all(np.isfinite(step)) or slope >= 0:
            break
        t = 1.0
        while t > 1e-12:
            f_new, w_new, g_new = _objective(a, logp, theta + t * step)
            if f_new <= f + 1e-4 * t * slope or np.abs(g_new).sum() < np.abs(g).sum():
                break
            t /= 2
        else:
            break
        theta = theta + t * step
        f, w, g = f_new, w_new, g_new
    return logp + a @ theta


def _newton_step(a, w, g) -> np.ndarray:
    """Solve (Aᵀ diag(w) A) d = -g by conjugate gradients with a diagonal preconditioner: the
    matrix is a weighted graph Laplacian of the sub-windows (singular along constants, which g is
    orthogonal to), so CG needs a few dozen products where a sparse LU fills in badly."""
    h = (a.T @ a.multiply(w[:, None])).tocsr()
    diag = np.maximum(h.diagonal(), 1e-300)
    precond = scipy.sparse.linalg.LinearOperator(h.shape, matvec=lambda x: x / diag)
    step, _ = scipy.sparse.linalg.cg(h, -g, M=precond, rtol=1e-6, maxiter=500)
    return step


def _objective(a, logp, theta):
    """f = log Σ exp(log p + Aθ), the normalised weights w and the gradient Aᵀw."""
    z = logp + a @ theta
    top = z.max()
    e = np.exp(z - top)
    s = e.sum()
    w = e / s
    return float(top + np.log(s)), w, a.T @ w


# -- the chain's classes (§4.5, Massaloux) ---------------------------------------------------------

def chain_roles(dpj: DPJ) -> np.ndarray:
    """Each entry's role in the horizontal chain once dead ends are pruned: MAIN (its left
    sub-window is in the closed class carrying the most probability), DEAD_END, TRANSIENT or
    MINOR_CLOSED (see :class:`texeditor.markov.chain.Chain`).

    Entries that are not MAIN are the ones a long synthesis cannot keep reaching: the editor marks
    them, and :func:`restrict` removes them.
    """
    return dpj.chain.roles


def unreachable_entries(dpj: DPJ) -> np.ndarray:
    """Entries a long synthesis leaves behind: dead ends, transient states, small closed classes."""
    return chain_roles(dpj) != MAIN


def restrict(dpj: DPJ) -> DPJ:
    """Massaloux's restriction (§4.5): the dead ends pruned, the main closed class of the
    horizontal chain kept, normalised."""
    return dpj.restrict()


# -- generators (§5.2.2) ---------------------------------------------------------------------------

def random_dpj(window: tuple[int, int], levels: int, seed: int, *, sparsity: float = 0.0,
               evenness: float = 1.0, palette=None, meta: dict | None = None) -> DPJ:
    """A DPJ drawn from a seed, as the thesis's second function (§5.2.2): same seed, same DPJ.

    Each configuration gets a Gamma(``evenness``) weight (so the law is a Dirichlet draw): with
    evenness 1 most get a small value — a granular texture; lower, a few dominate — patterned.
    ``sparsity`` (0..1) is the share of configurations set to zero; every configuration keeps a
    non-zero probability at 0. The drop draws do not depend on ``sparsity``, so raising it only
    removes more entries.
    """
    u, v = check_window(window, levels)
    if not 0 <= sparsity < 1:
        raise InputError(f"sparsity is a share in [0, 1), got {sparsity}")
    if not 0.05 <= evenness <= 100:
        raise InputError(f"evenness must be 0.05..100, got {evenness}")
    n = levels ** (u * v)
    if n > MAX_RANDOM_CONFIGS:
        raise InputError(f"a {u}×{v} window with G = {levels} has {n:,} configurations, too many "
                         f"to draw them all (at most {MAX_RANDOM_CONFIGS:,}): use a smaller "
                         "window or fewer levels")
    rng = np.random.default_rng(np.random.SeedSequence(_seed(seed)))
    weights = np.maximum(rng.gamma(evenness, size=n), np.finfo(np.float64).tiny)
    kept = rng.random(n) >= sparsity
    if not kept.any():
        kept[np.argmax(weights)] = True
    codes = np.flatnonzero(kept).astype(np.int64)
    probs = weights[kept] / weights[kept].sum()
    meta = {"source": "seed", "seed": int(seed), "sparsity": float(sparsity),
            "evenness": float(evenness), **(meta or {})}
    return DPJ.from_codes(codes, probs, levels, window, palette=palette, meta=meta)


def _seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"the seed must be a non-negative integer, got {seed!r}")
    return int(seed)


def empty_config(dpj: DPJ) -> np.ndarray:
    """The empty configuration: every point level 0, the background (§5.2.2)."""
    u, v = dpj.window
    return np.zeros((v, u), np.uint8)


def full_config(dpj: DPJ) -> np.ndarray:
    """The all-maximum configuration: every point level G-1."""
    u, v = dpj.window
    return np.full((v, u), dpj.levels - 1, np.uint8)


def set_extremes(dpj: DPJ, *, empty: float | None = None, full: float | None = None) -> DPJ:
    """Set the empty (all 0: airy ↔ dense) and/or all-maximum weights exactly, scale the rest.

    The given entries take exactly the given values; every other entry is scaled so the whole
    sums to 1. A weight left as None is part of "the rest".
    """
    fixed = {}
    if empty is not None:
        fixed[int(encode(empty_config(dpj)[None], dpj.levels)[0])] = float(empty)
    if full is not None:
        fixed[int(encode(full_config(dpj)[None], dpj.levels)[0])] = float(full)
    values = np.array(list(fixed.values()), dtype=np.float64)
    _check_probabilities(values)
    rest = 1.0 - values.sum()
    if rest < -1e-12:
        raise InputError("the empty and all-maximum weights together exceed 1")
    codes = np.array(list(fixed), dtype=np.int64)
    others = ~np.isin(dpj.codes, codes)
    rest_sum = dpj.probs[others].sum()
    if rest > 0 and rest_sum <= 0:
        raise InputError("no other configuration to share the rest of the probability: add "
                         "some first")
    scaled = dpj.probs[others] * (max(rest, 0.0) / rest_sum) if rest_sum > 0 else dpj.probs[others]
    nonzero = values != 0
    return _rebuild(dpj, np.concatenate([dpj.codes[others], codes[nonzero]]),
                    np.concatenate([scaled, values[nonzero]]))


def merge_levels(dpj: DPJ, mapping, *, palette=None) -> DPJ:
    """Merge or remap the levels exactly: old level k becomes ``mapping[k]``.

    This is the recolouring R = QᵀPQ of joint statistics (digest §11) with a 0/1 matrix Q
    (``mapping`` may also be given as that G×G' matrix, one 1 per row): each configuration is
    recoloured and the probabilities of configurations that become equal are added, so the result
    is what estimating the merged-level image would give. G' = the highest new level + 1. Each
    new level's colour is the mean of the old ones merged into it (grey ramp where none).
    """
    mapping = _mapping(mapping, dpj.levels)
    new_levels = int(mapping.max()) + 1
    if new_levels < 2:
        raise InputError("merging every level into one leaves nothing to synthesise: keep at "
                         "least two levels")
    codes = encode(mapping[dpj.configs], new_levels)
    unique, inverse = np.unique(codes, return_inverse=True)
    probs = np.bincount(inverse.ravel(), weights=dpj.probs, minlength=len(unique))
    if palette is None:
        palette = _merged_palette(dpj.palette, mapping, new_levels)
    meta = {**dpj.meta, "merged_from": int(dpj.levels), "mapping": mapping.tolist()}
    return DPJ.from_codes(unique, probs, new_levels, dpj.window,
                          palette=check_palette(palette, new_levels), meta=meta)


def _mapping(mapping, levels: int) -> np.ndarray:
    m = np.asarray(mapping)
    if m.ndim == 2:
        if m.shape[0] != levels or not np.all((m == 0) | (m == 1)) or np.any(m.sum(1) != 1):
            raise InputError(f"Q must be a {levels}×G' matrix of 0/1 with one 1 per row")
        m = np.argmax(m, axis=1)
    if m.shape != (levels,) or m.dtype.kind not in "iu" and not np.all(m == np.round(m)):
        raise InputError(f"the mapping gives one new level for each of the {levels} levels")
    m = m.astype(np.int64)
    if m.min() < 0 or m.max() >= 16:
        raise InputError("new levels are 0..15")
    return m.astype(np.uint8)


def _merged_palette(palette: np.ndarray, mapping: np.ndarray, new_levels: int) -> np.ndarray:
    out = grey_ramp(new_levels).astype(np.float64)
    for j in range(new_levels):
        members = palette[mapping == j]
        if len(members):
            out[j] = members.mean(axis=0)
    return np.round(out).astype(np.uint8)


# -- what the editor's charts show -----------------------------------------------------------------

def level_marginal(dpj: DPJ) -> np.ndarray:
    """P(a point has level k), k = 0..G-1: every cell of every window counted, by probability."""
    cells = dpj.window[0] * dpj.window[1]
    total = dpj.total
    if not len(dpj) or total <= 0:
        return np.zeros(dpj.levels)
    counts = np.bincount(dpj.configs.reshape(len(dpj), cells).ravel(),
                         weights=np.repeat(dpj.probs, cells), minlength=dpj.levels)
    return counts / (cells * total)


def transition_matrix(dpj: DPJ, max_states: int = 48):
    """The horizontal chain's transitions m(L → R) between (u-1)-column sub-windows (digest §6).

    Only the ``max_states`` states of highest probability are kept (the rows still sum to the
    probability of staying among them). Returns (state configurations (k, v, u-1), the k×k
    matrix, the number of states in all).
    """
    u, v = dpj.window
    if u == 1 or not len(dpj) or dpj.total <= 0:
        return np.zeros((0, v, max(u - 1, 1)), np.uint8), np.zeros((0, 0)), 0
    left, right = dpj.horizontal_states()
    states, ids = np.unique(np.concatenate([left, right]), return_inverse=True)
    ids = ids.ravel()
    li, ri = ids[:len(left)], ids[len(left):]
    mass = np.bincount(li, weights=dpj.probs, minlength=len(states))
    top = np.sort(np.argsort(-mass, kind="stable")[:max_states])
    pos = np.full(len(states), -1)
    pos[top] = np.arange(len(top))
    inside = (pos[li] >= 0) & (pos[ri] >= 0)
    matrix = np.zeros((len(top), len(top)))
    np.add.at(matrix, (pos[li[inside]], pos[ri[inside]]), dpj.probs[inside])
    row_mass = mass[top]
    matrix = np.divide(matrix, row_mass[:, None], out=np.zeros_like(matrix),
                       where=row_mass[:, None] > 0)
    return decode(states[top], dpj.levels, v, u - 1), matrix, len(states)


def level_presence(dpj: DPJ) -> np.ndarray:
    """(entries, G) bool: which levels each configuration contains (the table's level filter)."""
    n = len(dpj)
    present = np.zeros((n, dpj.levels), bool)
    flat = dpj.configs.reshape(n, -1)
    rows = np.repeat(np.arange(n), flat.shape[1])
    present[rows, flat.ravel()] = True
    return present
