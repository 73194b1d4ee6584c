"""Relief (issue 20, companion document 003): bump normals N' = (−∂P/∂u, −∂P/∂v, 1) against the
finite-difference formula written out point by point, seamless normal maps, the shading
I = k_a + k_d·max(0, N̂'·L̂) against hand values, the 16-bit height map and the OpenGL/DirectX
normal maps read back from their PNG files, and the previews' shading."""

import math

import imageio.v3 as iio
import numpy as np
import pytest

from texeditor.errors import InputError
from texeditor.export import write_picture
from texeditor.relief import (encode_normals, height_map16, heights, light_direction,
                              normal_map, plane_preview, shade, sphere_preview,
                              write_height_map, write_normal_map)
from texeditor.relief import previews

GREYS = np.array([[0, 0, 0], [60, 60, 60], [200, 200, 200], [255, 255, 255]], np.uint8)


def formula(P, wrap):
    """The normals written out point by point: central differences one point apart, on the
    torus or one-sided at the border; v points up the picture (towards row 0)."""
    h, w = P.shape
    out = np.zeros((h, w, 3))
    for r in range(h):
        for c in range(w):
            if wrap:
                du = (P[r, (c + 1) % w] - P[r, (c - 1) % w]) / 2
                dv = (P[(r - 1) % h, c] - P[(r + 1) % h, c]) / 2
            else:
                left, right = max(c - 1, 0), min(c + 1, w - 1)
                up, down = max(r - 1, 0), min(r + 1, h - 1)
                du = (P[r, right] - P[r, left]) / max(right - left, 1)
                dv = (P[up, c] - P[down, c]) / max(down - up, 1)
            n = np.array([-du, -dv, 1.0])
            out[r, c] = n / math.sqrt(n @ n)
    return out


RAMP = 0.5 * np.arange(5)[None, :] - 0.25 * np.arange(4)[:, None]       # up-right slope
BUMP = np.pad(np.ones((1, 1)), 2)                                          # one point raised
RANDOM = np.random.default_rng(20).random((6, 7)) * 3


@pytest.mark.parametrize("P", [RAMP, BUMP, RANDOM], ids=["ramp", "bump", "random"])
@pytest.mark.parametrize("wrap", [True, False])
def test_normals_are_unit_vectors_given_by_the_finite_difference_formula(P, wrap):
    n = normal_map(P, wrap=wrap)
    assert n.shape == P.shape + (3,)
    assert np.abs(np.linalg.norm(n, axis=-1) - 1).max() < 1e-6
    assert np.abs(n - formula(P, wrap)).max() < 1e-6


def test_hand_values_of_the_ramp_and_the_bump():
    """The ramp rises 0.5 a column to the right and 0.25 a row up the picture: its normal leans
    left and down. Around a raised point, normals lean away from it."""
    ramp = normal_map(RAMP, wrap=False)
    assert np.allclose(ramp, np.array([-0.5, -0.25, 1]) / math.sqrt(1.3125), atol=1e-12)
    bump = normal_map(BUMP, wrap=False)
    s = 1 / math.sqrt(1.25)
    assert np.allclose(bump[2, 1], [-0.5 * s, 0, s]) and np.allclose(bump[2, 3], [0.5 * s, 0, s])
    assert np.allclose(bump[1, 2], [0, 0.5 * s, s]) and np.allclose(bump[3, 2], [0, -0.5 * s, s])
    assert np.array_equal(bump[2, 2], [0, 0, 1]) and np.array_equal(bump[0, 0], [0, 0, 1])


def test_a_texture_that_tiles_gives_a_seamless_normal_map():
    field = np.random.default_rng(3).random((8, 10))
    n = normal_map(field, wrap=True)
    # the normals of the field rolled by half are the rolled normals: no seam is special
    rolled = np.roll(field, (4, 5), axis=(0, 1))
    assert np.abs(normal_map(rolled, wrap=True) - np.roll(n, (4, 5), axis=(0, 1))).max() < 1e-12
    # the wrap-around differences are the ones inside a 3×3 tiling of the texture
    tiled = normal_map(np.tile(field, (3, 3)), wrap=False)
    assert np.abs(tiled[8:16, 10:20] - n).max() < 1e-12
    # without wrap, the border is one-sided and differs from the tiling
    assert np.abs(normal_map(field, wrap=False)[0] - n[0]).max() > 1e-3


