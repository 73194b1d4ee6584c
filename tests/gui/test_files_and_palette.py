"""Files (save, reopen, recent, export, errors) and the palette dock, through the real widgets."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PySide6 import QtCore, QtGui, QtWidgets

from app.files import recent_files
from app.main import run
from texeditor.recipe.actions import SetPalette

from .support import hold

ROOT = Path(__file__).resolve().parents[2]

CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
LEFT = QtCore.Qt.MouseButton.LeftButton
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier


def choose(monkeypatch, name, path):
    monkeypatch.setattr(QtWidgets.QFileDialog, name, lambda *a, **k: (str(path), ""))


def test_save_then_reopen_gives_the_same_matrix(qtbot, window, tmp_path, monkeypatch):
    window.submit(SetPalette(np.array([[9, 9, 9], [90, 0, 0], [0, 90, 0], [0, 0, 90]], np.uint8)))
    levels = window.history.document.levels.copy()
    palette = window.history.document.palette.copy()
    actions = window.history.actions
    target = tmp_path / "my texture"                       # the suffix is added
    choose(monkeypatch, "getSaveFileName", target)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_S, CTRL)
    saved = tmp_path / "my texture.texture"
    assert saved.exists() and window.path == saved
    assert not window.is_modified() and "*" not in window.windowTitle()
    assert recent_files()[0] == str(saved.resolve())

    qtbot.keyClick(window, QtCore.Qt.Key.Key_N, CTRL)       # a blank canvas in between
    qtbot.keyClick(window.new_dialog, QtCore.Qt.Key.Key_Return)
    assert not window.history.document.levels.any()

    choose(monkeypatch, "getOpenFileName", saved)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_O, CTRL)
    assert window.runner.wait(60_000)
    doc = window.history.document
    assert np.array_equal(doc.levels, levels) and np.array_equal(doc.palette, palette)
    assert window.history.actions == actions
    assert np.array_equal(window.canvas.levels, levels)
    assert window.path == saved and not window.errors


def test_open_recent_menu(qtbot, window, tmp_path):
    path = tmp_path / "a.texture"
    assert window.save_to(path)
    window._fill_recent_menu()
    entries = [a for a in window.recent_menu.actions() if a.text() == "a.texture"]
    assert entries
    window.submit(SetPalette(np.zeros((4, 3), np.uint8)))
    window.mark_clean()
    entries[0].trigger()
    assert window.runner.wait(60_000)
    assert window.path == path and window.history.document.palette.any()


def test_opening_counts_the_steps_in_words(qtbot, window, tmp_path):
    """The status bar says "(1 step)" for a one-step file and "(2 steps)" for two."""
    window.history.goto(1)
    one = tmp_path / "one.texture"
    assert window.save_to(one) and len(window.history.actions) == 1
    window.submit(SetPalette(np.zeros((window.history.document.num_levels, 3), np.uint8)))
    two = tmp_path / "two.texture"
    assert window.save_to(two)
    for path, words in ((one, "(1 step)."), (two, "(2 steps).")):
        window.mark_clean()
        window.open_file(path)
        assert window.runner.wait(60_000)
        assert window.statusBar().currentMessage().endswith(words)


def test_a_damaged_file_is_a_dialog_and_the_document_stays(qtbot, window, tmp_path):
    bad = tmp_path / "bad.texture"
    bad.write_bytes(b"PK\x03\x04 not really a zip")
    before = window.history.document.levels.copy()
    steps = window.history.actions
    window.open_file(bad)
    assert window.runner.wait(60_000)
    assert window.errors and "bad.texture" in window.errors[-1][0]
    assert window.history.actions == steps
    assert np.array_equal(window.history.document.levels, before)
    assert window.path is None


def test_saving_to_an_impossible_place_is_a_dialog(window, tmp_path):
    assert not window.save_to(tmp_path / "no-such-folder" / "x.texture")
    assert window.errors and window.path is None


def test_export_png_with_upscale(qtbot, window, tmp_path, monkeypatch):
    choose(monkeypatch, "getSaveFileName", tmp_path / "out.png")
    monkeypatch.setattr(QtWidgets.QInputDialog, "getInt", lambda *a, **k: (3, True))
    qtbot.keyClick(window, QtCore.Qt.Key.Key_E, CTRL)
    image = QtGui.QImage(str(tmp_path / "out.png"))
    assert (image.width(), image.height()) == (64 * 3, 48 * 3)
    doc = window.history.document
    for x, y in ((0, 0), (10, 7), (63, 47)):
        expected = tuple(int(c) for c in doc.palette[doc.levels[y, x]])
        colour = image.pixelColor(3 * x + 1, 3 * y + 2)
        assert (colour.red(), colour.green(), colour.blue()) == expected


def test_a_large_export_is_written_in_the_worker_and_an_edit_meanwhile_is_not_in_it(
        qtbot, window, tmp_path, monkeypatch):
    import app.files
    from texeditor.recipe.actions import SetLevels
    monkeypatch.setattr(app.files, "BACKGROUND_EXPORT", 1000)     # the 64×48 texture, ×3
    writing, gate = hold(monkeypatch, app.files, "write_png")
    doc = window.history.document
    expected = doc.palette[doc.levels].repeat(3, 0).repeat(3, 1)
    out = tmp_path / "large.png"
    assert window.export_to(out, 3)
    assert writing.wait(30) and window.runner.busy and "Writing large.png" in \
        window.task_label.text()
    level = (int(doc.levels[0, 0]) + 1) % doc.num_levels
    assert window.submit(SetLevels(0, 0, 48, 64, level))          # an edit while it writes
    assert (window.history.document.levels == level).all()
    assert not window.export_to(tmp_path / "second.png", 3)       # one at a time, said so
    assert "Busy" in window.statusBar().currentMessage()
    window.runner.cancel()                                       # Esc once the write began:
    gate.set()                                                   # it ends, and says so
    assert window.runner.wait(30_000)
    image = QtGui.QImage(str(out)).convertToFormat(QtGui.QImage.Format.Format_RGB888)
    pixels = np.frombuffer(image.constBits(), np.uint8).reshape(
        image.height(), image.bytesPerLine())[:, :3 * image.width()].reshape(
        image.height(), image.width(), 3)
    assert np.array_equal(pixels, expected)                      # the texture when asked
    assert f"Exported {out}" in window.statusBar().currentMessage()
    assert not (tmp_path / "second.png").exists() and not window.errors


def test_a_large_export_that_fails_says_why(qtbot, window, tmp_path, monkeypatch):
    import app.files
    monkeypatch.setattr(app.files, "BACKGROUND_EXPORT", 1000)
    missing = tmp_path / "no such folder" / "out.png"
    assert window.export_to(missing, 3)                          # started; fails in the worker
    assert window.runner.wait(30_000)
    assert window.errors and window.errors[-1][0] == "Cannot export"
    assert not missing.exists()


def test_swatch_click_selects_and_double_click_edits_the_colour(qtbot, window, monkeypatch):
    dock = window.palette_dock
    bar = dock.swatches
    qtbot.mouseClick(bar, LEFT, pos=bar.swatch_rect(2).center())
    assert dock.current_level == 2 and "level 2" in dock.current_label.text()
    monkeypatch.setattr(QtWidgets.QColorDialog, "getColor",
                        lambda *a, **k: QtGui.QColor(250, 10, 20))
    old = window.history.document.palette.copy()
    qtbot.mouseDClick(bar, LEFT, pos=bar.swatch_rect(3).center())
    doc = window.history.document
    assert tuple(doc.palette[3]) == (250, 10, 20)
    assert isinstance(window.history.actions[-1], SetPalette)
    y, x = np.argwhere(doc.levels == 3)[0]
    assert window.canvas.displayed_colour(x, y) == (250, 10, 20)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    assert np.array_equal(window.history.document.palette, old)
    assert tuple(bar.palette_rgb[3]) == tuple(old[3])


def test_grey_scale_sliders_preview_then_commit_one_action(qtbot, window):
    dock = window.palette_dock
    steps = len(window.history.actions)
    dock.lightest.setFocus()
    for _ in range(5):
        qtbot.keyClick(dock.lightest, QtCore.Qt.Key.Key_PageDown)
    assert len(window.history.actions) == steps                  # still settling: preview only
    qtbot.waitUntil(lambda: len(window.history.actions) == steps + 1, timeout=3000)
    palette = window.history.document.palette
    assert palette[-1, 0] == dock.lightest.value() and palette[0, 0] == dock.darkest.value()
    dock.contrast.setValue(60)
    qtbot.waitUntil(lambda: len(window.history.actions) == steps + 2, timeout=3000)
    greys = window.history.document.palette[:, 0].astype(int)
    assert np.all(np.diff(greys) > 0)
    qtbot.mouseClick(dock.reset_button, LEFT)
    assert window.history.document.palette[0, 0] == 0
    assert window.history.document.palette[-1, 0] == 255


def test_screenshot_entry_point(tmp_path, qapp):
    out = tmp_path / "shot.png"
    assert run(["--screenshot", str(out), "--size", "900x600"]) == 0
    image = QtGui.QImage(str(out))
    assert (image.width(), image.height()) == (900, 600)


@pytest.mark.parametrize("size", ["abc", "99999x99999", "0x0", "1280x", "1e3x800", "80x60"])
def test_a_screenshot_size_out_of_bounds_is_one_clear_error(tmp_path, size):
    """A size Qt cannot paint (99999² crashed it) or cannot read exits 2 and names it, in a
    child process so that a crash would fail the test instead of pytest."""
    out = tmp_path / "shot.png"
    done = subprocess.run([sys.executable, "-m", "app.main", "--screenshot", str(out), "--size",
                           size], capture_output=True, text=True, timeout=120, cwd=ROOT,
                          env={**os.environ, "QT_QPA_PLATFORM": "offscreen"})
    assert done.returncode == 2, done.stderr[-800:]
    assert "argument --size" in done.stderr and size in done.stderr
    assert not out.exists()


def test_screenshot_of_an_opened_file(tmp_path, qapp, window):
    path = tmp_path / "x.texture"
    assert window.save_to(path)
    out = tmp_path / "shot.png"
    assert run(["--screenshot", str(out), "--open", str(path)]) == 0
    assert out.exists()
    assert run(["--screenshot", str(out), "--open", str(tmp_path / "missing.texture")]) == 2


def grey_sliders(dock):
    return dock.darkest.value(), dock.lightest.value(), dock.contrast.value()


def test_grey_scale_sliders_follow_undo_and_redo(qtbot, window):
    """Issue 16: the controls show the document's palette after undo/redo, Contrast included."""
    dock = window.palette_dock
    original, palette0 = grey_sliders(dock), window.history.document.palette.copy()
    steps = len(window.history.actions)
    dock.contrast.setFocus()
    for _ in range(4):
        qtbot.keyClick(dock.contrast, QtCore.Qt.Key.Key_PageUp)
    qtbot.waitUntil(lambda: len(window.history.actions) == steps + 1, timeout=3000)
    after_contrast = grey_sliders(dock)
    dock.darkest.setFocus()
    for _ in range(3):
        qtbot.keyClick(dock.darkest, QtCore.Qt.Key.Key_PageUp)
    qtbot.waitUntil(lambda: len(window.history.actions) == steps + 2, timeout=3000)
    changed = grey_sliders(dock)
    assert changed[2] != original[2] and changed[0] != original[0]
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    assert grey_sliders(dock) == after_contrast
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    assert np.array_equal(window.history.document.palette, palette0)
    assert grey_sliders(dock) == original
    assert [dock._value_labels[s].text() for s in (dock.darkest, dock.lightest, dock.contrast)] \
        == [str(v) for v in original]
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL | SHIFT)
    assert grey_sliders(dock) == after_contrast
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL | SHIFT)
    assert grey_sliders(dock) == changed


def test_synthesis_dock_shows_the_size_and_seed_of_the_texture_after_undo(qtbot, window):
    dock = window.synthesis_dock
    assert dock.values() == (64, 48, 7)
    dock.width_box.setValue(40)
    dock.seed.set_value(99)
    qtbot.mouseClick(dock.button, LEFT)
    assert window.runner.wait(60_000)
    assert window.document.shape == (48, 40)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    assert window.document.shape == (48, 64) and dock.values() == (64, 48, 7)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL | SHIFT)
    assert dock.values() == (40, 48, 99)
