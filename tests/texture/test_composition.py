"""Composition of textures (issue 9, thesis §5.4.1): truth tables of every operator on tiny
inputs, weights, negation, incrustation with two and N textures, level conversion and tiling."""

import numpy as np
import pytest

from texeditor.texture import composition as cp
from texeditor.errors import InputError

X2, Y2 = np.array([[0, 0, 1, 1]]), np.array([[0, 1, 0, 1]])        # every pair, G = 2
X4, Y4 = np.meshgrid(np.arange(4), np.arange(4), indexing="ij")      # every pair, G = 4

TRUTH_G2 = {            # T3 for (x, y) = (0,0) (0,1) (1,0) (1,1): the truth tables of logic
    "and": [0, 0, 0, 1], "or": [0, 1, 1, 1], "xor": [0, 1, 1, 0], "min": [0, 0, 0, 1],
    "max": [0, 1, 1, 1], "add": [0, 1, 1, 1], "multiply": [0, 0, 0, 1], "replace": [0, 1, 1, 1],
}

TABLES_G4 = {           # row x, column y, G = 4 (codes 0..3)
    "and": [[0, 0, 0, 0], [0, 1, 0, 1], [0, 0, 2, 2], [0, 1, 2, 3]],
    "or": [[0, 1, 2, 3], [1, 1, 3, 3], [2, 3, 2, 3], [3, 3, 3, 3]],
    "xor": [[0, 1, 2, 3], [1, 0, 3, 2], [2, 3, 0, 1], [3, 2, 1, 0]],
    "min": [[0, 0, 0, 0], [0, 1, 1, 1], [0, 1, 2, 2], [0, 1, 2, 3]],
    "max": [[0, 1, 2, 3], [1, 1, 2, 3], [2, 2, 2, 3], [3, 3, 3, 3]],
    "add": [[0, 1, 2, 3], [1, 2, 3, 3], [2, 3, 3, 3], [3, 3, 3, 3]],
    "multiply": [[0, 0, 0, 0], [0, 0, 1, 1], [0, 1, 1, 2], [0, 1, 2, 3]],   # x·y/3, half up
    "replace": [[0, 1, 2, 3], [1, 1, 2, 3], [2, 1, 2, 3], [3, 1, 2, 3]],    # y over x
}


def test_every_operator_has_tables():
    assert set(TRUTH_G2) == set(TABLES_G4) == set(cp.OPS)


@pytest.mark.parametrize("op", cp.OPS)
def test_truth_table_on_two_levels(op):
    assert cp.mix(X2, Y2, levels=2, op2=op).tolist() == [TRUTH_G2[op]]


@pytest.mark.parametrize("op", cp.OPS)
def test_table_on_four_levels(op):
    assert cp.mix(X4, Y4, levels=4, op2=op).tolist() == TABLES_G4[op]


@pytest.mark.parametrize("op", cp.OPS)
def test_negation_is_the_complement_of_the_bracket(op):
    assert cp.mix(X4, Y4, levels=4, op2=op, negate=True).tolist() == \
        (3 - np.array(TABLES_G4[op])).tolist()
    assert cp.mix(X2, Y2, levels=2, op2=op, negate=True).tolist() == \
        [[1 - v for v in TRUTH_G2[op]]]


@pytest.mark.parametrize("op", cp.OPS)
def test_op4_with_the_constant_c(op):
    """[T1] op4 c, with c the top level (1) and the background (0)."""
    x = np.arange(4)[None]
    top = cp.mix(x, np.zeros_like(x), levels=4, op4=op, c=1.0)
    assert top.tolist() == [[TABLES_G4[op][v][3] for v in range(4)]]
    none = cp.mix(x, np.zeros_like(x), levels=4, op4=op, c=0.0)
    assert none.tolist() == [[TABLES_G4[op][v][0] for v in range(4)]]


