"""Grain rendering and density (issue 9, thesis §5.3): exact pixel grids for each grain shape and
size, the honeycomb offset, expansion along one axis, compression and its overlap rules."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY
from texeditor.texture import grain_render as gr
from texeditor.errors import InputError
from texeditor.paint.grains import anchor, grain_mask


def grid(text: str) -> np.ndarray:
    """A matrix from rows of digits ('.' is 0)."""
    return np.array([[0 if ch == "." else int(ch) for ch in row.split()]
                     for row in text.strip().splitlines()], dtype=np.uint8)


def reference(levels, mask, lattice, overlap):
    """The definition, one pixel at a time (the oracle for the compiled kernel)."""
    oh, ow = lattice.shape(levels.shape)
    out = np.zeros((oh, ow), np.uint8)
    ay, ax = mask.shape[0] // 2, mask.shape[1] // 2
    for r in range(levels.shape[0]):
        for c in range(levels.shape[1]):
            v = int(levels[r, c])
            if v == 0:
                continue
            top = r * lattice.pitch_y + lattice.pitch_y // 2 - ay
            left = c * lattice.pitch_x + (lattice.row_offset if r % 2 else 0) \
                + lattice.pitch_x // 2 - ax
            for y, x in zip(*np.nonzero(mask)):
                p = ((top + y) % oh, (left + x) % ow)
                old = int(out[p])
                out[p] = {"last": v, "max": max(old, v),
                          "min": v if old == 0 else min(old, v)}[overlap]
    return out


# -- each shape and size, exactly --------------------------------------------------------------

def test_square_grains_of_sizes_1_2_3():
    t = grid("1 2\n. 3")
    assert np.array_equal(gr.render(t, "square", 1), t)
    assert np.array_equal(gr.render(t, "square", 2), grid("""
        1 1 2 2
        1 1 2 2
        . . 3 3
        . . 3 3"""))
    assert np.array_equal(gr.render(t, "square", 3), np.kron(t, np.ones((3, 3), np.uint8)))


def test_rectangle_grains_are_size_long_and_aspect_high():
    assert np.array_equal(gr.render(grid("1 2"), "rectangle", 4, aspect=0.5), grid("""
        1 1 1 1 2 2 2 2
        1 1 1 1 2 2 2 2"""))


def test_circle_grains_touch_and_leave_the_corners_empty():
    assert np.array_equal(gr.render(grid("1 2"), "circle", 4), grid("""
        . 1 1 . . 2 2 .
        1 1 1 1 2 2 2 2
        1 1 1 1 2 2 2 2
        . 1 1 . . 2 2 ."""))
    assert np.array_equal(gr.render(grid("3"), "circle", 5), grid("""
        . 3 3 3 .
        3 3 3 3 3
        3 3 3 3 3
        3 3 3 3 3
        . 3 3 3 ."""))


def test_regular_polygon_and_diamond_grains():
    assert np.array_equal(gr.render(grid("2"), "polygon", 5, sides=3), grid("""
        . 2 2 .
        . 2 2 .
        2 2 2 2"""))
    assert np.array_equal(gr.render(grid("1"), "diamond", 5), grid("""
        . . 1 . .
        . 1 1 1 .
        1 1 1 1 1
        . 1 1 1 .
        . . 1 . ."""))


@pytest.mark.parametrize("shape, kw", [
    ("square", {}), ("rectangle", {"aspect": 0.4}), ("circle", {}), ("circle", {"aspect": 0.5}),
    ("diamond", {}), ("hexagon", {}), ("polygon", {"sides": 5}), ("polygon", {"sides": 8}),
    ("line", {"angle": 30}), ("bitmap", {"bitmap": "0110/1111/0110"})])
@pytest.mark.parametrize("size", [1, 2, 3, 5, 8])
def test_one_point_is_its_grain_mask(shape, kw, size):
    """On a grid lattice, one point of level 3 renders as the shape's mask painted 3 (the
    mask's box is the cell)."""
    mask = grain_mask(shape, size, **kw)
    out = gr.render(grid("3"), shape, size, lattice="grid", **kw)
    assert np.array_equal(out, mask * np.uint8(3))


