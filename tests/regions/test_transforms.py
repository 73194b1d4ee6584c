"""Global operators of thesis §3.4.3 (identity, isometry, similarity, affinity): exact small grids,
nearest-neighbour and wrap-around properties (issue 5)."""

import doctest

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY
from tests.support.regions import grid, grids, same
from texeditor.regions import transforms
from texeditor.errors import InputError
from texeditor.regions.extractext import shift_mask
from texeditor.regions.transforms import (affinity, identity, isometry, rotation_matrix, selection_centre,
                                  similarity, transform_mask, warp)

G = grid("""
    1 2 . . . .
    3 4 . . . .
    . . . . . .
    . . . . . 5
""")
G.flags.writeable = False


def test_the_docstring_examples_hold():
    assert doctest.testmod(transforms, optionflags=doctest.NORMALIZE_WHITESPACE).failed == 0


def test_rotation_matrices_of_quarter_turns_are_exact():
    assert rotation_matrix(0) == ((1, 0), (0, 1))
    assert rotation_matrix(90) == rotation_matrix(450) == rotation_matrix(-270) == ((0, -1), (1, 0))
    assert rotation_matrix(180) == ((-1, 0), (0, -1))
    (c, s), _ = rotation_matrix(30)
    assert c == round(np.cos(np.pi / 6), 12) and s == -0.5


# -- identity ------------------------------------------------------------------------------------

def test_identity_duplicates_a_selection():
    motif = G > 0
    motif[3, 5] = False
    assert same(identity(G, (2, 3), mask=motif), """
        1 2 . . . .
        3 4 . . . .
        . . . 1 2 .
        . . . 3 4 5""")


def test_identity_grid_repeats_with_the_box_as_default_step():
    motif = (G > 0) & (G < 5)
    assert same(identity(G, (0, 2), mask=motif, repeat=(2, 2)), """
        1 2 1 2 1 2
        3 4 3 4 3 4
        . . 1 2 1 2
        . . 3 4 3 4""")
    assert same(identity(G, (1, 1), mask=motif, repeat=(1, 3), step=(5, 2)), """
        1 2 . . . .
        3 1 2 1 2 1
        . 3 4 3 4 3
        . . . . . 5""")


def test_identity_copies_read_the_texture_as_it_was():
    line = grid("1 2 . . . .")
    assert same(identity(line, (0, 1), mask=line > 0, repeat=(1, 3), step=(0, 1)), "1 1 1 1 2 .")


def test_identity_partly_off_the_canvas_and_with_wrap():
    corner = G == 5
    assert not (identity(G, (1, 0), mask=corner) != G).any()          # wholly off: nothing
    wrapped = identity(G, (1, 1), mask=corner, wrap=True)
    assert wrapped[0, 0] == 5 and (wrapped != G).sum() == 1
    assert np.array_equal(identity(G, (1, 2), wrap=True), np.roll(G, (1, 2), axis=(0, 1)))
    band = identity(G, (0, 2))                         # the whole texture, no wrap: a band stays
    assert np.array_equal(band[:, 2:], G[:, :-2]) and np.array_equal(band[:, :2], G[:, :2])


def test_identity_refuses_an_empty_grid():
    with pytest.raises(InputError, match="repeat"):
        identity(G, (0, 1), repeat=(0, 1))


# -- isometry, similarity, affinity --------------------------------------------------------------

@pytest.mark.parametrize("n", [4, 5])
def test_quarter_turns_of_a_square_about_its_centre_are_exact(n):
    square = np.arange(n * n, dtype=np.uint8).reshape(n, n)
    c = ((n - 1) / 2, (n - 1) / 2)
    for k in range(4):
        assert np.array_equal(isometry(square, 90 * k, c), np.rot90(square, k))
    assert np.array_equal(isometry(square, -90, c, wrap=True), np.rot90(square, -1))


def test_isometry_of_a_rectangle_leaves_background_where_nothing_lands():
    out = isometry(G, 90, (1.5, 2.5), fill=7)      # 1, 3 and 5 turn off the canvas
    assert same(out, """
        7 . . . . 7
        7 . . . . 7
        7 . . . . 7
        7 2 4 . . 7""")
    kept = isometry(G, 90, (1.5, 2.5), keep_source=True)
    assert np.array_equal(kept[:, [0, 5]], G[:, [0, 5]])