def test_bitwise_results_beyond_the_top_level_are_clipped():
    """G = 3: 1 xor 2 = 3 and 1 or 2 = 3 do not exist; they become the top level 2."""
    one, two = np.array([[1]]), np.array([[2]])
    assert cp.mix(one, two, levels=3, op2="xor").item() == 2
    assert cp.mix(one, two, levels=3, op2="or").item() == 2
    assert cp.mix(one, two, levels=3, op2="and").item() == 0


def test_weights_set_the_proportions():
    """(½ × T1) add (½ × T2): the mean of the two greys, rounded half up."""
    t1, t2 = np.array([[0, 2, 2, 1, 0]]), np.array([[0, 0, 1, 1, 2]])
    out = cp.mix(t1, t2, levels=3, a=0.5, op1="multiply", op2="add", b=0.5, op3="multiply")
    assert out.tolist() == [[0, 1, 2, 1, 1]]
    only_t2 = cp.mix(t1, t2, levels=3, a=0.0, op2="add")
    assert only_t2.tolist() == t2.tolist()


def test_weight_with_a_logical_operator_masks_bits():
    """a = 2/3 on G = 4 is code 2 (binary 10): a and T1 keeps T1's high bit."""
    out = cp.mix(np.arange(4)[None], np.zeros((1, 4), int), levels=4, a=2 / 3, op1="and")
    assert out.tolist() == [[0, 0, 2, 2]]


def test_textures_of_different_g_mix_on_the_grey_scale():
    t1 = np.array([[0, 1, 1]])           # G = 2: black, white, white
    t2 = np.array([[3, 0, 2]])           # G = 4
    out = cp.mix(t1, t2, levels=8, levels1=2, levels2=4, op2="min")
    assert out.tolist() == [[0, 0, 5]]   # min(1, 2/3) = 2/3 → 4.67 → 5 of 0..7


def test_the_formula_in_full():
    """T3 = not[(a op1 T1) op2 (b op3 T2)] op4 c, checked point by point against its definition."""
    rng = np.random.default_rng(0)
    t1, t2 = rng.integers(0, 4, (5, 7)), rng.integers(0, 4, (5, 7))
    out = cp.mix(t1, t2, levels=4, a=1.0, op1="xor", op2="max", b=1 / 3, op3="or",
                 negate=True, op4="add", c=1 / 3)
    expect = np.minimum((3 - np.maximum(t1 ^ 3, t2 | 1)) + 1, 3)
    assert np.array_equal(out, expect)


def test_mix_table_is_indexed_by_levels():
    table = cp.mix_table(2, 4, 4, op2="max")
    assert table.shape == (2, 4) and table.tolist() == [[0, 1, 2, 3], [3, 3, 3, 3]]


def test_mix_errors():
    with pytest.raises(InputError, match="unknown operator"):
        cp.mix(X2, Y2, levels=2, op2="nand")
    with pytest.raises(InputError, match="weight a"):
        cp.mix(X2, Y2, levels=2, a=1.5)
    with pytest.raises(InputError, match="same shape"):
        cp.mix(X2, Y2.T, levels=2)
    with pytest.raises(InputError, match="levels outside"):
        cp.mix(X4, Y4, levels=2)


# -- incrustation ----------------------------------------------------------------------------------

def test_incrustation_with_a_boolean_is_if_then_else():
    t1, t2 = np.full((2, 3), 1), np.full((2, 3), 2)
    inside = np.array([[True, False, True], [False, False, True]])
    assert cp.incrust(inside, [t2, t1]).tolist() == [[1, 2, 1], [2, 2, 1]]   # if bool then T1


def test_incrustation_of_n_textures():
    sources = [np.full((2, 3), k + 1) for k in range(3)]
    membership = np.array([[0, 1, 2], [2, 1, 0]])
    assert cp.incrust(membership, sources).tolist() == [[1, 2, 3], [3, 2, 1]]


def test_incrustation_errors():
    with pytest.raises(InputError, match="only 2"):
        cp.incrust(np.array([[0, 2]]), [np.zeros((1, 2)), np.ones((1, 2))])
    with pytest.raises(InputError, match="shape"):
        cp.incrust(np.array([[0, 1]]), [np.zeros((1, 3)), np.ones((1, 2))])


