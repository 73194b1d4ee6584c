"""The steerable pyramid on the torus: a picture split into oriented band-pass sub-bands, octave by
octave, and put back together exactly — the transform Heeger–Bergen synthesis works in.

Built in the frequency domain (Simoncelli's construction): at every frequency the squared filters
sum to one, so the pyramid is a tight frame and ``reconstruct(decompose(x)) == x`` to rounding.
Filtering is a product of FFTs, so the picture is treated as periodic and whatever is made from
the sub-bands tiles. Frequencies are in radians per pixel (Nyquist = π), ``norm="forward"``
FFTs make a sub-band's values independent of the picture's size, so the sub-bands of a photo and
of a larger synthesis have comparable histograms.

Bands, in order: the high-pass residual (r ≥ π/2), then for each level ``orientations`` oriented
bands (level 0 at full size, each next level half as wide and tall), then the low-pass residual.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy import fft

from ..errors import InputError

ORIENTATIONS = 4        # Heeger and Bergen's choice
COARSEST = 8            # the low-pass residual of the smaller picture keeps at least this many px


def pyramid_levels(*shapes) -> int:
    """Levels that fit every one of ``shapes``: octaves until the smallest side's low-pass
    residual would be under COARSEST pixels (a photo and its synthesis must share the levels)."""
    side = min(min(shape[:2]) for shape in shapes)
    if side < 2 * COARSEST:
        raise InputError(f"pictures of {side} pixels are too small for a pyramid: "
                         f"at least {2 * COARSEST}x{2 * COARSEST} are needed")
    return int(math.floor(math.log2(side / COARSEST)))


def level_shapes(shape, levels: int) -> list[tuple[int, int]]:
    """The grid of each level, then of the low-pass residual: each side halved, rounded up, so
    the low-pass spectrum (zero from π/2 on) fits the smaller grid whatever the parity."""
    shapes = [(int(shape[0]), int(shape[1]))]
    for _ in range(levels):
        h, w = shapes[-1]
        shapes.append(((h + 1) // 2, (w + 1) // 2))
    return shapes


class SteerablePyramid:
    """The filters of one picture size (build it with :func:`steerable_pyramid`, which caches)."""

    def __init__(self, shape, levels: int, orientations: int = ORIENTATIONS,
                 dtype=np.float64):
        self.shapes = level_shapes(shape, levels)
        self.orientations = orientations
        self.dtype = np.dtype(dtype)
        complex_type = np.result_type(self.dtype, np.complex64)
        radius, _, _ = _frequencies(self.shapes[0])
        high, low = _split(radius, np.pi)
        self.high0, self.low0 = high.astype(self.dtype), low.astype(self.dtype)
        self.bands, self.lows = [], []
        for level_shape in self.shapes[:-1]:
            low, oriented = _level_filters(level_shape, orientations)
            self.bands.append([f.astype(complex_type) for f in oriented])
            self.lows.append(low.astype(self.dtype))

    def band_shapes(self) -> list[tuple[int, int]]:
        """The shape of each sub-band, in :meth:`decompose`'s order."""
        oriented = [s for s in self.shapes[:-1] for _ in range(self.orientations)]
        return [self.shapes[0], *oriented, self.shapes[-1]]

    def decompose(self, image: np.ndarray) -> list[np.ndarray]:
        """The sub-bands of ``image`` (its shape is the pyramid's), in the module's order."""
        spectrum = fft.rfft2(np.asarray(image, self.dtype), norm="forward")
        out = [self._picture(spectrum * self.high0, 0)]
        spectrum = spectrum * self.low0
        for level, (filters, low) in enumerate(zip(self.bands, self.lows)):
            out += [self._picture(spectrum * f, level) for f in filters]
            spectrum = _crop(spectrum * low, self.shapes[level + 1])
        out.append(self._picture(spectrum, len(self.lows)))
        return out

    def reconstruct(self, bands: list[np.ndarray]) -> np.ndarray:
        """The picture whose sub-bands are ``bands``; exact inverse of :meth:`decompose`, and for
        edited sub-bands the picture closest to them (the adjoint of a tight frame)."""
        k = self.orientations
        spectrum = fft.rfft2(bands[-1], norm="forward")
        for level in reversed(range(len(self.lows))):
            spectrum = _pad(spectrum, self.shapes[level]) * self.lows[level]
            for f, band in zip(self.bands[level], bands[1 + k * level:1 + k * (level + 1)]):
                spectrum += fft.rfft2(band, norm="forward") * f.conj()
        spectrum = spectrum * self.low0 + fft.rfft2(bands[0], norm="forward") * self.high0
        return fft.irfft2(spectrum, s=self.shapes[0], norm="forward")

    def _picture(self, spectrum, level: int) -> np.ndarray:
        return fft.irfft2(spectrum, s=self.shapes[level], norm="forward")


