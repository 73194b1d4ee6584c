"""A photo taken from the clipboard (Edit ▸ Paste as photo, the acquisition dialog's Paste) or
dropped on the window, and files dropped on it: what a painter brings from another program."""

import numpy as np
import pytest
from PySide6 import QtCore, QtGui, QtWidgets
from skimage import data

from app.acquire_dialog import PASTED
from app.images import photo_from_qimage, qimage_from_rgb
from texeditor.errors import ImageError
from texeditor.recipe.actions import Synthesize
from texeditor.recipe.texturefile import save_texture

CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier
LEFT = QtCore.Qt.MouseButton.LeftButton
GREY = np.ascontiguousarray(data.brick()[:96, :130])      # odd width: rows padded in a QImage
RGB = np.ascontiguousarray(data.astronaut()[200:290, 150:251])


def grey_qimage(grey: np.ndarray) -> QtGui.QImage:
    h, w = grey.shape
    return QtGui.QImage(grey.data, w, h, w, QtGui.QImage.Format.Format_Grayscale8).copy()


def put_on_clipboard(image: QtGui.QImage | None = None, urls=()) -> None:
    mime = QtCore.QMimeData()
    if image is not None:
        mime.setImageData(image)
    if urls:
        mime.setUrls([QtCore.QUrl.fromLocalFile(str(u)) for u in urls])
    QtWidgets.QApplication.clipboard().setMimeData(mime)


def test_pictures_read_as_a_photo_file_would_be():
    assert np.array_equal(photo_from_qimage(grey_qimage(GREY)), GREY)
    assert np.array_equal(photo_from_qimage(qimage_from_rgb(RGB)), RGB)
    opaque = qimage_from_rgb(RGB).convertToFormat(QtGui.QImage.Format.Format_ARGB32)
    assert np.array_equal(photo_from_qimage(opaque), RGB)          # an alpha that hides nothing
    rgba = np.dstack([RGB, np.full(RGB.shape[:2], 255, np.uint8)])
    rgba[:10, :20, 3] = 0
    h, w = rgba.shape[:2]
    image = QtGui.QImage(rgba.data, w, h, 4 * w, QtGui.QImage.Format.Format_RGBA8888).copy()
    assert np.array_equal(photo_from_qimage(image), rgba)
    grey_as_rgb = qimage_from_rgb(np.repeat(GREY[..., None], 3, axis=2))
    assert np.array_equal(photo_from_qimage(grey_as_rgb), GREY)     # one grey, not three
    with pytest.raises(ImageError, match="no pixels"):
        photo_from_qimage(QtGui.QImage())


def test_a_pasting_session_from_the_menu_and_in_the_dialog(qtbot, window, photo_path):
    before = len(window.history.actions)
    first = window.history.document.levels.copy()
    put_on_clipboard(grey_qimage(GREY))
    qtbot.keyClick(window.canvas, QtCore.Qt.Key.Key_V, CTRL | SHIFT)    # Edit ▸ Paste as photo
    dialog = window.acquire_dialog
    qtbot.waitExposed(dialog)
    assert dialog.wait()
    assert dialog.path == PASTED and dialog.source.currentText() == str(PASTED)
    assert np.array_equal(dialog.image, GREY) and dialog.dpj is not None
    assert not dialog.photo_view.pixmap().isNull()
    grey_dpj = dialog.dpj

    dialog.source.setCurrentIndex(dialog.source.findData(str(photo_path)))   # another photo
    dialog.source.activated.emit(dialog.source.currentIndex())
    assert dialog.wait() and dialog.path == photo_path
    dialog.source.setCurrentIndex(dialog.source.findData(str(PASTED)))       # and back
    dialog.source.activated.emit(dialog.source.currentIndex())
    assert dialog.wait() and np.array_equal(dialog.image, GREY)
    assert dialog.dpj == grey_dpj

    put_on_clipboard(qimage_from_rgb(RGB))                # a colour one, pasted in the dialog
    qtbot.mouseClick(dialog.paste, LEFT)
    assert dialog.wait() and np.array_equal(dialog.image, RGB)
    colour_dpj = dialog.dpj
    assert colour_dpj is not None and colour_dpj != grey_dpj

    QtWidgets.QApplication.clipboard().clear()            # nothing to paste: said, result kept
    qtbot.mouseClick(dialog.paste, LEFT)
    assert "holds no picture" in dialog.info.text()
    assert dialog.ok_button.isEnabled() and dialog.dpj == colour_dpj
    assert np.array_equal(dialog.image, RGB)

    qtbot.mouseClick(dialog.ok_button, LEFT)               # acquire and synthesise
    assert window.runner.wait(60_000)
    doc = window.history.document
    assert doc.dpj == colour_dpj and doc.dpj.meta["name"] == str(PASTED)
    assert isinstance(window.history.actions[-1], Synthesize)
    assert len(window.history.actions) == before + 1

    window.act_paste_photo.trigger()                      # again, with nothing on the clipboard
    assert window.acquire_dialog is dialog                # no dialog opened
    assert "holds no picture" in window.statusBar().currentMessage()
    for _ in range(len(window.history.actions)):          # undo to the start
        window.act_undo.trigger()
        assert window.runner.wait(60_000)
    assert window.history.index == 1
    assert np.array_equal(window.history.document.levels, first)
    assert np.array_equal(window.canvas.levels, first)


