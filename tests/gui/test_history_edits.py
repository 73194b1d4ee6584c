"""Editing a past step from the History dock, as a user does it: Apply & replay is one undoable
step, later region steps that now act on another region are marked, and a change that changes
nothing adds no step. Asserts are on the document and on what the History list shows."""

import numpy as np
from PySide6 import QtCore

from texeditor.recipe.actions import SetLevels, SetPalette
from texeditor.regions.actions import Fill

from .support import cell_pos, click, edit_and_apply, recipe

CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier
LEFT = QtCore.Qt.MouseButton.LeftButton
DISPLAY = QtCore.Qt.ItemDataRole.DisplayRole


def row_text(window, row: int) -> str:
    model = window.history_dock.model
    return model.data(model.index(row), DISPLAY)


def test_apply_and_replay_is_undone_and_redone_with_the_keys(qtbot, window):
    red = np.array([[0, 0, 0], [200, 0, 0], [0, 200, 0], [0, 0, 200]], np.uint8)
    window.submit(SetPalette(red))
    window.submit(SetLevels(2, 2, 5, 5, 3))
    labels = window.history.labels()
    before = edit_and_apply(qtbot, window, 0, "seed", "4242")   # clicked: at step 1 of 3
    after = recipe(window)
    assert window.history.actions[0].seed == 4242 and window.history.index == 3
    assert "Ctrl+Z undoes the edit" in window.statusBar().currentMessage()

    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)          # the whole edit, in one step
    assert recipe(window) == before and window.history.labels() == labels
    assert np.array_equal(window.canvas.levels, window.history.document.levels)
    assert window.history_dock.form.editor("seed").value() == 7
    assert not window.act_undo.isEnabled()                   # at the base step again
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL | SHIFT)
    assert recipe(window) == after
    assert window.history_dock.form.editor("seed").value() == 4242
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    dock = window.history_dock                                 # the old later steps are there
    qtbot.mouseClick(dock.view.viewport(), LEFT, pos=dock.row_rect(2).center())
    assert window.history.index == 3 and window.history.actions[0].seed == 7
    assert window.history.labels() == labels and not window.act_redo.isEnabled()
    assert np.array_equal(window.document.palette, red)


def test_an_edit_of_a_base_step_can_be_undone_at_step_one(qtbot, window):
    first = edit_and_apply(qtbot, window, 0, "seed", "31")
    assert window.history.index == 1 and window.act_undo.isEnabled()
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    assert recipe(window) == first and not window.act_undo.isEnabled()


def test_later_region_steps_that_now_act_elsewhere_are_marked(qtbot, window):
    h, w = window.document.shape
    window.submit(SetLevels(0, 0, h, w, 0))                  # a flat background...
    window.submit(SetLevels(4, 4, 6, 6, 1))                  # ...a square (step 3)...
    window.submit(Fill(6, 6, 2))                             # ...filled (step 4)
    window.submit(Fill(30, 30, 3))                           # the background filled (step 5)
    window.submit(SetLevels(40, 40, 2, 2, 1))                # no region: never marked
    assert not any(row_text(window, r).startswith("⚠") for r in range(6))
    edit_and_apply(qtbot, window, 2, "width", "12")          # the square grows
    marked = [r for r in range(6) if row_text(window, r).startswith("⚠")]
    assert marked == [3, 4]
    assert window.retargeted_label.text() == "⚠ 2 step(s) re-targeted"
    assert "2 later step(s) now act on a different region" in window.statusBar().currentMessage()
    levels = window.document.levels
    assert (levels[4:10, 4:16] == 2).all()                   # the fill followed the new square
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    assert window.retargeted_label.text() == ""
    assert not any(row_text(window, r).startswith("⚠") for r in range(6))


def test_a_fill_that_changes_nothing_adds_no_step_and_says_so(qtbot, window):
    qtbot.keyClick(window, QtCore.Qt.Key.Key_F)
    canvas = window.canvas
    level = int(window.document.levels[10, 10])
    window.palette_dock.swatches.current = level
    steps, before = window.history.index, recipe(window)
    click(canvas.viewport(), cell_pos(canvas, 10, 10))
    assert window.history.index == steps and recipe(window) == before
    assert "changes nothing" in window.statusBar().currentMessage()
    window.palette_dock.swatches.current = (level + 1) % window.document.num_levels
    click(canvas.viewport(), cell_pos(canvas, 10, 10))       # another level: a step
    assert window.history.index == steps + 1
    assert window.document.levels[10, 10] == (level + 1) % window.document.num_levels
    click(canvas.viewport(), cell_pos(canvas, 10, 10))       # the same click again: none
    assert window.history.index == steps + 1


def test_the_step_form_counts_points_colours_and_recipes_in_good_english():
    from app.params_form import ParamsForm
    assert ParamsForm._describe("points", [(3, 4)]) == "1 point"
    assert ParamsForm._describe("points", [(3, 4), (5, 6)]) == "2 points"
    assert ParamsForm._describe("palette", [(0, 0, 0)]).startswith("1 colour (")
    assert ParamsForm._describe("texts", ["a", "b"]).startswith("2 texture recipes (")


def test_a_scale_is_summed_up_with_what_it_is_drawn_given():
    """A photo model's scales as the Synthesis dock and the History form name them: the
    coarsest a plain DPJ, the one over it given its parents' 2 levels and the row's phase (16
    composite levels), the finest given 4."""
    import skimage as ski
    from app.params_form import dpj_summary
    from texeditor.markov.multiscale import estimate_scales
    model, _ = estimate_scales(ski.data.brick()[:128, :128], scales=3)
    said = [dpj_summary(d) for d in model.dpjs]
    assert "G = 2," in said[0]
    assert "G = 4 given 2 and the row's phase (16 composite levels)" in said[1]
    assert "G = 4 given 4 (16 composite levels)" in said[2]
