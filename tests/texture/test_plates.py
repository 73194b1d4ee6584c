"""Colour plates (thesis §1.2.3–1.2.4): I = I_plates + I_texture, the plates layer as Actions,
its undo, its replay and its files."""

import hashlib
import struct

import numpy as np
import pytest

from texeditor.errors import InputError, ReplayError
from texeditor.paint.actions import Stroke
from texeditor.recipe.actions import (CropCanvas, NewCanvas, ResizeCanvas, SetLevels, SetPalette,
                                      Synthesize)
from texeditor.recipe.codec import log_text, read_log
from texeditor.recipe.document import result_hash
from texeditor.recipe.history import History
from texeditor.recipe.logopt import optimize
from texeditor.recipe.replay import replay
from texeditor.recipe.texturefile import parse_texture, texture_bytes
from texeditor.regions.actions import Fill
from texeditor.spots.actions import DeleteSpot, PlaceSpot, spot_ref
from texeditor.texture.actions import RenderGrains
from texeditor.texture.plate_actions import AddPlates, OnPlates, PlatesFromPhoto, RemovePlates
from texeditor.texture import plates as plates_module
from texeditor.texture.plates import (document_picture, grid_of_text, grid_plates, grid_text,
                                      laid_on_plates, photo_grid, stretched_grid)

from ..support import REFS, TINY
from ..support import plates as sp
from ..support.spots import DISC


def grey(rgb):
    return 0.2125 * rgb[0] + 0.7154 * rgb[1] + 0.0721 * rgb[2]


# -- the picture --------------------------------------------------------------------------------------
def test_a_texture_on_plates_is_the_plate_colour_plus_the_grey_around_its_mean():
    palette = np.array([[0, 0, 0], [90, 90, 90], [255, 0, 0]], np.uint8)
    levels = np.array([[0, 1, 2], [1, 1, 0]], np.uint8)
    plates = np.array([[0, 0, 1], [1, 1, 1]], np.uint8)
    colours = np.array([[100, 150, 200], [250, 20, 120]], np.uint8)
    mean = (0 + 90 + grey((255, 0, 0)) + 90 + 90 + 0) / 6           # 54.19…
    picture = laid_on_plates(palette[levels], plates, colours)
    for (r, c), level in np.ndenumerate(levels):
        offset = grey(palette[level]) - mean
        expected = np.clip(np.rint(colours[plates[r, c]] + offset), 0, 255)
        np.testing.assert_array_equal(picture[r, c], expected)
    assert picture[1, 0].tolist() == [255, 56, 156]    # 250 + 35.8 clipped; 20 + 35.8; 120 + 35.8
    assert picture.dtype == np.uint8


def test_a_uniform_texture_shows_its_plates_exactly():
    levels = np.ones((3, 4), np.uint8)
    plates = np.array([[0, 1, 1, 0]] * 3, np.uint8)
    colours = [[10, 20, 30], [200, 100, 50]]
    picture = laid_on_plates(np.full((3, 4, 3), 77, np.uint8)[..., :3], plates, colours)
    np.testing.assert_array_equal(picture, np.asarray(colours, np.uint8)[plates])
    doc = sp.history().document
    np.testing.assert_array_equal(document_picture(doc), doc.palette[doc.levels])
    assert levels.sum() == 12


def test_the_picture_of_a_document_lays_its_levels_or_its_tone_on_its_plates():
    history = sp.history()
    history.apply(sp.EXAMPLES[0])
    doc = history.document
    picture = document_picture(doc)
    np.testing.assert_array_equal(picture, laid_on_plates(doc.palette[doc.levels], doc.plates,
                                                          doc.plate_colours))
    np.testing.assert_array_equal(document_picture(doc, plates=False), doc.palette[doc.levels])
    tone = np.full(doc.shape + (3,), 50, np.uint8)
    np.testing.assert_array_equal(document_picture(doc, tone), doc.plate_colours[doc.plates])


# -- the layer as Actions ------------------------------------------------------------------------------
def test_plates_are_painted_by_the_level_edits_and_undone_back_to_the_start():
    history = sp.history()
    start = history.document.result_hash()
    levels = history.document.levels.copy()
    expected = np.full((8, 12), 2, np.uint8)
    history.apply(sp.EXAMPLES[0])
    np.testing.assert_array_equal(history.document.plates, expected)
    history.apply(sp.EXAMPLES[1])                 # a 3-wide square brush along row 1, cols 1..8
    expected[0:3, 0:10] = 0
    np.testing.assert_array_equal(history.document.plates, expected)
    history.apply(sp.EXAMPLES[2])                 # fill the plate region around (6, 10) with 1
    expected[expected == 2] = 1
    np.testing.assert_array_equal(history.document.plates, expected)
    history.apply(sp.EXAMPLES[3])
    np.testing.assert_array_equal(history.document.plate_colours,
                                  [[250, 0, 0], [0, 0, 250], [250, 250, 250]])
    np.testing.assert_array_equal(history.document.levels, levels)     # the texture untouched
    assert history.document.palette.tolist() == [[0, 0, 0], [128, 128, 128], [255, 255, 255]]
    painted = history.document.result_hash()
    for _ in range(4):
        history.undo()
    assert history.document.plates is None and history.document.result_hash() == start
    for _ in range(4):
        history.redo()
    np.testing.assert_array_equal(history.document.plates, expected)
    assert history.document.result_hash() == painted


