"""Outline kinds named for what they are (issue 21, item 12): the thesis's Bézier curve and
B-spline on the envelope's points, Catmull–Rom and the interpolating spline under their own
names, and the names files stored before ("bezier", "bspline") keeping their meaning."""

import json

import numpy as np
import pytest

from texeditor.errors import InputError
from texeditor.recipe.actions import NewCanvas
from texeditor.recipe.codec import action_from_json
from texeditor.recipe.replay import replay
from texeditor.spots.actions import PlaceSpot, spot_ref
from texeditor.spots.envelope import (KINDS, LEGACY_KINDS, MAX_BEZIER_POINTS, Envelope, Meridian,
                                      bezier_curve, closed_bezier_polygon, uniform_bspline)
from texeditor.spots.library import SpotLibrary

STONE = {"a": [2.0, -20.0], "b": [-1.0, 19.0],
         "meridians": [[0.15, 8.0, 9.0], [0.45, 15.0, 13.0, True], [0.8, 11.0, 9.0]],
         "parallels": [[-4.0, 0.3, 0.7]]}
# Recorded with texeditor 3068df3, before the kinds had their true names: a placement and a
# scatter of the stone above, its kind stored as "bezier" (Catmull–Rom) or "bspline".
RECORDED = {"bezier": "2a53ca48a1cb28d11f0c3d6cf3507e98e12d77f0f387a47035f3db99c67fe2f9",
            "bspline": "0786e993468d3232d8a49e46d89931d04ae6acada9b9e3edf23b35aa7a48dbd7"}


def stored_log(kind):
    env = json.dumps({**STONE, "kind": kind}, separators=(",", ":"))
    return [{"type": "new_canvas", "version": 1, "width": 64, "height": 48, "levels": 4,
             "palette": None},
            {"type": "place_spot", "version": 1, "envelope": env, "row": 20.0, "col": 30.0,
             "angle": 25.0, "scale": 1.2, "seed": 3, "level": 2, "contour": 0.2, "fractal": 0.1},
            {"type": "scatter_spots", "version": 1, "envelope": env, "count": 5, "seed": 7,
             "scale": 0.5, "level": 1, "level_max": 3}]


# -- the Bézier curve ------------------------------------------------------------------------------

def test_de_casteljau_at_one_half_on_hand_points():
    # cubic: the midpoints of midpoints, by hand: (P0 + 3 P1 + 3 P2 + P3) / 8
    control = np.array([[0.0, 0.0], [0.0, 8.0], [8.0, 8.0], [8.0, 0.0]])
    # level 1: (0,4) (4,8) (8,4); level 2: (2,6) (6,6); level 3: (4,6)
    assert bezier_curve(control, np.array([0.5])).tolist() == [[4.0, 6.0]]
    # quadratic at 1/4: (1-s)² P0 + 2 s (1-s) P1 + s² P2 = (9 P0 + 6 P1 + P2) / 16
    quad = np.array([[0.0, 0.0], [16.0, 0.0], [16.0, 16.0]])
    assert bezier_curve(quad, np.array([0.25])).tolist() == [[7.0, 1.0]]
    # the ends are the first and last control points
    ends = bezier_curve(control, np.array([0.0, 1.0]))
    assert ends.tolist() == [[0.0, 0.0], [8.0, 0.0]]


def test_the_closed_bezier_outline_on_the_envelope_points():
    env = Envelope((0.0, 0.0), (0.0, 10.0), (Meridian(0.5, 4, 2),), kind="bezier_curve")
    pts = env.control_points()                  # a, left end, b, right end
    assert pts.tolist() == [[0, 0], [-4, 5], [0, 10], [2, 5]]
    control = closed_bezier_polygon(pts)        # M, a, L, b, R, M with M the middle of R–a
    assert control.tolist() == [[1, 2.5], [0, 0], [-4, 5], [0, 10], [2, 5], [1, 2.5]]
    # degree 5 at 1/2: (M + 5a + 10L + 10b + 5R + M) / 32, by hand
    assert np.allclose(bezier_curve(control, np.array([0.5])), [[-28 / 32, 180 / 32]])
    # B'(0) = n (P1 − P0) and B'(1) = n (P5 − P4): equal, the closed curve is smooth at M
    assert (control[1] - control[0]).tolist() == (control[-1] - control[-2]).tolist()
    outline = env.outline(0.25)
    assert outline[0].tolist() == [1.0, 2.5]    # it starts at M
    # it does not pass through the points (only a and b pull it; none is reached)
    assert np.min(np.linalg.norm(outline - [-4, 5], axis=1)) > 1


