"""The region tools on a real canvas: Fill, Translate, Copy and Extract, driven by mouse and keys."""

import numpy as np
import pytest
from PySide6 import QtCore

from app.tools.regions import CopyTool, ExtractTool, FillTool, TranslateTool
from texeditor.recipe.actions import NewCanvas, ResizeCanvas, SetLevels

from .support import cell_pos, click, drag, edit_and_apply, hold, mouse, press_key

LEFT = QtCore.Qt.MouseButton.LeftButton


@pytest.fixture
def board(window):
    """A 40×30 canvas, G = 4: background 0, a 6×4 block of level 2 at x 5..10, y 4..7, and a
    level-3 block at x 25..29, y 10..14."""
    window.submit(NewCanvas(40, 30, 4))
    window.submit(SetLevels(4, 5, 4, 6, 2))
    window.submit(SetLevels(10, 25, 5, 5, 3))
    window.canvas.fit()
    return window


def drag_cells(window, a, b):
    canvas = window.canvas
    pa, pb = cell_pos(canvas, *a), cell_pos(canvas, *b)
    drag(canvas.viewport(), LEFT, (pa.x(), pa.y()), (pb.x(), pb.y()))


def test_fill_tool_fills_the_clicked_region_with_the_current_level(board, qtbot):
    press_key(board, QtCore.Qt.Key.Key_F)
    assert isinstance(board.tool, FillTool)
    board.palette_dock.swatches.current = 1
    steps = board.history.index
    click(board.canvas.viewport(), cell_pos(board.canvas, 7, 5))
    levels = board.document.levels
    assert (levels[4:8, 5:11] == 1).all() and (levels[10:15, 25:30] == 3).all()
    assert board.history.index == steps + 1
    board.undo()
    assert (board.document.levels[4:8, 5:11] == 2).all()


