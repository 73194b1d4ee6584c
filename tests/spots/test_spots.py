"""Spots (issue 7, engine): envelopes, outlines, perturbation, rasterisation, fill and blend."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from texeditor.errors import InputError
from texeditor.spots.envelope import (APPROXIMATING, KINDS, Envelope, Meridian, Parallel,
                                     Perturbation, Placement, Stamp, blend,
                                     midpoint_displacement, pieces, place, polygon_area,
                                     polygon_mask, real_spot, spot_levels, tile)

STONE = Envelope((2.0, -20.0), (-1.0, 19.0),
                 (Meridian(0.15, 8, 9), Meridian(0.45, 15, 13, main=True), Meridian(0.8, 11, 9)))
ROUGH = Perturbation(contour=0.3, frequency=7, fractal=0.2, h=0.4)


def distance_to(outline, points):
    return np.min(np.linalg.norm(outline[:, None, :] - points[None, :, :], axis=-1), axis=0)


def meridian_ends(env):
    return np.array([env.at(m.t, m.left) for m in env.meridians]
                    + [env.at(m.t, -m.right) for m in env.meridians] + [env.a, env.b])


def inside_box(stamp, box):
    """Every point of the stamp lies in the (top, left, bottom, right) box (point centres)."""
    rows, cols = np.nonzero(stamp.mask)
    top, left, bottom, right = box
    return (rows + stamp.top >= top - 1e-9).all() and (rows + stamp.top <= bottom + 1e-9).all() \
        and (cols + stamp.left >= left - 1e-9).all() and (cols + stamp.left <= right + 1e-9).all()


# -- the envelope and its outline ------------------------------------------------------------------

@pytest.mark.parametrize("kind", sorted(set(KINDS) - set(APPROXIMATING)))
def test_the_outline_passes_through_every_meridian_end_point(kind):
    env = STONE.with_kind(kind).with_parallel(5.0, 0.05, 0.2)
    outline = env.outline()
    assert distance_to(outline, meridian_ends(env)).max() < 1e-9
    assert distance_to(outline, np.array([env.at(0.05, 5.0), env.at(0.2, 5.0)])).max() < 1e-9


@pytest.mark.parametrize("kind", KINDS)
def test_the_outline_is_closed_and_dense(kind):
    outline = STONE.with_kind(kind).outline(step=0.5)
    gaps = np.linalg.norm(np.diff(np.vstack([outline, outline[:1]]), axis=0), axis=1)
    assert gaps.max() < 1.0 and gaps.min() > 0


def test_linear_outline_is_the_polygon_of_the_control_points():
    env = Envelope((0.0, 0.0), (0.0, 10.0), (Meridian(0.5, 4, 2),), kind="linear")
    assert env.control_points().tolist() == [[0, 0], [-4, 5], [0, 10], [2, 5]]
    assert math.isclose(env.area(), 30.0)       # two triangles: 10·4/2 + 10·2/2


def test_meridians_given_crossed_are_sorted_along_the_equator():
    m = (Meridian(0.8, 3, 3), Meridian(0.2, 5, 1), Meridian(0.5, 6, 6))
    crossed = Envelope((0.0, 0.0), (0.0, 30.0), m)
    ordered = Envelope((0.0, 0.0), (0.0, 30.0), tuple(sorted(m, key=lambda x: x.t)))
    assert crossed == ordered and [x.t for x in crossed.meridians] == [0.2, 0.5, 0.8]


def test_main_meridian_is_the_marked_one_or_the_widest():
    assert STONE.main_index == 1
    env = Envelope((0.0, 0.0), (0.0, 30.0), (Meridian(0.2, 5, 5), Meridian(0.6, 9, 9)))
    assert env.main_index == 1
    with pytest.raises(InputError, match="only one meridian"):
        Envelope((0.0, 0.0), (0.0, 30.0), (Meridian(0.2, 5, 5, True), Meridian(0.6, 9, 9, True)))


def test_adding_a_meridian_where_the_outline_already_is_keeps_the_linear_shape():
    env = STONE.with_kind("linear")
    left, right = env.width_at(0.3)
    wider = env.with_meridian(0.3, left, right)
    assert len(wider.meridians) == 4
    assert math.isclose(wider.area(), env.area(), rel_tol=1e-9)
    assert wider.without_meridian(1) == env


def test_envelope_json_round_trip_and_validation():
    env = STONE.with_parallel(-4.0, 0.3, 0.7).with_kind("bezier_curve")
    assert Envelope.loads(env.dumps()) == env
    assert Envelope.from_json(env.to_json()) == env
    for bad, message in [("{", "not valid JSON"), ("[]", "JSON object"),
                         ('{"a": [0, 0]}', "end points"),
                         ('{"a": [0, 0], "b": [0, 1], "x": 1}', "unexpected"),
                         ('{"a": [0, 0], "b": [0, 1], "kind": "spline"}', "outline kind"),
                         ('{"a": [0, "x"], "b": [0, 1]}', "must be a number"),
                         ('{"a": [0, 0], "b": [0, 1e300]}', "out of range"),
                         ('{"a": [0, 0], "b": [0, 9], "meridians": [[0.5, 1]]}', "meridian")]:
        with pytest.raises(InputError, match=message):
            Envelope.loads(bad)


def test_a_freehand_contour_takes_its_longest_chord_as_equator():
    square = [(0, 0), (0, 10), (10, 10), (10, 0)]
    env = Envelope.from_contour(square, kind="linear")
    assert {env.a, env.b} in ({(0.0, 0.0), (10.0, 10.0)}, {(0.0, 10.0), (10.0, 0.0)})
    assert math.isclose(env.area(), 100.0)
    stamp = real_spot(env)
    assert stamp.area == 100          # rows 0..9 × cols 0..9 (the far edges are not inside)


# -- degenerate envelopes: a clear error or a sane result -----------------------------------------

def test_a_zero_length_equator_is_a_clear_error():
    with pytest.raises(InputError, match="equator has zero length"):
        Envelope((3.0, 4.0), (3.0, 4.0), (Meridian(0.5, 2, 2),))


def test_meridians_at_one_place_or_off_the_equator_are_clear_errors():
    with pytest.raises(InputError, match="same place"):
        Envelope((0.0, 0.0), (0.0, 9.0), (Meridian(0.5, 2, 2), Meridian(0.5, 4, 1)))
    for t in (0.0, 1.0, 1.5, -0.2):
        with pytest.raises(InputError, match="between its end points"):
            Envelope((0.0, 0.0), (0.0, 9.0), (Meridian(t, 2, 2),))
    with pytest.raises(InputError, match="≥ 0"):
        Envelope((0.0, 0.0), (0.0, 9.0), (Meridian(0.5, -1, 2),))
    with pytest.raises(InputError, match="off the equator"):
        Envelope((0.0, 0.0), (0.0, 9.0), parallels=(Parallel(0, 0.2, 0.4),))
    with pytest.raises(InputError, match="forwards"):
        Envelope((0.0, 0.0), (0.0, 9.0), parallels=(Parallel(2, 0.4, 0.2),))


@pytest.mark.parametrize("kind", KINDS)
def test_widths_of_zero_have_no_area_and_say_so(kind):
    flat = Envelope((0.0, 0.0), (0.0, 20.0), (Meridian(0.3, 0, 0), Meridian(0.7, 0, 0)), kind=kind)
    assert len(flat.outline()) >= 2                       # the editor can still draw it
    with pytest.raises(InputError, match="no width"):
        real_spot(flat)
    with pytest.raises(InputError, match="no width"):
        real_spot(Envelope((0.0, 0.0), (0.0, 20.0), kind=kind))     # no meridian at all


@pytest.mark.parametrize("kind", KINDS)
def test_one_sided_and_pinched_envelopes_give_sane_spots(kind):
    least = 10 if kind in APPROXIMATING else 50    # a curve that only follows its points is
    half = Envelope((0.0, 0.0), (0.0, 30.0), (Meridian(0.5, 8, 0),), kind=kind)   # thinner
    stamp = real_spot(half, ROUGH, seed=2)
    rows = np.nonzero(stamp.mask)[0] + stamp.top
    assert stamp.area > least and rows.max() <= 1      # all on the left (above) of the equator
    pinched = Envelope((0.0, 0.0), (0.0, 30.0),
                       (Meridian(0.25, 6, 6), Meridian(0.5, 0, 0), Meridian(0.75, 6, 6)), kind=kind)
    assert real_spot(pinched).area > least


def test_a_spot_smaller_than_a_point_still_marks_one_point():
    stamp = real_spot(Envelope.ellipse(1.0, 0.4), placement=Placement((5.3, 7.6), 30, 0.2))
    assert stamp.area == 1
    assert (stamp.top + np.nonzero(stamp.mask)[0][0], stamp.left + np.nonzero(stamp.mask)[1][0]) \
        == (5, 8)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.lists(st.tuples(st.floats(-0.5, 1.5), st.floats(-3, 12), st.floats(-3, 12)),
                max_size=6),
       st.sampled_from(KINDS), st.floats(-40, 40), st.floats(-40, 40), st.integers(0, 99))
def test_any_envelope_gives_a_spot_inside_its_box_or_a_clear_error(meridians, kind, br, bc, seed):
    try:
        env = Envelope((0.0, 0.0), (br, bc), tuple(Meridian(*m) for m in meridians), kind=kind)
        stamp = real_spot(env, ROUGH, seed=seed,
                          placement=Placement((3.5, 2.5), seed * 7.0, 0.5 + seed / 50))
    except InputError as exc:
        assert str(exc)
        return
    assert stamp.area >= 1 and stamp.mask.shape == stamp.alt.shape


# -- rasterising -----------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("angle, scale", [(0, 1), (37, 1), (90, 2.5), (-120, 0.6)])
def test_the_spot_covers_the_envelope_area_inside_its_box(kind, angle, scale):
    env = STONE.with_kind(kind)
    placement = Placement((40.0, 60.0), angle, scale)
    stamp = real_spot(env, placement=placement)
    outline = placement.apply(env, env.outline(0.25))
    box = (*outline.min(axis=0), *outline.max(axis=0))
    area = abs(polygon_area(outline))
    perimeter = np.linalg.norm(np.diff(outline, axis=0), axis=1).sum()
    assert inside_box(stamp, box)
    assert abs(stamp.area - area) < 0.3 * perimeter + 2


@pytest.mark.parametrize("kind", KINDS)
def test_the_real_spot_stays_inside_its_envelope(kind):
    env = STONE.with_kind(kind)
    placement = Placement((0.0, 0.0), 20, 1.5)
    whole = real_spot(env, placement=placement)
    for seed in range(5):
        stamp = real_spot(env, ROUGH, seed=seed, placement=placement)
        assert (stamp.top, stamp.left, stamp.shape) == (whole.top, whole.left, whole.shape)
        assert not (stamp.mask & ~whole.mask).any()
        assert 0.35 * whole.area < stamp.area < whole.area


def test_same_seed_same_spot_different_seeds_different_spots():
    pert = Perturbation(contour=0.25, frequency=6, fractal=0.15, interior="holes", density=0.2)
    spots = [real_spot(STONE, pert, seed=s, placement=Placement((9.0, 9.0), 15, 1.2))
             for s in (1, 1, 2, 3)]
    assert np.array_equal(spots[0].mask, spots[1].mask)
    assert not np.array_equal(spots[0].mask, spots[2].mask)
    assert not np.array_equal(spots[2].mask, spots[3].mask)
    assert len({s.area for s in spots[1:]}) == 3


def test_changing_the_interior_keeps_the_contour_draws():
    a = real_spot(STONE, Perturbation(contour=0.3), seed=4)
    b = real_spot(STONE, Perturbation(contour=0.3, interior="levels", density=0.4), seed=4)
    assert np.array_equal(a.mask, b.mask) and b.alt.any() and not (b.alt & ~b.mask).any()


def test_holes_and_level_patches_cover_about_their_density():
    env = Envelope.ellipse(80, 60)
    whole = real_spot(env).area
    for density in (0.2, 0.5):
        holes = real_spot(env, Perturbation(interior="holes", density=density, scale=3), seed=1)
        assert abs(1 - holes.area / whole - density) < 0.08
        patches = real_spot(env, Perturbation(interior="levels", density=density, scale=3), seed=1)
        assert patches.area == whole and abs(patches.alt.sum() / whole - density) < 0.08


@pytest.mark.parametrize("interior", ["holes", "levels"])
def test_interior_marks_are_mapped_by_bands_the_same(interior, monkeypatch):
    """A spot's interior marks are mapped a band of rows at a time (a 16000-point spot took
    2 GiB mapped at once and failed under a memory limit): bands of 3 rows, or of one point,
    mark the same points as the whole spot at once."""
    from texeditor.spots import envelope
    env = Envelope.ellipse(60, 35)
    pert = Perturbation(contour=0.2, interior=interior, density=0.35, scale=3)
    place = Placement((10.0, -7.0), 30, 1.5)
    whole = real_spot(env, pert, seed=2, placement=place)
    assert whole.mask.sum() > 3 * whole.shape[1] and whole.alt.any() != (interior == "holes")
    for points in (3 * whole.shape[1], 1):
        monkeypatch.setattr(envelope, "MARK_POINTS", points)
        banded = real_spot(env, pert, seed=2, placement=place)
        assert np.array_equal(banded.mask, whole.mask) and np.array_equal(banded.alt, whole.alt)


def test_holes_turn_with_the_spot():
    env, pert = Envelope.ellipse(40, 40), Perturbation(interior="holes", density=0.3, scale=2)
    a = real_spot(env, pert, seed=3, placement=Placement((0.0, 0.0), 0))
    b = real_spot(env, pert, seed=3, placement=Placement((0.0, 0.0), 90))
    assert a.shape == b.shape
    assert (np.rot90(a.mask) != b.mask).mean() < 0.03


def test_polygon_mask_gives_skimage_points():
    from skimage.draw import polygon
    rng = np.random.default_rng(1)
    for _ in range(100):
        pts = rng.uniform(-5, 45, (rng.integers(3, 30), 2))
        expected = np.zeros((40, 40), bool)
        expected[polygon(pts[:, 0], pts[:, 1], (40, 40))] = True
        assert np.array_equal(polygon_mask(pts[:, 0], pts[:, 1], (40, 40)), expected)


# -- fractal roughening ---------------------------------------------------------------------------

def test_midpoint_displacement_is_closed_and_seeded():
    a = midpoint_displacement(8, 0.5, np.random.default_rng(3))
    b = midpoint_displacement(8, 0.5, np.random.default_rng(3))
    assert a.shape == (256,) and a[0] == 0 and np.array_equal(a, b)


def test_midpoint_displacement_keeps_coarse_points_when_refined():
    """Each point is computed once: a deeper profile only adds points between the old ones."""
    coarse = midpoint_displacement(5, 0.7, np.random.default_rng(9))
    fine = midpoint_displacement(8, 0.7, np.random.default_rng(9))
    assert np.array_equal(fine[::8], coarse)


@pytest.mark.parametrize("h", [0.3, 0.8])
def test_midpoint_displacement_variogram_slope_is_about_2h(h):
    lags = np.array([4, 8, 16, 32])
    v = np.zeros(len(lags))
    for seed in range(200):
        g = midpoint_displacement(10, h, np.random.default_rng(seed))
        v += [np.mean((np.roll(g, -d) - g) ** 2) for d in lags]
    slope = np.polyfit(np.log(lags), np.log(v), 1)[0]
    assert abs(slope - 2 * h) < 0.2


# -- fill, blend and wrap --------------------------------------------------------------------------

SQUARE = Stamp(1, 1, np.array([[1, 1, 0], [1, 1, 1]], bool), np.array([[0, 1, 0], [0, 0, 0]], bool))


def test_fill_with_a_level_and_a_shift_for_the_patches():
    assert spot_levels(SQUARE, 2, shift=1, num_levels=4).tolist() == [[2, 3, 2], [2, 2, 2]]
    assert spot_levels(SQUARE, 3, shift=2, num_levels=4)[0, 1] == 3      # clipped to G - 1


def test_fill_with_a_lower_level_texture_repeats_it_at_its_plane_place():
    texture = np.array([[1, 2], [3, 0]], np.uint8)
    assert tile(texture, 1, 1, (2, 3)).tolist() == [[0, 3, 0], [2, 1, 2]]
    assert spot_levels(SQUARE, texture, shift=0).tolist() == [[0, 3, 0], [2, 1, 2]]
    assert tile(texture, 0, 0, (1, 2), offset=(1, 0)).tolist() == [[3, 0]]


@pytest.mark.parametrize("rule, expected", [
    ("over", [[0, 0, 0, 0], [0, 2, 2, 3], [0, 2, 2, 2]]),
    ("under", [[0, 0, 0, 0], [0, 2, 1, 3], [0, 2, 3, 2]]),
    ("max", [[0, 0, 0, 0], [0, 2, 2, 3], [0, 2, 3, 2]]),
    ("min", [[0, 0, 0, 0], [0, 0, 1, 3], [0, 0, 2, 2]]),
])
def test_blend_rules(rule, expected):
    levels = np.array([[0, 0, 0, 0], [0, 0, 1, 3], [0, 0, 3, 2]], np.uint8)
    stamp = Stamp(1, 1, SQUARE.mask)
    assert place(levels, stamp, 2, blend_rule=rule).tolist() == expected
    with pytest.raises(InputError, match="blend"):
        blend(levels, levels > 0, levels, "mix")


def test_a_stamp_off_the_edge_is_clipped_or_wrapped():
    levels = np.zeros((3, 4), np.uint8)
    stamp = Stamp(2, 3, np.ones((2, 2), bool))
    assert place(levels, stamp, 1).tolist() == [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1]]
    assert place(levels, stamp, 1, wrap=True).tolist() == [[1, 0, 0, 1], [0, 0, 0, 0],
                                                           [1, 0, 0, 1]]
    assert len(pieces(stamp, (3, 4), wrap=True)) == 4
    assert pieces(Stamp(-5, -5, np.ones((2, 2), bool)), (3, 4)) == []


def test_relief_lights_the_rim_towards_the_top_left_whatever_the_turn():
    env = Envelope.ellipse(40, 30)
    for angle in (0, 70, 180):
        stamp = real_spot(env, Perturbation(interior="relief", density=0.3),
                          placement=Placement((0.0, 0.0), angle))
        rows, cols = np.nonzero(stamp.mask)
        centre = rows.mean(), cols.mean()
        lit, shaded = np.nonzero(stamp.steps == 1), np.nonzero(stamp.steps == -1)
        assert lit[0].mean() < centre[0] and lit[1].mean() < centre[1]
        assert shaded[0].mean() > centre[0] and shaded[1].mean() > centre[1]
        assert 0.15 < stamp.alt.mean() / stamp.mask.mean() < 0.6
    assert spot_levels(stamp, 2, shift=1, num_levels=4)[stamp.steps == -1].max() == 1