def test_orientation_turns_the_grain():
    out = gr.render(grid("1"), "square", 5, angle=45)
    assert np.array_equal(out, grid("""
        . . . 1 . . .
        . . 1 1 1 . .
        . 1 1 1 1 1 .
        1 1 1 1 1 1 1
        . 1 1 1 1 1 .
        . . 1 1 1 . .
        . . . 1 . . ."""))
    assert np.array_equal(gr.render(grid("1 2"), "rectangle", 4, aspect=0.5, angle=90), grid("""
        1 1 2 2
        1 1 2 2
        1 1 2 2
        1 1 2 2"""))


def test_symmetric_grains_sit_on_their_centre_of_gravity():
    for shape in ("square", "circle", "hexagon", "diamond"):
        for size in (3, 4, 7, 8):
            mask = grain_mask(shape, size)
            assert anchor(mask) == (mask.shape[0] // 2, mask.shape[1] // 2)


def test_custom_bitmap_grain():
    out = gr.render(grid("1 2"), "bitmap", 3, bitmap="010/111/010")
    assert np.array_equal(out, grid("""
        . 1 . . 2 .
        1 1 1 2 2 2
        . 1 . . 2 ."""))


# -- the honeycomb ---------------------------------------------------------------------------------

def test_hexagons_on_a_honeycomb_odd_rows_shifted_by_half_a_pitch():
    assert gr.natural_lattice(grain_mask("hexagon", 5), honeycomb=True) == gr.Lattice(4, 4, 2)
    assert np.array_equal(gr.render(grid("1 2\n3 4"), "hexagon", 5), grid("""
        4 1 1 3 3 2 2 4
        1 1 1 1 2 2 2 2
        1 1 1 1 2 2 2 2
        1 1 1 1 2 2 2 2
        4 1 1 3 3 2 2 4
        4 4 3 3 3 3 4 4
        4 4 3 3 3 3 4 4
        4 4 3 3 3 3 4 4"""))


@pytest.mark.parametrize("size", [6, 8, 12])
def test_the_offset_moves_an_odd_row_by_half_a_pitch(size):
    lat = gr.grain_lattice(grain_mask("hexagon", size), shape="hexagon")
    assert lat.row_offset == lat.pitch_x // 2 > 0
    even, odd = np.zeros((4, 4), np.uint8), np.zeros((4, 4), np.uint8)
    even[0, 1], odd[1, 1] = 2, 2
    a, b = gr.render(even, "hexagon", size), gr.render(odd, "hexagon", size)
    assert np.array_equal(np.roll(a, (lat.pitch_y, lat.row_offset), axis=(0, 1)), b)


@pytest.mark.parametrize("size", range(2, 17))
def test_hexagons_are_continuous_in_both_directions(size):
    """A texture with no background renders with no hole (thesis §5.3.1: the beehive)."""
    out = gr.render(np.ones((6, 5), np.uint8), "hexagon", size)
    assert out.min() == 1


def test_circles_can_be_packed_on_a_honeycomb_too():
    lat = gr.grain_lattice(grain_mask("circle", 8), shape="circle", lattice="honeycomb")
    assert lat.row_offset == lat.pitch_x // 2 and lat.pitch_y <= 8


# -- density: expansion and compression ------------------------------------------------------------

def test_expansion_along_x_only_inserts_blank_columns():
    out = gr.render(grid("1 2\n3 .") , "square", 2, explosion_x=2)
    assert np.array_equal(out, grid("""
        . 1 1 . . 2 2 .
        . 1 1 . . 2 2 .
        . 3 3 . . . . .
        . 3 3 . . . . ."""))


def test_expansion_along_y_only_inserts_blank_rows():
    out = gr.render(grid("1 2\n3 ."), "square", 2, explosion_y=2)
    assert np.array_equal(out, grid("""
        . . . .
        1 1 2 2
        1 1 2 2
        . . . .
        . . . .
        3 3 . .
        3 3 . .
        . . . ."""))


@pytest.mark.parametrize("overlap, row", [("last", "3 2 2 3 3 3"), ("max", "3 2 2 3 3 3"),
                                          ("min", "1 1 1 2 2 1")])
def test_compression_overlaps_and_the_overlap_rule_decides(overlap, row):
    """Squares of 4 at pitch 2 (compression 0.5): each pixel lies under two grains."""
    out = gr.render(grid("1 2 3"), "square", 4, compression=0.5, overlap=overlap)
    assert out.shape == (2, 6)
    assert np.array_equal(out, grid(f"{row}\n{row}"))


@pytest.mark.parametrize("overlap, row", [("last", "2 3 3 2 2 2"), ("max", "2 3 3 3 3 2"),
                                          ("min", "1 1 1 2 2 1")])
def test_overlap_rules_in_scan_order(overlap, row):
    out = gr.render(grid("1 3 2"), "square", 4, compression=0.5, overlap=overlap)
    assert np.array_equal(out, grid(f"{row}\n{row}"))


def test_background_points_draw_nothing_and_hide_nothing():
    out = gr.render(grid("1 . 2"), "square", 4, compression=0.5, overlap="last")
    assert np.array_equal(out[0], grid("2 1 1 2 2 2")[0])


def test_strong_compression_turns_grains_into_spots():
    """Compressed circles merge: fewer, larger connected regions per grain drawn (§5.3.2)."""
    from skimage.measure import label
    rng = np.random.default_rng(1)
    t = (rng.random((24, 24)) < 0.3).astype(np.uint8)
    loose = gr.render(t, "circle", 8, explosion_x=1.5, explosion_y=1.5)
    tight = gr.render(t, "circle", 8, compression=0.6)
    assert label(tight > 0).max() < label(loose > 0).max() / 3


def test_compression_across_only_overlaps_grains_along_rows_only():
    """Squares of 4 at pitch 2 across, 4 down: grain c covers columns 2c−1..2c+2 (mod 6), every
    row; the later grain wins where two lie: 1 on {5,0,1,2}, 2 on {1..4}, 3 on {3,4,5,0}."""
    out = gr.render(grid("1 2 3"), "square", 4, compression=0.0, compression_x=0.5)
    assert out.shape == (4, 6)
    assert np.array_equal(out, grid("\n".join(["3 2 2 3 3 3"] * 4)))


def test_compression_down_only_overlaps_grains_along_columns_only():
    out = gr.render(grid("1\n2\n3"), "square", 4, compression=0.5, compression_x=0.0)
    assert out.shape == (6, 4)
    assert np.array_equal(out, grid("\n".join(["3 3 3 3", "2 2 2 2", "2 2 2 2", "3 3 3 3",
                                                 "3 3 3 3", "3 3 3 3"])))


def test_compression_per_axis_sets_each_pitch():
    nat = gr.Lattice(8, 8)
    assert gr.density_lattice(nat, compression=0.5, compression_x=0.0) == gr.Lattice(4, 8)
    assert gr.density_lattice(nat, compression=0.0, compression_x=0.5) == gr.Lattice(8, 4)
    assert gr.density_lattice(nat, explosion_x=2, compression=0.25, compression_x=0.25) == \
        gr.Lattice(6, 12)                  # round(8·2·0.75) across, round(8·0.75) down
    # no compression across of its own: the one down applies to both axes, as before
    assert gr.density_lattice(nat, compression=0.25, compression_x=None) == gr.Lattice(6, 6)
    honey = gr.density_lattice(gr.Lattice(7, 8, 4), compression=0.0, compression_x=0.5)
    assert honey == gr.Lattice(7, 4, 2)   # odd rows shift by half the new pitch


def test_pitch_follows_explosion_and_compression():
    nat = gr.Lattice(8, 8)
    assert gr.density_lattice(nat, explosion_x=2) == gr.Lattice(8, 16)
    assert gr.density_lattice(nat, compression=0.25) == gr.Lattice(6, 6)
    assert gr.density_lattice(nat, explosion_x=2, compression=0.5) == gr.Lattice(4, 8)
    assert gr.density_lattice(gr.Lattice(1, 1), compression=0.9) == gr.Lattice(1, 1)


@pytest.mark.parametrize("kw", [{"explosion_x": 0.5}, {"explosion_y": 9}, {"compression": 0.95},
                                {"compression": -0.1}, {"compression_x": 0.95},
                                {"compression_x": -0.1}])
def test_density_out_of_range_is_an_input_error(kw):
    with pytest.raises(InputError):
        gr.render(grid("1"), "square", 2, **kw)


def test_errors_name_what_to_change():
    with pytest.raises(InputError, match="overlap rule"):
        gr.render(grid("1"), "square", 2, overlap="sum")
    with pytest.raises(InputError, match="lattice"):
        gr.render(grid("1"), "square", 2, lattice="hex")
    with pytest.raises(InputError, match="largest canvas"):
        gr.render_grains(np.ones((4096, 4096), np.uint8), np.ones((8, 8), bool), gr.Lattice(8, 8))


# -- the compiled kernel is the definition ---------------------------------------------------------

@PROPERTY
@given(levels=st.tuples(st.integers(1, 5), st.integers(1, 5)).flatmap(
           lambda hw: st.lists(st.integers(0, 4), min_size=hw[0] * hw[1],
                               max_size=hw[0] * hw[1]).map(
               lambda v: np.array(v, np.uint8).reshape(hw))),
       shape=st.sampled_from(["square", "circle", "hexagon", "diamond", "rectangle", "line"]),
       size=st.integers(1, 7), angle=st.sampled_from([0.0, 30.0, 90.0]),
       ex=st.sampled_from([1.0, 1.5, 2.0]), ey=st.sampled_from([1.0, 2.0]),
       comp=st.sampled_from([0.0, 0.3, 0.6]), overlap=st.sampled_from(gr.OVERLAP_RULES),
       lattice=st.sampled_from(gr.LATTICES))
def test_kernel_matches_the_definition(levels, shape, size, angle, ex, ey, comp, overlap,
                                       lattice):
    t = levels
    mask = grain_mask(shape, size, angle=angle, aspect=0.5 if shape == "rectangle" else 1.0)
    lat = gr.grain_lattice(mask, shape=shape, lattice=lattice, explosion_x=ex, explosion_y=ey,
                           compression=comp)
    assert np.array_equal(gr.render_grains(t, mask, lat, overlap),
                          reference(t, mask, lat, overlap))


def test_banded_render_with_progress_is_the_same_picture_and_can_be_cancelled():
    from texeditor.errors import Cancelled
    from texeditor.texture.actions import RenderGrains
    from texeditor.recipe.document import Document
    t = np.random.default_rng(3).integers(0, 4, (40, 30), dtype=np.uint8)
    action = RenderGrains("hexagon", 6, explosion_x=1.9, compression=0.3, overlap="max")
    seen = []
    banded = action.render(t, progress=seen.append, cancel=lambda: False)
    assert np.array_equal(banded, action.render(t))
    assert seen[-1] == 1.0 and len(seen) > 10 and seen == sorted(seen)
    with pytest.raises(Cancelled):
        action.render(t, progress=seen.append, cancel=lambda: len(seen) > 15)
    # a picture handed over from a worker is used once, only for the levels it was made from
    doc = Document()
    with doc.step():
        doc.set_levels(t, np.zeros((4, 3), np.uint8))
    action.use_result(t.copy(), np.full(banded.shape, 3, np.uint8))
    with doc.step():
        action.apply(doc)
    assert np.all(doc.levels == 3)
    with doc.step():
        doc.set_levels(t, np.zeros((4, 3), np.uint8))
    action.use_result(t + 1, np.full(banded.shape, 3, np.uint8))   # stale: rendered again
    with doc.step():
        action.apply(doc)
    assert np.array_equal(doc.levels, banded)