def test_membership_from_levels_and_points():
    m = np.array([[0, 1, 2], [3, 1, 0]])
    assert cp.membership_from_levels(m, cp.parse_level_set("1,3")).tolist() == \
        [[False, True, False], [True, True, False]]
    assert cp.membership_from_points([(0, 2), (1, 0), (5, 5), (-1, 0)], (2, 3)).tolist() == \
        [[False, False, True], [True, False, False]]


def test_level_sets():
    assert cp.parse_level_set("1,3-5") == {1, 3, 4, 5}
    assert cp.parse_level_set(" 0 , 2 ") == {0, 2}
    assert cp.parse_level_set("") == set()
    for bad in ("1-", "a", "3-1", "16"):
        with pytest.raises(InputError):
            cp.parse_level_set(bad)


# -- bringing sources to the canvas ---------------------------------------------------------------

def test_fit_repeats_a_small_texture_and_crops_a_large_one():
    t = np.array([[1, 2], [3, 4]])
    assert cp.fit(t, (3, 5)).tolist() == [[1, 2, 1, 2, 1], [3, 4, 3, 4, 3], [1, 2, 1, 2, 1]]
    assert cp.fit(t, (1, 1)).tolist() == [[1]]


def test_convert_levels_keeps_the_greys():
    assert cp.convert_levels(np.arange(4), 4, 8).tolist() == [0, 2, 5, 7]
    assert cp.convert_levels(np.arange(8), 8, 2).tolist() == [0, 0, 0, 0, 1, 1, 1, 1]
    assert cp.convert_levels(np.arange(3), 3, 3).tolist() == [0, 1, 2]


# -- incrustation by blocks (pavés, issue 21 item 9) ---------------------------------------------

def test_a_mask_texture_at_block_scale_gives_each_of_its_points_a_block():
    diagonal = np.array([[1, 0], [0, 1]])
    assert cp.pave(diagonal, 2, (4, 4)).tolist() == [[1, 1, 0, 0], [1, 1, 0, 0],
                                                    [0, 0, 1, 1], [0, 0, 1, 1]]
    # blocks of 3 on 4×5: the last row and the last two columns are blocks cut by the edge
    assert cp.pave(diagonal, 3, (4, 5)).tolist() == [[1, 1, 1, 0, 0], [1, 1, 1, 0, 0],
                                                    [1, 1, 1, 0, 0], [0, 0, 0, 1, 1]]
    # a mask smaller than the grid of blocks is repeated, as any source is
    assert cp.pave(np.array([[2, 0]]), 1, (2, 3)).tolist() == [[2, 0, 2], [2, 0, 2]]
    assert cp.pave(np.array([[2, 0]]), 2, (4, 8))[:, ::2].tolist() == [[2, 0, 2, 0]] * 4


def test_a_point_mask_by_blocks_holds_where_half_a_block_does():
    painted = cp.membership_from_points([(0, 0), (1, 1), (2, 2), (4, 4)], (5, 5))
    # blocks of 2: (0,0) has 2 of its 4 points, (1,1) 1 of 4, the corner block (2,2) 1 of 1
    assert cp.by_blocks(painted, 2).astype(int).tolist() == [
        [1, 1, 0, 0, 0], [1, 1, 0, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 0, 1]]
    assert np.array_equal(cp.by_blocks(painted, 1), painted)
    with pytest.raises(InputError, match="block"):
        cp.by_blocks(painted, 0)


# -- an expression over N textures (issue 21 item 9) ------------------------------------------------

def test_three_textures_averaged_on_the_grey_scale():
    """(0.34·T1) + (0.33·T2) + (0.33·T3) of black/white textures on G = 4: the share of white,
    0, 0.34, 0.67, 0.66, 1, gives levels floor(3·x + 1/2) = 0, 1, 2, 2, 3. T3 has G = 2: its
    white is 1 on its own scale."""
    t1, t2 = np.array([[0, 3, 3, 0, 3]]), np.array([[0, 0, 3, 3, 3]])
    t3 = np.array([[0, 0, 0, 1, 1]])
    out = cp.evaluate("(0.34 multiply T1) add (0.33 multiply T2) add (0.33 multiply T3)",
                      [(t1, 4), (t2, 4), (t3, 2)], 4)
    assert out.tolist() == [[0, 1, 2, 2, 3]]