@lru_cache(maxsize=16)
def steerable_pyramid(shape, levels: int, orientations: int = ORIENTATIONS,
                      dtype=np.float64) -> SteerablePyramid:
    """The pyramid for ``shape``, its filters computed once per size (they cost as much as an
    iteration of the synthesis)."""
    return SteerablePyramid(tuple(shape), levels, orientations, np.dtype(dtype))


def _frequencies(shape):
    """Radius r, and (ωy, ωx), of each coefficient of an rfft2 spectrum of ``shape``."""
    wy = 2 * np.pi * np.fft.fftfreq(shape[0])[:, None]
    wx = 2 * np.pi * np.fft.rfftfreq(shape[1])[None, :]
    return np.hypot(wy, wx), wy, wx


def _split(radius, edge):
    """(high, low) raised-cosine pair over the octave [edge/2, edge] of log radius: high² + low²
    = 1, high exactly 0 below edge/2 and low exactly 0 from edge on (so the low band fits a grid
    half as fine with nothing lost)."""
    with np.errstate(divide="ignore"):
        u = np.clip(np.log2(edge / radius), 0.0, 1.0)     # 0 at and above edge, 1 below edge/2
    high = np.where(u >= 1.0, 0.0, np.cos(np.pi / 2 * u))
    return high, np.sin(np.pi / 2 * u)


def _level_filters(shape, orientations: int):
    """Low-pass and oriented band-pass filters of one level: band(r)·α·cos^(K−1)(θ−θk)
    times (−i)^(K−1), whose squares sum to band(r)² (α from Simoncelli's steerable pyramid).
    cos(θ − θk) is written (ωx cos θk + ωy sin θk)/r, exactly odd in ω, so each filter is
    exactly Hermitian and its sub-band real."""
    radius, wy, wx = _frequencies(shape)
    band, low = _split(radius, np.pi / 2)
    k = orientations - 1
    alpha = 2.0 ** k * math.factorial(k) / math.sqrt(orientations * math.factorial(2 * k))
    safe = np.where(radius > 0, radius, 1.0)
    oriented = []
    for j in range(orientations):
        theta = np.pi * j / orientations
        cosine = np.where(radius > 0, (wx * np.cos(theta) + wy * np.sin(theta)) / safe, 0.0)
        oriented.append((-1j) ** k * alpha * cosine ** k * band)
    return low, oriented


def _crop(spectrum, shape):
    """The coefficients of an rfft2 spectrum that a grid of ``shape`` holds (its fftfreq rows,
    its rfftfreq columns): the low-pass picture subsampled, with nothing lost."""
    top, bottom = (shape[0] + 1) // 2, shape[0] // 2
    rows = np.concatenate([spectrum[:top], spectrum[spectrum.shape[0] - bottom:]])
    return rows[:, :shape[1] // 2 + 1]


def _pad(spectrum, shape):
    """The inverse of :func:`_crop`: the coarse spectrum placed in a grid of ``shape``, zeros
    elsewhere."""
    out = np.zeros((shape[0], shape[1] // 2 + 1), spectrum.dtype)
    top, bottom = (spectrum.shape[0] + 1) // 2, spectrum.shape[0] // 2
    out[:top, :spectrum.shape[1]] = spectrum[:top]
    out[shape[0] - bottom:, :spectrum.shape[1]] = spectrum[top:]
    return out