def test_a_pasted_picture_is_read_in_the_worker_not_as_it_is_pasted(qtbot, window,
                                                                       monkeypatch):
    """Paste as photo, the dialog's Paste, a dropped picture and the Plates dock's Paste: the
    picture becomes an array off the GUI thread (a 36-megapixel one takes 0.6 s), and the
    results are those of the picture."""
    import threading
    import app.images
    read_on_gui_thread = []
    real = app.images.photo_from_qimage

    def spy(image):
        read_on_gui_thread.append(threading.current_thread() is threading.main_thread())
        return real(image)

    monkeypatch.setattr(app.images, "photo_from_qimage", spy)
    steps = len(window.history.applied)
    put_on_clipboard(qimage_from_rgb(RGB))
    dialog = window.paste_photo()
    assert dialog.wait() and np.array_equal(dialog.image, RGB) and dialog.dpj is not None
    put_on_clipboard(grey_qimage(GREY))
    qtbot.mouseClick(dialog.paste, LEFT)
    assert dialog.wait() and np.array_equal(dialog.image, GREY)
    dialog.source.setCurrentIndex(0)                      # another photo, then back: not read
    dialog.source.activated.emit(0)                       # again
    assert dialog.wait()
    dialog.source.setCurrentIndex(dialog.source.findData(str(PASTED)))
    dialog.source.activated.emit(dialog.source.currentIndex())
    assert dialog.wait() and np.array_equal(dialog.image, GREY)
    dialog.reject()
    assert read_on_gui_thread == [False, False]

    mime = QtCore.QMimeData()
    mime.setImageData(qimage_from_rgb(RGB))
    assert drop(window, mime)
    dialog = window.acquire_dialog
    assert dialog.wait() and np.array_equal(dialog.image, RGB)
    dialog.reject()
    window.act_plates_dock.trigger()
    window.plates_dock.count.setValue(2)
    put_on_clipboard(qimage_from_rgb(RGB))
    qtbot.mouseClick(window.plates_dock.paste_button, LEFT)
    assert window.runner.wait(60_000)
    assert window.document.plates is not None and len(window.history.applied) == steps + 1
    assert read_on_gui_thread == [False] * 4 and not window.errors


def test_a_file_copied_in_a_file_manager_is_pasted_as_its_path(qtbot, window, photo_path):
    put_on_clipboard(urls=[photo_path])
    dialog = window.paste_photo()
    assert dialog.wait() and dialog.path == photo_path and dialog.dpj is not None
    dialog.reject()


def test_a_picture_too_large_is_refused_with_its_size(qtbot, window, monkeypatch):
    import app.images
    monkeypatch.setattr(app.images, "MAX_PIXELS", 1000)
    put_on_clipboard(grey_qimage(GREY))
    assert window.paste_photo() is None
    assert window.errors and "130x96" in window.errors[-1][1]


