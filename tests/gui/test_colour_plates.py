"""Colour in the window: plates added, painted with the brush and the fill tool, taken from a
photo, shown and exported; a level's hue, saturation and value edited; undo back to the start."""

import colorsys

import numpy as np
from PySide6 import QtCore, QtTest, QtWidgets
from skimage import io
from skimage.segmentation import flood

from texeditor.recipe.actions import SetPalette
from texeditor.recipe.document import Document
from texeditor.texture.plate_actions import AddPlates, OnPlates, PlatesFromPhoto

from .support import CTRL, LEFT, Key, cell_pos, click, drag, press_key

GREY = np.array([0.2125, 0.7154, 0.0721])


def on_plates(doc, palette=None, colours=None):
    """I = plate colour + grey of the level − mean grey, computed point by point."""
    palette = doc.palette if palette is None else np.asarray(palette)
    colours = doc.plate_colours if colours is None else np.asarray(colours)
    grey = palette[doc.levels].astype(float) @ GREY
    picture = colours[doc.plates].astype(float) + (grey - grey.mean())[..., None]
    return np.clip(np.rint(picture), 0, 255).astype(np.uint8)


def choose_swatch(window, k):
    bar = window.palette_dock.swatches
    click(bar, bar.swatch_rect(k).center())
    assert window.current_level == k


def brush(window, a, b):
    """A brush drag on the canvas from cell a to cell b (x, y)."""
    press_key(window, Key.Key_B)
    canvas = window.canvas
    QtTest.QTest.qWait(30)              # the tool's options settle the layout first
    a, b = cell_pos(canvas, *a), cell_pos(canvas, *b)
    drag(canvas.viewport(), LEFT, (a.x(), a.y()), (b.x(), b.y()))


def fill(window, x, y):
    press_key(window, Key.Key_F)
    click(window.canvas.viewport(), cell_pos(window.canvas, x, y))


def test_a_plates_session_painted_filled_exported_and_undone(qtbot, window, tmp_path,
                                                            monkeypatch):
    doc = window.document
    start, levels, steps = doc.result_hash(), doc.levels.copy(), window.history.index
    assert not window.act_plates.isEnabled() and not window.act_paint_plates.isEnabled()
    assert not window.plates_dock.isVisible()
    window.act_plates_dock.trigger()                            # Image ▸ Colour plates…
    assert window.plates_dock.isVisible()
    window.plates_dock.count.setValue(3)
    qtbot.mouseClick(window.plates_dock.add_button, LEFT)
    assert isinstance(window.history.applied[-1], AddPlates)
    assert doc.plates.shape == doc.shape and not doc.plates.any() and len(doc.plate_colours) == 3
    assert window.act_plates.isEnabled() and window.act_plates.isChecked()

    qtbot.mouseClick(window.plates_dock.paint_box, LEFT)         # Paint on the plates
    assert window.act_paint_plates.isChecked()
    np.testing.assert_array_equal(window.palette_dock.swatches.palette_rgb, doc.plate_colours)
    assert not window.palette_dock.grey_group.isVisible()
    choose_swatch(window, 1)
    brush(window, (5, 10), (50, 10))                            # the same tool twice
    choose_swatch(window, 2)
    brush(window, (20, 2), (20, 40))
    painted = doc.plates.copy()
    assert painted[10, 5:51].tolist() == [1] * 14 + [2] * 3 + [1] * 29    # a 3-point brush
    assert painted[2:41, 20].tolist() == [2] * 39 and set(np.unique(painted)) == {0, 1, 2}
    np.testing.assert_array_equal(doc.levels, levels)           # the texture never changed
    strokes = window.history.applied[-2:]
    assert all(isinstance(a, OnPlates) and a.inner.TYPE == "stroke" for a in strokes)
    scratch = Document.new(64, 48, 3)           # the same strokes on levels paint the same
    for step in strokes:
        scratch.apply(step.inner)
    np.testing.assert_array_equal(scratch.levels, painted)

    expected = painted.copy()                   # the fill tool, on the plates, switched to
    expected[flood(painted, (45, 60), connectivity=1)] = 2
    fill(window, 60, 45)
    np.testing.assert_array_equal(doc.plates, expected)
    assert window.history.applied[-1].inner.TYPE == "fill"
    picture = on_plates(doc)
    for x, y in ((0, 0), (20, 10), (60, 45), (5, 30)):
        assert window.canvas.displayed_colour(x, y) == tuple(picture[y, x])

    out = tmp_path / "rgb.png"                  # File ▸ Export PNG: the picture on show
    monkeypatch.setattr(QtWidgets.QFileDialog, "getSaveFileName", lambda *a, **k: (str(out), ""))
    monkeypatch.setattr(QtWidgets.QInputDialog, "getInt", lambda *a, **k: (1, True))
    qtbot.keyClick(window, Key.Key_E, CTRL)
    np.testing.assert_array_equal(io.imread(out), picture)

    window.act_plates.trigger()                 # View ▸ Show plates off: the palette again
    assert window.canvas.displayed_colour(20, 10) == tuple(doc.palette[doc.levels[10, 20]])
    window.act_plates.trigger()

    qtbot.keyClick(window, Key.Key_P, QtCore.Qt.KeyboardModifier.ShiftModifier)   # the texture
    assert not window.plates_dock.paint_box.isChecked()
    choose_swatch(window, 3)
    brush(window, (0, 30), (63, 30))
    assert (doc.levels[30] == 3).sum() > 50
    np.testing.assert_array_equal(doc.plates, expected)

    while window.history.index > steps:
        qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert doc.plates is None and doc.result_hash() == start
    assert not window.act_paint_plates.isEnabled() and not window.plates_dock.paint_box.isEnabled()
    assert window.canvas.displayed_colour(20, 10) == tuple(doc.palette[doc.levels[10, 20]])
    assert not window.errors


