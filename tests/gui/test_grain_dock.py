"""The Grain rendering dock, the composition dialog and the doubling dialog (issue 9), driven by
mouse and keys on the real widgets; every check is on the document."""

import numpy as np
import pytest
from PySide6 import QtCore, QtWidgets

from app.grain_rendering_dock import grain_step
from app.tools.regions import FillTool
from texeditor.texture import grain_render as gr
from texeditor.regions import extractext as regions
from texeditor.recipe.replay import replay
from texeditor.texture.actions import DoubleLevels, Incrust, Mix, RenderGrains

from .support import cell_pos, click, drag, hold, press_key

LEFT = QtCore.Qt.MouseButton.LeftButton


@pytest.fixture
def dock(window):
    d = window.density_dock
    d.show()
    d.raise_()
    window.canvas.fit()
    QtWidgets.QApplication.processEvents()
    return d


def handle_pos(vs, value=None) -> QtCore.QPoint:
    """Where a ValueSlider's handle is drawn (for ``value``: where it would be)."""
    s = vs.slider
    style = s.style()
    length = style.pixelMetric(QtWidgets.QStyle.PixelMetric.PM_SliderLength, None, s)
    v = s.value() if value is None else round(value * vs.scale)
    x = QtWidgets.QStyle.sliderPositionFromValue(s.minimum(), s.maximum(), v,
                                                 s.width() - length)
    return QtCore.QPoint(x + length // 2, s.height() // 2)


def slide(vs, value) -> None:
    """Drag the slider's handle with the mouse to (about) ``value``; the release commits."""
    a, b = handle_pos(vs), handle_pos(vs, value)
    drag(vs.slider, LEFT, (a.x(), a.y()), (b.x(), b.y()))


def settled(window, qtbot) -> None:
    assert window.runner.wait(60_000)
    qtbot.wait(10)


def test_moving_size_and_density_sliders_renders_the_document_and_undo_returns(window, dock,
                                                                                qtbot):
    normal = window.document.levels.copy()
    steps = window.history.index
    slide(dock.size_slider, 6)
    settled(window, qtbot)
    size = dock.size_slider.value()
    assert size > 1 and dock.size_slider.slider.isSliderDown() is False
    assert window.history.index == steps + 1
    assert window.document.shape == (48 * size, 64 * size)
    assert np.array_equal(window.document.levels, gr.render(normal, "square", size))

    slide(dock.explode_x, 2.0)
    settled(window, qtbot)
    ex = dock.explode_x.value()
    assert ex > 1.0
    assert window.history.index == steps + 1              # the same grain step, edited
    assert np.array_equal(window.document.levels,
                          gr.render(normal, "square", size, explosion_x=ex))
    assert window.document.shape[1] == 64 * round(size * ex)

    slide(dock.compression, 0.5)
    settled(window, qtbot)
    comp = dock.compression.value()
    assert np.array_equal(window.document.levels,
                          gr.render(normal, "square", size, explosion_x=ex, compression=comp))

    # each setting is one undoable edit of the grain step; the controls follow every undo/redo
    states = [(1, 1.0, 0.0), (size, 1.0, 0.0), (size, ex, 0.0), (size, ex, comp)]
    for expect in reversed(states[:-1]):
        window.act_undo.trigger()
        assert (dock.size_slider.value(), dock.explode_x.value(), dock.compression.value()) == \
            expect
        if expect[0] > 1:
            assert np.array_equal(window.document.levels, gr.render(
                normal, "square", expect[0], explosion_x=expect[1], compression=expect[2]))
    assert np.array_equal(window.document.levels, normal)  # back to the normalised texture
    for expect in states[1:]:
        window.act_redo.trigger()
        assert (dock.size_slider.value(), dock.explode_x.value(), dock.compression.value()) == \
            expect
    assert np.array_equal(window.document.levels,
                          gr.render(normal, "square", size, explosion_x=ex, compression=comp))


def test_changing_the_shape_renders_hexagons_on_a_honeycomb(window, dock, qtbot):
    normal = window.document.levels.copy()
    slide(dock.size_slider, 8)
    settled(window, qtbot)
    size = dock.size_slider.value()
    dock.shape_box.setCurrentIndex(dock.shape_box.findData("hexagon"))
    settled(window, qtbot)
    assert np.array_equal(window.document.levels, gr.render(normal, "hexagon", size))
    assert "odd rows shifted" in dock.info.text()
    assert not dock.preview.pixmap().isNull()


def test_compression_along_one_axis_then_both_and_undo_to_the_start(window, dock, qtbot):
    """Unlinked, the sliders compress across and down apart; each setting is one edit of the
    grain step, and undo brings the controls and the document back step by step."""
    normal = window.document.levels.copy()
    slide(dock.size_slider, 6)
    settled(window, qtbot)
    size = dock.size_slider.value()
    assert not dock.compression_x.isEnabled()               # linked: across follows down
    steps = window.history.index
    qtbot.mouseClick(dock.same_compression, LEFT,
                     pos=QtCore.QPoint(6, dock.same_compression.height() // 2))
    settled(window, qtbot)
    assert not dock.same_compression.isChecked() and dock.compression_x.isEnabled()
    assert window.history.index == steps                    # unlinking alone changes nothing
    slide(dock.compression_x, 0.5)
    settled(window, qtbot)
    across = dock.compression_x.value()
    assert across > 0.3 and dock.compression.value() == 0
    step = window.history.actions[grain_step(window.history)]
    assert (step.compression, step.compression_x) == (0.0, across)
    assert window.document.shape == (48 * size, 64 * round(size * (1 - across)))
    assert np.array_equal(window.document.levels,
                          gr.render(normal, "square", size, compression=0, compression_x=across))
    assert "across" in dock.info.text()
    slide(dock.compression, 0.3)                            # now down too, by its own amount
    settled(window, qtbot)
    down = dock.compression.value()
    assert dock.compression_x.value() == across
    assert np.array_equal(window.document.levels, gr.render(
        normal, "square", size, compression=down, compression_x=across))
    window.act_undo.trigger()
    assert (dock.compression.value(), dock.compression_x.value()) == (0.0, across)
    assert not dock.same_compression.isChecked()
    window.act_undo.trigger()                               # before the size: linked again
    assert dock.same_compression.isChecked() and dock.size_slider.value() == size
    window.act_undo.trigger()
    assert np.array_equal(window.document.levels, normal)
    assert dock.same_compression.isChecked() and not dock.compression_x.isEnabled()


def test_editing_the_grain_size_after_a_fill_replays_the_fill(window, dock, qtbot):
    normal = window.document.levels.copy()
    slide(dock.size_slider, 4)
    settled(window, qtbot)
    size = dock.size_slider.value()
    grain_index = grain_step(window.history)
    # a later edit: the Fill tool clicked on the rendered canvas
    press_key(window, QtCore.Qt.Key.Key_F)
    assert isinstance(window.tool, FillTool)
    window.palette_dock.swatches.current = 0
    window.canvas.fit()
    qtbot.wait(20)
    click(window.canvas.viewport(), cell_pos(window.canvas, 5, 5))
    fill = window.history.actions[-1]
    assert window.history.index == grain_index + 2 and fill.TYPE == "fill"

    slide(dock.size_slider, 7)                                   # back in the dock: a new size
    settled(window, qtbot)
    new = dock.size_slider.value()
    assert new != size
    assert window.history.actions[grain_index] == RenderGrains("square", new)
    assert window.history.actions[grain_index + 1] == fill   # the fill is still there...
    rendered = gr.render(normal, "square", new)
    expect = regions.fill(rendered, (fill.row, fill.col), fill.value)
    assert not np.array_equal(expect, rendered)
    assert np.array_equal(window.document.levels, expect)    # ...replayed on the new canvas
    again = replay(window.history.applied, window.document.dpjs)
    assert again.result_hash() == window.document.result_hash()


def test_keyboard_steps_commit_after_a_pause(window, dock, qtbot):
    dock.size_slider.slider.setFocus()
    for _ in range(3):
        press_key(dock.size_slider.slider, QtCore.Qt.Key.Key_Right)
    assert dock.size_slider.value() == 4
    qtbot.waitUntil(lambda: grain_step(window.history) is not None, timeout=5000)
    assert window.document.shape == (48 * 4, 64 * 4)


# -- composition -------------------------------------------------------------------------------

def open_composition(window, qtbot):
    window.act_compose.trigger()
    dialog = window.composition_dialog
    qtbot.waitExposed(dialog)
    settled(window, qtbot)
    return dialog


def test_incrust_a_synthesis_where_this_texture_is_background(window, qtbot):
    before = window.document.levels.copy()
    assert (before == 0).any()
    dialog = open_composition(window, qtbot)
    dialog.tabs.setCurrentIndex(0)
    dialog.mask_kind.setCurrentIndex(dialog.mask_kind.findData("levels"))
    dialog.mask_levels.setText("0")
    dialog.source.seed.set_value(99)
    dialog.update_preview()
    settled(window, qtbot)
    assert "points change" in dialog.status.text()
    assert np.array_equal(window.document.levels, before)    # a preview never edits
    dialog.apply_button.click()
    settled(window, qtbot)
    action = window.history.actions[-1]
    assert isinstance(action, Incrust) and action.mask == "levels"
    from texeditor.recipe.sources import render_recipe
    t2, _ = render_recipe(action.source, {r: window.document.dpjs[r]
                                          for r in action.source_dpjs})
    assert np.array_equal(window.document.levels, np.where(before == 0, t2, before))
    window.act_undo.trigger()
    assert np.array_equal(window.document.levels, before)
    dialog.close()


def test_incrust_by_blocks_then_point_by_point_and_undo(window, qtbot):
    """Blocks (pavés): where this texture is background on half a block of 4×4 or more, the
    whole block shows T2; then the same point by point; undo twice gives the start back."""
    from texeditor.recipe.sources import render_recipe
    from texeditor.texture.composition import by_blocks

    before = window.document.levels.copy()
    dialog = open_composition(window, qtbot)
    dialog.tabs.setCurrentIndex(0)
    dialog.mask_kind.setCurrentIndex(dialog.mask_kind.findData("levels"))
    dialog.mask_levels.setText("0")
    dialog.source.seed.set_value(99)
    dialog.block.setFocus()
    for _ in range(3):                                      # 1 → 4, with the keyboard
        press_key(dialog.block, QtCore.Qt.Key.Key_Up)
    assert dialog.block.value() == 4
    dialog.update_preview()
    settled(window, qtbot)
    assert "by blocks of 4" in dialog.status.text()
    dialog.apply_button.click()
    settled(window, qtbot)
    action = window.history.actions[-1]
    assert isinstance(action, Incrust) and action.block == 4
    t2, _ = render_recipe(action.source, {r: window.document.dpjs[r] for r in action.source_dpjs})
    blocks = by_blocks(before == 0, 4)
    assert np.array_equal(window.document.levels, np.where(blocks, t2, before))
    assert blocks.any() and not np.array_equal(blocks, before == 0)
    dialog.block.setValue(1)
    dialog.update_preview()
    settled(window, qtbot)
    dialog.apply_button.click()
    settled(window, qtbot)
    assert window.history.actions[-1].block == 1
    window.act_undo.trigger()
    window.act_undo.trigger()
    assert np.array_equal(window.document.levels, before)
    dialog.close()


def test_mix_preset_xor_with_another_seed(window, qtbot):
    before = window.document.levels.copy()
    dialog = open_composition(window, qtbot)
    dialog.tabs.setCurrentIndex(1)
    dialog.preset.setCurrentIndex(dialog.preset.findText("Exclusive or"))
    dialog.source.seed.set_value(5)
    dialog.apply_button.setEnabled(True)
    dialog.apply_button.click()
    settled(window, qtbot)
    action = window.history.actions[-1]
    assert isinstance(action, Mix) and action.op2 == "xor"
    assert not np.array_equal(window.document.levels, before)
    dialog.close()


def test_painted_incrustation_changes_only_the_painted_points(window, qtbot):
    before = window.document.levels.copy()
    dialog = open_composition(window, qtbot)
    dialog.tabs.setCurrentIndex(0)
    dialog.mask_kind.setCurrentIndex(dialog.mask_kind.findData("painted"))
    dialog.source.seed.set_value(11)
    dialog.radius.setValue(2)
    settled(window, qtbot)
    preview = dialog.preview
    a = QtCore.QPoint(preview._origin[0] + int(10.5 * preview._scale),
                      preview._origin[1] + int(10.5 * preview._scale))
    b = QtCore.QPoint(a.x() + int(20 * preview._scale), a.y())
    drag(preview, LEFT, (a.x(), a.y()), (b.x(), b.y()))
    assert preview.painted_mask.sum() > 20
    dialog.update_preview()
    settled(window, qtbot)
    dialog.apply_button.click()
    settled(window, qtbot)
    action = window.history.actions[-1]
    assert isinstance(action, Incrust) and action.mask == "points"
    changed = window.document.levels != before
    assert changed.any() and not changed[~preview.painted_mask].any()
    assert {tuple(p) for p in action.points} == set(map(tuple, np.argwhere(preview.painted_mask)))
    dialog.close()


# -- doubling ----------------------------------------------------------------------------------

def test_double_the_levels_from_the_photo(window, qtbot):
    before = window.document.levels.copy()
    g = window.document.num_levels
    window.act_double.trigger()
    dialog = window.doubling_dialog
    qtbot.waitExposed(dialog)
    assert dialog.wait()                            # learnt in the worker, the window live
    assert dialog.apply_button.isEnabled(), dialog.info.text()
    assert "neighbours" in dialog.info.text()
    qtbot.waitUntil(lambda: dialog.info.geometry().top()            # the report, arrived
                    >= dialog.result_view.geometry().bottom())      # late, not over the views
    first = dialog.result_view.pixmap().toImage()
    dialog.seed.set_value(2)                        # a new seed: the preview only, not relearnt
    assert not dialog.apply_button.isEnabled()
    assert dialog.wait() and dialog.apply_button.isEnabled()
    assert len(dialog.learnt) == 1 and dialog.result_view.pixmap().toImage() != first
    dialog.apply_button.click()                     # doubled in the worker, then applied
    assert window.runner.wait(60_000)
    doc = window.document
    assert isinstance(window.history.actions[-1], DoubleLevels)
    assert doc.num_levels == 2 * g and np.array_equal(doc.levels // 2, before)
    assert window.history.actions[-1].seed == 2
    window.act_undo.trigger()
    assert doc.num_levels == g and np.array_equal(doc.levels, before)


def test_cancel_while_the_levels_are_doubled_adds_no_step(window, qtbot, monkeypatch):
    import shiboken6
    started, gate = hold(monkeypatch, DoubleLevels, "doubled")
    before, steps = window.document.levels.copy(), len(window.history.actions)
    window.act_double.trigger()
    dialog = window.doubling_dialog
    assert dialog.wait()
    dialog.apply_button.click()
    assert started.wait(30) and window.runner.busy and not dialog.apply_button.isEnabled()
    dialog.reject()                                 # Cancel while it works
    gate.set()
    assert window.runner.wait(60_000)
    assert len(window.history.actions) == steps
    assert np.array_equal(window.document.levels, before) and not window.errors
    window.act_double.trigger()                     # and again, to the end this time
    dialog = window.doubling_dialog
    assert dialog.wait()
    dialog.apply_button.click()
    assert window.runner.wait(60_000)
    assert not shiboken6.isValid(dialog) or not dialog.isVisible()     # closed once applied
    assert isinstance(window.history.actions[-1], DoubleLevels)
    assert np.array_equal(window.document.levels // 2, before)


def test_double_the_levels_from_a_photo_that_cannot_be_read(window, qtbot, tmp_path):
    bad = tmp_path / "torn.jpg"
    bad.write_bytes(b"\xff\xd8\xff torn")
    window.act_double.trigger()
    dialog = window.doubling_dialog
    dialog.set_photo(bad)
    assert dialog.wait()
    assert "torn.jpg" in dialog.info.text() and not dialog.apply_button.isEnabled()
    dialog.photo.setCurrentIndex(0)                 # back to a good photo: Double again
    assert dialog.wait() and dialog.apply_button.isEnabled()
    dialog.reject()


# -- the output size, said before rendering; slow renders in the worker (issue 16) ----------------

def test_output_size_is_said_live_before_rendering(window, dock, qtbot):
    steps = len(window.history.actions)
    dock.size_slider.slider.setFocus()
    press_key(dock.size_slider.slider, QtCore.Qt.Key.Key_Right)
    press_key(dock.size_slider.slider, QtCore.Qt.Key.Key_Right)
    # said at once, while the setting waits for its pause: nothing rendered yet
    assert len(window.history.actions) == steps and window.document.shape == (48, 64)
    assert "Output <b>192×144</b> px: 3× the 64×48 texture (square grain 3 px)" in dock.info.text()
    dock.explode_x.slider.setFocus()
    for _ in range(9):
        press_key(dock.explode_x.slider, QtCore.Qt.Key.Key_Right)
    assert dock.explode_x.value() == pytest.approx(1.9)
    assert "Output <b>384×144</b> px: 6×3 the 64×48 texture" in dock.info.text()
    assert "explosion 1.9×1" in dock.info.text() and "Large" not in dock.info.text()
    dock.size_slider.set_value(32)
    dock.explode_x.set_value(2.5)
    dock.explode_y.set_value(2.5)
    assert "Output <b>5120×3840</b>" in dock.info.text()
    assert "Large: 19 M pixels" in dock.info.text()              # a warning first
    dock.explode_x.set_value(4)
    dock.explode_y.set_value(4)
    assert "Output <b>8192×6144</b>" in dock.info.text() and "Large: 48 M" in dock.info.text()


@pytest.fixture
def slow_renders(monkeypatch):
    """Every render counts as slow, and each band of rows takes 30 ms."""
    import time

    from app import grain_rendering_dock
    monkeypatch.setattr(grain_rendering_dock, "WORKER_COST", 0)
    draw = gr._draw

    def slow_draw(*args):
        time.sleep(0.03)
        return draw(*args)

    monkeypatch.setattr(gr, "_draw", slow_draw)


def test_a_slow_render_shows_progress_and_cancel_leaves_the_document(window, dock, qtbot,
                                                                      slow_renders):
    normal, steps = window.document.levels.copy(), len(window.history.actions)
    slide(dock.size_slider, 6)
    size = dock.size_slider.value()
    assert window.runner.busy and window.cancel_button.isVisible()
    assert "Rendering grains" in window.task_label.text()
    qtbot.waitUntil(lambda: window.progress.maximum() > 0 and window.progress.value() > 0,
                    timeout=5000)                               # progress moves
    assert window.document.shape == (48, 64)                    # nothing applied meanwhile
    qtbot.mouseClick(window.cancel_button, LEFT)
    settled(window, qtbot)
    assert np.array_equal(window.document.levels, normal)
    assert len(window.history.actions) == steps
    assert "cancelled" in window.statusBar().currentMessage()
    qtbot.waitUntil(lambda: dock.size_slider.value() == 1, timeout=2000)   # back on the document

    slide(dock.size_slider, 5)                                  # and this one runs to its end
    size = dock.size_slider.value()
    assert window.runner.busy
    settled(window, qtbot)
    assert len(window.history.actions) == steps + 1
    assert np.array_equal(window.document.levels, gr.render(normal, "square", size))
    assert "Grains rendered" in window.statusBar().currentMessage()


def test_hexagons_of_a_512_texture_count_as_slow(window, dock):
    action = RenderGrains("hexagon", 8, explosion_x=1.9)
    assert dock.slow(action, (512, 512))
    assert not dock.slow(RenderGrains("square", 4), (48, 64))


def test_undo_right_after_a_key_step_drops_the_setting_and_keeps_the_redo(window, dock, qtbot):
    """A setting still waiting for its pause when Ctrl+Z comes is dropped: committed after the
    undo, it would have replaced the step just undone and lost its redo."""
    from app.grain_rendering_dock import COMMIT_DELAY_MS

    steps = window.history.index
    slide(dock.size_slider, 6)
    settled(window, qtbot)
    rendered = window.document.levels.copy()
    assert window.history.index == steps + 1
    dock.compression.slider.setFocus()
    press_key(dock.compression.slider, QtCore.Qt.Key.Key_Right)   # waits for its pause...
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, QtCore.Qt.KeyboardModifier.ControlModifier)
    qtbot.wait(COMMIT_DELAY_MS + 200)                              # ...which never comes
    settled(window, qtbot)
    assert window.history.index == steps and window.history.can_redo
    assert dock.size_slider.value() == 1 and dock.compression.value() == 0.0
    window.act_redo.trigger()
    assert np.array_equal(window.document.levels, rendered)
