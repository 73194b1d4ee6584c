"""The tone's finish: a tone picture's fine-scale power brought to the photo's.

A tone picture is made of short copies of the photo. Where two copies meet, the step between
them is sharper than anything the camera's blur left in the photo, and the outlines the copies
cut hold less power at periods 4–8 than the photo's: measured against the photo (bench_quality's
bands, 8 photos, 2 seeds), the picture had +0.04 to +0.31 too much log10 power at periods 2–2.7
and up to −0.19 too little at 2.7–8. The finish scales the picture's spectrum, ring by ring, by
√(photo's power / picture's power), fully at periods up to PERIOD / 2 and fading out to PERIOD
(the layout is left as drawn), the gain held within GAIN: one zero-phase linear filter that sets
the pixel-scale sharpness to the photo's. A tiling picture is filtered on the torus, so it stays
seamless; another with mirrored margins. The levels, which are the document, are not touched.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numba import njit
from scipy import fft as sfft

PERIOD = 8.0           # periods (points) from which the picture is finished, fully from half of it
GAIN = (0.5, 2.0)      # the amplitude gain of a ring, at most
RING = 1 / 128         # the width of a ring of the power's radial profile (cycles per point)
RINGS = 91             # ... so many reach the corners (√2 / 2 cycle per point)
SMOOTH = 2             # the gain's log is averaged over 2·SMOOTH + 1 rings
MARGIN = 16            # mirrored margin of a picture that does not tile
SMALLEST = 16          # a picture with a shorter side is left as it is
SAMPLE = 1024          # the power is measured on a central square this wide at most
WORKERS = 2            # threads of an FFT (the same numbers on one thread or more)


def radial_power(grey: np.ndarray, periodic: bool = False) -> np.ndarray:
    """(RINGS,) mean power of ``grey`` (mean removed, Hann window; its central SAMPLE² at
    most, which says as much and bounds the time) in rings of radius k·RING .. (k + 1)·RING
    cycles per point; NaN where a ring holds no frequency (a small picture). ``periodic``: a
    whole tiling picture, which has no edges to hide (no window, so the power, and the
    finish, do not change when the picture is rolled)."""
    grey = np.asarray(grey)
    h, w = grey.shape
    top, left = max(0, (h - SAMPLE) // 2), max(0, (w - SAMPLE) // 2)
    x = grey[top:top + SAMPLE, left:left + SAMPLE].astype(np.float64)
    x -= x.mean()
    energy = float(x.size)
    if not (periodic and x.shape == grey.shape):
        window = np.outer(np.hanning(x.shape[0]), np.hanning(x.shape[1]))
        x *= window
        energy = max(float((window ** 2).sum()), 1e-12)
    power = np.abs(sfft.rfft2(x, workers=WORKERS)) ** 2 / energy
    ring = _rings(*x.shape).ravel()
    counts = np.bincount(ring, minlength=RINGS)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.bincount(ring, power.ravel(), minlength=RINGS) / counts


@lru_cache(maxsize=4)
def _rings(h: int, w: int) -> np.ndarray:
    """The ring of each frequency of an (h, w) rfft2 (kept: a canvas is finished again and
    again at one size)."""
    radius = np.hypot(*np.meshgrid(sfft.fftfreq(h), sfft.rfftfreq(w), indexing="ij"))
    rings = np.minimum((radius / RING).astype(np.uint8), RINGS - 1)
    rings.flags.writeable = False
    return rings


def gain(picture_power: np.ndarray, photo_power: np.ndarray) -> np.ndarray:
    """(RINGS,) amplitude gain of each ring: √ of the power ratio, within GAIN, its log
    smoothed over neighbouring rings (a ring either lacks is read between its neighbours),
    faded to 1 towards the periods above PERIOD."""
    with np.errstate(invalid="ignore", divide="ignore"):
        log = 0.5 * np.log(photo_power / picture_power)
    centre = (np.arange(RINGS) + 0.5) * RING               # cycles per point
    known = np.isfinite(log)
    if not known.any():
        return np.ones(RINGS)
    log = np.clip(np.interp(centre, centre[known], log[known]), *np.log(GAIN))
    kernel = np.ones(2 * SMOOTH + 1) / (2 * SMOOTH + 1)
    log = np.convolve(np.pad(log, SMOOTH, mode="edge"), kernel, mode="valid")
    fade = np.clip(centre * PERIOD - 1.0, 0.0, 1.0)        # 0 at PERIOD, 1 from PERIOD / 2
    return np.exp(log * fade)


def finished(grey: np.ndarray, pixels: np.ndarray | None, photo_power: np.ndarray,
             wrap: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """``grey`` (H, W) uint8 filtered by its gain against the photo's radial power, and the
    same change of grey added to each channel of ``pixels`` (H, W, C) uint8 (a colour
    picture's pixel noise is in its lightness); ``wrap``: the picture tiles (filtered on the
    torus). Computed in float64, so a grey's rounding does not hang on the FFT's last bits."""
    h, w = grey.shape
    if min(h, w) < SMALLEST or not np.isfinite(photo_power).any():
        return grey, pixels
    ring_gain = gain(radial_power(grey, periodic=wrap), photo_power)
    margin = 0 if wrap else MARGIN
    plane = np.pad(grey.astype(np.float64), margin, mode="symmetric")
    spectrum = sfft.rfft2(plane, workers=WORKERS)
    spectrum *= ring_gain[_rings(*plane.shape)]
    plane = sfft.irfft2(spectrum, s=plane.shape, workers=WORKERS, overwrite_x=True)
    filtered = plane[margin:margin + h, margin:margin + w]
    out = _changed(grey[..., None], grey, filtered)[..., 0]
    return out, None if pixels is None else _changed(pixels, grey, filtered)


@njit(cache=True, nogil=True)
def _changed(planes, grey, filtered):
    """``planes`` (H, W, C) uint8, each moved by the change the filter made to ``grey``,
    rounded to the nearest and clipped (numpy's clip and rint took 0.3 s at 2048²)."""
    h, w, c = planes.shape
    out = np.empty((h, w, c), np.uint8)
    for i in range(h):
        for j in range(w):
            change = filtered[i, j] - grey[i, j]
            for k in range(c):
                out[i, j, k] = min(max(np.rint(planes[i, j, k] + change), 0.0), 255.0)
    return out