def set_hsv(qtbot, window, hue=None, saturation=None, value=None):
    """Type into the HSV spin boxes, then let the edit settle into one step."""
    dock = window.palette_dock
    steps = window.history.index
    for box, v in ((dock.hue, hue), (dock.saturation, saturation), (dock.value, value)):
        if v is not None:
            box.setValue(v)
    qtbot.waitUntil(lambda: window.history.index == steps + 1, timeout=3000)


def test_hue_saturation_and_value_of_a_level_and_of_a_plate(qtbot, window):
    doc = window.document
    window.submit(SetPalette([(0, 0, 0), (200, 40, 40), (90, 90, 90), (250, 250, 250)]))
    before = doc.palette.copy()
    choose_swatch(window, 1)
    dock = window.palette_dock
    assert (dock.hue.value(), dock.saturation.value(), dock.value.value()) == (0, 80, 78)
    set_hsv(qtbot, window, hue=120)
    h, s, v = colorsys.rgb_to_hsv(200 / 255, 40 / 255, 40 / 255)
    green = tuple(round(255 * c) for c in colorsys.hsv_to_rgb(1 / 3, s, v))
    assert tuple(doc.palette[1]) == green == (40, 200, 40)
    np.testing.assert_array_equal(np.delete(doc.palette, 1, 0), np.delete(before, 1, 0))
    y, x = np.argwhere(doc.levels == 1)[0]
    assert window.canvas.displayed_colour(x, y) == green
    assert isinstance(window.history.applied[-1], SetPalette)
    set_hsv(qtbot, window, saturation=0)                    # a grey of the same value
    assert tuple(doc.palette[1]) == (200, 200, 200)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    np.testing.assert_array_equal(doc.palette, before)
    assert (dock.hue.value(), dock.saturation.value()) == (0, 80)

    window.submit(AddPlates(((200, 100, 50), (50, 100, 200))))
    window.act_paint_plates.trigger()
    choose_swatch(window, 0)
    set_hsv(qtbot, window, value=40)                        # the plate's colour, darker
    assert isinstance(window.history.applied[-1], OnPlates)
    assert tuple(doc.plate_colours[0]) == (102, 51, 26)     # 200·0.4/0.784…, the same hue
    np.testing.assert_array_equal(doc.palette, before)
    assert window.canvas.displayed_colour(0, 0) == tuple(on_plates(doc)[0, 0])
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert tuple(doc.plate_colours[0]) == (200, 100, 50)
    assert not window.errors


def test_plates_from_a_photo_through_the_dock(qtbot, window, tmp_path, monkeypatch):
    photo = np.zeros((60, 80, 3), np.uint8)
    photo[:, :40], photo[:, 40:] = (220, 30, 30), (30, 30, 220)
    path = tmp_path / "halves.png"
    io.imsave(path, photo)
    monkeypatch.setattr(QtWidgets.QFileDialog, "getOpenFileName",
                        lambda *a, **k: (str(path), ""))
    window.act_plates_dock.trigger()
    dock = window.plates_dock
    dock.count.setValue(2)
    qtbot.mouseClick(dock.photo_button, LEFT)
    assert window.runner.wait(60_000)              # read in the worker, the window live
    step = window.history.applied[-1]
    assert isinstance(step, PlatesFromPhoto) and step.name == "halves.png" and step.plates == 2
    plates = window.document.plates
    assert (plates[:, :24] == 1).all() and (plates[:, 40:] == 0).all()    # blue the darker
    assert "2 plates" in dock.info.text()
    qtbot.mouseClick(dock.remove_button, LEFT)
    assert window.document.plates is None and "No plates" in dock.info.text()
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    np.testing.assert_array_equal(window.document.plates, plates)
    assert not window.errors


