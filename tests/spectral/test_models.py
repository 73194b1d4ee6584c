"""Random-phase noise, the texton and histogram matching (companion documents 001 and 004,
digest §11), checked against their definitions on small hand-made images."""

import numpy as np
import pytest
from skimage.exposure import match_histograms

from texeditor.errors import InputError
from texeditor.spectral import match_histogram, periodic_component, random_phase_noise, texton

RNG = np.random.default_rng(7)
GREY = RNG.random((12, 10)) * 80 + np.linspace(0, 120, 10)[None]     # a ramp: borders jump
COLOUR = RNG.integers(0, 256, (9, 14, 3)).astype(np.uint8)


def dft(u):
    """The DFT from its definition, û(ξ) = Σ u(x) e^{-2iπ⟨x,ξ⟩}, ⟨x,ξ⟩ = x₁ξ₁/M + x₂ξ₂/N
    (with the 2π the document's formula drops: the erratum)."""
    M, N = u.shape
    x1, x2 = np.arange(M), np.arange(N)
    e1 = np.exp(-2j * np.pi * np.outer(x1, x1) / M)
    e2 = np.exp(-2j * np.pi * np.outer(x2, x2) / N)
    return e1 @ u @ e2


def idft(v):
    M, N = v.shape
    return np.conj(dft(np.conj(v))) / (M * N)


def laplacian_periodic(u):
    return sum(np.roll(u, s, axis=a) for s in (1, -1) for a in (0, 1)) - 4 * u


def laplacian_interior(u):
    """Σ over the neighbours inside the image of (u(y) − u(x)) (Moisan's Δ_i)."""
    out = np.zeros_like(u)
    out[1:] += u[:-1] - u[1:]
    out[:-1] += u[1:] - u[:-1]
    out[:, 1:] += u[:, :-1] - u[:, 1:]
    out[:, :-1] += u[:, 1:] - u[:, :-1]
    return out


def test_the_periodic_component_is_moisans():
    """p is periodic with Δ_per p = Δ_i u (so u − p is smooth) and keeps the mean."""
    p = periodic_component(GREY)
    assert np.allclose(laplacian_periodic(p), laplacian_interior(GREY))
    assert p.mean() == pytest.approx(GREY.mean())


def test_the_periodic_component_of_colour_is_per_channel():
    p = periodic_component(COLOUR)
    for c in range(3):
        assert np.allclose(p[..., c], periodic_component(COLOUR[..., c]))


def test_rpn_keeps_the_modulus_of_the_periodic_component():
    p = periodic_component(GREY)
    out = random_phase_noise(GREY, seed=3)
    assert np.allclose(np.abs(dft(out)), np.abs(dft(p)))
    assert out.mean() == pytest.approx(GREY.mean())
    assert not np.allclose(out, p)                          # a new sample, not the image


def test_rpn_is_seeded_and_the_same_phase_serves_every_channel():
    colour = COLOUR.astype(np.float64)
    a, b = random_phase_noise(colour, seed=5), random_phase_noise(colour, seed=5)
    assert np.array_equal(a, b) and not np.allclose(a, random_phase_noise(colour, seed=6))
    p_hat = np.fft.fft2(periodic_component(colour), axes=(0, 1))
    out_hat = np.fft.fft2(a, axes=(0, 1))
    assert np.allclose(np.abs(out_hat), np.abs(p_hat))
    # the phase each channel gained is the same θ: the shifts between channels are kept
    gained = out_hat * np.conj(p_hat)
    big = np.abs(p_hat).min(axis=2) > 1e-6
    for c in (1, 2):
        assert np.allclose(np.angle(gained[..., c] / gained[..., 0])[big], 0, atol=1e-6)


@pytest.mark.parametrize("size", [(24, 30), (40, 17), (7, 6), (12, 10)])
def test_rpn_of_any_size_keeps_mean_and_variance(size):
    out = random_phase_noise(GREY, size, seed=1)
    p = periodic_component(GREY)
    assert out.shape == size
    assert out.mean() == pytest.approx(GREY.mean())
    if size[0] >= 12 and size[1] >= 10:          # zero padding: the spot's energy, rescaled
        assert out.std() == pytest.approx(p.std())


def test_rpn_larger_interpolates_the_spectrum():
    """Twice the size: at the even frequencies the modulus is the image's (the zero-padded
    spot's DFT samples the same continuous spectrum), times √(HW/hw) = 2."""
    out = random_phase_noise(GREY, (24, 20), seed=2)
    p = periodic_component(GREY)
    even = np.abs(np.fft.fft2(out))[::2, ::2]
    even[0, 0] = 0                                                     # the mean, kept apart
    assert np.allclose(even, 2 * np.abs(np.fft.fft2(p - p.mean())))


