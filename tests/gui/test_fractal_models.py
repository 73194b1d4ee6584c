"""Models ▸ Fractal relief… / IFS motif… and the spot editor's fractal curve (issue 22 item 5)
as sessions: each dialog opened twice with other settings, OK, the document's levels checked
against the engine, undo to the start, redo; a fractal spot placed with the Spot tool."""

import numpy as np
import pytest

from texeditor.fractal.actions import heights_picture
from texeditor.fractal.ifs import ifs_attractor
from texeditor.fractal.midpoint import midpoint_displacement
from texeditor.spectral.actions import model_levels
from texeditor.spots.actions import PlaceSpot

from .support import (cell_pos, click, fill_a_cell, model_ok, open_model_dialog, spot_tool,
                      undo_to_start)


@pytest.fixture(autouse=True)
def own_spot_library(tmp_path, monkeypatch):
    """Saved spots go to a temporary data folder, never the user's own."""
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path / "data"))




def relief_levels(w, h, seed, roughness, g):
    return model_levels(heights_picture(midpoint_displacement((h, w), roughness, seed=seed)), g)


def test_fractal_models_session(window, qtbot):
    start = (window.document.levels.copy(), window.document.palette.copy())
    dialog = open_model_dialog(window, qtbot, "fractal_relief")
    dialog.width_box.setValue(48)
    dialog.height_box.setValue(40)
    dialog.levels.setValue(6)
    dialog.roughness.setValue(70)
    for seed in (3, 4, 5):                         # the latest wins
        dialog.seed.set_value(seed)
    assert not dialog.ok.isEnabled()
    assert dialog.wait() and not dialog.shaded_view.pixmap().isNull()    # the relief, shaded
    model_ok(dialog, qtbot)
    doc = window.document
    levels, palette = relief_levels(48, 40, 5, 0.7, 6)
    assert doc.shape == (40, 48) and doc.num_levels == 6
    assert np.array_equal(doc.levels, levels) and np.array_equal(doc.palette, palette)
    first = doc.levels.copy()

    dialog = open_model_dialog(window, qtbot, "fractal_relief")   # again, rougher
    assert dialog.width_box.value() == 48                    # the texture's size proposed
    dialog.roughness.setValue(20)
    dialog.seed.set_value(5)
    model_ok(dialog, qtbot)
    assert np.array_equal(doc.levels, relief_levels(48, 40, 5, 0.2, 6)[0])
    assert not np.array_equal(doc.levels, first)
    fill_a_cell(qtbot, window)
    before_motif = doc.levels.copy()

    dialog = open_model_dialog(window, qtbot, "ifs_motif")
    dialog.motif.setCurrentIndex(dialog.motif.findData("fern"))
    dialog.size_box.setValue(30)
    dialog.row_box.setValue(20)
    dialog.col_box.setValue(24)
    dialog.level.setValue(5)
    dialog.points.setValue(20_000)
    dialog.seed.set_value(2)
    model_ok(dialog, qtbot)
    mask = ifs_attractor("fern", (30, 30), points=20_000, seed=2) > 0
    expected = before_motif.copy()
    expected[5:35, 9:39][mask] = 5
    assert np.array_equal(doc.levels, expected)

    dialog = open_model_dialog(window, qtbot, "ifs_motif")          # again: the tree, elsewhere
    dialog.motif.setCurrentIndex(dialog.motif.findData("tree"))
    dialog.size_box.setValue(16)
    dialog.row_box.setValue(8)
    dialog.col_box.setValue(8)
    dialog.level.setValue(0)
    model_ok(dialog, qtbot)
    assert [a.TYPE for a in window.history.actions[-5:]] == [
        "fractal_relief", "fractal_relief", "fill", "ifs_motif", "ifs_motif"]
    after = doc.levels.copy()
    assert (after[0:16, 0:16] == 0).sum() > (expected[0:16, 0:16] == 0).sum()
    assert not window.errors

    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start[0])
    assert np.array_equal(window.document.palette, start[1])
    for _ in range(5):                                        # the five steps again
        window.act_redo.trigger()
    assert np.array_equal(window.document.levels, after)


def test_cancel_applies_nothing_and_a_motif_needs_a_texture(window, qtbot):
    steps = len(window.history.actions)
    dialog = open_model_dialog(window, qtbot, "fractal_relief")
    assert dialog.wait()
    dialog.reject()
    assert len(window.history.actions) == steps


def test_a_fractal_curve_spot_is_placed_with_its_roughness(window, qtbot):
    tool = spot_tool(window)
    editor = tool.editor
    editor.load(editor.library.get("Ellipse"))
    assert not editor.curve_roughness.isEnabled()
    editor.kind.setCurrentIndex(editor.kind.findData("fractal_curve"))
    assert editor.curve_roughness.isEnabled()
    assert editor.envelope.kind == "fractal_curve" and editor.envelope.roughness == 0.5
    smooth = editor.envelope.outline().copy()
    editor.curve_roughness.set_value(1.0)
    assert editor.envelope.roughness == 1.0
    assert not np.array_equal(editor.envelope.outline(), smooth)
    canvas = window.canvas
    start = window.document.levels.copy()
    click(canvas.viewport(), cell_pos(canvas, 30, 20))
    action = window.history.actions[-1]
    assert isinstance(action, PlaceSpot)
    assert '"kind":"fractal_curve"' in action.envelope and '"roughness":1.0' in action.envelope
    placed = window.document.levels.copy()
    assert not np.array_equal(placed, start)
    window.act_undo.trigger()
    assert np.array_equal(window.document.levels, start)
    window.act_redo.trigger()
    assert np.array_equal(window.document.levels, placed)
    editor.kind.setCurrentIndex(editor.kind.findData("catmull_rom"))    # back to smooth
    assert editor.envelope.kind == "catmull_rom" and not editor.curve_roughness.isEnabled()
