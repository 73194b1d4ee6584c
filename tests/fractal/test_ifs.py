"""IFS motifs (companion 002): the chaos game's picture is the attractor — invariant under its
maps — the Sierpinski triangle has dimension log 3 / log 2, and the same seed draws the same."""

import math

import numpy as np
import pytest
from scipy import ndimage

from texeditor.errors import InputError
from texeditor.fractal.ifs import BUILTINS, attractor_frame, ifs_attractor, ifs_points


@pytest.mark.parametrize("name", sorted(BUILTINS))
def test_the_attractor_is_invariant_under_its_maps(name):
    """T_i(A) ⊂ A: each map sends attractor points onto the drawn attractor, within a point."""
    shape, n = (256, 256), 400_000
    mask = ifs_attractor(name, shape, points=n, seed=1) > 0
    frame = attractor_frame(name, shape, points=n, seed=1)
    near = ndimage.binary_dilation(mask, np.ones((3, 3), bool))
    xy = ifs_points(BUILTINS[name], 20_000, seed=9)
    for i in range(len(BUILTINS[name].maps)):
        rc = np.floor(frame.to_pixels(BUILTINS[name].apply(i, xy))).astype(int)
        inside = (rc >= 0).all(axis=1) & (rc[:, 0] < 256) & (rc[:, 1] < 256)
        assert inside.mean() > 0.999
        assert near[rc[inside, 0], rc[inside, 1]].mean() > 0.999, (name, i)


def test_a_shifted_mask_is_not_invariant():
    """The invariance check can fail: a map that moves the tree off itself lands off it."""
    shape = (256, 256)
    mask = ifs_attractor("tree", shape, points=400_000, seed=1) > 0
    frame = attractor_frame("tree", shape, points=400_000, seed=1)
    xy = ifs_points(BUILTINS["tree"], 5000, seed=9) + [0.37, 0.0]
    rc = np.floor(frame.to_pixels(xy)).astype(int).clip(0, 255)
    assert mask[rc[:, 0], rc[:, 1]].mean() < 0.5


def box_dimension(mask: np.ndarray, sizes) -> float:
    counts = [np.count_nonzero(mask.reshape(mask.shape[0] // s, s, -1, s).any(axis=(1, 3)))
              for s in sizes]
    return -np.polyfit(np.log(sizes), np.log(counts), 1)[0]


def test_the_sierpinski_triangle_has_dimension_log3_over_log2():
    mask = ifs_attractor("sierpinski", (1024, 1024), points=3_000_000, seed=2) > 0
    assert abs(box_dimension(mask, [2, 4, 8, 16, 32, 64]) - math.log(3) / math.log(2)) < 0.05


def test_the_fern_is_not_a_line_nor_a_plane():
    mask = ifs_attractor("fern", (512, 512), points=1_000_000, seed=2) > 0
    assert 1.3 < box_dimension(mask, [2, 4, 8, 16, 32]) < 1.95


def test_the_same_seed_draws_the_same_picture_and_another_differs():
    a = ifs_attractor("fern", (100, 80), points=50_000, seed=5)
    assert np.array_equal(a, ifs_attractor("fern", (100, 80), points=50_000, seed=5))
    assert not np.array_equal(a, ifs_attractor("fern", (100, 80), points=50_000, seed=6))
    assert a.sum() == 50_000 and a.dtype == np.uint32          # every point lands in the frame


def test_the_tree_stands_on_its_trunk_and_is_symmetric():
    """The digest's tree: T0 and T1 alone fix the trunk x = 0, y ∈ [0, 1], so it is drawn;
    T2 and T3 turn by ±π/4, so the tree is its own mirror image."""
    mask = ifs_attractor("tree", (201, 201), points=600_000, seed=0) > 0
    frame = attractor_frame("tree", (201, 201), points=600_000, seed=0)
    trunk = np.floor(frame.to_pixels(np.column_stack([np.zeros(50), np.linspace(0.02, 0.98, 50)])))
    assert mask[trunk[:, 0].astype(int), trunk[:, 1].astype(int)].all()
    mirror = np.fliplr(mask)
    assert (mask & mirror).sum() > 0.9 * mask.sum()
    assert (mask & np.roll(mirror, 9, axis=1)).sum() < 0.6 * mask.sum()


@pytest.mark.parametrize("name, shape, points", [
    ("oak", (10, 10), 10), (None, (10, 10), 10), ("tree", (0, 10), 10),
    ("tree", (10, float("nan")), 10), ("tree", (10**6, 10), 10), ("tree", (10, 10), 0),
    ("tree", (10, 10), 10**12), ("tree", (10, 10), 2.5), ("tree", "big", 10)])
def test_bad_requests_are_input_errors(name, shape, points):
    with pytest.raises(InputError):
        ifs_attractor(name, shape, points=points)