def test_rpn_is_tileable_where_the_photo_is_not():
    """Across the wrap seam the output jumps no more than between inner neighbours."""
    out = random_phase_noise(GREY, (64, 64), seed=4)
    inner = np.abs(np.diff(out, axis=1)).mean()
    seam = np.abs(out[:, 0] - out[:, -1]).mean()
    assert seam < 1.5 * inner
    assert np.abs(GREY[:, 0] - GREY[:, -1]).mean() > 3 * np.abs(np.diff(GREY, axis=1)).mean()


def test_rpn_returns_the_images_kind():
    out = random_phase_noise(COLOUR, (33, 20), seed=0)
    assert out.dtype == np.uint8 and out.shape == (33, 20, 3)
    assert random_phase_noise(GREY.astype(np.float32), seed=0).dtype == np.float32


def test_the_texton_from_its_definition():
    """T(u) = F⁻¹(|û|) with û(0) kept, by the definition's own sums (the 2π restored)."""
    u = GREY - 100           # a negative mean: û(0) < 0 must be kept, not its modulus
    u_hat = dft(u)
    t_hat = np.abs(u_hat)
    t_hat[0, 0] = u_hat[0, 0].real
    expected = np.real(idft(t_hat))
    assert np.allclose(texton(u, periodic=False, centred=False), expected)


def test_the_texton_is_idempotent_translation_invariant_real_and_even():
    T = texton(GREY, periodic=False, centred=False)
    assert np.allclose(texton(T, periodic=False, centred=False), T)
    for shift in [(3, 0), (0, 7), (5, 9)]:
        moved = np.roll(GREY, shift, axis=(0, 1))
        assert np.allclose(texton(moved, periodic=False, centred=False), T)
    assert np.allclose(T, np.roll(T[::-1, ::-1], (1, 1), axis=(0, 1)))      # T(−x) = T(x)
    assert np.unravel_index(T.argmax(), T.shape) == (0, 0)                  # maximal at 0


def test_the_colour_texton_keeps_every_amplitude_and_its_luminance_is_the_grey_texton():
    u = COLOUR.astype(np.float64)
    T = texton(u, periodic=False, centred=False)
    assert np.allclose(np.abs(np.fft.fft2(T, axes=(0, 1))), np.abs(np.fft.fft2(u, axes=(0, 1))))
    alpha = np.array([0.33, 0.5, 0.17])
    assert np.allclose(T @ alpha, texton(u @ alpha, periodic=False, centred=False))
    assert np.allclose(texton(T, periodic=False, centred=False), T)
    moved = np.roll(u, (2, 5), axis=(0, 1))
    assert np.allclose(texton(moved, periodic=False, centred=False), T)


def test_the_texton_shown_is_centred_and_of_the_periodic_component():
    shown = texton(GREY)
    raw = texton(periodic_component(GREY), periodic=False, centred=False)
    assert np.allclose(shown, np.fft.fftshift(raw))
    assert np.unravel_index(shown.argmax(), shown.shape) == (6, 5)
    assert texton(COLOUR).dtype == np.uint8


def test_match_histogram_gives_the_reference_quantiles_in_the_pictures_order():
    picture = RNG.permutation(np.arange(60.0)).reshape(6, 10) ** 1.5
    reference = RNG.normal(size=(6, 10)) * 30
    out = match_histogram(picture, reference)
    assert np.allclose(np.sort(out, axis=None), np.sort(reference, axis=None))
    order = np.argsort(picture, axis=None)
    assert np.all(np.diff(out.ravel()[order]) >= 0)          # φ is increasing


def test_match_histogram_to_a_larger_reference_takes_its_quantiles():
    """φ = c_f⁻¹ ∘ c_g: the k-th of n picture values takes the reference quantile k/n."""
    picture = np.array([[3.0, 1.0], [4.0, 2.0]])
    reference = np.arange(8.0).reshape(2, 4) * 10      # quantiles 1/4, 2/4, 3/4, 1: 10, 30, 50, 70
    out = match_histogram(picture, reference)
    assert np.allclose(out, [[50, 10], [70, 30]])


def test_match_histogram_of_colour_is_per_channel_and_keeps_uint8():
    reference = RNG.integers(0, 256, (20, 20, 3)).astype(np.uint8)
    out = match_histogram(COLOUR, reference)
    assert out.dtype == np.uint8
    expected = match_histograms(COLOUR.astype(float), reference.astype(float), channel_axis=-1)
    assert np.array_equal(out, np.clip(np.round(expected), 0, 255).astype(np.uint8))
    with pytest.raises(InputError):
        match_histogram(COLOUR, reference[..., 0])


@pytest.mark.parametrize("bad", [np.zeros((1, 5)), np.zeros((4, 4, 2)), np.full((4, 4), np.nan),
                                 np.array([["a", "b"], ["c", "d"]])])
def test_bad_images_are_refused(bad):
    with pytest.raises(InputError):
        random_phase_noise(bad)
    with pytest.raises(InputError):
        texton(bad)


def test_bad_sizes_are_refused():
    for size in [(0, 4), (4, 9000), "ab", None.__class__]:
        with pytest.raises(InputError):
            random_phase_noise(GREY, size)
