"""Quality figures for photographic synthesis, and an image-quilting baseline to compare with.

Each metric compares an output texture with the photo it was made from (grey uint8 (H, W));
bench_quality.py prints them for texeditor, quilting and GIMP's Resynthesizer. Variants checked
against the figures published in the photographic-synthesis issue (512² scikit-image photos):

- GLCM distance: as defined (grey // 8, symmetric normed GLCMs, distances 1, 2, 4 × 4 angles,
  mean total variation). Reproduces every half-vs-half figure and both gravel Resynthesizer
  figures to the third decimal; brick and grass Resynthesizer files in ../shared/peers are not the
  runs the issue measured (brick-30: 0.013 here, 0.061 there; the 3×3 TV disagrees as well).
- 3×3 TV: thresholds from the *reference's* own Lloyd quantisation (for half vs half, the top
  half's; the full photo's gives 0.078 / 0.240 / 0.150). Reproduces the same rows to the third
  decimal.
- Spectrum distance: mean removed, separable Hann window (np.hanning), power per windowed pixel,
  log10 of its mean in integer bins floor(ρ·S) of the radius ρ in cycles/pixel, S the shortest
  side of the two images, bins 1..S/2 (Nyquist). It gives 0.387 / 0.160 / 0.062 for the half-vs-half rows (issue:
  0.371 / 0.155 / 0.051) and 0.162 / 0.027 for gravel Resynthesizer-9 / -30 (issue: 0.112 /
  0.018). No variant tried fits every row: with or without mean removal, np.hanning, periodic,
  radial (skimage) or one-axis Hann, Tukey or no window, round or floor bins, index or normalised
  radii, log of the mean or mean of the log, total-power or log-mean normalisation, Welch tiles.
  Without a window gravel-9 falls to 0.108 but gravel-30 rises to 0.043 (edge leakage), so the
  plain Hann variant is kept; read its figures against each other, not against the issue's.
- Copied 8×8 blocks: exact, every stride-1 window, hashed then checked byte for byte.
"""

from __future__ import annotations

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from pathlib import Path

from scipy import fft as sfft
from skimage import data
from skimage.color import rgb2gray, rgba2rgb
from skimage.feature import graycomatrix
from skimage.util import img_as_float, img_as_ubyte

import texeditor

GLCM_DISTANCES = (1, 2, 4)
GLCM_ANGLES = (0.0, np.pi / 4, np.pi / 2, 3 * np.pi / 4)
TV_LEVELS = 4
BLOCK = 8


def photo(name: str) -> np.ndarray:
    """A scikit-image data photo by name, else a picture file (a file of that name wins)."""
    if not Path(name).exists() and callable(getattr(data, name, None)):
        return getattr(data, name)()
    return texeditor.load_image(name)


def grey_u8(image) -> np.ndarray:
    """(H, W) uint8 grey of a grey, RGB or RGBA picture: every metric reads greys."""
    image = np.asarray(image)
    if image.ndim == 3 and image.shape[2] <= 2:     # grey, grey + alpha
        image = image[..., 0]
    if image.ndim == 3:
        rgb = rgba2rgb(image) if image.shape[2] == 4 else img_as_float(image)
        return img_as_ubyte(rgb2gray(rgb))
    return image if image.dtype == np.uint8 else img_as_ubyte(img_as_float(image))


def total_variation(p: np.ndarray, q: np.ndarray) -> float:
    """0.5 · Σ|p − q| of two distributions: 0 same, 1 disjoint."""
    return 0.5 * float(np.abs(p - q).sum())


# -- GLCM ------------------------------------------------------------------------------------
def glcm(grey: np.ndarray) -> np.ndarray:
    """Normalised symmetric co-occurrences of 32 greys, (32, 32, distances, angles)."""
    return graycomatrix(grey_u8(grey) // 8, GLCM_DISTANCES, GLCM_ANGLES, levels=32,
                        symmetric=True, normed=True)


