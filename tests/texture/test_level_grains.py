"""A primitive per level at the grain stage (issue 21 item 5, thesis §5.3): each level of the
normalised texture drawn with its own grain shape and size, on the lattice of all the grains."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY
from texeditor.errors import InputError
from texeditor.paint.grains import grain_mask
from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.recipe.replay import replay
from texeditor.texture import grain_render as gr
from texeditor.texture.actions import RenderGrains


def grid(text: str) -> np.ndarray:
    """A matrix from rows of digits ('.' is 0)."""
    return np.array([[0 if ch == "." else int(ch) for ch in row.split()]
                     for row in text.strip().splitlines()], dtype=np.uint8)


T = grid("1 2\n2 1")


def test_two_levels_two_primitives_squares_and_diamonds():
    """Level 1 a square of 3, level 2 a diamond of 3: both 3×3 boxes, so the pitch stays 3."""
    expected = grid("""
        1 1 1 . 2 .
        1 1 1 2 2 2
        1 1 1 . 2 .
        . 2 . 1 1 1
        2 2 2 1 1 1
        . 2 . 1 1 1""")
    assert np.array_equal(gr.render(T, "square", 3, level_grains="2: diamond 3"), expected)
    action = RenderGrains("square", 3, level_grains="2: diamond 3")
    assert np.array_equal(action.render(T), expected)


def test_the_lattice_fits_the_largest_grain_and_each_sits_on_its_cell_centre():
    """Squares of 2 for level 1, circles of 4 for level 2: 4×4 cells; the square's box cell
    (1, 1) lands on the cell's (2, 2), as the circle's (2, 2) does."""
    expected = grid("""
        . . . . . 2 2 .
        . 1 1 . 2 2 2 2
        . 1 1 . 2 2 2 2
        . . . . . 2 2 .
        . 2 2 . . . . .
        2 2 2 2 . 1 1 .
        2 2 2 2 . 1 1 .
        . 2 2 . . . . .""")
    action = RenderGrains("square", 2, level_grains="2: circle 4")
    assert action.grain_lattice() == gr.Lattice(4, 4)
    assert action.canvas_shape((2, 2)) == (8, 8)
    assert np.array_equal(action.render(T), expected)


def test_levels_not_listed_keep_the_texture_grain():
    t = grid("1 2 3")
    picture = gr.render(t, "square", 3, level_grains="3: diamond 3")
    assert (picture[:, 0:6] == np.repeat([1, 2], 3)).all()         # squares for 1 and 2
    assert np.array_equal(picture[:, 6:] == 3, grain_mask("diamond", 3))


def test_no_table_is_the_old_rendering_bit_for_bit():
    t = np.random.default_rng(2).integers(0, 4, (9, 7), dtype=np.uint8)
    for shape, size in (("hexagon", 6), ("circle", 5), ("square", 2)):
        old = gr.render_grains(t, grain_mask(shape, size), RenderGrains(shape, size)
                               .grain_lattice())
        for table in (None, "", f"2: {shape} {size}"):
            assert np.array_equal(RenderGrains(shape, size, level_grains=table).render(t), old)


def test_overlap_rules_apply_across_primitives():
    """Squares of 2 for level 1 and of 4 for level 2 make 4×4 cells; compressed by half, the
    pitch is 2 and the level-2 square (columns 1..4) overlaps both its neighbours."""
    t = grid("1 2 1")
    rows = {overlap: RenderGrains("square", 2, compression=0.5, overlap=overlap,
                                  level_grains="2: square 4").render(t)
            for overlap in gr.OVERLAP_RULES}
    assert all(p.shape == (2, 6) and (p[0] == p[1]).all() for p in rows.values())
    assert rows["last"][0].tolist() == [1, 2, 2, 2, 1, 1]      # scan order: the last 1 wins
    assert rows["max"][0].tolist() == [1, 2, 2, 2, 2, 1]
    assert rows["min"][0].tolist() == [1, 1, 2, 2, 1, 1]


def test_a_replayed_step_with_level_grains_gives_the_same_picture():
    log = [NewCanvas(3, 2, 4), SetLevels(0, 0, 1, 2, 1), SetLevels(1, 1, 1, 2, 3),
           RenderGrains("circle", 5, level_grains="1: hexagon 6, 3: line 5 angle=45")]
    a, b = replay(log, {}), replay(log, {})
    assert np.array_equal(a.levels, b.levels) and a.levels.shape == log[-1].canvas_shape((2, 3))
    assert set(np.unique(a.levels)) == {0, 1, 3}


@pytest.mark.parametrize("table, message", [
    ("0: circle 3", "background"), ("1: circle 3, 1: square 2", "each once"),
    ("2 circle 3", "level: shape size"), ("2: blob 3", "shape"), ("2: circle 65", "at most 64"),
    ("16: circle 3", "1..15"), ("2: circle 3 colour=red", "key=value")])
def test_bad_tables_are_refused_with_what_to_change(table, message):
    with pytest.raises(InputError, match=message):
        RenderGrains("square", 3, level_grains=table)


def reference(levels, masks, lattice):
    """The definition of a per-level rendering, one pixel at a time (overlap 'last')."""
    oh, ow = lattice.shape(levels.shape)
    out = np.zeros((oh, ow), np.uint8)
    for r in range(levels.shape[0]):
        for c in range(levels.shape[1]):
            v = int(levels[r, c])
            if v == 0:
                continue
            mask = masks[v]
            top = r * lattice.pitch_y + lattice.pitch_y // 2 - mask.shape[0] // 2
            left = c * lattice.pitch_x + (lattice.row_offset if r % 2 else 0) \
                + lattice.pitch_x // 2 - mask.shape[1] // 2
            for y, x in zip(*np.nonzero(mask)):
                out[(top + y) % oh, (left + x) % ow] = v
    return out


SHAPES = st.sampled_from(["square", "circle", "hexagon", "diamond", "line"])


@PROPERTY
@given(levels=st.lists(st.integers(0, 3), min_size=12, max_size=12).map(
           lambda v: np.array(v, np.uint8).reshape(3, 4)),
       shapes=st.lists(SHAPES, min_size=3, max_size=3),
       sizes=st.lists(st.integers(1, 7), min_size=3, max_size=3),
       comp=st.sampled_from([0.0, 0.4]))
def test_kernel_matches_the_definition_with_a_grain_per_level(levels, shapes, sizes, comp):
    table = ", ".join(f"{v}: {s} {n}" for v, s, n in zip((1, 2, 3), shapes, sizes))
    action = RenderGrains("square", 3, compression=comp, level_grains=table)
    masks = {v: grain_mask(s, n) for v, s, n in zip((1, 2, 3), shapes, sizes)}
    assert np.array_equal(action.render(levels),
                          reference(levels, masks, action.grain_lattice()))
