"""Heeger–Bergen synthesis (Heeger and Bergen 1995; companion document 004, §6.2.2): noise made
to share a photo's histograms of steerable-pyramid sub-bands and of grey levels, by iterated
histogram matching; colour through the photo's principal components.

Histogram matching is φ = c_f⁻¹ ∘ c_g, g the picture changed and f the reference (the document
writes the inverse order — an erratum): each value goes to the reference's value at its own
rank. It gives scikit-image's ``exposure.match_histograms`` (tested), but the reference's
quantiles are computed once for the whole iteration rather than at every matching.
"""

from __future__ import annotations

import functools
import os
from concurrent.futures import ThreadPoolExecutor
from typing import Callable

import numpy as np

from ..errors import Cancelled, InputError
from .steerable import pyramid_levels, steerable_pyramid

ITERATIONS = 5          # Heeger and Bergen: "about five iterations" suffice
MAX_ITERATIONS = 100
MAX_PIXELS = 2**26      # the largest output: its float32 pyramid takes some 2 GB
WORK_TYPE = np.float32  # sub-band histograms need no more, and the FFTs run twice as fast


def quantiles(reference_sorted: np.ndarray, n: int) -> np.ndarray:
    """The reference's quantile function c_f⁻¹ at the ranks of n values: value i (0-based) at
    cumulated frequency (i + 1)/n, interpolated between the reference's own (j + 1)/m
    (scikit-image's convention, so the sizes may differ)."""
    m = reference_sorted.size
    if m == n:
        return reference_sorted.copy()
    return np.interp(np.arange(1, n + 1) / n, np.arange(1, m + 1) / m,
                     reference_sorted).astype(reference_sorted.dtype)


def match_quantiles(values: np.ndarray, target: np.ndarray) -> np.ndarray:
    """``values`` with the histogram of ``target`` (its :func:`quantiles` at values.size): the
    value of rank i becomes target[i], so the result's sorted values are exactly ``target``."""
    out = np.empty(values.size, target.dtype)
    out[np.argsort(values, axis=None)] = target
    return out.reshape(values.shape)


def heeger_bergen(image, shape, *, seed: int, iterations: int = ITERATIONS,
                  progress: Callable[[float], None] | None = None,
                  cancel: Callable[[], bool] | None = None) -> np.ndarray:
    """A (H, W) texture like the photo ``image``, grey (h, w) or colour (h, w, 3) (an alpha
    channel is ignored); of the photo's dtype when uint8, else float64, in the photo's range.

    Starts from noise drawn from ``seed`` with the photo's histogram, then ``iterations`` times:
    match every sub-band's histogram to the photo's, rebuild the picture, match its histogram.
    The pyramid is periodic, so the texture tiles. ``progress(fraction)`` is called after each
    iteration; ``cancel()`` returning True stops the work with :class:`Cancelled` before the
    next one."""
    photo = _check_photo(image)
    height, width = _check_shape(shape)
    seed, iterations = _check_seed(seed), _check_iterations(iterations)
    channels, colours = principal_channels(photo)
    levels = pyramid_levels(photo.shape, (height, width))
    analysis = steerable_pyramid(photo.shape[:2], levels, dtype=WORK_TYPE)
    pyramid = steerable_pyramid((height, width), levels, dtype=WORK_TYPE)
    sizes = [h * w for h, w in pyramid.band_shapes()]
    targets = [_targets(analysis, c, sizes, height * width) for c in channels]
    rng = np.random.default_rng(seed)
    outs = [match_quantiles(rng.standard_normal((height, width), WORK_TYPE), picture)
            for _, picture in targets]
    for done in range(iterations):
        if cancel is not None and cancel():
            raise Cancelled("Heeger–Bergen synthesis cancelled")
        outs = [_iterate(pyramid, out, bands, picture)
                for out, (bands, picture) in zip(outs, targets)]
        if progress is not None:
            progress((done + 1) / iterations)
    return colours(outs)


