"""Micro-textures after Desolneux, Moisan & Ronsin (companion document 001, digest §11), and
histogram matching (document 004).

A micro-texture is perceptually unchanged when the phases of its Fourier transform are drawn
at random: the modulus |û| is the model. Random-phase noise (RPN) draws a sample of it; the
texton is the one sample whose phases are all zero — a compact picture of the model, real, even
and at its largest at the origin. Both work on the image's periodic component (Moisan's
periodic + smooth decomposition), so the borders of a photo add no cross to the spectrum.

The DFT here is numpy's, û(ξ) = Σ u(x) e^{-2iπ⟨x, ξ⟩} with ⟨x, ξ⟩ = x₁ξ₁/M + x₂ξ₂/N: the
document's formula drops the 2π (erratum).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

# The luminance weights of the document's colour texton (its figure 3): the phase removed from
# the three channels is that of α·u, so the phase shift between channels is kept.
LUMINANCE = np.array([0.33, 0.5, 0.17])
MAX_OUTPUT_SIDE = 8192


def periodic_component(u) -> np.ndarray:
    """Moisan's periodic component p of u (float64, per channel): u = p + s, where s is smooth
    and p has no jump across the periodic borders. s solves Δs = v, v being the border jumps of
    u, with the DFT's Laplacian; p keeps u's mean."""
    u = _as_float(u)
    h, w = u.shape[:2]
    v = np.zeros_like(u)
    v[0] += u[-1] - u[0]
    v[-1] += u[0] - u[-1]
    v[:, 0] += u[:, -1] - u[:, 0]
    v[:, -1] += u[:, 0] - u[:, -1]
    q = np.cos(2 * np.pi * np.arange(h) / h)[:, None]
    r = np.cos(2 * np.pi * np.arange(w) / w)[None, :]
    laplacian = 2 * q + 2 * r - 4
    laplacian[0, 0] = 1.0                    # s has zero mean: its DC term is set to 0 below
    if u.ndim == 3:
        laplacian = laplacian[..., None]
    s_hat = np.fft.fft2(v, axes=(0, 1)) / laplacian
    s_hat[0, 0] = 0
    return u - np.real(np.fft.ifft2(s_hat, axes=(0, 1)))


def random_phase_noise(image, size=None, *, seed: int = 0) -> np.ndarray:
    """RPN(u) = F⁻¹(û e^{iθ}): a sample of the micro-texture of ``image`` of ``size`` (H, W)
    (default: the image's), with θ the phase of the DFT of a white noise drawn from ``seed``.

    θ is added to the phase of each channel — the same θ for all three, so the phase shift
    between channels, hence the colours, are kept (the document's Proposition 2); for a grey
    image û e^{iθ} and |û| e^{iθ} are the same random field. θ(0) = 0 keeps the mean.

    Any size: the spectrum is resampled the document's way (its figure 2). The periodic
    component less its mean is a spot centred on the origin; laid on an H × W torus — padded
    with zeros when larger, folded onto it when smaller — its DFT there samples the same
    continuous spectrum (zero padding interpolates it, folding subsamples it); the spot is
    scaled by √(HW / hw) so the output's variance is the image's. At the image's own size the
    spot is the periodic component itself and |FFT(RPN(u))| = |û| exactly. The output is a
    periodic DFT synthesis: tileable by construction.

    Returns the image's kind: uint8 in → uint8 out (rounded, clipped), float in → float out.
    """
    kind = np.asarray(image).dtype
    p = periodic_component(image)
    h, w = p.shape[:2]
    H, W = (h, w) if size is None else _size(size)
    mean = p.mean(axis=(0, 1))
    spot = _fold(p - mean, H, W) * np.sqrt(H * W / (h * w))
    # e^{iθ} = ŵ / |ŵ|; real signals: half spectra (rfft2), which halves the work
    phase = np.fft.rfft2(np.random.default_rng(seed).standard_normal((H, W)))
    phase /= np.maximum(np.abs(phase), np.finfo(np.float64).tiny)
    phase[0, 0] = 1.0
    if spot.ndim == 3:
        phase = phase[..., None]
    spectrum = np.fft.rfft2(spot, axes=(0, 1))
    spectrum *= phase
    out = np.fft.irfft2(spectrum, s=(H, W), axes=(0, 1))
    return _as_kind(out + mean, kind)


def texton(image, *, periodic: bool = True, centred: bool = True) -> np.ndarray:
    """T(u): the image with the same Fourier modulus and mean as u and zero phases, i.e.
    F⁻¹(|û|) with û(0) kept (for colour, the phase of α·û removed from every channel, α the
    luminance weights: the document's colour texton). Real and even; T(T(u)) = T(u); the same
    for every circular translation of u.

    ``periodic``: of the image's periodic component (as the document's figures; off for the
    exact identities); ``centred``: the origin moved to the middle of the picture, for display.
    Returns the image's kind (uint8 clipped)."""
    kind = np.asarray(image).dtype
    u = periodic_component(image) if periodic else _as_float(image)
    u_hat = np.fft.fft2(u, axes=(0, 1))
    if u.ndim == 2:
        t_hat = np.abs(u_hat)
    else:
        phase = np.angle(u_hat @ LUMINANCE)
        t_hat = u_hat * np.exp(-1j * phase)[..., None]
    t_hat[0, 0] = u_hat[0, 0].real            # the sum of u: real
    t = np.real(np.fft.ifft2(t_hat, axes=(0, 1)))
    if centred:
        t = np.fft.fftshift(t, axes=(0, 1))
    return _as_kind(t, kind)


def match_histogram(picture, reference) -> np.ndarray:
    """φ(picture) with φ = c_f⁻¹ ∘ c_g (c_g the cumulative histogram of the picture, c_f the
    reference's; the document writes the inverse order, an erratum): the picture's values
    replaced, in the same order, by the reference's quantiles — per channel for colour.
    scikit-image's ``match_histograms`` does it. Returns the picture's kind."""
    from skimage.exposure import match_histograms
    picture, reference = np.asarray(picture), np.asarray(reference)
    if picture.ndim != reference.ndim or (picture.ndim == 3
                                          and picture.shape[2] != reference.shape[2]):
        raise InputError(f"a picture of shape {picture.shape} cannot take the histogram of one "
                         f"of shape {reference.shape}: both grey or both colour")
    # as float: on uint8, scikit-image would truncate its interpolated values, not round them
    matched = match_histograms(_as_float(picture), _as_float(reference),
                               channel_axis=-1 if picture.ndim == 3 else None)
    return _as_kind(matched, picture.dtype)


# -- helpers --------------------------------------------------------------------------------------

def _as_float(image) -> np.ndarray:
    """A grey (h, w) or colour (h, w, 3) image of finite numbers as float64 (uint8 kept 0..255,
    so a uint8 result is on the same scale)."""
    image = np.asarray(image)
    if not (image.ndim == 2 or (image.ndim == 3 and image.shape[2] == 3)) \
            or image.dtype.kind not in "uif" or min(image.shape[:2]) < 2:
        raise InputError(f"an image of shape {image.shape} and type {image.dtype} is not a grey "
                         "(h, w) or colour (h, w, 3) picture of at least 2×2 numbers")
    u = image.astype(np.float64)
    if not np.all(np.isfinite(u)):
        raise InputError("the image holds NaN or infinite values")
    return u


def _as_kind(values: np.ndarray, kind: np.dtype) -> np.ndarray:
    if kind == np.uint8:
        return np.clip(np.round(values), 0, 255).astype(np.uint8)
    return values.astype(kind if kind.kind == "f" else np.float64)


def _size(size) -> tuple[int, int]:
    try:
        H, W = (int(s) for s in size)
    except (TypeError, ValueError):
        raise InputError(f"the output size must be (height, width), got {size!r}") from None
    if not (1 <= H <= MAX_OUTPUT_SIDE and 1 <= W <= MAX_OUTPUT_SIDE):
        raise InputError(f"an output of {W}×{H} is out of range: each side 1..{MAX_OUTPUT_SIDE}")
    return H, W


def _fold(spot: np.ndarray, H: int, W: int) -> np.ndarray:
    """The spot centred on the origin laid on an H × W torus: each point x of the centred domain
    I_h × I_w is added at (x mod H, x mod W) — zero padding when H ≥ h, aliasing when smaller."""
    h, w = spot.shape[:2]
    rows = (np.arange(h) - h // 2) % H
    cols = (np.arange(w) - w // 2) % W
    centred = np.fft.fftshift(spot, axes=(0, 1))          # the origin at (h // 2, w // 2)
    out = np.zeros((H, W) + spot.shape[2:])
    np.add.at(out, (rows[:, None], cols[None, :]), centred)
    return out
