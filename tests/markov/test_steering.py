"""Steering: a field's law tilted band by band so its level shares keep to the DPJ's."""

import numpy as np
import pytest
import skimage as ski

from texeditor import DPJ, estimate_dpj, synthesize
from texeditor.errors import InputError
from texeditor.markov import multiscale, steering
from texeditor.markov.synthesis import synthesize_given


def share_error(levels, want):
    return np.abs(np.bincount(levels.ravel(), minlength=len(want)) / levels.size - want).max()


@pytest.fixture(scope="module")
def chelsea():
    model, _ = multiscale.estimate_scales(ski.data.chelsea())
    return model


def test_steering_keeps_a_scene_at_its_level_shares_where_a_plain_draw_strays(chelsea):
    """Drawn given synthetic parents, chelsea's finest scale favours some levels (0.02–0.07 off,
    seed after seed); steered, its shares keep within 0.01 — before any border is moved."""
    want = chelsea.frequencies(chelsea.scales - 1)
    plain, steered = [], []
    for seed in range(3):
        for steer, errors in ((False, plain), (True, steered)):
            drawn = multiscale.synthesize_scales(chelsea, (512, 512), seed=seed, rebalance=False,
                                                 steer=steer)
            errors.append(share_error(drawn.levels, want))
    assert max(steered) <= 0.01 and max(plain) > 0.03
    assert all(s < p for s, p in zip(steered, plain))


def test_a_steered_draw_is_the_plain_one_until_its_first_band_has_been_seen(chelsea):
    """Steering tilts the law; it is not another sampler: the first band (no tilt yet) is
    the plain draw's, point for point, and the rows after it differ."""
    k = chelsea.scales - 1
    parents = multiscale.synthesize_scales(multiscale.MultiScaleDPJ(chelsea.dpjs[:k]),
                                           (128, 128), seed=1).levels
    up = multiscale.upsample(parents, (256, 256))
    gp = multiscale.parent_levels(chelsea.dpjs, k)
    plain = synthesize_given(chelsea.dpjs[k], up, gp, seed=5).levels
    steered = synthesize_given(chelsea.dpjs[k], up, gp, seed=5,
                               steer=chelsea.frequencies(k)).levels
    band = steering.band_rows(256)
    assert np.array_equal(steered[:band], plain[:band])
    assert not np.array_equal(steered[band:], plain[band:])


def test_no_window_of_a_steered_draw_leaves_the_dpj():
    """A tilt only reweighs the DPJ's windows: a steered field pulled far from the shares its
    law would settle on still has every window in the DPJ (no dead end here to back off)."""
    rng = np.random.default_rng(3)
    photo = (ski.filters.gaussian(rng.random((96, 96)), 2) > 0.5).astype(np.uint8)
    dpj = estimate_dpj(photo, (2, 2), 2, wrap=True)
    drawn = synthesize(dpj, (200, 200), seed=2, steer=[0.3, 0.7])
    assert drawn.repairs == 0
    seen = estimate_dpj(drawn.levels, (2, 2), 2)
    assert np.isin(seen.codes, dpj.codes).all()
    plain = synthesize(dpj, (200, 200), seed=2).levels.mean()
    assert abs(drawn.levels.mean() - 0.7) < abs(plain - 0.7)


def test_the_aims_add_up_to_the_shares_over_the_fields_parents():
    """Each parent's aims are a law over the levels; over the field's parents they give the
    shares asked for, the photo's law tilted by one factor per level."""
    law = np.array([[0.9, 0.1, 0.0], [0.2, 0.6, 0.2], [0.0, 0.3, 0.7]])
    field = np.array([0.5, 0.3, 0.2])
    shares = np.array([0.3, 0.4, 0.3])
    aims = steering._fitted(law, field, shares)
    assert np.allclose(aims.sum(axis=1), 1) and np.allclose(field @ aims, shares, atol=1e-4)
    assert np.all(aims[law == 0] == 0)

    def factor(p, a, b):        # level a's tilt over level b's, over parent p
        return (aims[p, a] / law[p, a]) / (aims[p, b] / law[p, b])
    assert np.isclose(factor(0, 1, 0), factor(1, 1, 0)) and np.isclose(factor(1, 2, 1),
                                                                       factor(2, 2, 1))
    assert not np.isclose(factor(0, 1, 0), 1.0)          # a tilt there was


@pytest.mark.parametrize("shares", [[0.5], [0.5, 0.6], [np.nan, 1.0], [-0.1, 1.1]])
def test_shares_to_steer_towards_are_checked(shares):
    dpj = DPJ(np.array([[[0, 1]], [[1, 0]], [[0, 0]], [[1, 1]]], np.uint8),
              np.full(4, 0.25), 2)
    with pytest.raises(InputError, match="steer"):
        synthesize(dpj, (8, 8), steer=shares)