def test_a_bezier_curve_on_too_many_points_says_to_use_the_b_spline():
    many = [(10 * np.cos(a), 10 * np.sin(a))
            for a in np.linspace(0, 2 * np.pi, MAX_BEZIER_POINTS + 1, endpoint=False)]
    with pytest.raises(InputError, match="B-spline"):
        Envelope.from_contour(many, kind="bezier_curve")
    assert len(Envelope.from_contour(many, kind="uniform_bspline").outline()) > 0


# -- the uniform cubic B-spline --------------------------------------------------------------------

def test_the_b_spline_at_its_knots_is_the_thesis_weighting_of_three_points():
    pts = np.array([[0.0, 0.0], [0.0, 6.0], [6.0, 12.0], [12.0, 6.0], [6.0, 0.0]])
    curve = uniform_bspline(pts)
    for i in range(len(pts)):                   # piece i starts at (P_i + 4 P_i+1 + P_i+2) / 6
        expected = (pts[i] + 4 * pts[(i + 1) % 5] + pts[(i + 2) % 5]) / 6
        assert np.allclose(curve(float(i)), expected)


@pytest.mark.parametrize("moved", [0, 4, 9])
def test_moving_one_b_spline_point_changes_exactly_four_pieces(moved):
    n = 10
    pts = np.random.default_rng(moved).uniform(-20, 20, (n, 2))
    s = np.arange(n * 16) / 16                  # 16 samples in each piece [i, i + 1)
    before = uniform_bspline(pts)(s)
    pts[moved] += (3.0, -2.0)
    after = uniform_bspline(pts)(s)
    changed = {int(i) for i in np.floor(s[np.any(before != after, axis=1)])}
    assert changed == {(moved - k) % n for k in range(4)}       # pieces moved-3 .. moved
    unchanged = ~np.isin(np.floor(s).astype(int), list(changed))
    assert np.array_equal(before[unchanged], after[unchanged])  # bit for bit elsewhere


# -- the stored names ------------------------------------------------------------------------------

@pytest.mark.parametrize("stored", sorted(LEGACY_KINDS))
def test_old_placements_replay_bit_identical(stored):
    actions = [action_from_json(obj) for obj in stored_log(stored)]
    assert actions[1].envelope_model().kind == LEGACY_KINDS[stored]
    assert replay(actions, {}).result_hash() == RECORDED[stored]
    # the placement's JSON, hence the fingerprint a deletion names it by, is the stored one
    assert actions[1].to_json()["envelope"] == stored_log(stored)[1]["envelope"]
    again = action_from_json(json.loads(json.dumps(actions[1].to_json())))
    assert spot_ref(again) == spot_ref(actions[1])


@pytest.mark.parametrize("stored", sorted(LEGACY_KINDS))
def test_a_stored_name_draws_what_its_true_name_draws(stored):
    old = Envelope.from_json({**STONE, "kind": stored})
    new = Envelope.from_json({**STONE, "kind": LEGACY_KINDS[stored]})
    assert old == new and np.array_equal(old.outline(), new.outline())
    assert new.to_json()["kind"] == LEGACY_KINDS[stored]       # written under the true name
    a = PlaceSpot(old.dumps(), 20.0, 24.0, seed=1, level=2)
    b = PlaceSpot(json.dumps({**STONE, "kind": stored}), 20.0, 24.0, seed=1, level=2)
    canvas = NewCanvas(48, 40, 3)
    assert replay([canvas, a], {}).result_hash() == replay([canvas, b], {}).result_hash()


def test_the_old_names_are_refused_when_building_an_envelope():
    for stored, true in LEGACY_KINDS.items():
        with pytest.raises(InputError, match=true):
            Envelope.ellipse(20, 10, kind=stored)
    assert set(LEGACY_KINDS).isdisjoint(KINDS)


def test_the_spot_library_reads_a_stored_name_with_its_meaning(tmp_path):
    items = [{"name": "Mine", "envelope": {**STONE, "kind": "bezier"}}]
    (tmp_path / "spots.json").write_text(json.dumps({"format": "spots", "version": 1,
                                                     "items": items}))
    library = SpotLibrary(tmp_path)
    assert library.problems == [] and library.get("Mine").envelope.kind == "catmull_rom"
    assert library.get("Stone").envelope.kind == "catmull_rom"     # the built-in looks the same