def drop(window, mime: QtCore.QMimeData) -> bool:
    """Drag ``mime`` over the window and drop it; True when the window took the drag."""
    pos = QtCore.QPoint(window.width() // 2, window.height() // 2)
    action = QtCore.Qt.DropAction.CopyAction
    enter = QtGui.QDragEnterEvent(pos, action, mime, LEFT, QtCore.Qt.KeyboardModifier.NoModifier)
    enter.ignore()
    QtWidgets.QApplication.sendEvent(window, enter)
    if not enter.isAccepted():
        return False
    event = QtGui.QDropEvent(QtCore.QPointF(pos), action, mime, LEFT,
                             QtCore.Qt.KeyboardModifier.NoModifier)
    QtWidgets.QApplication.sendEvent(window, event)
    return True


def urls(*paths) -> QtCore.QMimeData:
    mime = QtCore.QMimeData()
    mime.setUrls([QtCore.QUrl.fromLocalFile(str(p)) for p in paths])
    return mime


def test_dropping_a_texture_a_dpj_a_photo_and_a_picture(qtbot, window, tmp_path, photo_path,
                                                       small_dpj):
    texture = tmp_path / "kept.texture"
    save_texture(texture, window.history)
    levels = window.history.document.levels.copy()
    window.synthesis_dock.seed.set_value(8)
    window.synthesise_from_dock()
    assert window.runner.wait(60_000)
    window.mark_clean()
    assert drop(window, urls(texture))                     # a texture opens
    assert window.runner.wait(60_000)
    assert window.path == texture
    assert np.array_equal(window.history.document.levels, levels)

    dpj_file = tmp_path / "other.dpj"
    other = small_dpj.__class__(small_dpj.configs, small_dpj.probs, small_dpj.levels,
                                meta={"name": "other"})
    dpj_file.write_bytes(other.to_bytes())
    assert drop(window, urls(dpj_file))                    # a DPJ becomes the current one
    assert window.history.document.dpj.meta["name"] == "other"

    assert drop(window, urls(photo_path))                  # a photo: acquire from it
    dialog = window.acquire_dialog
    assert dialog.wait() and dialog.path == photo_path and dialog.dpj is not None
    dialog.reject()

    mime = QtCore.QMimeData()                              # a picture dragged from a browser
    mime.setImageData(qimage_from_rgb(RGB))
    assert drop(window, mime)
    dialog = window.acquire_dialog
    assert dialog.wait() and np.array_equal(dialog.image, RGB)
    dialog.reject()

    text = QtCore.QMimeData()                              # words are not taken
    text.setText("brick")
    assert not drop(window, text)
    assert window.path == texture and not window.errors


def test_dropped_files_that_are_not_what_they_say_leave_the_texture_alone(qtbot, window,
                                                                          tmp_path):
    levels = window.history.document.levels.copy()
    damaged = tmp_path / "damaged.texture"
    damaged.write_bytes(b"PK\x03\x04 not a zip at all")
    assert drop(window, urls(damaged))
    assert window.runner.wait(60_000)
    assert window.errors and "damaged.texture" in window.errors[-1][0]
    bad_dpj = tmp_path / "bad.dpj"
    bad_dpj.write_bytes(b"\x00" * 100)
    assert drop(window, urls(bad_dpj))
    assert "bad.dpj" in window.errors[-1][0]
    folder = tmp_path / "a folder.png"
    folder.mkdir()
    assert drop(window, urls(folder))                      # read in the dialog, refused there
    dialog = window.acquire_dialog
    assert dialog.wait() and dialog.dpj is None and not dialog.ok_button.isEnabled()
    assert "a folder.png" in dialog.info.text()
    dialog.reject()
    assert np.array_equal(window.history.document.levels, levels) and window.path is None


def test_ctrl_v_pastes_a_photo_but_a_number_into_a_field_with_the_focus(qtbot, window,
                                                                       photo_path):
    dialog = window.acquire()
    assert dialog.wait() and dialog.path == photo_path
    QtWidgets.QApplication.clipboard().setText("5")
    dialog.levels.setFocus()
    dialog.levels.lineEdit().selectAll()
    qtbot.keyClick(dialog.levels, QtCore.Qt.Key.Key_V, CTRL)     # the field's own paste
    assert dialog.levels.value() == 5 and dialog.path == photo_path
    put_on_clipboard(grey_qimage(GREY))
    dialog.source.setFocus()
    qtbot.keyClick(dialog.source, QtCore.Qt.Key.Key_V, CTRL)     # the dialog's: the photo
    assert dialog.wait() and dialog.path == PASTED and np.array_equal(dialog.image, GREY)
    assert dialog.dpj.levels == 5
    dialog.reject()