def glcm_distance(output, photo) -> float:
    """Mean TV distance between the GLCMs: pairs of greys at short range (texture contrast,
    edges), which a per-pixel histogram misses and 4 levels cannot show."""
    tv = 0.5 * np.abs(glcm(output) - glcm(photo)).sum(axis=(0, 1))
    return float(tv.mean())


# -- spectrum --------------------------------------------------------------------------------
def log_spectrum(grey, bins: int) -> np.ndarray:
    """log10 radially averaged power spectrum over normalised-radius bins 1..bins (Nyquist =
    ``bins``) and power per windowed pixel, so two sizes share frequencies and scale. Mean removed
    and Hann window: the picture's edges and its mean grey do not leak into the spectrum."""
    x = grey_u8(grey).astype(np.float64)
    x -= x.mean()
    h, w = x.shape
    window = np.outer(np.hanning(h), np.hanning(w))
    x *= window
    power = np.abs(sfft.fft2(x)) ** 2 / (window ** 2).sum()    # per pixel: sizes compare
    radius = np.hypot(sfft.fftfreq(h)[:, None], sfft.fftfreq(w)[None, :]) * 2 * bins
    index = np.floor(radius).astype(np.intp).ravel()
    counts = np.bincount(index, minlength=bins + 1)[1:bins + 1]
    sums = np.bincount(index, power.ravel(), minlength=bins + 1)[1:bins + 1]
    return np.log10(np.maximum(sums / np.maximum(counts, 1), 1e-30))


def spectrum_distance(output, photo) -> float:
    """RMS difference of the log spectra: the scale of the texture (grain size, blur, periodic
    bricks) independently of where things are. Bins: up to half the shortest side of both."""
    a, b = grey_u8(output), grey_u8(photo)
    bins = min(min(a.shape), min(b.shape)) // 2
    d = log_spectrum(a, bins) - log_spectrum(b, bins)
    return float(np.sqrt(np.mean(d ** 2)))


SPECTRUM_BANDS = (0, 1 / 32, 1 / 4, 3 / 4, 1)   # radius over Nyquist: periods ≥ 64, 8–64,
#                                                 2.7–8, 2–2.7 points


def spectrum_by_band(output, photo) -> list[float]:
    """The mean log10-power difference (output − photo) over bands of spectrum_distance's
    radial bins (SPECTRUM_BANDS), which says where the distance comes from: structure too
    large, or pixel noise."""
    a, b = grey_u8(output), grey_u8(photo)
    bins = min(min(a.shape), min(b.shape)) // 2
    d = log_spectrum(a, bins) - log_spectrum(b, bins)
    radius = np.arange(1, bins + 1) / bins
    bands = [(radius > lo) & (radius <= hi) for lo, hi in zip(SPECTRUM_BANDS, SPECTRUM_BANDS[1:])]
    return [float(d[band].mean()) if band.any() else float("nan") for band in bands]


# -- 3×3 level configurations ------------------------------------------------------------------
def window_histogram(levels: np.ndarray, g: int, window: int = 3) -> np.ndarray:
    """Frequencies of the window×window configurations (g^(window²) codes, no wrap): the
    statistic a 3×3 DPJ reproduces, so a synthesis from it should score well here."""
    levels = np.asarray(levels, dtype=np.int64)
    h, w = levels.shape
    codes = np.zeros((h - window + 1, w - window + 1), np.int64)
    for dy in range(window):
        for dx in range(window):
            codes = codes * g + levels[dy:dy + h - window + 1, dx:dx + w - window + 1]
    return np.bincount(codes.ravel(), minlength=g ** (window * window)) / codes.size


def tv3x3_distance(output, photo, levels: int = TV_LEVELS) -> float:
    """TV distance of 3×3 configurations, both cut at the photo's own Lloyd thresholds (so a
    texture with the wrong tones is penalised, not re-quantised to look right)."""
    thresholds = texeditor.quantize(grey_u8(photo), levels, "lloyd").thresholds
    cut = [np.searchsorted(thresholds, grey_u8(x) / 255.0, side="right")
           for x in (output, photo)]
    return total_variation(*(window_histogram(c, levels) for c in cut))


