"""The random manipulation of every region at once (thesis §3.4.3, issue 21 item 3): hand-made
grids whose result is computed here from the definition — each region turned, zoomed or moved
about the centre of its box, painted in scan order — the draws, the seed, the Action."""

import json

import numpy as np
import pytest

from tests.support.regions import grid, history_of, same
from texeditor.errors import FormatError, InputError
from texeditor.recipe.codec import action_from_json
from texeditor.recipe.replay import replay
from texeditor.regions.actions import ScatterRegions
from texeditor.regions.scatter import random_maps, region_labels, scatter_regions

# Three regions with odd boxes (a quarter turn keeps their centre on a point): an L of 1s, a T
# of 2s, a bar of 3s; far enough apart that no turn makes them meet.
R = grid("""
    . . . . . . . . .
    . 1 1 1 . 2 2 2 .
    . 1 . . . . 2 . .
    . 1 . . . . 2 . .
    . . . . . . . . .
    . . 3 . . . . . .
    . . 3 . . . . . .
    . . 3 . . . . . .
    . . . . . . . . .""")
BOXES = [(1, 1, 4, 4), (1, 5, 4, 8), (5, 2, 8, 3)]     # the 1s, 2s, 3s: the scan order


def turned_by_hand(levels, boxes, quarters, fill=0):
    """Each box's region cut out and turned k quarters counter-clockwise (np.rot90) about the
    centre of its box; the vacated points take ``fill``."""
    out = levels.copy()
    pieces = []
    for (t, l, b, r), k in zip(boxes, quarters):
        patch = levels[t:b, l:r]
        out[t:b, l:r][patch > 0] = fill
        pieces.append(((t, l, b, r), np.rot90(patch, k)))
    for (t, l, b, r), turned in pieces:
        h, w = turned.shape
        top, left = (t + b - h) // 2, (l + r - w) // 2
        window = out[top:top + h, left:left + w]
        window[turned > 0] = turned[turned > 0]
    return out


def test_the_regions_are_found_in_scan_order_with_their_boxes():
    labels, order, boxes = region_labels(R)
    assert [boxes[k] for k in order] == BOXES
    assert [int(R[labels == k][0]) for k in order] == [1, 2, 3]


