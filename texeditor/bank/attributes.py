"""Texture attributes (thesis §1.5): the words a user describes a texture with, as numbers.

Computed from a finished level matrix and its palette when a texture enters the bank, where they
serve range filters and "more like this". Each attribute is one short function; docs/attributes.md
gives the formulas.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields

import numpy as np
import skimage as ski     # its subpackages load on first use: skimage.feature pulls in scipy.stats

from ..errors import FormatError, InputError

VERSION = 1                  # bump when a formula changes: the bank then recomputes its entries
MAX_SIDE = 512               # attributes are statistics: a central crop of this size is enough
LUMA = np.array([0.299, 0.587, 0.114])   # Rec. 601: the grey a colour shows on a grey screen
HALF = 0.5                   # the correlation level that bounds the central lobe
PERIODIC = 0.3               # below this peak height no period is reported
LAG = 3                      # lags reach a third of the texture's size
NEARLY = 0.9                 # peaks this close to the highest count as the same repetition


@dataclass(frozen=True)
class Attributes:
    """The attributes of one texture (see docs/attributes.md for each formula).

    contrast ∈ [0, 1], granularity ≥ 1 (points), density ∈ [0, 1], directivity ∈ [0, 1],
    orientation ∈ [0, 180) degrees, regularity ∈ [0, 1], period ≥ 0 (points, 0 = none found),
    coarseness ≥ 0 (points).
    """

    contrast: float
    granularity: float
    density: float
    directivity: float
    orientation: float
    regularity: float
    period: float
    coarseness: float

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, obj) -> "Attributes":
        """Read back a stored dict, refusing missing, extra or non-finite values."""
        names = [f.name for f in fields(cls)]
        if not isinstance(obj, dict) or sorted(obj) != sorted(names):
            raise FormatError(f"attributes must be an object with exactly {names}")
        values = {}
        for name in names:
            v = obj[name]
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise FormatError(f"attribute {name} must be a finite number, got {v!r}")
            values[name] = float(v)
        return cls(**values)


NAMES = tuple(f.name for f in fields(Attributes))
DESCRIPTIONS = {
    "contrast": "spread of the greys (0 flat .. 1 half black, half white)",
    "granularity": "mean size of a region of one level, in points",
    "density": "share of points that are not background (level 0)",
    "directivity": "strength of the dominant orientation (0 isotropic .. 1 stripes)",
    "orientation": "dominant direction in degrees, counter-clockwise from horizontal",
    "regularity": "height of the highest autocorrelation peak away from the origin",
    "period": "distance of that peak, in points (0: none)",
    "coarseness": "distance at which the autocorrelation falls to 1/2, in points",
}


def compute(levels: np.ndarray, palette) -> Attributes:
    """All attributes of a level matrix seen through its palette."""
    levels = np.asarray(levels)
    if levels.ndim != 2 or levels.size == 0:
        raise InputError("attributes need a non-empty level matrix")
    levels = central_crop(levels, MAX_SIDE)
    grey = greys(palette)[levels]
    acf = autocorrelation(grey)
    strength, angle = directivity(grey)
    peak, period = regularity(acf)
    return Attributes(contrast=contrast(levels, palette), granularity=granularity(levels),
                      density=density(levels), directivity=strength, orientation=angle,
                      regularity=peak, period=period, coarseness=coarseness(acf))


def central_crop(levels: np.ndarray, side: int) -> np.ndarray:
    h, w = levels.shape[:2]
    top, left = max(0, (h - side) // 2), max(0, (w - side) // 2)
    return levels[top:top + side, left:left + side]


def greys(palette) -> np.ndarray:
    """Each level's grey in [0, 1]: the luma of its palette colour."""
    return np.asarray(palette, dtype=float).reshape(-1, 3) @ LUMA / 255.0


# -- the attributes -------------------------------------------------------------------------------

def contrast(levels: np.ndarray, palette) -> float:
    """Twice the standard deviation of the points' greys (§1.5.2: contrast follows the grey
    scale, not the structure): 0 for a flat texture, 1 for half black and half white."""
    return float(min(1.0, 2.0 * greys(palette)[levels].std()))


def granularity(levels: np.ndarray) -> float:
    """Mean size, in points, of the regions of one level (4-connected): grains (§1.5.1) are
    small regions, spots large ones. Points / number of regions."""
    regions = ski.measure.label(levels, background=-1, connectivity=1, return_num=True)[1]
    return float(levels.size / max(regions, 1))


def density(levels: np.ndarray) -> float:
    """Share of the points that are not background (§1.5.1; level 0 is "an empty place")."""
    return float(np.count_nonzero(levels) / levels.size)


def directivity(grey: np.ndarray) -> tuple[float, float]:
    """(strength, orientation) from the structure tensor J of the greys averaged over the image
    (§1.5.5). Strength = (λ1 - λ2) / (λ1 + λ2) of J (0 isotropic, 1 all variation across one
    direction); orientation = the direction along which the grey changes least, in degrees
    counter-clockwise from the horizontal, in [0, 180). Sobel derivatives do not see a pattern
    of period 2 (nor does regularity: the resolution of the attributes is 3 points)."""
    if min(grey.shape) < 3:
        return 0.0, 0.0
    arr, arc, acc = (a.mean() for a in ski.feature.structure_tensor(grey, sigma=1.0, mode="reflect"))
    jxx, jyy, jxy = acc, arr, -arc            # x = column, y = up = -row
    trace = jxx + jyy
    strength = math.hypot(jxx - jyy, 2 * jxy) / trace if trace > 1e-12 else 0.0
    if strength < 1e-9:
        return 0.0, 0.0
    gradient = 0.5 * math.degrees(math.atan2(2 * jxy, jxx - jyy))
    return float(min(strength, 1.0)), float(round((gradient + 90.0) % 180.0, 6) % 180.0)