def level_frequencies(levels: np.ndarray, g: int | None = None) -> np.ndarray:
    """Share of each level in a level matrix: a synthesis should keep its model's."""
    levels = np.asarray(levels)
    g = int(levels.max()) + 1 if g is None else g
    return np.bincount(levels.ravel(), minlength=g) / levels.size


# -- copying ---------------------------------------------------------------------------------
def _block_words(grey: np.ndarray, block: int) -> np.ndarray:
    """Every block×block window as a row of bytes, (windows, block²) uint8, contiguous."""
    win = sliding_window_view(grey_u8(grey), (block, block))
    return np.ascontiguousarray(win.reshape(-1, block * block))


def _hash_rows(rows: np.ndarray) -> np.ndarray:
    """A 64-bit hash of each row of bytes (rows padded to whole uint64 words)."""
    pad = (-rows.shape[1]) % 8
    if pad:
        rows = np.pad(rows, ((0, 0), (0, pad)))
    words = rows.view(np.uint64)
    mult = np.random.default_rng(0x5EED).integers(1, 2**63, words.shape[1], dtype=np.uint64) | 1
    h = np.zeros(len(words), np.uint64)
    with np.errstate(over="ignore"):
        for i in range(words.shape[1]):
            h = (h ^ words[:, i]) * mult[i]
            h ^= h >> np.uint64(29)
    return h


def copied_share(output, photo, block: int = BLOCK) -> float:
    """Share of the output's block×block windows found byte for byte in the photo: 0 for a
    texture drawn afresh, 1 for a copy; patch-based methods sit in between."""
    out_rows, ref_rows = _block_words(output, block), _block_words(photo, block)
    out_h, ref_h = _hash_rows(out_rows), _hash_rows(ref_rows)
    order = np.argsort(ref_h, kind="stable")
    ref_sorted = ref_h[order]
    pos = np.minimum(np.searchsorted(ref_sorted, out_h), len(ref_sorted) - 1)
    hit = ref_sorted[pos] == out_h
    match = order[pos[hit]]      # verify: a hash collision must not count as a copy
    hit[hit] = np.all(out_rows[hit] == ref_rows[match], axis=1)
    return float(hit.mean())