def test_plates_pasted_from_the_clipboard_through_the_dock(qtbot, window, tmp_path):
    """The Plates dock's Paste: nothing on the clipboard says so and changes nothing; a picture
    copied (left red, right blue) gives two plates named "Pasted picture"; an image file copied
    in a file manager (the picture mirrored) is taken as From a photo takes it: the plates
    mirrored; Remove, then undo three times to the texture without plates."""
    from PySide6 import QtGui
    photo = np.zeros((60, 80, 3), np.uint8)
    photo[:, :40], photo[:, 40:] = (220, 30, 30), (30, 30, 220)
    clipboard = QtWidgets.QApplication.clipboard()
    clipboard.clear()
    window.act_plates_dock.trigger()
    dock = window.plates_dock
    dock.count.setValue(2)
    steps = len(window.history.applied)
    qtbot.mouseClick(dock.paste_button, LEFT)
    assert "no picture" in window.statusBar().currentMessage()
    assert len(window.history.applied) == steps and window.document.plates is None
    image = QtGui.QImage(photo.data, 80, 60, 240, QtGui.QImage.Format.Format_RGB888).copy()
    clipboard.setImage(image)
    qtbot.mouseClick(dock.paste_button, LEFT)
    assert window.runner.wait(60_000)
    step = window.history.applied[-1]
    assert isinstance(step, PlatesFromPhoto) and step.name == "Pasted picture"
    pasted = window.document.plates.copy()
    assert (pasted[:, :24] == 1).all() and (pasted[:, 40:] == 0).all()    # blue the darker
    path = tmp_path / "halves.png"
    io.imsave(path, photo[:, ::-1])                         # blue left, red right
    mime = QtCore.QMimeData()
    mime.setUrls([QtCore.QUrl.fromLocalFile(str(path))])
    clipboard.setMimeData(mime)
    qtbot.mouseClick(dock.paste_button, LEFT)
    assert window.runner.wait(60_000)
    step = window.history.applied[-1]
    assert step.name == "halves.png" and np.array_equal(window.document.plates, pasted[:, ::-1])
    qtbot.mouseClick(dock.remove_button, LEFT)
    assert window.document.plates is None
    for _ in range(3):
        qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert len(window.history.applied) == steps and window.document.plates is None
    assert not window.errors


def test_plates_from_a_photo_that_cannot_be_read_say_why_and_change_nothing(qtbot, window,
                                                                           tmp_path):
    bad = tmp_path / "torn.png"
    bad.write_bytes(b"\x89PNG\r\n\x1a\n torn off")
    levels = window.document.levels.copy()
    steps = len(window.history.applied)
    assert window.plates_from_photo(3, 0.02, bad)
    assert window.runner.wait(60_000)
    assert window.errors and "torn.png" in window.errors[-1][0]
    assert len(window.history.applied) == steps and window.document.plates is None
    assert np.array_equal(window.document.levels, levels)
    window.synthesis_dock.seed.set_value(3)                 # the window goes on working
    window.synthesise_from_dock()
    assert window.runner.wait(60_000) and len(window.history.applied) == steps + 1


def test_acquire_with_colour_classes_synthesises_in_the_photo_colours(qtbot, window, tmp_path,
                                                                     monkeypatch):
    from skimage import data

    from texeditor.markov.levels import quantize

    photo = data.coffee()[::4, ::4]
    path = tmp_path / "coffee.png"
    io.imsave(path, photo)
    qtbot.keyClick(window, Key.Key_I, CTRL)
    dialog = window.acquire_dialog
    qtbot.waitExposed(dialog)
    assert dialog.wait()
    monkeypatch.setattr(QtWidgets.QFileDialog, "getOpenFileName", lambda *a, **k: (str(path), ""))
    qtbot.mouseClick(dialog.browse, LEFT)
    dialog.levels.setValue(5)
    dialog.method.setCurrentIndex(dialog.method.findData("lab"))
    assert dialog.wait()
    expected = quantize(photo, 5, "lab")
    np.testing.assert_array_equal(dialog.quantization.levels, expected.levels)
    np.testing.assert_array_equal(dialog.dpj.palette, expected.palette)
    assert dialog.dpj.meta["quantiser"] == "lab"
    qtbot.mouseClick(dialog.ok_button, LEFT)
    assert window.runner.wait(60_000)
    doc = window.document
    np.testing.assert_array_equal(doc.palette, expected.palette)
    y, x = np.argwhere(doc.levels == 4)[0]
    assert window.canvas.displayed_colour(x, y) == tuple(expected.palette[4])
    assert not window.errors