def test_heights_are_the_displayed_grey_times_the_strength():
    levels = np.array([[0, 1], [2, 3]], np.uint8)
    assert np.allclose(heights(levels, GREYS, 2.0), np.array([[0, 60], [200, 255]]) / 255 * 2)
    colours = np.array([[255, 0, 0], [0, 255, 0], [0, 0, 255]], np.uint8)
    assert np.allclose(heights(np.array([[0, 1, 2]], np.uint8), colours),
                       [[0.2125, 0.7154, 0.0721]])       # luminance (Rec. 709 weights)
    for bad in (-1, float("nan"), 1e9, "4"):
        with pytest.raises(InputError, match="strength"):
            heights(levels, GREYS, bad)


def test_light_directions():
    assert np.allclose(light_direction(0, 0), [1, 0, 0])          # from the right, grazing
    assert np.allclose(light_direction(90, 0), [0, 1, 0])         # from the top of the picture
    assert np.allclose(light_direction(135, 45), [-0.5, 0.5, math.sqrt(0.5)])
    assert np.allclose(light_direction(-45, 90), [0, 0, 1])
    for az, el in ((0, 95), (0, -1), (float("inf"), 30), (0, float("nan"))):
        with pytest.raises(InputError, match="light"):
            light_direction(az, el)


def test_shading_against_hand_values():
    flat = normal_map(np.zeros((3, 3)))
    assert np.allclose(shade(flat, light_direction(10, 90), 0.2, 0.7), 0.9)    # k_a + k_d
    assert np.allclose(shade(flat, light_direction(10, 0), 0.2, 0.7), 0.2)     # grazing: k_a
    slope = np.array([-0.6, 0.0, 0.8])      # a face turned left
    assert shade(slope, light_direction(180, 0), 0.1, 0.5) == pytest.approx(0.1 + 0.5 * 0.6)
    assert shade(slope, light_direction(0, 0), 0.1, 0.5) == pytest.approx(0.1)   # max(0, ·)
    assert shade(slope, light_direction(0, 30), 0.1, 0.5) == pytest.approx(
        0.1 + 0.5 * max(0, -0.6 * math.cos(math.pi / 6) + 0.8 * 0.5))
    with pytest.raises(InputError, match="ambient"):
        shade(flat, light_direction(0, 90), -0.1, 0.5)


def test_16_bit_png_round_trips_exactly(tmp_path):
    picture = np.random.default_rng(1).integers(0, 65536, (17, 23)).astype(np.uint16)
    picture[0, :2] = (0, 65535)
    write_picture(tmp_path / "h.png", picture)
    back = iio.imread(tmp_path / "h.png")
    assert back.dtype == np.uint16 and np.array_equal(back, picture)
    with pytest.raises(InputError, match="uint16"):
        write_picture(tmp_path / "x.png", np.zeros((2, 2, 3), np.uint16))


def test_the_height_map_file_holds_the_greys_in_16_bits(tmp_path):
    levels = np.array([[0, 1, 2], [3, 2, 1]], np.uint8)
    write_height_map(tmp_path / "h.png", levels, GREYS)
    back = iio.imread(tmp_path / "h.png")
    assert back.dtype == np.uint16
    assert np.array_equal(back, GREYS[levels, 0].astype(np.uint16) * 257)
    assert np.array_equal(height_map16(levels, GREYS), back)


def test_the_normal_map_encoding():
    n = normal_map(np.random.default_rng(2).random((9, 9)) * 4)
    rgb = encode_normals(n)
    assert rgb.dtype == np.uint8
    assert np.abs(rgb / 255 * 2 - 1 - n).max() <= 1 / 255 + 1e-12       # (n + 1)/2·255, rounded
    assert encode_normals(np.array([0.0, 0.0, 1.0])).tolist() == [128, 128, 255]
    assert encode_normals(np.array([-1.0, 1.0, 0.0])).tolist() == [0, 255, 128]