def test_undo_through_snapshots_and_replays_keeps_the_plates():
    history = History(snapshot_every=2, undo_memory=0)
    for action in sp.history().applied + tuple(sp.EXAMPLES[:4]):
        history.apply(action)
    final = history.document.result_hash()
    plates = history.document.plates.copy()
    history.goto(4)
    np.testing.assert_array_equal(history.document.plates, np.full((8, 12), 2))
    history.goto(len(history.actions))
    np.testing.assert_array_equal(history.document.plates, plates)
    assert history.document.result_hash() == final
    assert replay(history.applied, {}).result_hash() == final


def test_the_result_hash_covers_the_plates_and_is_unchanged_without_them():
    history = sp.history()
    doc = history.document
    h, w = doc.shape
    digest = hashlib.sha256(b"texeditor-levels-v1" + struct.pack("<3I", h, w, 3))
    digest.update(doc.levels.tobytes() + doc.palette.tobytes())
    assert doc.result_hash() == digest.hexdigest()
    history.apply(AddPlates((sp.RED, sp.BLUE)))
    digest.update(b"texeditor-plates-v1" + struct.pack("<I", 2))
    digest.update(np.zeros((h, w), np.uint8).tobytes() + bytes(sp.RED + sp.BLUE))
    assert doc.result_hash() == digest.hexdigest()
    assert doc.result_hash() != result_hash(doc.levels, doc.palette)


def test_plates_follow_the_canvas_crop_resize_and_grains_and_a_new_canvas_drops_them():
    history = sp.history()
    history.apply(AddPlates((sp.RED, sp.BLUE, sp.CREAM)))
    history.apply(OnPlates.of(SetLevels(0, 6, 8, 6, 1)))       # right half on plate 1
    history.apply(CropCanvas(2, 4, 4, 5))                       # columns 4..8
    np.testing.assert_array_equal(history.document.plates, [[0, 0, 1, 1, 1]] * 4)
    history.apply(ResizeCanvas(5, 7))                           # the edge plate carried on
    np.testing.assert_array_equal(history.document.plates,
                                  [[0, 0, 1, 1, 1, 1, 1]] * 5)
    history.apply(RenderGrains("square", 2))                    # each point a 2×2 grain
    np.testing.assert_array_equal(history.document.plates,
                                  [[0] * 4 + [1] * 10] * 10)
    history.apply(NewCanvas(10, 10, 2))
    assert history.document.plates is None
    history.undo()
    assert history.document.plates.shape == (10, 14)


def test_a_synthesis_starts_without_plates():
    history = History()
    history.document.dpjs.update(TINY)
    history.apply(Synthesize(REFS[0], 9, 7, 1))
    history.apply(AddPlates((sp.RED, sp.BLUE)))
    history.apply(Synthesize(REFS[0], 9, 7, 2))
    assert history.document.plates is None


def test_plates_from_a_photo_split_it_where_its_colours_change():
    photo = sp.two_colour_photo()
    grid = photo_grid(photo, 0.02, side=30)
    assert grid.shape == (20, 30, 3)
    np.testing.assert_array_equal(grid_of_text(grid_text(grid)), grid)
    history = sp.history(w=24, h=6)
    history.apply(PlatesFromPhoto(grid_text(grid), plates=2, name="halves"))
    doc = history.document
    # L*: the blue (30, 60, 190) is darker than the red (200, 40, 30): plate 0 is the blue one
    np.testing.assert_array_equal(doc.plates[:, :10], 1)
    np.testing.assert_array_equal(doc.plates[:, 14:], 0)
    assert np.abs(doc.plate_colours.astype(int) - [sp.BLUE, sp.RED]).max() < 30
    assert doc.plate_colours.tolist() == grid_plates(grid, (6, 24), 2)[1].tolist()
    assert history.applied[-1].label() == "Plates from halves (2 plates)"


def _stretched_whole(grid, shape):
    """The grid stretched as every release before did it: the whole canvas at once."""
    import skimage as ski
    canvas = ski.transform.resize(grid / 255.0, shape, order=1, anti_aliasing=False)
    return np.round(canvas * 255).astype(np.uint8)