def test_isometry_of_a_selection_about_a_point():
    motif = (G > 0) & (G < 5)
    out = isometry(G, 180, (0.5, 2), mask=motif)
    assert same(out, """
        . . . 4 3 .
        . . . 2 1 .
        . . . . . .
        . . . . . 5""")
    dup = isometry(G, 180, (0.5, 2), mask=motif, keep_source=True)
    assert np.array_equal(dup[:2, :2], G[:2, :2]) and np.array_equal(dup[:2, 3:5], out[:2, 3:5])


def test_similarity_zooms_about_a_point():
    out = similarity(G, 2, (-0.5, -0.5), mask=(G > 0) & (G < 5))
    assert same(out, """
        1 1 2 2 . .
        1 1 2 2 . .
        3 3 4 4 . .
        3 3 4 4 . 5""")
    small = similarity(out, 0.5, (-0.5, -0.5))
    assert np.array_equal(small[:2, :2], G[:2, :2]) and not small[2:].any()


def test_similarity_below_one_with_wrap_repeats_the_texture():
    tex = np.arange(64, dtype=np.uint8).reshape(8, 8)
    out = similarity(tex, 0.5, (-0.5, -0.5), wrap=True)
    assert np.array_equal(out[:4, :4], tex[1::2, 1::2])      # ties round half up
    assert np.array_equal(out, np.tile(out[:4, :4], (2, 2)))


def test_affinity_shear_and_flip():
    col = np.zeros((3, 5), np.uint8)
    col[:, 1] = [1, 2, 3]
    assert same(affinity(col, ((1, 0), (1, 1))), """
        . 1 . . .
        . . 2 . .
        . . . 3 .""")
    assert same(affinity(col, ((1, 0), (1, 1)), (2, 0), wrap=True), """
        . . . . 1
        2 . . . .
        . 3 . . .""")
    assert np.array_equal(affinity(G, ((1, 0), (0, -1)), (0, 2.5)), G[:, ::-1])
    assert np.array_equal(affinity(G, ((1, 0), (0, 1)), offset=(1, 0)), np.vstack([[0] * 6, G[:3]]))