def autocorrelation(grey: np.ndarray) -> np.ndarray | None:
    """Normalised autocorrelation ρ of the greys for lags up to a third of the size each way,
    centred (ρ = 1 at the centre). Computed by FFT on a zero-padded image and divided by the
    number of overlapping points, so a texture that is not tileable gets no seam; the third
    keeps at least 4/9 of the points in each product, where half the size let chance peaks
    of small textures pass for a repetition. None if flat."""
    x = grey - grey.mean()
    var = float((x * x).mean())
    if var <= 1e-12:
        return None
    h, w = x.shape
    shape = (2 * h, 2 * w)
    power = np.abs(np.fft.rfft2(x, shape)) ** 2
    raw = np.fft.irfft2(power, shape)
    overlap = np.fft.irfft2(np.abs(np.fft.rfft2(np.ones_like(x), shape)) ** 2, shape)
    acf = np.fft.fftshift(raw / np.maximum(np.round(overlap), 1.0) / var)
    rh, rw = h // LAG, w // LAG
    return acf[h - rh:h + rh + 1, w - rw:w + rw + 1]


def regularity(acf: np.ndarray | None) -> tuple[float, float]:
    """(regularity, period): the height of the highest local maximum of ρ outside the central
    lobe (the 8-connected lags around 0 where ρ > 1/2), and the distance of the nearest peak
    at least 0.9 as high (the fundamental; 0 when the height is under 0.3). A periodic
    placement (§1.5.4) repeats the pattern: ρ rises again, to 1 for a perfect repetition; a
    random one stays near 0."""
    if acf is None:
        return 0.0, 0.0
    centre = (acf.shape[0] // 2, acf.shape[1] // 2)
    lobe = _central_lobe(acf, centre)
    peaks = ski.feature.peak_local_max(acf, min_distance=1, threshold_abs=0.0, exclude_border=False)
    peaks = [p for p in peaks if not lobe[tuple(p)]]
    if not peaks:
        return 0.0, 0.0
    heights = np.array([acf[tuple(p)] for p in peaks])
    height = float(np.clip(heights.max(), 0.0, 1.0))
    if height < PERIODIC:
        return height, 0.0
    # the fundamental: the nearest peak nearly as high as the highest (multiples tie with it)
    near = [p for p, v in zip(peaks, heights) if v >= NEARLY * heights.max()]
    return height, float(min(math.hypot(p[0] - centre[0], p[1] - centre[1]) for p in near))


def coarseness(acf: np.ndarray | None) -> float:
    """Distance (points) at which the ring-averaged ρ first falls to 1/2, interpolated between
    rings: fine textures decorrelate within a point, coarse ones far away (thesis §2, Kaiser,
    Pratt: "the spread of the autocorrelation tells the coarseness")."""
    if acf is None:
        return 0.0
    centre = np.array(acf.shape) // 2
    rr, cc = np.indices(acf.shape)
    ring = np.rint(np.hypot(rr - centre[0], cc - centre[1])).astype(int)
    limit = min(centre)
    inside = ring <= limit
    profile = (np.bincount(ring[inside], weights=acf[inside])
               / np.maximum(np.bincount(ring[inside]), 1))
    below = np.flatnonzero(profile <= HALF)
    if not len(below):
        return float(limit)
    r = int(below[0])
    before, after = profile[r - 1], profile[r]
    return float(r - 1 + (before - HALF) / (before - after))


def _central_lobe(acf: np.ndarray, centre) -> np.ndarray:
    regions = ski.measure.label(acf > HALF, connectivity=2)
    return regions == regions[centre]


# -- "more like this" -----------------------------------------------------------------------------

def feature_vector(a: Attributes) -> np.ndarray:
    """The coordinates "more like this" measures distances in: sizes on a log scale (a grain
    twice as large is as different at any size), the orientation as a doubled angle weighted by
    its strength (so a weak orientation, or 0° against 179°, hardly counts)."""
    return feature_matrix(np.array([[getattr(a, name) for name in NAMES]]))[0]


def feature_matrix(values: np.ndarray) -> np.ndarray:
    """feature_vector of many textures at once: ``values`` is (n, 8) in the order of NAMES."""
    v = dict(zip(NAMES, np.asarray(values, dtype=float).T))
    doubled = np.radians(2 * v["orientation"])
    return np.column_stack([v["contrast"], np.log2(np.maximum(v["granularity"], 1.0)),
                            v["density"], v["directivity"] * np.cos(doubled),
                            v["directivity"] * np.sin(doubled), v["regularity"],
                            np.log2(1.0 + v["coarseness"])])


def nearest(target: np.ndarray, others: np.ndarray, spread: np.ndarray | None = None
            ) -> np.ndarray:
    """Order of the rows of ``others`` (feature vectors) by distance to ``target``, each
    coordinate divided by its spread (by default over ``others``; the bank passes the spread
    over all its entries), so no attribute dominates by its unit."""
    if not len(others):
        return np.zeros(0, dtype=int)
    spread = np.array(others.std(axis=0) if spread is None else spread, dtype=float)
    spread[spread < 1e-9] = 1.0
    distance = np.sqrt((((others - target) / spread) ** 2).sum(axis=1))
    return np.argsort(distance, kind="stable")