@pytest.mark.parametrize("band", [1, 7, 2**20])
def test_a_grid_stretched_band_by_band_is_the_whole_canvas_stretched_bit_for_bit(monkeypatch, band):
    """Plates from a photo stretch its grid over the canvas a band of rows at a time (2^26 points
    at once took 4.9 GB); the colours, so the plates, are those of the whole canvas at once:
    grids and canvases of any shape, a grid as large as the canvas, bands of one row or of a few."""
    monkeypatch.setattr(plates_module, "_STRETCH_POINTS", band)
    rng = np.random.default_rng(band)
    cases = [((2, 2), (2, 2)), ((2, 2), (37, 300)), ((1, 1), (5, 3)), ((64, 64), (7, 300)),
             ((3, 5), (1, 1)), ((1, 4), (90, 1)), ((13, 9), (13, 9))]
    cases += [((int(rng.integers(1, 65)), int(rng.integers(1, 65))),
               (int(rng.integers(1, 150)), int(rng.integers(1, 150)))) for _ in range(25)]
    for grid_shape, shape in cases:
        grid = rng.integers(0, 256, grid_shape + (3,)).astype(np.uint8)
        stretched = stretched_grid(grid, shape)
        assert stretched.dtype == np.uint8 and stretched.shape == shape + (3,)
        np.testing.assert_array_equal(stretched, _stretched_whole(grid, shape),
                                      err_msg=f"{grid_shape} over {shape}")
    grid = rng.integers(0, 256, (5, 6, 3)).astype(np.uint8)
    plates, colours = grid_plates(grid, (40, 70), 3)
    from texeditor.markov.levels import quantize
    whole = quantize(_stretched_whole(grid, (40, 70)), 3, "lab")
    np.testing.assert_array_equal(plates, whole.levels)
    np.testing.assert_array_equal(colours, whole.palette)


def test_plates_from_a_photo_never_hold_the_canvas_in_float():
    """A 2048×1024 canvas: the float64 canvas alone was 48 MiB, and each temporary as much."""
    import tracemalloc
    grid = np.random.default_rng(3).integers(0, 256, (2, 2, 3)).astype(np.uint8)
    tracemalloc.start()
    try:
        stretched = stretched_grid(grid, (1024, 2048))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert stretched.nbytes == 6 * 2**20
    assert peak < stretched.nbytes + 30 * 2**20         # a band: 24 MiB of float64


def test_photo_grids_and_steps_on_the_plates_are_checked():
    for bad in ("", "ff00", "ff0000/ff00", "FF0000", "gg0000", "/".join(["ff0000"] * 65)):
        with pytest.raises(InputError, match="photo grid"):
            PlatesFromPhoto(bad)
    with pytest.raises(InputError, match="blur"):
        photo_grid(sp.two_colour_photo(), 0)
    flat = grid_text(np.full((3, 3, 3), 90, np.uint8))
    history = sp.history()
    with pytest.raises(InputError, match="plates from a photo"):
        history.apply(PlatesFromPhoto(flat, plates=3))
    with pytest.raises(InputError, match="no plates"):
        history.apply(OnPlates.of(Fill(0, 0, 1)))
    with pytest.raises(InputError, match="no plates to remove"):
        history.apply(RemovePlates())
    for step in (CropCanvas(0, 0, 2, 2), Synthesize(REFS[0], 4, 4), AddPlates((sp.RED, sp.BLUE)),
                 OnPlates.of(Fill(0, 0, 1)), DeleteSpot(1, "0" * 16)):
        with pytest.raises(InputError, match="cannot be done on the plates"):
            OnPlates.of(step)
    from ..support.texture import SYNTH
    from texeditor.texture.actions import Mix
    with pytest.raises(InputError, match="names DPJs"):
        OnPlates.of(Mix(SYNTH, (REFS[0],)))
    with pytest.raises(InputError, match="unknown action type"):
        OnPlates('{"type": "nothing", "version": 1}')
    with pytest.raises(InputError, match="fits|does not exist"):
        AddPlates((sp.RED, sp.BLUE), fill=2)
    history.apply(AddPlates((sp.RED, sp.BLUE)))
    before = history.document.result_hash()
    with pytest.raises(InputError, match="level 2 does not exist"):
        history.apply(OnPlates.of(SetLevels(0, 0, 2, 2, 2)))        # P = 2 plates
    assert history.document.result_hash() == before


def test_a_plates_log_replays_bit_for_bit_from_a_file_and_a_recipe_text():
    history = sp.history()
    for action in sp.EXAMPLES[:5]:
        history.apply(action)
    data, manifest = texture_bytes(history.document, history.applied)
    tex = parse_texture(data)
    assert [a.to_json() for a in tex.actions] == [a.to_json() for a in history.applied]
    again = replay(tex.actions, {})
    assert again.result_hash() == manifest.result_sha256 == history.document.result_hash()
    np.testing.assert_array_equal(again.plates, history.document.plates)
    assert read_log(log_text(history.applied), "log") == history.applied
    assert replay(optimize(history.applied), {}).result_hash() == manifest.result_sha256


