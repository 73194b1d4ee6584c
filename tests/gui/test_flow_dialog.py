"""Models ▸ Flow texture… as a session: the photo's grain, then strokes dragged on the pad with
the mouse, another seed, OK; the document holds exactly the step's texture; undo to the start,
redo, and the dialog opened again keeps working."""

import numpy as np
from PySide6 import QtCore

from app.step_dialog import exemplar_from
from texeditor.flow import flow_texture
from texeditor.markov.levels import load_image, quantize

from .support import model_ok, open_model_dialog, undo_to_start

LEFT = QtCore.Qt.MouseButton.LeftButton




def drag(qtbot, pad, points):
    """A stroke drawn with the mouse: press, moves, release."""
    qtbot.mousePress(pad, LEFT, pos=QtCore.QPoint(*points[0]))
    for x, y in points[1:]:
        qtbot.mouseMove(pad, QtCore.QPoint(x, y))
    qtbot.mouseRelease(pad, LEFT, pos=QtCore.QPoint(*points[-1]))


def cut(picture, levels):
    return quantize(np.round(picture * 255).astype(np.uint8), levels, "lab")


def test_flow_texture_session(window, qtbot, photo_path):
    doc = window.document
    start = (doc.levels.copy(), doc.palette.copy(), len(window.history.actions))
    photo, _ = exemplar_from(load_image(photo_path))

    dialog = open_model_dialog(window, qtbot, "flow_texture")   # the photo's grain
    assert dialog.source.currentData() == "photo" and dialog.pad.glyphs
    dialog.width_box.setValue(48)
    dialog.height_box.setValue(40)
    dialog.levels.setValue(5)
    dialog.length.setValue(10)
    dialog.seed.set_value(3)
    model_ok(dialog, qtbot)
    step = window.history.actions[-1]
    assert step.TYPE == "flow_texture" and step.source == "photo" and step.seed == 3
    expected = cut(flow_texture((40, 48), photo=photo, seed=3, length=10), 5)
    assert doc.shape == (40, 48) and doc.num_levels == 5
    assert np.array_equal(doc.levels, expected.levels)
    assert np.array_equal(doc.palette, expected.palette)
    first = doc.levels.copy()

    dialog = open_model_dialog(window, qtbot, "flow_texture")   # again: strokes drawn on the pad
    assert dialog.width_box.value() == 48                     # the canvas's size
    dialog.length.setValue(12)
    pad = dialog.pad
    glyphs = list(pad.glyphs)
    drag(qtbot, pad, [(20, 200), (80, 150), (140, 110), (200, 40)])
    assert dialog.source.currentData() == "strokes" and len(pad.strokes) == 1
    assert pad.glyphs != glyphs                               # the pad shows the drawn field
    qtbot.mouseClick(pad, LEFT, pos=QtCore.QPoint(100, 100))  # a click draws nothing
    assert len(pad.strokes) == 1
    dialog.seed.set_value(8)
    assert not dialog.ok.isEnabled()                          # the new preview is coming
    side = pad.height()
    model_ok(dialog, qtbot)
    step = window.history.actions[-1]
    assert step.source == "strokes" and step.seed == 8 and len(step.strokes) == 6
    h, w = doc.shape
    (r0, c0), (r1, c1) = step.strokes[0], step.strokes[-1]
    assert r0 > r1 and c0 < c1                                # up and to the right, as drawn
    assert (r0, c0) == (round(200 / side * (h - 1)), round(20 / side * (w - 1)))
    expected = cut(flow_texture((40, 48), photo=photo, strokes=step.segments(), seed=8,
                                length=12), 5)
    assert np.array_equal(doc.levels, expected.levels)
    assert not np.array_equal(doc.levels, first)
    after = doc.levels.copy()
    assert not window.errors

    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start[0])
    assert np.array_equal(window.document.palette, start[1])
    while window.history.can_redo:
        window.act_redo.trigger()
    assert np.array_equal(window.document.levels, after)

    dialog = open_model_dialog(window, qtbot, "flow_texture")   # a third time: Clear, then Cancel
    drag(qtbot, dialog.pad, [(30, 30), (200, 60)])
    assert dialog.wait() and dialog.ok.isEnabled()
    qtbot.mouseClick(dialog.clear, LEFT)
    assert dialog.pad.strokes == [] and not dialog.ok.isEnabled()
    assert "drag on the pad" in dialog.info.text()
    dialog.source.setCurrentIndex(dialog.source.findData("photo"))
    assert dialog.wait() and dialog.ok.isEnabled()
    dialog.reject()
    assert np.array_equal(window.document.levels, after) and not window.errors