def test_four_textures_under_logic_and_brackets():
    bits = [np.array([[0, 1, 0, 1, 0, 1, 0, 1]]), np.array([[0, 0, 1, 1, 0, 0, 1, 1]]),
            np.array([[0, 0, 0, 0, 1, 1, 1, 1]]), np.array([[1, 1, 1, 1, 1, 1, 1, 0]])]
    ts = [(b, 2) for b in bits]
    parity = bits[0] ^ bits[1] ^ bits[2]
    assert np.array_equal(cp.evaluate("T1 xor T2 xor T3 and T4", ts, 2), parity & bits[3])
    # left to right unless grouped: T1 or (T2 and T3) is not (T1 or T2) and T3
    grouped = cp.evaluate("T1 or (T2 and T3) max (0 multiply T4)", ts, 2)
    assert np.array_equal(grouped, bits[0] | (bits[1] & bits[2]))
    assert np.array_equal(cp.evaluate("not [T1 max T2 max T3] min T4", ts, 2),
                          (1 - (bits[0] | bits[1] | bits[2])) & bits[3])


def test_the_thesis_formula_as_an_expression_gives_the_two_texture_mix():
    ops = dict(a=0.5, op1="multiply", op2="max", b=1.0, op3="and", negate=True, op4="add",
               c=0.25)
    expected = cp.mix(X4, Y4, levels=4, **ops)
    text = "not[(0.5 multiply T1) max (1 and T2)] add 0.25"
    assert np.array_equal(cp.evaluate(text, [(X4, 4), (Y4, 4)], 4), expected)


@pytest.mark.parametrize("text, n, message", [
    ("", 3, "empty"), ("T1 max T2", 3, "does not use T3"), ("T1 max T4", 3, "names T4"),
    ("T1 max", 1, "ends where"), ("(T1 max T2", 2, "not closed"), ("[T1 max T2)", 2, "not closed"),
    ("T1 T2", 2, "goes on after its end"), ("T1 nand T2", 2, "unknown operator"),
    ("T1 max 1.5", 1, "outside 0..1"), ("T1 + T2", 2, "neither a texture"),
    ("T1 max " + "(" * 40 + "T2" + ")" * 40, 2, "nests more than"),
    ("T1 max T2 " * 200, 2, "longer than"),
])
def test_bad_expressions_say_what_is_wrong(text, n, message):
    with pytest.raises(InputError, match=message):
        cp.parse_expression(text, n)


def test_expression_inputs_are_checked():
    with pytest.raises(InputError, match="same shape"):
        cp.evaluate("T1 max T2", [(X2, 2), (Y2.T, 2)], 2)
    with pytest.raises(InputError, match="levels outside"):
        cp.evaluate("T1 max T2", [(X4, 2), (Y4, 4)], 4)


def _evaluated_whole(text, textures, levels):
    """An expression as every release before evaluated it: each texture's greys over the
    whole canvas at once (float64), then the tree, then the levels."""
    tree = cp.parse_expression(text, len(textures))
    greys = [cp.to_scale(t, g) for t, g in textures]
    return cp.from_scale(np.broadcast_to(cp._value(tree, greys, levels),
                                         np.shape(textures[0][0])), levels)


EXPRESSIONS = ["T1 and T2 or T3", "not[(0.5 multiply T1) max T2] min (T3 xor 0.75)",
               "T1 replace T2 add (0.3 multiply T3)", "(0.34 multiply T1) add (0.33 multiply T2) "
               "add (0.33 multiply T3)", "T3 multiply not T1 min T2", "T1 xor T2 xor T3 add 0.1"]


