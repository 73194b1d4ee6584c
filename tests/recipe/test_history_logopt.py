"""Log optimisation (digest §10): each rule on a hand-made log, and a focused property test."""

from hypothesis import given, settings
from hypothesis import strategies as st

from tests.support import PROPERTY, REFS, TINY
from texeditor.recipe.actions import (CropCanvas, NewCanvas, ResizeCanvas, SetLevels, SetPalette,
                               Synthesize)
from texeditor.recipe.replay import replay
from texeditor.recipe.logopt import optimize

GREY3 = ((0, 0, 0), (128, 128, 128), (255, 255, 255))
RED3 = ((255, 0, 0), (128, 128, 128), (255, 255, 255))


def check(log, expected=None, dpjs=None):
    out = optimize(log, dpjs)
    assert replay(out, TINY).result_hash() == replay(log, TINY).result_hash()
    if expected is not None:
        assert out == expected
    return out


def test_everything_before_a_new_canvas_goes():
    log = [NewCanvas(4, 4, 3), SetLevels(0, 0, 2, 2, 1), ResizeCanvas(6, 6), NewCanvas(3, 3, 2)]
    check(log, [NewCanvas(3, 3, 2)])


def test_everything_before_a_synthesis_goes():
    log = [NewCanvas(4, 4, 3), SetPalette(RED3), Synthesize(REFS[0], 5, 5, 1)]
    check(log, [Synthesize(REFS[0], 5, 5, 1)])


def test_a_full_canvas_fill_drops_earlier_fills_but_keeps_the_canvas_change():
    log = [NewCanvas(4, 4, 3), SetLevels(0, 0, 1, 1, 2), ResizeCanvas(6, 5, 1),
           SetLevels(-1, -1, 10, 10, 2)]
    check(log, [NewCanvas(4, 4, 3), ResizeCanvas(6, 5, 1), SetLevels(-1, -1, 10, 10, 2)])


def test_a_fill_that_no_longer_covers_after_a_resize_keeps_the_earlier_ones():
    log = [NewCanvas(4, 4, 3), SetLevels(1, 1, 1, 1, 2), ResizeCanvas(8, 8, 1),
           SetLevels(0, 0, 4, 4, 1)]
    out = check(log)
    assert SetLevels(1, 1, 1, 1, 2) not in out    # inside the later 4×4 fill: dropped
    log = [NewCanvas(4, 4, 3), SetLevels(0, 0, 4, 4, 2), ResizeCanvas(8, 8, 1),
           SetLevels(0, 0, 4, 4, 1), CropCanvas(2, 2, 6, 6)]
    check(log)


def test_a_fill_inside_a_later_fill_goes():
    log = [NewCanvas(6, 6, 3), SetLevels(1, 1, 2, 2, 1), SetPalette(RED3), SetLevels(0, 0, 4, 4, 2)]
    check(log, [NewCanvas(6, 6, 3), SetPalette(RED3), SetLevels(0, 0, 4, 4, 2)])


def test_a_fill_cut_away_by_a_later_crop_or_resize_goes():
    log = [NewCanvas(6, 6, 3), SetLevels(0, 0, 1, 1, 1), SetLevels(4, 4, 1, 1, 2),
           CropCanvas(2, 2, 4, 4), ResizeCanvas(2, 2)]
    check(log, [NewCanvas(6, 6, 3), CropCanvas(2, 2, 4, 4), ResizeCanvas(2, 2)])
    log = [NewCanvas(6, 6, 3), SetLevels(3, 3, 1, 1, 2), CropCanvas(2, 2, 4, 4),
           SetLevels(1, 1, 1, 1, 1)]
    check(log, [NewCanvas(6, 6, 3), CropCanvas(2, 2, 4, 4), SetLevels(1, 1, 1, 1, 1)])


def test_noops_go():
    log = [NewCanvas(4, 4, 3), SetLevels(9, 9, 2, 2, 1), ResizeCanvas(4, 4, 2),
           CropCanvas(-1, -1, 9, 9), SetPalette(GREY3), SetLevels(0, 0, 1, 1, 1)]
    check(log, [NewCanvas(4, 4, 3), SetLevels(0, 0, 1, 1, 1)])