@pytest.mark.parametrize("call, message", [
    (lambda: affinity(G, ((1, 2), (2, 4))), "singular"),
    (lambda: affinity(G, ((1, 0), (0, float("nan")))), "finite"),
    (lambda: affinity(G, ((1, 0, 0), (0, 1, 0))), "2×2 matrix"),
    (lambda: similarity(G, 0, (0, 0)), "positive"),
    (lambda: similarity(G, "big", (0, 0)), "number"),
    (lambda: isometry(G, float("inf"), (0, 0)), "finite"),
    (lambda: isometry(G, 30, (0, 0), fill=300), "not a level"),
    (lambda: isometry(G, 30, (0, None)), "two numbers"),
    (lambda: warp(G, ((1, 0), (0, 1)), mask=np.ones((2, 2), bool)), "shape"),
    (lambda: similarity(G, 1e6, (0, 0), mask=G > 0, wrap=True), "smaller factor"),
    (lambda: selection_centre(np.zeros((2, 2), bool)), "empty"),
])
def test_bad_maps_are_input_errors(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_transform_mask_is_where_the_selection_lands():
    motif = (G > 0) & (G < 5)
    landed = transform_mask(motif, ((1, 0), (0, 1)), offset=(2, 3))
    assert np.array_equal(landed, shift_mask(motif, (2, 3)))
    turned = transform_mask(motif, rotation_matrix(90), centre=(0.5, 0.5))
    assert np.array_equal(turned, motif)
    assert not transform_mask(np.zeros((3, 3), bool), ((2, 0), (0, 2))).any()


def test_wrapped_folds_of_a_big_zoom_are_deterministic():
    motif = (G > 0) & (G < 5)
    a = similarity(G, 5, (0.5, 0.5), mask=motif, wrap=True)
    b = similarity(G, 5, (0.5, 0.5), mask=motif, wrap=True)
    assert np.array_equal(a, b) and set(np.unique(a)) <= {1, 2, 3, 4}


# -- properties ----------------------------------------------------------------------------------

maps = st.one_of(
    st.builds(rotation_matrix, st.floats(-360, 360)),
    st.tuples(st.floats(0.3, 3), st.floats(0.3, 3)).map(lambda f: ((f[0], 0.0), (0.0, f[1]))),
    st.tuples(st.floats(-2, 2), st.floats(-2, 2)).map(lambda s: ((1.0, s[0]), (s[1], 1.0))),
).filter(lambda m: abs(m[0][0] * m[1][1] - m[0][1] * m[1][0]) > 0.05)


@PROPERTY
@given(grids(), st.integers(-12, 12), st.integers(-12, 12), st.booleans())
def test_identity_then_its_inverse_offset_restores_the_untouched_original(g, dr, dc, wrap):
    back = identity(identity(g, (dr, dc), wrap=wrap), (-dr, -dc), wrap=wrap)
    if wrap:
        assert np.array_equal(back, g)
    else:
        h, w = g.shape
        rows, cols = np.ogrid[:h, :w]
        kept = (rows + dr >= 0) & (rows + dr < h) & (cols + dc >= 0) & (cols + dc < w)
        assert np.array_equal(back[kept], g[kept])


@PROPERTY
@given(grids(), st.data())
def test_an_identity_grid_writes_only_its_copies_and_each_copy_shifts_back(g, data):
    mask = data.draw(st.lists(st.booleans(), min_size=g.size, max_size=g.size))
    mask = np.array(mask).reshape(g.shape)
    offset = (data.draw(st.integers(-6, 6)), data.draw(st.integers(-6, 6)))
    repeat = (data.draw(st.integers(1, 3)), data.draw(st.integers(1, 3)))
    step = (data.draw(st.integers(-4, 4)), data.draw(st.integers(-4, 4)))
    wrap = data.draw(st.booleans())
    out = identity(g, offset, mask=mask, repeat=repeat, step=step, wrap=wrap)
    copies = [(offset[0] + i * step[0], offset[1] + j * step[1])
              for i in range(repeat[0]) for j in range(repeat[1])]
    touched = np.zeros_like(mask)
    for o in copies:
        touched |= shift_mask(mask, o, wrap=wrap)
    assert np.array_equal(out[~touched], g[~touched])       # untouched points keep their level
    last = copies[-1]                                        # the last copy lies over the others
    landed = shift_mask(mask, last, wrap=wrap)
    back = identity(out, (-last[0], -last[1]), mask=landed, wrap=wrap)
    source = shift_mask(landed, (-last[0], -last[1]), wrap=wrap)
    assert np.array_equal(back[source], g[source])


@PROPERTY
@given(grids(max_side=9), st.integers(-4, 4), st.integers(-4, 4), st.booleans())
def test_four_quarter_turns_of_a_square_restore_it(g, cr, cc, wrap):
    n = min(g.shape)
    square = g[:n, :n]
    centre = ((n - 1) / 2 + cr, (n - 1) / 2 + cc) if wrap else ((n - 1) / 2, (n - 1) / 2)
    out = square
    for _ in range(4):
        out = isometry(out, 90, centre, wrap=wrap)
    assert np.array_equal(out, square)


@PROPERTY
@given(grids(), maps, st.floats(-3, 12), st.floats(-3, 12), st.booleans(), st.integers(0, 9))
def test_levels_stay_levels_and_a_carried_selection_lands_where_transform_mask_says(
        g, matrix, cr, cc, wrap, fill):
    out = warp(g, matrix, centre=(cr, cc), wrap=wrap, fill=fill)
    assert set(np.unique(out)) <= set(np.unique(g)) | {fill}
    mask = g % 2 == 1
    carried = warp(g, matrix, centre=(cr, cc), mask=mask, wrap=wrap, fill=fill)
    landed = transform_mask(mask, matrix, centre=(cr, cc), wrap=wrap)
    assert set(np.unique(carried[landed])) <= set(np.unique(g[mask]))
    assert (carried[mask & ~landed] == fill).all()
    assert np.array_equal(carried[~mask & ~landed], g[~mask & ~landed])


@PROPERTY
@given(grids(max_side=4), st.sampled_from(["turn", "shear", "zoom", "shift"]), st.integers(0, 7),
       st.integers(0, 7))
def test_wrap_keeps_a_tileable_texture_tileable(tile, kind, cr, cc):
    k = min(tile.shape)
    tile = tile[:k, :k]
    texture = np.tile(tile, (2, 2))                        # period k in both directions
    if kind == "turn":
        out = isometry(texture, 90, (cr / 2, cc / 2), wrap=True)
    elif kind == "shear":
        out = affinity(texture, ((1, 0), (1, 1)), (cr, cc), wrap=True)
    elif kind == "zoom":
        out = similarity(texture, 0.5, (cr - 0.5, cc - 0.5), wrap=True)
    else:
        out = identity(texture, (cr, cc), wrap=True)
    assert np.array_equal(out, np.roll(out, k, axis=0))
    assert np.array_equal(out, np.roll(out, k, axis=1))


def _blocks(shape, seed, levels=4, block=5):
    """A random texture of blocks with a few stray points: regions of every size."""
    rng = np.random.default_rng(seed)
    h, w = shape
    coarse = rng.integers(0, levels, (-(-h // block), -(-w // block))).astype(np.uint8)
    out = np.kron(coarse, np.ones((block, block), np.uint8))[:h, :w].copy()
    points = rng.integers(0, [h, w], (h * w // 20 + 1, 2))
    out[points[:, 0], points[:, 1]] = rng.integers(0, levels, len(points))
    return out


@pytest.mark.parametrize("band", [1, 3, 17, 256])
def test_a_selection_carried_band_by_band_lands_as_the_whole_box_did(monkeypatch, band):
    """A carried selection's index arrays over its whole box took 2.5 GB for 2^26 points: the
    box is carried a band of points at a time (and a long row cut). The levels, the landed mask
    and every overlap of folds (last in scan order) are those of the box in one band."""
    cases = []
    for seed in range(6):
        levels = _blocks((23, 31), seed)
        mask = levels == levels[seed, 2 * seed] if seed % 2 else levels > 0   # several levels
        cases.append((levels, mask, ((2, 0), (0, 0.5)), (11.5, 4), (0, 0)))         # scale
        cases.append((levels, mask, rotation_matrix(30 + 50 * seed), (3, 7.5), (1.5, -2)))
        cases.append((levels, mask, ((3.5, 0.4), (-1, 2.7)), (0, 0), (-4, 40)))    # folds
        cases.append((levels, mask, ((0.3, 0), (0, 0.2)), (20, 20), (0.25, 0)))
    results = {}
    for band_points in (2**62, band):
        monkeypatch.setattr(transforms, "BAND_POINTS", band_points)
        results[band_points] = [
            (warp(levels, m, centre=c, offset=o, mask=mask, wrap=wrap, fill=3, keep_source=keep),
             transform_mask(mask, m, centre=c, offset=o, wrap=wrap))
            for levels, mask, m, c, o in cases for wrap in (False, True) for keep in (False, True)]
    for (levels, landed), (whole, whole_landed) in zip(results[band], results[2**62]):
        np.testing.assert_array_equal(levels, whole)
        np.testing.assert_array_equal(landed, whole_landed)


def test_a_carried_selection_never_holds_its_box_of_indices():
    """Half a 2048×1024 canvas zoomed ×2 and folded back (wrap): 298 MiB of index arrays, now
    a band's (the levels themselves are 2 MiB)."""
    import tracemalloc
    levels = np.zeros((1024, 2048), np.uint8)
    levels[:, :1024] = 1
    tracemalloc.start()
    try:
        similarity(levels, 2, (3, 3), mask=levels == 1, wrap=True)
        folded = tracemalloc.get_traced_memory()[1]
        tracemalloc.reset_peak()
        similarity(levels, 2, (3, 3), angle=45, mask=levels == 1)
        turned = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert folded < 120 * 2**20
    assert turned < 60 * 2**20                      # was 84 MiB