def test_translate_tool_moves_the_region_and_shows_a_ghost_while_dragging(board, qtbot):
    press_key(board, QtCore.Qt.Key.Key_M)
    assert isinstance(board.tool, TranslateTool)
    canvas = board.canvas
    start, mid = cell_pos(canvas, 6, 5), cell_pos(canvas, 9, 9)
    none = QtCore.Qt.MouseButton.NoButton
    Type = QtCore.QEvent.Type
    mouse(canvas.viewport(), Type.MouseButtonPress, start, LEFT, LEFT)
    for k in range(1, 4):
        qtbot.wait(25)
        p = QtCore.QPoint(start.x() + (mid.x() - start.x()) * k // 3,
                          start.y() + (mid.y() - start.y()) * k // 3)
        mouse(canvas.viewport(), Type.MouseMove, p, none, LEFT)
    assert canvas.overlay.isVisible()          # the ghost follows the pointer
    assert board.history.index == 4            # nothing is applied before the release
    mouse(canvas.viewport(), Type.MouseButtonRelease, mid, LEFT, none)
    levels = board.document.levels
    assert not canvas.overlay.isVisible()
    assert (levels[8:12, 8:14] == 2).all() and np.count_nonzero(levels == 2) == 24
    assert (levels[4:8, 5:8] == 0).all()       # left behind: the background


def test_copy_tool_keeps_the_source(board, qtbot):
    press_key(board, QtCore.Qt.Key.Key_C)
    assert isinstance(board.tool, CopyTool)
    drag_cells(board, (26, 11), (26, 20))
    levels = board.document.levels
    assert (levels[10:15, 25:30] == 3).all() and (levels[19:24, 25:30] == 3).all()


def test_extract_selects_then_recolours_deletes_and_duplicates(board, qtbot):
    press_key(board, QtCore.Qt.Key.Key_E)
    tool = board.tool
    assert isinstance(tool, ExtractTool)
    click(board.canvas.viewport(), cell_pos(board.canvas, 27, 12))
    assert board.canvas.overlay.isVisible() and "25 points" in tool.status.text()
    board.palette_dock.swatches.current = 1
    qtbot.mouseClick(tool.panel.recolour, LEFT)
    assert (board.document.levels[10:15, 25:30] == 1).all()
    tool.panel.dx.setValue(-20)
    tool.panel.dy.setValue(0)
    qtbot.mouseClick(tool.panel.duplicate, LEFT)
    assert (board.document.levels[10:15, 5:10] == 1).all()
    qtbot.mouseClick(tool.panel.delete, LEFT)
    assert (board.document.levels[10:15, 25:30] == 0).all()
    assert not tool.panel.isEnabled()          # nothing left selected
    board.undo()
    assert (board.document.levels[10:15, 25:30] == 1).all()


def test_extract_neighbours_selects_every_region_touching_the_clicked_one(board, qtbot):
    board.submit(SetLevels(8, 5, 1, 6, 3))      # a strip of 3 under the block of 2
    press_key(board, QtCore.Qt.Key.Key_E)
    tool = board.tool
    tool.opts.kind.setCurrentIndex(tool.opts.kind.findData("neighbours"))
    click(board.canvas.viewport(), cell_pos(board.canvas, 7, 5))
    mask = tool.mask()
    assert mask[8, 5:11].all() and mask[3, 5:11].all()   # the strip and the background around
    assert not mask[4:8, 5:11].any()                      # not the clicked block itself


def test_extract_steps_through_the_neighbours_one_at_a_time_and_acts_on_one(board, qtbot):
    """LIMITROPHES/ISOLER: the block of 2 touches the background (found first), a strip of 1
    on its right (second) and a strip of 3 under it (third); each is selected alone in turn,
    the second is recoloured, undone, and the stepper comes back round to all of them."""
    from texeditor.recipe.replay import replay
    from texeditor.regions.actions import ChangeLevel, DeleteSelection

    board.submit(SetLevels(4, 11, 4, 2, 1))       # the strip of 1, x 11..12, y 4..7
    board.submit(SetLevels(8, 5, 1, 6, 3))        # the strip of 3, x 5..10, y 8
    start = board.document.levels.copy()
    press_key(board, QtCore.Qt.Key.Key_E)
    tool = board.tool
    tool.opts.kind.setCurrentIndex(tool.opts.kind.findData("neighbours"))
    click(board.canvas.viewport(), cell_pos(board.canvas, 7, 5))
    stepper = tool.neighbours
    assert stepper.isVisible() and stepper.label.text() == "All 3 neighbours"
    background = start == 0
    strip1, strip3 = np.zeros_like(background), np.zeros_like(background)
    strip1[4:8, 11:13] = True
    strip3[8, 5:11] = True
    assert np.array_equal(tool.mask(), background | strip1 | strip3)
    for k, expected in ((1, background), (2, strip1)):
        qtbot.mouseClick(stepper.next, LEFT)
        assert stepper.label.text() == f"Neighbour {k} of 3"
        assert np.array_equal(tool.mask(), expected)
        assert f"{int(expected.sum())} points selected (neighbour {k}" in tool.status.text()
    board.palette_dock.swatches.current = 2
    qtbot.mouseClick(tool.panel.recolour, LEFT)                    # the second one only
    assert board.history.actions[-1] == ChangeLevel(5, 7, 2, kind="neighbours", neighbour=2)
    expected = start.copy()
    expected[strip1] = 2
    assert np.array_equal(board.document.levels, expected)         # it joins the block of 2
    again = replay(board.history.applied, board.document.dpjs)
    assert again.result_hash() == board.document.result_hash()
    board.undo()
    assert np.array_equal(board.document.levels, start)
    assert stepper.label.text() == "Neighbour 2 of 3" and np.array_equal(tool.mask(), strip1)
    qtbot.mouseClick(stepper.next, LEFT)
    assert np.array_equal(tool.mask(), strip3)
    qtbot.mouseClick(tool.panel.delete, LEFT)                      # the same panel, again
    assert board.history.actions[-1] == DeleteSelection(5, 7, kind="neighbours", neighbour=3)
    assert not board.document.levels[strip3].any()
    board.undo()
    click(board.canvas.viewport(), cell_pos(board.canvas, 7, 5))   # a new click: all of them
    assert stepper.label.text() == "All 3 neighbours"
    qtbot.mouseClick(stepper.previous, LEFT)                       # back from all: the last
    assert np.array_equal(tool.mask(), strip3)
    qtbot.mouseClick(stepper.next, LEFT)
    assert stepper.label.text() == "All 3 neighbours"
    tool.opts.kind.setCurrentIndex(tool.opts.kind.findData("region"))
    click(board.canvas.viewport(), cell_pos(board.canvas, 7, 5))
    assert not stepper.isVisible()
    assert np.array_equal(board.document.levels, start)


def test_global_operators_dialog_rotates_the_whole_texture_or_the_selection(board, qtbot):
    from texeditor.regions import transforms

    before = board.document.levels.copy()
    qtbot.keyClick(board, QtCore.Qt.Key.Key_G, QtCore.Qt.KeyboardModifier.ControlModifier)
    dialog = board._global_dialog
    assert dialog.isVisible() and "whole texture" in dialog.target.text()
    dialog.operator.setCurrentIndex(dialog.operator.findData("isometry"))
    dialog.angle.setValue(90)
    dialog.wrap.setChecked(False)
    qtbot.mouseClick(dialog.apply_button, LEFT)
    expected = transforms.isometry(before, 90, (14.5, 19.5))
    assert np.array_equal(board.document.levels, expected)
    board.undo()
    # with a selection, only the selection is copied: 2 copies side by side, the first 10 left
    press_key(board, QtCore.Qt.Key.Key_E)
    click(board.canvas.viewport(), cell_pos(board.canvas, 27, 12))
    dialog.operator.setCurrentIndex(dialog.operator.findData("identity"))
    dialog.dx.setValue(-10)
    dialog.dy.setValue(0)
    dialog.copies.setValue(2)
    assert "selection" in dialog.target.text()
    qtbot.mouseClick(dialog.apply_button, LEFT)
    levels = board.document.levels
    assert (levels[10:15, 15:20] == 3).all() and (levels[10:15, 20:25] == 3).all()
    assert (levels[4:8, 5:11] == 2).all()


def test_a_selection_left_off_a_smaller_canvas_is_not_acted_on(board, qtbot):
    """A selection clicked on the 40×30 canvas, then a smaller canvas (a new texture, a model,
    an undo): the global operators act on the whole texture instead of failing on a point
    that is no longer there; a click on the canvas selects again, then Ctrl+Z walks back."""
    from texeditor.regions import transforms

    press_key(board, QtCore.Qt.Key.Key_E)
    click(board.canvas.viewport(), cell_pos(board.canvas, 27, 12))       # the level-3 block
    assert board.tool.live_selection() is not None
    steps = board.history.index
    board.submit(ResizeCanvas(10, 20, 0))
    board.canvas.fit()
    assert board.tool.live_selection() is None and board.tool.mask() is None
    qtbot.keyClick(board, QtCore.Qt.Key.Key_G, QtCore.Qt.KeyboardModifier.ControlModifier)
    dialog = board._global_dialog
    assert "whole texture" in dialog.target.text()
    dialog.operator.setCurrentIndex(dialog.operator.findData("isometry"))
    dialog.angle.setValue(180)
    dialog.wrap.setChecked(False)
    before = board.document.levels.copy()
    qtbot.mouseClick(dialog.apply_button, LEFT)
    assert not board.errors
    assert np.array_equal(board.document.levels, transforms.isometry(before, 180, (4.5, 9.5)))
    dialog.close()
    click(board.canvas.viewport(), cell_pos(board.canvas, 3, 3))
    assert board.tool.live_selection() is not None
    while board.history.index > steps:
        board.undo()
    assert board.document.shape == (30, 40)


def test_scatter_every_region_from_the_global_dialog_then_undo_to_the_start(board, qtbot):
    """Random manipulation of all regions (§3.4.3): the whole texture, again with the same seed
    (on the scattered texture), a level only, then the Extract selection; undo to the start."""
    from texeditor.regions.actions import ScatterRegions
    from texeditor.regions.scatter import scatter_regions

    board.submit(SetLevels(20, 5, 3, 3, 1))          # a third region, of level 1
    start = board.document.levels.copy()
    steps = board.history.index
    qtbot.keyClick(board, QtCore.Qt.Key.Key_G, QtCore.Qt.KeyboardModifier.ControlModifier)
    dialog = board._global_dialog
    dialog.operator.setCurrentIndex(dialog.operator.findData("scatter"))
    assert dialog.seed.isVisible() and not dialog.angle.isVisible()
    assert dialog.target.text() == "Applies to every region of the whole texture."
    dialog.radius.setValue(4)
    dialog.rotation.setCurrentIndex(dialog.rotation.findData("any"))
    dialog.scale_min.setValue(0.5)
    dialog.scale_max.setValue(1.5)
    dialog.wrap.setChecked(False)
    dialog.seed.set_value(11)
    expected = scatter_regions(start, 11, radius=4, rotation="any", scale=(0.5, 1.5))
    assert not np.array_equal(expected, start)
    qtbot.mouseClick(dialog.apply_button, LEFT)
    assert np.array_equal(board.document.levels, expected)
    qtbot.mouseClick(dialog.apply_button, LEFT)      # the same seed on the scattered texture
    expected = scatter_regions(expected, 11, radius=4, rotation="any", scale=(0.5, 1.5))
    assert np.array_equal(board.document.levels, expected)
    board.undo()
    board.undo()
    assert np.array_equal(board.document.levels, start)

    dialog.level.setValue(3)                         # the level-3 block only, moved
    dialog.rotation.setCurrentIndex(dialog.rotation.findData("none"))
    dialog.radius.setValue(3)
    dialog.scale_min.setValue(1)
    dialog.scale_max.setValue(1)
    dialog.fill.setValue(1)
    assert dialog.target.text() == "Applies to every region of level 3."
    qtbot.mouseClick(dialog.apply_button, LEFT)
    assert board.history.actions[-1] == ScatterRegions(11, radius=3, level=3, fill=1)
    expected = scatter_regions(start, 11, mask=start == 3, radius=3, fill=1)
    assert np.array_equal(board.document.levels, expected) and (expected != start).any()
    assert (board.document.levels[4:8, 5:11] == 2).all()

    dialog.scale_min.setValue(2)                     # a range upside down: said, not applied
    qtbot.mouseClick(dialog.apply_button, LEFT)
    assert board.errors and "scale_min" in board.errors[-1][1]
    dialog.scale_min.setValue(1)

    press_key(board, QtCore.Qt.Key.Key_E)            # with a selection: it, not the level
    click(board.canvas.viewport(), cell_pos(board.canvas, 7, 5))
    dialog._show_target()                            # as when the dialog is activated again
    assert not dialog.level.isEnabled() and "selection at x 7, y 5" in dialog.target.text()
    before = board.document.levels.copy()
    dialog.radius.setValue(6)
    qtbot.mouseClick(dialog.apply_button, LEFT)
    action = board.history.actions[-1]
    assert (action.row, action.col, action.level) == (5, 7, None)
    assert np.array_equal(board.document.levels, scatter_regions(
        before, 11, mask=before == 2, radius=6, fill=1))
    while board.history.index > steps:
        board.undo()
    assert np.array_equal(board.document.levels, start)


def test_a_scatter_step_edited_in_the_history_draws_again_with_its_new_seed(board, qtbot):
    from texeditor.regions.scatter import scatter_regions

    start = board.document.levels.copy()
    qtbot.keyClick(board, QtCore.Qt.Key.Key_G, QtCore.Qt.KeyboardModifier.ControlModifier)
    dialog = board._global_dialog
    dialog.operator.setCurrentIndex(dialog.operator.findData("scatter"))
    dialog.radius.setValue(5)
    dialog.seed.set_value(1)
    qtbot.mouseClick(dialog.apply_button, LEFT)
    step = board.history.index - 1
    assert np.array_equal(board.document.levels,
                          scatter_regions(start, 1, radius=5, rotation="quarter", wrap=True))
    edit_and_apply(qtbot, board, step, "seed", "2")
    assert board.history.actions[step].seed == 2
    assert np.array_equal(board.document.levels,
                          scatter_regions(start, 2, radius=5, rotation="quarter", wrap=True))


def test_a_large_scatter_is_drawn_in_the_worker_and_not_applied_over_an_edit(board, qtbot,
                                                                             monkeypatch):
    """A scatter of a large texture runs in the worker (here every texture is large): the
    window stays live, the step is the same; a texture edited meanwhile is not overwritten."""
    import app.global_dialog
    from texeditor.regions.actions import ScatterRegions
    from texeditor.regions.scatter import scatter_regions
    monkeypatch.setattr(app.global_dialog, "IN_WORKER", 1)
    start, steps = board.document.levels.copy(), len(board.history.actions)
    qtbot.keyClick(board, QtCore.Qt.Key.Key_G, QtCore.Qt.KeyboardModifier.ControlModifier)
    dialog = board._global_dialog
    dialog.operator.setCurrentIndex(dialog.operator.findData("scatter"))
    dialog.radius.setValue(4)
    dialog.wrap.setChecked(False)
    dialog.seed.set_value(11)
    qtbot.mouseClick(dialog.apply_button, LEFT)
    assert board.runner.busy and len(board.history.actions) == steps   # in the worker
    assert board.runner.wait(30_000)
    assert isinstance(board.history.actions[-1], ScatterRegions)
    assert np.array_equal(board.document.levels, scatter_regions(start, 11, radius=4))
    board.undo()
    assert np.array_equal(board.document.levels, start)

    started, gate = hold(monkeypatch, ScatterRegions, "scattered")
    qtbot.mouseClick(dialog.apply_button, LEFT)
    assert started.wait(30) and board.runner.busy
    board.submit(SetLevels(0, 0, 2, 2, 1))          # an edit while it is drawn
    edited = board.document.levels.copy()
    gate.set()
    assert board.runner.wait(30_000)
    assert np.array_equal(board.document.levels, edited)            # the edit kept
    assert len(board.history.actions) == steps + 1                  # no scatter over it
    assert "changed meanwhile" in board.statusBar().currentMessage()
    qtbot.mouseClick(dialog.apply_button, LEFT)                     # applied again: in
    assert board.runner.wait(30_000)
    assert np.array_equal(board.document.levels, scatter_regions(edited, 11, radius=4))
    assert not board.errors
    dialog.close()