def test_directx_is_opengl_with_green_flipped_read_back_from_the_files(tmp_path):
    levels = np.random.default_rng(4).integers(0, 4, (12, 16)).astype(np.uint8)
    write_normal_map(tmp_path / "gl.png", levels, GREYS, strength=3.0)
    write_normal_map(tmp_path / "dx.png", levels, GREYS, strength=3.0, directx=True)
    gl, dx = iio.imread(tmp_path / "gl.png"), iio.imread(tmp_path / "dx.png")
    assert gl.shape == dx.shape == (12, 16, 3) and gl.dtype == np.uint8
    assert np.array_equal(gl[..., [0, 2]], dx[..., [0, 2]])
    assert np.array_equal(dx[..., 1], 255 - gl[..., 1])
    expected = formula(GREYS[levels, 0] / 255 * 3.0, wrap=True)
    assert np.abs(gl / 255 * 2 - 1 - expected).max() <= 1 / 255 + 1e-9


def test_the_normal_map_of_a_tiling_texture_tiles(tmp_path):
    levels = np.random.default_rng(5).integers(0, 4, (10, 12)).astype(np.uint8)
    write_normal_map(tmp_path / "n.png", levels, GREYS, strength=2.0)
    write_normal_map(tmp_path / "t.png", np.tile(levels, (3, 3)), GREYS, strength=2.0,
                     wrap=False)
    one, tiled = iio.imread(tmp_path / "n.png"), iio.imread(tmp_path / "t.png")
    assert np.array_equal(tiled[10:20, 12:24], one)
    write_normal_map(tmp_path / "b.png", levels, GREYS, strength=2.0, wrap=False)
    assert not np.array_equal(iio.imread(tmp_path / "b.png"), one)     # its border is one-sided


def test_a_tileable_synthesis_gives_a_normal_map_that_tiles(tmp_path):
    """Issue 20's target on a real texture: drawn on the torus, its normal map is the middle
    tile of the normal map of its 3×3 tiling (ordinary differences everywhere there)."""
    from texeditor import DPJ, synthesize
    from texeditor.resources import bundled_dpj

    dpj = DPJ.load(bundled_dpj("gravel-3x3-g4"))
    levels = synthesize(dpj, (40, 48), seed=5, tileable=True).levels
    write_normal_map(tmp_path / "n.png", levels, dpj.palette, strength=5.0)
    write_normal_map(tmp_path / "t.png", np.tile(levels, (3, 3)), dpj.palette, strength=5.0,
                     wrap=False)
    assert np.array_equal(iio.imread(tmp_path / "t.png")[40:80, 48:96],
                          iio.imread(tmp_path / "n.png"))


# -- previews ---------------------------------------------------------------------------------------

def supersampled(values, size):
    """The mean of each pixel's SUPERSAMPLE² samples, rounded, as the previews draw."""
    k = previews.SUPERSAMPLE
    return np.rint(values.reshape(size, k, size, k, -1).mean(axis=(1, 3)))


def test_a_flat_texture_lit_from_above_is_its_colour_times_ka_plus_kd():
    levels = np.full((16, 16), 2, np.uint8)
    picture = plane_preview(levels, GREYS, size=32, strength=5.0, azimuth=20, elevation=90,
                            ambient=0.25, diffuse=0.5)
    assert picture.shape == (32, 32, 3) and (picture == round(200 * 0.75)).all()


def test_the_sphere_of_a_flat_texture_is_a_lambert_sphere():
    """Light from the viewer: I = k_a + k_d·z where z = √(1 − x² − y²); grey outside."""
    size, k = 24, previews.SUPERSAMPLE
    picture = sphere_preview(np.full((8, 8), 3, np.uint8), GREYS, size=size, strength=2.0,
                             elevation=90, ambient=0.2, diffuse=0.6)
    s = (np.arange(size * k) + 0.5) / (size * k) * 2 - 1
    x, y = np.meshgrid(s, s)
    r2 = x * x + y * y
    grey = np.where(r2 < 1, 255 * (0.2 + 0.6 * np.sqrt(np.clip(1 - r2, 0, 1))),
                    previews.BACKGROUND)
    expected = supersampled(grey[..., None], size)[..., 0]
    assert np.abs(picture[..., 0].astype(int) - expected).max() <= 1
    assert (picture == picture[..., :1]).all()