def _iterate(pyramid, picture, band_targets, picture_target):
    """One Heeger–Bergen iteration: sub-band histograms, rebuild, picture histogram. The
    bands are matched side by side (numpy sorts without the GIL; the sorts are most of the
    time, and each band's result is the same on any thread)."""
    bands = list(_pool().map(match_quantiles, pyramid.decompose(picture), band_targets))
    return match_quantiles(pyramid.reconstruct(bands), picture_target)


@functools.lru_cache(maxsize=1)
def _pool() -> ThreadPoolExecutor:
    return ThreadPoolExecutor(max_workers=max(1, min(4, os.cpu_count() or 1)),
                              thread_name_prefix="heeger-bergen")


def _targets(analysis, channel, band_sizes, size):
    """The photo channel's sub-band and picture quantiles at the output's sizes."""
    bands = [quantiles(np.sort(b, axis=None), n)
             for b, n in zip(analysis.decompose(channel), band_sizes)]
    return bands, quantiles(np.sort(channel, axis=None), size)


def principal_channels(photo: np.ndarray):
    """The photo as independent channels, and the function that makes the output picture from
    them: grey is one channel; colour is decorrelated into its principal components (PCA of
    the RGB pixels, Heeger and Bergen's way), so synthesising each apart keeps the colours'
    correlations."""
    low, high = _channel_range(photo)
    if photo.ndim == 2:
        return [photo.astype(WORK_TYPE)], lambda outs: _finish(outs[0], low, high, photo.dtype)
    pixels = photo.reshape(-1, 3).astype(np.float64)
    mean = pixels.mean(axis=0)
    _, axes = np.linalg.eigh(np.cov(pixels - mean, rowvar=False, bias=True))
    components = ((pixels - mean) @ axes).astype(WORK_TYPE).reshape(photo.shape)
    channels = [np.ascontiguousarray(components[..., k]) for k in range(3)]

    def colours(outs):
        rgb = np.stack(outs, axis=-1).astype(np.float64) @ axes.T + mean
        return _finish(rgb, low, high, photo.dtype)
    return channels, colours


def _channel_range(photo):
    return photo.min(axis=(0, 1)), photo.max(axis=(0, 1))


def _finish(picture, low, high, dtype) -> np.ndarray:
    """The picture within the photo's range (per channel), as uint8 if the photo was."""
    picture = np.clip(picture.astype(np.float64), low, high)
    return np.round(picture).astype(np.uint8) if dtype == np.uint8 else picture


def _check_photo(image) -> np.ndarray:
    photo = np.asarray(image)
    if photo.ndim == 3 and photo.shape[2] == 4:
        photo = photo[..., :3]
    if not (photo.ndim == 2 or (photo.ndim == 3 and photo.shape[2] == 3)):
        raise InputError(f"a photo of shape {photo.shape} cannot be used: expected grey "
                         "(height, width) or colour (height, width, 3) pixels")
    if photo.dtype.kind not in "biuf":
        raise InputError(f"pixels of type {photo.dtype} cannot be used: expected numbers")
    if photo.dtype.kind == "b":
        photo = photo.astype(np.uint8) * 255
    if photo.dtype.kind == "f" and not np.all(np.isfinite(photo)):
        raise InputError("the photo holds NaN or infinite values")
    pyramid_levels(photo.shape)
    return photo


def _check_shape(shape) -> tuple[int, int]:
    try:
        height, width = (int(x) for x in shape)
    except (TypeError, ValueError):
        raise InputError(f"size must be (height, width), got {shape!r}") from None
    pyramid_levels((height, width))
    if height * width > MAX_PIXELS:
        raise InputError(f"{width}x{height} is more than {MAX_PIXELS} pixels: choose a smaller "
                         "size")
    return height, width


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"the seed must be a non-negative integer, got {seed!r}")
    return int(seed)


def _check_iterations(iterations) -> int:
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)) \
            or not 0 <= iterations <= MAX_ITERATIONS:
        raise InputError(f"iterations must be an integer from 0 to {MAX_ITERATIONS}, "
                         f"got {iterations!r}")
    return int(iterations)
