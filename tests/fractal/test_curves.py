"""Projected-IFS (fractal Bézier) curves (companion 002): roughness 0 is de Casteljau's Bézier
curve exactly, the ends stay, a closed outline stays closed, seeded; the spot outline kind."""

import json

import numpy as np
import pytest
from scipy.interpolate import BPoly

from texeditor.errors import InputError
from texeditor.fractal.curves import BEZIER_T0, BEZIER_T1, catmull_rom_pieces, fractal_curve
from texeditor.spots.envelope import Envelope, catmull_rom_outline, real_spot

PIECE = np.array([[[0.0, 0.0], [10.0, 3.0], [4.0, 12.0], [15.0, 15.0]]])
OVAL = np.array([[0, 0], [-8, 10], [0, 20], [12, 24], [20, 10], [10, -4]], float)


def test_the_matrices_are_barycentric_and_meet():
    assert np.allclose(BEZIER_T0.sum(axis=0), 1) and np.allclose(BEZIER_T1.sum(axis=0), 1)
    assert np.array_equal(BEZIER_T0[:, 3], BEZIER_T1[:, 0])


def test_roughness_zero_is_the_bezier_curve():
    points = fractal_curve(PIECE, 6, 0.0)
    s = np.arange(64) / 64
    exact = BPoly(PIECE[0][:, None, :], [0.0, 1.0])(s)
    assert np.abs(points - exact).max() < 1e-12


def test_roughness_zero_on_an_outline_is_the_catmull_rom_curve():
    """The spot kind at roughness 0: the Catmull–Rom outline through the points, at s = k/4 of
    each piece (where the smooth kind, this coarse, samples it too)."""
    smooth = catmull_rom_outline(OVAL, 64.0)                         # 4 samples a piece
    assert len(smooth) == 4 * len(OVAL)
    assert np.abs(fractal_curve(catmull_rom_pieces(OVAL), 2, 0.0) - smooth).max() < 1e-12
    kind = Envelope.from_contour(OVAL, kind="fractal_curve").with_fractal(0.0).outline(64.0)
    per = len(kind) // len(OVAL)
    assert np.abs(kind[::per] - OVAL).max() < 1e-12                  # through every point


@pytest.mark.parametrize("r", [0.3, 1.0])
def test_the_ends_stay_and_the_outline_closes(r):
    points = fractal_curve(PIECE, 8, r, seed=4)
    assert np.array_equal(points[0], PIECE[0, 0])
    pieces = catmull_rom_pieces(OVAL)
    outline = fractal_curve(pieces, 7, r, seed=4)
    per = 2 ** 7
    assert np.array_equal(outline[::per], OVAL)                      # every piece's start, exactly
    gaps = np.linalg.norm(np.diff(np.vstack([outline, outline[:1]]), axis=0), axis=1)
    assert gaps.max() < 3.0                          # closed: the last point is next to the first


def test_roughness_moves_the_curve_and_a_deeper_curve_refines_a_shallower_one():
    smooth = fractal_curve(PIECE, 7, 0.0)
    rough = fractal_curve(PIECE, 7, 1.0, seed=2)
    assert np.abs(rough - smooth).max() > 0.5
    assert np.array_equal(fractal_curve(PIECE, 6, 1.0, seed=2), rough[::2])
    assert np.array_equal(rough, fractal_curve(PIECE, 7, 1.0, seed=2))
    assert not np.array_equal(rough, fractal_curve(PIECE, 7, 1.0, seed=3))


def test_rougher_is_longer():
    length = [np.linalg.norm(np.diff(fractal_curve(PIECE, 10, r, seed=1), axis=0), axis=1).sum()
              for r in (0.0, 0.5, 1.0)]
    assert length[0] < length[1] < length[2]


@pytest.mark.parametrize("r", [float("nan"), -0.1, 1.1, "x", True])
def test_bad_roughness_is_an_input_error(r):
    with pytest.raises(InputError):
        fractal_curve(PIECE, 3, r)
    with pytest.raises(InputError):
        Envelope.ellipse(20, 10).with_fractal(r)


def test_the_envelope_json_holds_roughness_and_seed_only_for_the_fractal_kind():
    plain = Envelope.ellipse(30, 12)
    assert "roughness" not in plain.dumps() and "seed" not in plain.dumps()
    assert Envelope.loads(plain.dumps()) == plain
    rough = plain.with_fractal(0.7, seed=12)
    obj = json.loads(rough.dumps())
    assert obj["kind"] == "fractal_curve" and obj["roughness"] == 0.7 and obj["seed"] == 12
    again = Envelope.loads(rough.dumps())
    assert again == rough and np.array_equal(again.outline(), rough.outline())
    assert Envelope.loads(json.dumps({**obj, "roughness": None}).replace("null", "0")) != rough
    with pytest.raises(InputError):
        Envelope.from_json({**obj, "seed": -1})
    with pytest.raises(InputError):
        Envelope.from_json({**obj, "roughness": 2})


def test_a_fractal_spot_is_placed_and_rougher_spots_differ():
    env = Envelope.ellipse(60, 30, kind="fractal_curve")
    masks = [real_spot(env.with_fractal(r, seed=3)).mask for r in (0.0, 0.5, 1.0)]
    smooth = real_spot(Envelope.ellipse(60, 30, kind="catmull_rom")).mask
    assert abs(int(masks[0].sum()) - int(smooth.sum())) < 0.01 * smooth.sum()
    assert all(m.sum() > 0.7 * smooth.sum() for m in masks)
    assert not np.array_equal(masks[1], masks[2])
