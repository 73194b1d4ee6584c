"""The log optimiser reorders (issue 21, item 10; thesis §5.4.2 "simplifiée et réorganisée"):
the commutation test, hand-made logs where a move enables a merge (the optimised log and its
notes written out), and random logs that must replay bit for bit after optimisation."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tests.support import PROPERTY
from texeditor.recipe.actions import (CropCanvas, NewCanvas, ResizeCanvas, SetLevels,
                                      SetPalette)
from texeditor.recipe.logopt import commute, optimize, optimize_with_notes
from texeditor.recipe.replay import replay
from texeditor.paint.actions import PlaceGrains, Stroke
from texeditor.regions.actions import Fill
from texeditor.spots.actions import DeleteSpot, PlaceSpot, spot_ref
from texeditor.spots.envelope import Envelope

GREY3 = ((0, 0, 0), (128, 128, 128), (255, 255, 255))
RED3 = ((255, 0, 0), (128, 128, 128), (255, 255, 255))
SPOT = Envelope.ellipse(4.0, 3.0, kind="linear").dumps()


def levels_of(log):
    doc = replay(log, {})
    return doc.levels.copy(), doc.palette.copy()


def same_result(one, other) -> bool:
    (a, p), (b, q) = levels_of(one), levels_of(other)
    return a.shape == b.shape and np.array_equal(a, b) and np.array_equal(p, q)


def check(log, expected, notes):
    out = optimize_with_notes(log)
    assert list(out.actions) == expected
    assert list(out.notes) == notes
    assert same_result(expected, log)


# -- the commutation test ---------------------------------------------------------------------------

def test_fills_commute_when_their_rectangles_are_apart():
    assert commute(SetLevels(0, 0, 2, 2, 1), SetLevels(0, 2, 2, 2, 2), (4, 4))
    assert not commute(SetLevels(0, 0, 2, 3, 1), SetLevels(0, 2, 2, 2, 2), (4, 4))
    # the overlap really matters: point (0, 2) ends 2 one way, 1 the other
    one = levels_of([NewCanvas(4, 4, 3), SetLevels(0, 0, 2, 3, 1), SetLevels(0, 2, 2, 2, 2)])[0]
    two = levels_of([NewCanvas(4, 4, 3), SetLevels(0, 2, 2, 2, 2), SetLevels(0, 0, 2, 3, 1)])[0]
    assert one[0, 2] == 2 and two[0, 2] == 1


def test_a_palette_commutes_with_what_does_not_read_the_palette():
    for step in (SetLevels(0, 0, 9, 9, 1), ResizeCanvas(9, 2, 1), CropCanvas(1, 1, 2, 2)):
        assert commute(SetPalette(RED3), step, (4, 4)) and commute(step, SetPalette(RED3), (4, 4))
    assert not commute(SetPalette(RED3), SetPalette(GREY3), (4, 4))


def test_a_resize_commutes_with_a_fill_of_the_points_both_shapes_keep():
    # 4×4 → 6×6 writes rows 4–5 and columns 4–5 (the new points, at fill level 1)
    assert commute(SetLevels(1, 1, 3, 3, 2), ResizeCanvas(6, 6, 1), (4, 4))
    assert commute(ResizeCanvas(6, 6, 1), SetLevels(0, 0, 4, 4, 2), (4, 4))
    assert not commute(ResizeCanvas(6, 6, 1), SetLevels(3, 3, 2, 2, 2), (4, 4))
    # the fill reaching the new points: (4, 4) is 2 when the fill comes last, 1 otherwise
    last = levels_of([NewCanvas(4, 4, 3), ResizeCanvas(6, 6, 1), SetLevels(3, 3, 2, 2, 2)])[0]
    first = levels_of([NewCanvas(4, 4, 3), SetLevels(3, 3, 2, 2, 2), ResizeCanvas(6, 6, 1)])[0]
    assert last[4, 4] == 2 and first[4, 4] == 1
    # a shrink cuts rows and columns 3..: a fill there is lost only if it comes first
    assert not commute(SetLevels(3, 0, 1, 1, 2), ResizeCanvas(3, 3), (4, 4))


def test_a_crop_at_the_corner_removes_points_a_crop_elsewhere_moves_them_all():
    assert commute(CropCanvas(0, 0, 3, 3), SetLevels(1, 1, 2, 2, 2), (4, 4))
    assert not commute(CropCanvas(0, 0, 3, 3), SetLevels(2, 2, 2, 2, 2), (4, 4))
    assert not commute(CropCanvas(1, 1, 3, 3), SetLevels(0, 0, 1, 1, 2), (4, 4))


def test_what_cannot_say_what_it_touches_never_commutes():
    spot = PlaceSpot(SPOT, 1.0, 1.0, level=2)
    for unknown in (spot, Fill(0, 0, 1), DeleteSpot(1, spot_ref(spot)), NewCanvas(4, 4, 3)):
        assert not commute(unknown, SetPalette(RED3), (4, 4))
        assert not commute(SetLevels(3, 3, 1, 1, 1), unknown, (4, 4))
    assert not commute(ResizeCanvas(6, 6), CropCanvas(0, 0, 2, 2), (4, 4))   # two extents
    assert not commute(ResizeCanvas(6, 6), SetLevels(0, 0, 1, 1, 1), None)    # shape unknown
    assert commute(SetPalette(RED3), SetLevels(0, 0, 1, 1, 1), None)         # needs none


PAIR_STEPS = st.one_of(
    st.builds(SetLevels, st.integers(-1, 5), st.integers(-1, 5), st.integers(1, 4),
              st.integers(1, 4), st.integers(0, 2)),
    st.builds(ResizeCanvas, st.integers(1, 7), st.integers(1, 7), st.integers(0, 2)),
    st.builds(CropCanvas, st.integers(0, 2), st.integers(0, 2), st.integers(1, 6),
              st.integers(1, 6)),
    st.sampled_from([SetPalette(RED3), SetPalette(GREY3)]),
    st.builds(lambda pts, lv, size, cloud, seed: Stroke(
        tuple(pts), lv, size, shape="square", distribution="cloud" if cloud else "solid",
        density=0.5, seed=seed), st.lists(st.tuples(st.integers(-2, 7), st.integers(-2, 7)),
                                          min_size=1, max_size=3),
        st.integers(0, 2), st.integers(1, 3), st.booleans(), st.integers(0, 9)),
    st.builds(lambda pts, lv, jitter, seed: PlaceGrains(tuple(pts), lv, "diamond", 3,
                                                        jitter=jitter, seed=seed),
              st.lists(st.tuples(st.integers(-2, 7), st.integers(-2, 7)), min_size=1,
                       max_size=3), st.integers(0, 2), st.sampled_from([0.0, 2.0]),
              st.integers(0, 9)))


@settings(PROPERTY, max_examples=400)
@given(st.integers(2, 6), st.integers(2, 6), st.lists(st.integers(0, 2), min_size=36,
                                                       max_size=36), PAIR_STEPS, PAIR_STEPS)
def test_steps_that_commute_give_the_same_document_in_either_order(h, w, cells, a, b):
    start = [NewCanvas(w, h, 3)] + [SetLevels(k // w, k % w, 1, 1, v)
                                    for k, v in enumerate(cells[:h * w]) if v]
    if commute(a, b, (h, w)):
        assert same_result(start + [a, b], start + [b, a])


# -- hand-made logs: a move enables a merge ----------------------------------------------------------

def test_a_crop_moves_back_to_merge_with_the_crop_before_the_fill():
    log = [NewCanvas(8, 8, 3), CropCanvas(1, 1, 7, 7), SetLevels(1, 1, 1, 1, 2),
           CropCanvas(0, 0, 4, 4)]
    # 8×8 → rows/cols 1..7 → their first four: rows/cols 1..4 of the canvas
    check(log, [NewCanvas(8, 8, 3), CropCanvas(1, 1, 4, 4), SetLevels(1, 1, 1, 1, 2)],
          ["moved step 4 (Crop to 4×4 at (0, 0)) before step 3 so it merges with step 2",
           "merged step 2 (Crop to 7×7 at (1, 1)) and step 4 (Crop to 4×4 at (0, 0)) into one "
           "step: Crop to 4×4 at (1, 1)"])


def test_a_resize_moves_back_across_a_fill_of_the_kept_points():
    log = [NewCanvas(4, 4, 3), ResizeCanvas(6, 6, 1), SetLevels(1, 1, 2, 2, 2),
           ResizeCanvas(8, 8, 1)]
    check(log, [NewCanvas(4, 4, 3), ResizeCanvas(8, 8, 1), SetLevels(1, 1, 2, 2, 2)],
          ["moved step 4 (Resize canvas to 8×8) before step 3 so it merges with step 2",
           "merged step 2 (Resize canvas to 6×6) and step 4 (Resize canvas to 8×8) into one "
           "step: Resize canvas to 8×8"])


def test_two_fills_of_one_level_come_together_and_make_one_rectangle():
    log = [NewCanvas(6, 6, 3), SetLevels(0, 0, 2, 3, 1), SetLevels(4, 4, 1, 1, 2),
           SetLevels(0, 3, 2, 3, 1)]
    check(log, [NewCanvas(6, 6, 3), SetLevels(0, 0, 2, 6, 1), SetLevels(4, 4, 1, 1, 2)],
          ["moved step 4 (Set 3×2 at (0, 3) to 1) before step 3 so it merges with step 2",
           "merged step 2 (Set 3×2 at (0, 0) to 1) and step 4 (Set 3×2 at (0, 3) to 1) into "
           "one step: Set 6×2 at (0, 0) to 1"])


def test_the_earlier_step_moves_forward_when_the_later_cannot_move_back():
    # step 3 overlaps step 4 (at (0, 3)) but not step 2: step 2 goes forward instead
    log = [NewCanvas(6, 6, 3), SetLevels(0, 0, 1, 2, 1), SetLevels(0, 3, 2, 2, 2),
           SetLevels(0, 2, 1, 2, 1)]
    check(log, [NewCanvas(6, 6, 3), SetLevels(0, 3, 2, 2, 2), SetLevels(0, 0, 1, 4, 1)],
          ["moved step 2 (Set 2×1 at (0, 0) to 1) after step 3 so it merges with step 4",
           "merged step 2 (Set 2×1 at (0, 0) to 1) and step 4 (Set 2×1 at (0, 2) to 1) into "
           "one step: Set 4×1 at (0, 0) to 1"])
    expected = np.zeros((6, 6), np.uint8)          # by hand: row 0 is 1 1 1 1 2 0
    expected[0, :4], expected[0, 4], expected[1, 3:5] = 1, 2, 2
    assert np.array_equal(levels_of(log)[0], expected)


def test_a_palette_moves_across_a_canvas_change_and_a_fill_to_the_next_palette():
    log = [NewCanvas(4, 4, 3), SetPalette(RED3), ResizeCanvas(5, 5), SetLevels(0, 0, 1, 1, 2),
           SetPalette(GREY3)]
    check(log, [NewCanvas(4, 4, 3), ResizeCanvas(5, 5), SetLevels(0, 0, 1, 1, 2)],
          ["dropped step 2 (Set palette (3 colours)): step 5 sets the palette again and "
           "nothing between reads it",
           "dropped step 5 (Set palette (3 colours)): it changes nothing here"])


def test_fills_merge_across_a_stroke_and_grains_painted_elsewhere():
    stroke = Stroke(((6, 0), (6, 5)), 2, 1, shape="square", distribution="cloud", density=0.5,
                    seed=3)
    grains = PlaceGrains(((7, 7),), 1, "square", 1, jitter=0.4, seed=1)
    log = [NewCanvas(8, 8, 3), SetLevels(0, 0, 2, 2, 1), stroke, grains, SetLevels(0, 2, 2, 2, 1)]
    out = optimize(log)
    assert out == [NewCanvas(8, 8, 3), SetLevels(0, 0, 2, 4, 1), stroke, grains]
    assert same_result(out, log)
    # a stroke over both rectangles: neither moves across it
    near = Stroke(((1, 1), (1, 3)), 2, 1, shape="square")
    assert len(optimize(log[:2] + [near] + log[4:])) == 4
    # a wrapping stroke may land anywhere: it cannot say
    assert Stroke(((0, 0),), 1, wrap=True).access((8, 8)) is None


def test_nothing_moves_across_a_step_that_cannot_say_what_it_touches():
    blocked = [NewCanvas(6, 6, 3), SetLevels(0, 0, 2, 3, 1), Fill(5, 5, 2),
               SetLevels(0, 3, 2, 3, 1)]
    check(blocked, blocked, [])
    palettes = [NewCanvas(6, 6, 3), SetPalette(RED3), PlaceSpot(SPOT, 3.0, 3.0, level=2),
                SetPalette(RED3[::-1])]
    check(palettes, palettes, [])
    overlapping = [NewCanvas(6, 6, 3), SetLevels(0, 0, 2, 3, 1), SetLevels(0, 2, 2, 2, 2),
                   SetLevels(0, 3, 2, 3, 1)]
    check(overlapping, overlapping, [])


def test_drops_say_why():
    log = [NewCanvas(4, 4, 3), SetLevels(0, 0, 2, 2, 1), SetLevels(9, 9, 1, 1, 1),
           NewCanvas(3, 3, 2)]
    check(log, [NewCanvas(3, 3, 2)],
          ["dropped step 1 (New canvas 4×4, G = 3): step 4 (New canvas 3×3, G = 2) starts "
           "afresh",
           "dropped step 2 (Set 2×2 at (0, 0) to 1): step 4 (New canvas 3×3, G = 2) starts "
           "afresh",
           "dropped step 3 (Set (9, 9) to 1): step 4 (New canvas 3×3, G = 2) starts afresh"])


def test_a_placement_a_later_deletion_names_is_kept():
    spot = PlaceSpot(SPOT, 3.0, 3.0, level=2)
    log = [NewCanvas(8, 8, 3), spot, SetLevels(0, 0, 8, 8, 1), DeleteSpot(1, spot_ref(spot))]
    out = optimize(log)
    assert spot in out                   # without it the deletion could not find its spot
    assert same_result(out, log)


# -- random logs -----------------------------------------------------------------------------------

@st.composite
def reorder_logs(draw):
    """Logs of fills on an even grid (so that rectangles meet), palettes, crops and resizes,
    with spots, region fills and deletions the optimiser cannot move across."""
    g = draw(st.integers(3, 4))
    log = [NewCanvas(draw(st.integers(4, 10)), draw(st.integers(4, 10)), g)]
    for _ in range(draw(st.integers(0, 16))):
        kind = draw(st.sampled_from(["fill"] * 8 + ["crop", "resize", "resize", "palette",
                                                    "spot", "region", "delete", "stroke"]))
        if kind == "fill":
            log.append(SetLevels(2 * draw(st.integers(0, 3)), 2 * draw(st.integers(0, 3)),
                                 2 * draw(st.integers(1, 2)), 2 * draw(st.integers(1, 2)),
                                 draw(st.integers(1, 2))))
        elif kind == "crop":
            corner = draw(st.booleans())
            log.append(CropCanvas(0 if corner else draw(st.integers(0, 2)),
                                  0 if corner else draw(st.integers(0, 2)),
                                  draw(st.integers(1, 9)), draw(st.integers(1, 9))))
        elif kind == "resize":
            log.append(ResizeCanvas(draw(st.integers(1, 10)), draw(st.integers(1, 10)),
                                    draw(st.integers(0, 1))))
        elif kind == "palette":
            grey = draw(st.integers(0, 2))
            log.append(SetPalette(tuple((grey * k, k, 0) for k in range(g))))
        elif kind == "spot":
            log.append(PlaceSpot(SPOT, draw(st.floats(0, 8)), draw(st.floats(0, 8)),
                                 level=draw(st.integers(0, g - 1))))
        elif kind == "stroke":
            log.append(Stroke(((draw(st.integers(0, 9)), draw(st.integers(0, 9))),
                               (draw(st.integers(0, 9)), draw(st.integers(0, 9)))),
                              draw(st.integers(0, g - 1)), draw(st.integers(1, 3)),
                              shape="square", distribution="cloud", density=0.5,
                              seed=draw(st.integers(0, 9))))
        elif kind == "region":
            log.append(Fill(draw(st.integers(0, 3)), draw(st.integers(0, 3)),
                            draw(st.integers(0, g - 1))))
        else:
            placed = [k for k, a in enumerate(log) if isinstance(a, PlaceSpot)]
            if placed:
                k = draw(st.sampled_from(placed))
                log.append(DeleteSpot(k, spot_ref(log[k])))
    return log


def replayable(log) -> bool:
    try:
        levels_of(log)
    except Exception:               # a crop off the canvas, a spot off a resized canvas…
        return False
    return True


@settings(PROPERTY, max_examples=400)
@given(reorder_logs())
def test_optimised_random_logs_replay_bit_for_bit(log):
    if not replayable(log):
        return
    out = optimize_with_notes(log)
    assert len(out.actions) <= len(log)
    assert replay(list(out.actions), {}).result_hash() == replay(log, {}).result_hash()
    assert bool(out.notes) == (list(out.actions) != log)       # a change is always said


def seeded_log(rng) -> list:
    """Twelve steps on a 10×10 canvas: fills on an even grid, palettes, crops at the corner,
    resizes and, now and then, a region fill the optimiser cannot move across."""
    log = [NewCanvas(10, 10, 3)]
    for _ in range(12):
        roll = rng.random()
        if roll < 0.6:
            r, c, h, w = (2 * int(v) for v in rng.integers(0, 4, 4))
            log.append(SetLevels(r, c, h + 2, w + 2, int(rng.integers(1, 3))))
        elif roll < 0.7:
            log.append(SetPalette(RED3 if rng.random() < 0.5 else GREY3))
        elif roll < 0.8:
            log.append(CropCanvas(0, 0, *(int(v) for v in rng.integers(6, 12, 2))))
        elif roll < 0.95:
            log.append(ResizeCanvas(*(int(v) for v in rng.integers(6, 12, 2)), 1))
        else:
            log.append(Fill(*(int(v) for v in rng.integers(0, 5, 2)), 2))
    return log


def test_seeded_random_logs_get_reordered_and_replay_bit_for_bit():
    """The property above with many moves (it is not vacuous): every optimised log replays to
    the same result, and moves happen."""
    rng = np.random.default_rng(21)
    moved = 0
    for _ in range(300):
        log = seeded_log(rng)
        out = optimize_with_notes(log)
        moved += sum(n.startswith("moved") for n in out.notes)
        assert same_result(list(out.actions), log)
    assert moved >= 50


@pytest.mark.parametrize("n", [2000])
def test_a_long_log_is_optimised_quickly(n):
    import time
    rng = np.random.default_rng(5)
    log = [NewCanvas(200, 200, 4)] + [
        SetLevels(int(rng.integers(0, 190)), int(rng.integers(0, 190)), int(rng.integers(1, 8)),
                  int(rng.integers(1, 8)), int(rng.integers(0, 4))) for _ in range(n)]
    start = time.perf_counter()
    out = optimize(log)
    assert time.perf_counter() - start < 10
    assert same_result(out, log)
