"""Tileable synthesis in the window, as a session: tick Tileable in the Synthesis dock, draw,
check the texture on the torus, paint over it, undo back, draw without the box, redo; the box
follows the step shown; a photo model's scales and tone tile too."""

import numpy as np
from PySide6 import QtCore, QtWidgets

from texeditor.markov.levels import load_image
from texeditor.markov.multiscale import SCALES_CLOSURE
from texeditor.markov.particles import PARTICLES
from texeditor.photo import acquire_model, tone

from .support import fill_a_cell, synthesise, undo_to_start

CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier
LEFT = QtCore.Qt.MouseButton.LeftButton
Key = QtCore.Qt.Key


def test_tick_tileable_draw_paint_undo_redraw(qtbot, window):
    dock, dpj = window.synthesis_dock, window.document.dpj
    start = window.document.levels.copy()
    qtbot.mouseClick(dock.tileable_box, LEFT)
    assert dock.tileable()
    synthesise(qtbot, window, 72, 56, 4)
    step = window.history.actions[-1]
    assert step.TYPE == "synthesize" and step.tileable and step.seed == 4
    tiled = window.document.levels.copy()
    assert tiled.shape == (56, 72)
    # the window drew what its step says: the torus draw (the engine tests check its seams)
    assert np.array_equal(tiled, step.render_result(dpj).levels)
    plain = type(step)(step.dpj, 72, 56, 4).render_result(dpj).levels
    assert not np.array_equal(tiled, plain)
    assert "tileable" in step.label()

    fill_a_cell(qtbot, window)                       # a click after the draw
    fill_a_cell(qtbot, window)                       # the same tool twice
    qtbot.mouseClick(dock.tileable_box, LEFT)        # untick: the next draw is plain
    synthesise(qtbot, window, 72, 56, 4)
    assert not window.history.actions[-1].tileable
    assert np.array_equal(window.document.levels, plain)

    qtbot.keyClick(window, Key.Key_Z, CTRL)          # back to the painted tileable texture
    assert window.history.applied[-1].TYPE == "fill"
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.document.levels, tiled)
    assert dock.tileable()                           # the dock shows the step that made it
    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start)
    assert not dock.tileable()


def test_a_photo_model_draws_and_shows_a_tiling_texture(qtbot, window, photo_path, tmp_path,
                                                        monkeypatch):
    model_path = tmp_path / "model.dpj"
    acquire_model(load_image(photo_path), scales=3).save(model_path)
    monkeypatch.setattr(QtWidgets.QFileDialog, "getOpenFileName",
                        lambda *a, **k: (str(model_path), ""))
    qtbot.keyClick(window, Key.Key_O, CTRL | SHIFT)
    dock = window.synthesis_dock
    qtbot.mouseClick(dock.tileable_box, LEFT)
    synthesise(qtbot, window, 96, 64, 2)
    step = window.history.actions[-1]
    assert step.TYPE == "synthesize_scales" and step.tileable
    assert step.closure == SCALES_CLOSURE
    assert step.particles == PARTICLES
    assert np.array_equal(window.document.levels, window.photo_model.synthesize(
        (64, 96), seed=2, tileable=True, tone=False).levels)     # the model's own draw
    picture = window.canvas.picture
    current = tone.TILED_LANES | tone.BALANCED | tone.FINISHED       # the current tiling tone
    expected = window.photo_model.render(window.document.levels, seed=2, wrap=current)
    assert np.array_equal(picture[..., 0] if expected.ndim == 2 else picture,
                          expected if expected.ndim == 2 else expected)
    first_way = window.photo_model.render(window.document.levels, seed=2, wrap=tone.TILED)
    assert not np.array_equal(first_way, expected)     # the way of closure 2's steps

    def shows_its_tone():
        pic = window.canvas.picture
        want = window.photo_model.render(window.document.levels, seed=2, wrap=current)
        return np.array_equal(pic[..., 0] if want.ndim == 2 else pic, want)
    drawn = window.document.levels.copy()
    fill_a_cell(qtbot, window)                         # the tone after an edit, then another
    assert not np.array_equal(window.document.levels, drawn) and shows_its_tone()
    fill_a_cell(qtbot, window)
    assert shows_its_tone()
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.document.levels, drawn) and shows_its_tone()
    undo_to_start(qtbot, window)