@pytest.mark.parametrize("band", [1, 5, 64, 2**18])
def test_an_expression_evaluated_band_by_band_gives_the_whole_canvas_bit_for_bit(monkeypatch,
                                                                                  band):
    """Eight float64 copies of a 2^26-point canvas took 4 GiB: the expression is evaluated a
    band of rows at a time, every operator point by point, so the levels are the same."""
    monkeypatch.setattr(cp, "BAND_POINTS", band)
    rng = np.random.default_rng(band)
    for shape in [(37, 23), (1, 50), (50, 1), (9, 200), (0, 4), (3,), ()]:
        for text in EXPRESSIONS:
            gs = [int(g) for g in rng.integers(2, 17, 3)]
            textures = [(rng.integers(0, g, shape), g) for g in gs]
            for levels in (2, 7, 16):
                out = cp.evaluate(text, textures, levels)
                expected = _evaluated_whole(text, textures, levels)
                assert out.dtype == expected.dtype == np.uint8
                np.testing.assert_array_equal(out, expected, err_msg=f"{shape} {text}")


@pytest.mark.parametrize("band", [1, 7, 2**18])
def test_textures_fitted_band_by_band_mix_as_their_fitted_copies(monkeypatch, band):
    """mix_textures repeats or crops each Ti to the canvas: ``evaluate_fitted`` takes the rows
    of each a band needs, never the whole copies, and gives what evaluate gives of the copies;
    a level out of range is an error only where fit() keeps it."""
    monkeypatch.setattr(cp, "BAND_POINTS", band)
    rng = np.random.default_rng(band)
    shape = (23, 31)
    sources = [rng.integers(0, 3, (1, 1)), rng.integers(0, 2, (2, 40)),
               rng.integers(0, 16, (50, 9)).astype(np.uint8), rng.integers(0, 4, shape),
               rng.integers(0, 5, (23, 7)).astype(np.int16), rng.integers(0, 2, (30, 31))]
    gs = [3, 2, 16, 4, 5, 2]
    textures = [(rng.integers(0, 8, shape).astype(np.uint8), 8)] + list(zip(sources, gs))
    for text in ["T1 add T2 add T3 add T4 add T5 add T6 add T7",
                 "not[T1 xor T2] or (T3 max T4) multiply T5 replace T6 min T7",
                 "T7 replace T6 replace T5 min T4 and T3 or T2 xor T1"]:
        for levels in (2, 8, 16):
            fitted = [(cp.fit(t, shape), g) for t, g in textures]
            np.testing.assert_array_equal(cp.evaluate_fitted(text, textures, levels, shape),
                                          _evaluated_whole(text, fitted, levels))
    cropped = np.zeros((30, 40), np.uint8)
    cropped[23:, :] = cropped[:, 31:] = 9           # out of range for G = 2, but cropped away
    assert cp.evaluate_fitted("T1 max T2", [(textures[0][0], 8), (cropped, 2)], 8,
                              shape).tolist() == textures[0][0].tolist()
    cropped[22, 30] = 2
    with pytest.raises(InputError, match=r"T2 holds levels outside 0\.\.1"):
        cp.evaluate_fitted("T1 max T2", [(textures[0][0], 8), (cropped, 2)], 8, shape)
    with pytest.raises(InputError, match="does not use T2"):
        cp.evaluate_fitted("T1 max T1", [(textures[0][0], 8), (cropped, 2)], 8, shape)


def test_an_expression_never_holds_the_canvas_in_float():
    """Eight textures on a 2048×1024 canvas: their float64 greys were 16 MiB each, 128 MiB
    before the operators' own temporaries; now a band's greys and temporaries (about 40 MiB)."""
    import tracemalloc
    rng = np.random.default_rng(1)
    textures = [(rng.integers(0, 4, (1024, 2048)).astype(np.uint8), 4) for _ in range(8)]
    text = " add ".join(f"(0.1 multiply T{k})" for k in range(1, 9))
    tracemalloc.start()
    try:
        out = cp.evaluate(text, textures, 16)
        fitted = cp.evaluate_fitted(text, [textures[0]] + [(np.eye(3, dtype=np.uint8), 2)] * 7,
                                    16, (1024, 2048))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert out.shape == fitted.shape == (1024, 2048)
    assert peak < 48 * 2**20