def test_the_plane_preview_shades_each_point_with_its_wrapped_normal():
    levels = np.random.default_rng(6).integers(0, 4, (20, 24)).astype(np.uint8)
    size, strength, light = 20, 3.0, light_direction(200, 35)
    picture = plane_preview(levels, GREYS, size=size, strength=strength, azimuth=200,
                            elevation=35, ambient=0.3, diffuse=0.8)
    rows, cols = previews.plane_view(levels.shape, size).rows_cols
    n = formula(GREYS[levels, 0] / 255 * strength, wrap=True)[rows, cols]
    colour = GREYS[levels[rows, cols]] * (0.3 + 0.8 * np.maximum(0, n @ light))[:, None]
    expected = supersampled(colour.reshape(size * 2, size * 2, 3), size)
    assert np.abs(picture.astype(int) - expected).max() <= 1


def test_the_plane_is_seen_in_perspective():
    """Far rows (the top of the preview) cover more of the texture per pixel than near ones,
    by the ratio of their depths."""
    size = 64
    view = previews.plane_view((4, 1_000_000), size)
    cols = view.rows_cols[1].reshape(size * 2, size * 2)
    top, bottom = np.median(np.diff(cols[0])), np.median(np.diff(cols[-1]))
    sin, cos, fov = math.sin(previews.PITCH), math.cos(previews.PITCH), previews.FOV
    y = fov * (1 - 1 / (size * 2))              # the first and last sample rows
    assert top / bottom == pytest.approx((sin + y * cos) / (sin - y * cos), rel=0.02)
    assert bottom * size * 2 == pytest.approx(previews.NEAR_WIDTH * 1_000_000, rel=0.02)


def test_the_sphere_frames_are_orthonormal_and_face_the_viewer_at_the_centre():
    view = previews.sphere_view((16, 16), 16)
    t, b, n = view.frame.transpose(1, 0, 2).astype(np.float64)
    for a in (t, b, n):
        assert np.allclose(np.linalg.norm(a, axis=0), 1, atol=1e-6)
    assert np.allclose((t * b).sum(0), 0, atol=1e-6) and np.allclose((t * n).sum(0), 0, atol=1e-6)
    assert np.allclose(np.cross(t, b, axis=0), n, atol=1e-6)       # right-handed: T × B = N
    centre = np.argmin(np.abs(n[0]) + np.abs(n[1]))
    assert np.allclose(view.frame[:, :, centre], np.eye(3), atol=0.1)      # T, B, N = x, y, z
    # T runs the way the texture's columns do: left to right across the middle of the sphere
    rows, cols = view.rows_cols
    middle = np.abs(n[1]) < 0.05
    order = np.argsort(n[0][middle])
    steps = np.diff(np.unwrap(cols[middle][order] * 2 * np.pi / 16))
    assert (steps >= -1e-9).all() and steps.sum() > 0


def test_the_sphere_preview_turns_each_wrapped_normal_into_the_spheres_frame():
    levels = np.random.default_rng(7).integers(0, 4, (16, 20)).astype(np.uint8)
    size, strength, light = 16, 2.5, light_direction(60, 40)
    picture = sphere_preview(levels, GREYS, size=size, strength=strength, azimuth=60,
                             elevation=40, ambient=0.1, diffuse=0.9)
    view = previews.sphere_view(levels.shape, size)
    rows, cols = view.rows_cols
    n = formula(GREYS[levels, 0] / 255 * strength, wrap=True)[rows, cols]
    world = np.einsum("ki,jik->kj", n, view.frame.astype(np.float64))    # n_u T + n_v B + n_z N
    samples = np.full(((size * 2) ** 2, 3), float(previews.BACKGROUND))
    intensity = 0.1 + 0.9 * np.maximum(0, world @ light)
    samples[view.pixels] = GREYS[levels[rows, cols]] * intensity[:, None]
    expected = supersampled(samples.reshape(size * 2, size * 2, 3), size)
    assert np.abs(picture.astype(int) - expected).max() <= 1