# -- image quilting baseline ---------------------------------------------------------------------
def quilt(photo, shape: tuple[int, int], *, patch: int | None = None, overlap: int | None = None,
          tolerance: float = 0.1, seed: int = 0) -> np.ndarray:
    """Efros & Freeman's image quilting (SIGGRAPH 2001): square patches laid in raster order, each
    chosen at random among the photo positions whose overlap error is within ``tolerance`` of the
    best, then joined to the canvas along a minimum-error boundary cut.

    ``photo``: grey (H, W) or colour (H, W, C) uint8; returns ``shape`` with the photo's channels.
    ``patch`` defaults to 32 px (less for a small photo), ``overlap`` to a sixth of it.
    """
    src = np.asarray(photo)
    grey = src.ndim == 2
    img = (src[..., None] if grey else src).astype(np.float32) / 255.0
    hp, wp, _ = img.shape
    patch = patch or max(4, min(32, hp // 2, wp // 2))
    overlap = overlap or max(1, patch // 6)
    if patch > min(hp, wp) or not 0 < overlap < patch:
        raise ValueError(f"patch {patch} / overlap {overlap} do not fit a {hp}x{wp} photo")
    rng = np.random.default_rng(seed)
    search = _OverlapSearch(img, patch, overlap)
    h, w = shape
    step = patch - overlap
    rows, cols = -(-max(h - overlap, 1) // step), -(-max(w - overlap, 1) // step)
    canvas = np.zeros((rows * step + overlap, cols * step + overlap, img.shape[2]), np.float32)
    for i in range(rows):
        for j in range(cols):
            y, x = i * step, j * step
            target = canvas[y:y + patch, x:x + patch]
            py, px = search.pick(target, top=i > 0, left=j > 0, tolerance=tolerance, rng=rng)
            new = img[py:py + patch, px:px + patch]
            keep_new = _boundary_mask(target, new, overlap, top=i > 0, left=j > 0)
            target[keep_new] = new[keep_new]
    out = np.round(canvas[:h, :w] * 255).astype(np.uint8)
    return out[..., 0] if grey else out


class _OverlapSearch:
    """Sum of squared differences on the overlap for every photo position at once, by FFT
    correlation: SSD = Σm·p² − 2·Σm·t·p + Σm·t² with m the overlap mask, t the canvas."""

    def __init__(self, img: np.ndarray, patch: int, overlap: int):
        self.img, self.patch, self.overlap = img, patch, overlap
        self.shape = img.shape[:2]
        self.valid = (img.shape[0] - patch + 1, img.shape[1] - patch + 1)
        self.spectra = [sfft.rfft2(img[..., c]) for c in range(img.shape[2])]
        squares = sfft.rfft2((img ** 2).sum(axis=2))
        self.energy = {key: self._correlate([squares], [self.mask(*key)])
                       for key in ((True, False), (False, True), (True, True))}

    def mask(self, top: bool, left: bool) -> np.ndarray:
        m = np.zeros((self.patch, self.patch), np.float32)
        if top:
            m[:self.overlap] = 1
        if left:
            m[:, :self.overlap] = 1
        return m

    def _correlate(self, spectra, kernels) -> np.ndarray:
        """Σ_c Σ_uv k_c(u, v) · x_c(y + u, x + v) at every valid (y, x) (circular = valid here)."""
        total = 0
        for spec, k in zip(spectra, kernels):
            total = total + np.conj(sfft.rfft2(k, s=self.shape)) * spec
        out = sfft.irfft2(total, s=self.shape)
        return out[:self.valid[0], :self.valid[1]]

    def pick(self, target, *, top: bool, left: bool, tolerance: float, rng) -> tuple[int, int]:
        if not (top or left):
            return int(rng.integers(self.valid[0])), int(rng.integers(self.valid[1]))
        m = self.mask(top, left)
        cross = self._correlate(self.spectra, [m * target[..., c] for c in range(target.shape[2])])
        err = self.energy[(top, left)] - 2 * cross + float((m[..., None] * target ** 2).sum())
        err = np.maximum(err, 0)
        ys, xs = np.nonzero(err <= err.min() * (1 + tolerance))
        k = int(rng.integers(len(ys)))
        return int(ys[k]), int(xs[k])


def _boundary_mask(old: np.ndarray, new: np.ndarray, overlap: int, *, top: bool,
                   left: bool) -> np.ndarray:
    """Where the new patch shows: past the minimum-error cut through each overlap strip."""
    err = ((old - new) ** 2).sum(axis=2)
    show = np.ones(err.shape, bool)
    if left:
        show &= _vertical_cut(err[:, :overlap], err.shape[1])
    if top:
        show &= _vertical_cut(err[:overlap].T, err.shape[0]).T
    return show


def _vertical_cut(strip: np.ndarray, width: int) -> np.ndarray:
    """Dynamic programming down a (rows, overlap) error strip: the cheapest 8-connected path;
    returns a (rows, width) mask, True right of the path (the new patch's side)."""
    rows, ov = strip.shape
    cost = strip.astype(np.float64).copy()
    for r in range(1, rows):
        prev = np.pad(cost[r - 1], 1, constant_values=np.inf)
        cost[r] += np.minimum(np.minimum(prev[:-2], prev[1:-1]), prev[2:])
    path = np.empty(rows, np.intp)
    path[-1] = int(np.argmin(cost[-1]))
    for r in range(rows - 2, -1, -1):
        c = path[r + 1]
        lo, hi = max(c - 1, 0), min(c + 2, ov)
        path[r] = lo + int(np.argmin(cost[r, lo:hi]))
    return np.arange(width)[None, :] >= path[:, None]
