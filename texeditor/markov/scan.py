"""The scan direction (thesis §4.3.2, §5.2.1b): the order in which the window sweeps the texture.

The 2-D Markov process is not isotropic: it runs along rows, row after row, so it reproduces best
the structure that lies along its scan. The thesis scans in the texture's own direction. Here a
scan is a turn of the picture — the photo is turned before its windows are counted, the texture
drawn in the turned frame and turned back — so estimation and the sampler stay one code path.
A DPJ acquired in a scan is a law of the turned photo's windows; its meta records the scan.

A 2×3 matrix and its four scans (what the sampler sees as its rows, top to bottom):

>>> m = np.array([[0, 1, 2], [3, 4, 5]])
>>> for scan in SCANS:
...     print(scan, to_scan(m, scan).tolist())
rows [[0, 1, 2], [3, 4, 5]]
rows-up [[3, 4, 5], [0, 1, 2]]
columns [[0, 3], [1, 4], [2, 5]]
columns-left [[2, 5], [1, 4], [0, 3]]
>>> all(np.array_equal(from_scan(to_scan(m, s), s), m) for s in SCANS)
True
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import InputError

ROWS = "rows"
SCANS = (ROWS, "rows-up", "columns", "columns-left")
SCAN_NAMES = {"rows": "Rows, top to bottom", "rows-up": "Rows, bottom to top",
              "columns": "Columns, left to right", "columns-left": "Columns, right to left"}


def check_scan(scan) -> str:
    if scan not in SCANS:
        raise InputError(f"the scan must be one of {', '.join(SCANS)}, got {scan!r}")
    return scan


def _matrix(matrix) -> np.ndarray:
    m = np.asarray(matrix)
    if m.ndim != 2 or m.size == 0:
        raise InputError(f"a level matrix must be a non-empty 2-D array, got shape {m.shape}")
    return m


def to_scan(matrix: np.ndarray, scan: str) -> np.ndarray:
    """The matrix as the scan sees it: its lines in the order the scan takes them, as rows."""
    m = _matrix(matrix)
    turned = {"rows": m, "rows-up": m[::-1], "columns": m.T,
              "columns-left": m[:, ::-1].T}[check_scan(scan)]
    return np.ascontiguousarray(turned)


def from_scan(matrix: np.ndarray, scan: str) -> np.ndarray:
    """Inverse of :func:`to_scan`: a matrix drawn in the scan's frame, turned back."""
    m = _matrix(matrix)
    turned = {"rows": m, "rows-up": m[::-1], "columns": m.T,
              "columns-left": m.T[:, ::-1]}[check_scan(scan)]
    return np.ascontiguousarray(turned)


def scan_shape(shape: tuple[int, int], scan: str) -> tuple[int, int]:
    """The (height, width) to draw in the scan's frame for an (H, W) result."""
    h, w = shape
    return (w, h) if check_scan(scan).startswith("columns") else (h, w)


def synthesize(dpj, shape: tuple[int, int], *, scan: str = ROWS, **kw):
    """:func:`texeditor.markov.synthesis.synthesize` in a scan: drawn in the scan's frame, then
    turned back to (H, W). The rows scan is the sampler itself, untouched."""
    from .synthesis import synthesize as draw
    if check_scan(scan) == ROWS:
        return draw(dpj, shape, **kw)
    if kw.get("rows_final") is not None:
        raise InputError("rows drawn in another scan are not the texture's rows: "
                         "rows_final needs the rows scan")
    result = draw(dpj, scan_shape(shape, scan), **kw)
    return dataclasses.replace(result, levels=from_scan(result.levels, scan))