def test_the_palette_of_a_synthesis_is_known_from_its_dpj():
    dpj = TINY[REFS[0]]
    same = SetPalette(tuple(tuple(int(c) for c in rgb) for rgb in dpj.palette))
    log = [Synthesize(REFS[0], 4, 4, 0), same]
    check(log, [Synthesize(REFS[0], 4, 4, 0)], TINY)
    assert optimize(log) == log                     # without the DPJs it cannot know


def test_consecutive_palettes_collapse_to_the_last():
    log = [NewCanvas(4, 4, 3), SetPalette(RED3), SetLevels(0, 0, 1, 1, 2), SetPalette(GREY3),
           SetPalette(RED3)]
    check(log, [NewCanvas(4, 4, 3), SetLevels(0, 0, 1, 1, 2), SetPalette(RED3)])


def test_consecutive_crops_merge():
    log = [NewCanvas(8, 8, 3), SetLevels(3, 3, 1, 1, 2), CropCanvas(2, 2, 9, 9),
           CropCanvas(1, 1, 2, 3)]
    check(log, [NewCanvas(8, 8, 3), SetLevels(3, 3, 1, 1, 2), CropCanvas(3, 3, 2, 3)])


def test_resizes_merge_only_when_the_first_keeps_what_the_second_keeps():
    grow = [NewCanvas(4, 4, 3), SetLevels(3, 3, 1, 1, 2), ResizeCanvas(6, 6, 1),
            ResizeCanvas(8, 8, 1)]
    check(grow, [NewCanvas(4, 4, 3), SetLevels(3, 3, 1, 1, 2), ResizeCanvas(8, 8, 1)])
    shrink_then_grow = [NewCanvas(4, 4, 3), SetLevels(1, 1, 1, 1, 2), ResizeCanvas(2, 2, 1),
                        ResizeCanvas(8, 8, 1)]
    check(shrink_then_grow, shrink_then_grow)
    other_fill = [NewCanvas(4, 4, 3), ResizeCanvas(6, 6, 1), ResizeCanvas(8, 8, 2)]
    check(other_fill, other_fill)


def test_never_longer_and_idempotent():
    log = [NewCanvas(4, 4, 3), SetLevels(0, 0, 1, 1, 1)]
    assert optimize(log) == log and optimize(optimize(log)) == log


@st.composite
def canvas_logs(draw):
    """Logs rich in canvas changes and overlapping fills, where the rules interact."""
    g = draw(st.integers(2, 4))
    log = [NewCanvas(draw(st.integers(1, 6)), draw(st.integers(1, 6)), g)]
    for _ in range(draw(st.integers(0, 12))):
        kind = draw(st.sampled_from(["fill", "fill", "crop", "resize", "palette"]))
        if kind == "fill":
            log.append(SetLevels(draw(st.integers(-2, 6)), draw(st.integers(-2, 6)),
                                 draw(st.integers(1, 8)), draw(st.integers(1, 8)),
                                 draw(st.integers(0, g - 1))))
        elif kind == "crop":
            log.append(CropCanvas(draw(st.integers(-1, 3)), draw(st.integers(-1, 3)),
                                  draw(st.integers(1, 7)), draw(st.integers(1, 7))))
        elif kind == "resize":
            log.append(ResizeCanvas(draw(st.integers(1, 7)), draw(st.integers(1, 7)),
                                    draw(st.integers(0, 1))))
        else:
            grey = draw(st.integers(0, 2))
            log.append(SetPalette(tuple((grey * k, k, 0) for k in range(g))))
    return log


@settings(PROPERTY, max_examples=300)
@given(canvas_logs())
def test_optimised_canvas_logs_replay_identically(log):
    try:
        expected = replay(log, TINY).result_hash()
    except Exception:
        return                              # a crop outside the canvas: not a valid log
    out = optimize(log)
    assert len(out) <= len(log)
    assert replay(out, TINY).result_hash() == expected