def test_a_file_whose_plates_are_not_the_recorded_ones_is_refused():
    """The same levels, other plates: the recorded SHA-256 tells them apart."""
    history = sp.history()
    history.apply(AddPlates((sp.RED, sp.BLUE)))
    before = replay(history.applied, {})
    history.apply(OnPlates.of(SetLevels(0, 0, 1, 1, 1)))
    np.testing.assert_array_equal(before.levels, history.document.levels)
    data, _ = texture_bytes(before, history.applied)      # this log, the earlier result's hash
    from texeditor.recipe.stored import open_recipe
    with pytest.raises(ReplayError):
        open_recipe(parse_texture(data).recipe)


def test_a_spot_placed_after_painting_plates_is_deleted_with_the_plates_kept():
    history = sp.history(w=32, h=32)
    history.apply(AddPlates((sp.RED, sp.BLUE)))
    history.apply(OnPlates.of(Stroke(points=((4, 4), (4, 20)), level=1, size=3)))
    plates = history.document.plates.copy()
    before = history.document.levels.copy()
    spot = PlaceSpot(DISC, 16, 16, level=2)
    history.apply(spot)
    assert not np.array_equal(history.document.levels, before)
    history.apply(DeleteSpot(len(history.applied) - 1, spot_ref(spot)))
    np.testing.assert_array_equal(history.document.levels, before)
    np.testing.assert_array_equal(history.document.plates, plates)


def test_plate_colours_are_edited_by_a_palette_on_the_plates():
    history = sp.history()
    history.apply(AddPlates((sp.RED, sp.BLUE)))
    with pytest.raises(InputError, match="palette has 3 colours"):
        history.apply(OnPlates.of(SetPalette((sp.RED, sp.BLUE, sp.CREAM))))
    history.apply(OnPlates.of(SetPalette((sp.CREAM, sp.BLUE))))
    assert history.document.plate_colours.tolist() == [list(sp.CREAM), list(sp.BLUE)]
    history.undo()
    assert history.document.plate_colours.tolist() == [list(sp.RED), list(sp.BLUE)]


def _painted_on_plates(log, action):
    """The plates a document gets from the level steps of ``log`` (after its new canvas) and
    ``action``, each done on the plates of a blank canvas with plates all 0."""
    first = log[0]
    plates = History()
    plates.apply(NewCanvas(first.width, first.height, first.levels))
    plates.apply(AddPlates(tuple(map(tuple, replay(log[:1], {}).palette)), fill=0))
    for step in list(log[1:]) + [action]:
        plates.apply(OnPlates.of(step))
    return plates.document


def test_every_level_step_paints_on_the_plates_what_it_paints_on_the_levels():
    from ..support import paint, regions
    cases = [(regions.history_of(regions.T).applied, a) for a in regions.EXAMPLES]
    cases += [(paint.textured().actions, a) for a in paint.EXAMPLES]
    cases += [(sp.history().applied, PlaceSpot(DISC, 4, 6, level=1, contour=0.3, seed=2)),
              (sp.history().applied, SetPalette((sp.RED, sp.BLUE, sp.CREAM)))]
    for log, action in cases:
        levels = replay(list(log) + [action], {})
        plates = _painted_on_plates(log, action)
        np.testing.assert_array_equal(plates.plates, levels.levels, err_msg=action.label())
        np.testing.assert_array_equal(plates.plate_colours, levels.palette)
        assert not plates.levels.any()                    # the texture stays blank


def test_plates_from_a_photo_follow_an_edit_of_the_canvas_size_before_them():
    """A replay after the canvas under the plates changed size lays them again: the plates kept
    from the last replay were for the old size (the history's cache of slow parts is by shape)."""
    history = History()
    history.apply(NewCanvas(64, 48, 4))
    grid = np.zeros((6, 8, 3), np.uint8)
    grid[:, 4:] = 200
    step = PlatesFromPhoto(grid_text(grid), plates=2)
    history.apply(step)
    assert history.document.plates.shape == (48, 64)
    history.replace(0, NewCanvas(80, 60, 4), to_end=True)
    assert history.document.plates.shape == (60, 80)
    assert np.array_equal(history.document.plates, grid_plates(grid, (60, 80), 2)[0])
    history.replace(0, NewCanvas(64, 48, 4), to_end=True)            # and back: kept again
    assert np.array_equal(history.document.plates, grid_plates(grid, (48, 64), 2)[0])