@pytest.mark.parametrize("seed", range(8))
def test_quarter_turns_without_moves_turn_each_region_about_its_own_centre(seed):
    quarters = [int(m.angle) // 90 for m in random_maps(3, seed, rotation="quarter")]
    assert np.array_equal(scatter_regions(R, seed, rotation="quarter"),
                          turned_by_hand(R, BOXES, quarters))


def test_the_eight_seeds_draw_every_quarter_turn():
    drawn = {m.angle for seed in range(8) for m in random_maps(3, seed, rotation="quarter")}
    assert drawn == {0.0, 90.0, 180.0, 270.0}


def test_a_zoom_of_two_doubles_each_block_about_its_centre():
    blocks = grid("""
        . . . . . . . . .
        . . . . . . . . .
        . . 1 2 . . . . .
        . . 3 1 . . . . .
        . . . . . . . . .
        . . . . . . 2 2 .
        . . . . . . 2 2 .
        . . . . . . . . .""")
    # every point is its own region but the 2×2 of 2s: a point (r, c) becomes the 2×2 at rows
    # r − 1..r, columns c − 1..c (its preimages q/2 rounded half up), painted in scan order;
    # the 2×2 block, ×2 about (5.5, 6.5), the 4×4 at rows 4..7, columns 5..8
    assert same(scatter_regions(blocks, 11, scale=(2.0, 2.0)), """
        . . . . . . . . .
        . 1 2 2 . . . . .
        . 3 1 1 . . . . .
        . 3 1 1 . . . . .
        . . . . . 2 2 2 2
        . . . . . 2 2 2 2
        . . . . . 2 2 2 2
        . . . . . 2 2 2 2""")


def test_overlapping_regions_are_painted_in_scan_order():
    pair = grid("""
        . . . . . . .
        . . . . . . .
        . . 1 . 2 . .
        . . . . . . .
        . . . . . . .""")
    assert same(scatter_regions(pair, 0, scale=(3.0, 3.0)), """
        . . . . . . .
        . 1 1 2 2 2 .
        . 1 1 2 2 2 .
        . 1 1 2 2 2 .
        . . . . . . .""")                     # the 2s, later, over the 1s' third column


def test_moves_stay_within_the_radius_and_go_every_way():
    maps = random_maps(500, 4, radius=6)
    offsets = np.array([m.offset for m in maps])
    assert (np.hypot(*offsets.T) <= 6 + np.sqrt(0.5)).all()       # each coordinate rounded
    assert offsets.min(axis=0).tolist() == [-6, -6] and offsets.max(axis=0).tolist() == [6, 6]
    assert all(m.angle == 0 and m.factor == 1 for m in maps)
    turns = random_maps(500, 4, rotation="any", scale=(0.5, 2.0))
    assert [m.offset for m in turns] == [(0, 0)] * 500
    angles, factors = np.array([m.angle for m in turns]), np.array([m.factor for m in turns])
    assert 0 <= angles.min() < 10 and 350 < angles.max() < 360
    assert 0.5 <= factors.min() < 0.55 and 1.95 < factors.max() <= 2.0


@pytest.mark.parametrize("wrap", [False, True])
def test_moves_carry_each_region_by_its_own_offset(wrap):
    """Moves only: each region's points shifted by its draw (folded back with wrap, lost
    without), in scan order over what is there."""
    out = scatter_regions(R, 9, radius=5, fill=4, wrap=wrap)
    offsets = [m.offset for m in random_maps(3, 9, radius=5)]
    assert len(set(offsets)) == 3 and any(o != (0, 0) for o in offsets)
    expected = np.where(R > 0, 4, 0).astype(np.uint8)
    labels, order, _ = region_labels(R)
    for k, (dr, dc) in zip(order, offsets):
        for r, c in np.argwhere(labels == k):
            q = (r + dr, c + dc)
            if wrap:
                q = (q[0] % 9, q[1] % 9)
            if 0 <= q[0] < 9 and 0 <= q[1] < 9:
                expected[q] = R[r, c]
    assert np.array_equal(out, expected)


def test_nothing_drawn_changes_nothing_and_seeds_differ():
    assert np.array_equal(scatter_regions(R, 3), R)
    a = scatter_regions(R, 1, radius=3, rotation="any", scale=(0.7, 1.6))
    assert np.array_equal(a, scatter_regions(R, 1, radius=3, rotation="any", scale=(0.7, 1.6)))
    assert not np.array_equal(a, scatter_regions(R, 2, radius=3, rotation="any",
                                                 scale=(0.7, 1.6)))


def test_only_the_selected_regions_move():
    mask = R == 2
    out = scatter_regions(R, 3, mask=mask, rotation="quarter")
    quarter = int(random_maps(1, 3, rotation="quarter")[0].angle) // 90
    assert np.array_equal(out, turned_by_hand(R, BOXES[1:2], [quarter]))


# -- the Action ------------------------------------------------------------------------------------

def test_the_action_on_a_level_replays_bit_for_bit_and_undoes():
    history = history_of(R)
    start = history.document.levels.copy()
    action = ScatterRegions(6, rotation="quarter", level=3, fill=1)
    history.apply(action)
    quarter = int(random_maps(1, 6, rotation="quarter")[0].angle) // 90
    assert np.array_equal(history.document.levels,
                          turned_by_hand(R, BOXES[2:], [quarter], fill=1))
    assert action.label() == "Scatter regions of level 3, seed 6"
    again = action_from_json(json.loads(json.dumps(action.to_json())))
    assert again == action
    assert replay([action_from_json(a.to_json()) for a in history.actions], {}).result_hash() \
        == history.document.result_hash()
    history.undo()
    assert np.array_equal(history.document.levels, start)


def test_the_action_on_the_texture_and_on_a_selection():
    whole = history_of(R)
    whole.apply(ScatterRegions(2, radius=4, rotation="any", scale_min=0.5, scale_max=1.5,
                               wrap=True))
    assert np.array_equal(whole.document.levels, scatter_regions(
        R, 2, radius=4, rotation="any", scale=(0.5, 1.5), wrap=True))
    one = history_of(R)
    one.apply(ScatterRegions(3, rotation="quarter", row=1, col=6))
    assert np.array_equal(one.document.levels, scatter_regions(R, 3, mask=R == 2,
                                                               rotation="quarter"))
    assert ScatterRegions(3, row=1, col=6).label() == "Scatter regions of region at (1, 6), seed 3"


@pytest.mark.parametrize("make, message", [
    (lambda: ScatterRegions(1, level=2, row=0, col=0), "a selection or of a level"),
    (lambda: ScatterRegions(1, scale_min=2, scale_max=1), "scale_min 2 is above"),
    (lambda: ScatterRegions(1, rotation="random"), "rotation must be one of"),
    (lambda: ScatterRegions(1, radius=-1), "radius = -1"),
])
def test_bad_parameters_are_input_errors(make, message):
    with pytest.raises(InputError, match=message):
        make()


def test_a_missing_level_fails_cleanly_and_keeps_the_document():
    history = history_of(R)
    before = history.document.result_hash()
    with pytest.raises(InputError, match="level 9 does not exist"):
        history.apply(ScatterRegions(1, level=9))
    with pytest.raises(InputError, match="level 7 does not exist"):
        history.apply(ScatterRegions(1, fill=7))
    assert history.document.result_hash() == before
    with pytest.raises(FormatError, match="rotation"):
        action_from_json({"type": "scatter_regions", "version": 1, "rotation": "spin"})


@pytest.mark.parametrize("band", [1, 7, 64, 2**20])
def test_the_regions_first_points_are_found_band_by_band_as_by_sorting_them_all(monkeypatch,
                                                                                 band):
    """Sorting the 2^26 labels of a canvas at once to find each region's first point took
    1.6 GB: they are looked through a band at a time, with the same labels, order and boxes."""
    from texeditor.regions import scatter, transforms
    rng = np.random.default_rng(band)
    monkeypatch.setattr(scatter, "LABEL_BAND", band)
    for shape in [(1, 1), (1, 40), (40, 1), (17, 23), (30, 30)]:
        for levels in (2, 4):
            texture = rng.integers(0, levels, shape).astype(np.uint8)
            labels, order, boxes = region_labels(texture, connectivity=4 + 4 * (levels == 2))
            ids, first = np.unique(labels.ravel(), return_index=True)
            assert order == [int(k) for k in ids[np.argsort(first, kind="stable")] if k]
            found_ids, found_first = scatter._first_points(labels)
            np.testing.assert_array_equal(found_ids, ids)
            np.testing.assert_array_equal(found_first, first)
    assert scatter._first_points(np.zeros((0, 3), np.intp))[0].size == 0
    texture = rng.integers(0, 4, (29, 37)).astype(np.uint8)
    monkeypatch.setattr(transforms, "BAND_POINTS", band)        # each region's box in bands
    scattered = scatter_regions(texture, 3, radius=9, rotation="any", scale=(0.5, 2.5), wrap=True)
    monkeypatch.setattr(scatter, "LABEL_BAND", 2**62)
    monkeypatch.setattr(transforms, "BAND_POINTS", 2**62)      # each region's box at once
    np.testing.assert_array_equal(scattered, scatter_regions(texture, 3, radius=9,
                                                             rotation="any", scale=(0.5, 2.5),
                                                             wrap=True))
