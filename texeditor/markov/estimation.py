"""Automatic DPJ acquisition (thesis §5.2.1): count every u×v window of a level matrix.

Sits between quantisation (photo → levels) and synthesis: the counts divided by the number of
windows are the DPJ. Counting is vectorised: each window's code is built from u·v shifted views.
"""

from __future__ import annotations

import numpy as np

from .dpj import DPJ, check_window
from .dpj_edit import make_stationary, residuals
from .scan import ROWS, to_scan
from ..errors import InputError

STATIONARY_CHECK = 1e-9     # the L1 residual (per unit of mass) the checks call stationary


def window_codes(levels: np.ndarray, window: tuple[int, int], num_levels: int,
                 wrap: bool = False) -> np.ndarray:
    """The code of every u×v window of ``levels`` (see :func:`texeditor.dpj.encode`).

    With ``wrap`` the matrix is read on the torus, so there are exactly H·W windows and the
    resulting DPJ is exactly stationary in both directions.
    """
    u, v = check_window(window, num_levels)
    levels = _check_matrix(levels, num_levels)
    h, w = levels.shape
    if u > w or v > h:
        raise InputError(f"the {u}x{v} window is larger than the {w}x{h} image")
    if wrap:
        levels = np.pad(levels, ((0, v - 1), (0, u - 1)), mode="wrap")
    rows, cols = levels.shape[0] - v + 1, levels.shape[1] - u + 1
    # int32 when every code fits: half the memory of a 64-megapixel photo's codes, same values
    dtype = np.int32 if num_levels ** (u * v) <= np.iinfo(np.int32).max else np.int64
    codes = np.zeros((rows, cols), dtype=dtype)
    for i in range(v):
        for j in range(u):
            codes *= num_levels
            codes += levels[i:i + rows, j:j + cols]
    return codes.ravel()


def estimate_dpj(matrix: np.ndarray, window: tuple[int, int] = (2, 2), levels: int | None = None,
                 *, wrap: bool = False, scan: str = ROWS, stationary: bool = False,
                 palette=None, meta: dict | None = None, cancel=None) -> DPJ:
    """Estimate the DPJ of a level matrix: the frequency of each u×v configuration.

    ``levels`` (G) defaults to the highest level present + 1. The result has at most as many
    entries as the matrix has windows, and its entries sum to 1. ``scan`` (§5.2.1b): the
    windows are those of the matrix as that scan sees it (:mod:`texeditor.markov.scan`).
    ``stationary``: the estimate is then made to satisfy the thesis's stationarity condition
    (§5.2.2; :func:`texeditor.markov.dpj_edit.make_stationary`, which ``cancel()`` stops); a
    DPJ estimated with ``wrap`` already does. The meta records a scan other than rows and a
    stationarity enforced, so a DPJ acquired as before keeps its former bytes.
    """
    matrix = to_scan(_integers(matrix), scan)
    if meta is not None and not isinstance(meta, dict):
        raise InputError(f"a DPJ's meta must be a dict, got {type(meta).__name__}")
    if levels is None:
        levels = max(2, int(matrix.max()) + 1) if matrix.size else 2
    codes = window_codes(matrix, window, levels, wrap)
    unique, counts = np.unique(codes, return_counts=True)
    del codes
    meta = {"source": "estimated", "wrap": bool(wrap), **(meta or {})}
    if scan != ROWS:
        meta["scan"] = scan
    if stationary:
        meta["stationary"] = True
    dpj = DPJ.from_codes(unique, counts / counts.sum(), levels, window, palette=palette, meta=meta)
    return _stationary(dpj, cancel) if stationary else dpj


def _stationary(dpj: DPJ, cancel) -> DPJ:
    """The estimate made stationary, or an error saying it could not be (never a DPJ that
    claims stationarity in its meta without it)."""
    done = make_stationary(dpj, cancel=cancel)
    if max(residuals(done)) > STATIONARY_CHECK * done.total:
        raise InputError("this estimate could not be made stationary (the balance of its "
                         f"{len(dpj):,} configurations did not converge): tick wrap, or choose "
                         "fewer levels or a smaller window")
    return done


def _integers(levels) -> np.ndarray:
    """A level matrix of integers (a float one, NaN included, is refused before its highest
    level is read)."""
    try:
        levels = np.asarray(levels)
    except (ValueError, TypeError):
        raise InputError("a level matrix must be a 2-D array of integers") from None
    if levels.dtype.kind not in "ui" and levels.dtype != bool:
        raise InputError(f"a level matrix must hold integers, got {levels.dtype}")
    return levels


def _check_matrix(levels: np.ndarray, num_levels: int) -> np.ndarray:
    levels = _integers(levels)
    if levels.ndim != 2 or levels.size == 0:
        raise InputError(f"a level matrix must be a non-empty 2-D array, got shape {levels.shape}")
    if levels.min() < 0 or levels.max() >= num_levels:
        raise InputError(f"the matrix holds levels outside 0..{num_levels - 1}")
    return levels if levels.dtype == np.uint8 else levels.astype(np.int64)
