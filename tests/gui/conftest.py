"""Offscreen Qt for the GUI tests, with settings kept away from the user's own."""

import os

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

import PySide6  # noqa: E402
import pytest  # noqa: E402
from PySide6 import QtCore, QtWidgets  # noqa: E402

if PySide6.__version__ == "6.12.0":
    # Its signals drop a reference to True/False on every emit: after a few thousand emits the
    # interpreter aborts ("bool_dealloc"). pyproject.toml excludes it; say so instead of crashing.
    pytest.exit("PySide6 6.12.0 corrupts bool reference counts; run "
                "`pip install 'PySide6-Essentials!=6.12.0'` (6.11.3 works)", returncode=3)


@pytest.fixture(autouse=True)
def isolated_settings(tmp_path, monkeypatch):
    """Recent files and window state go to a temporary INI file, never the real QSettings."""
    QtCore.QSettings.setDefaultFormat(QtCore.QSettings.Format.IniFormat)
    QtCore.QSettings.setPath(QtCore.QSettings.Format.IniFormat, QtCore.QSettings.Scope.UserScope,
                             str(tmp_path / "settings"))
    yield


@pytest.fixture(scope="session")
def photo_path(tmp_path_factory):
    """A bundled sample photo when the repository has one, else gravel written as a PNG."""
    from app import resources
    samples = resources.sample_images()
    if samples:
        return samples[0]
    from skimage import data, io
    path = tmp_path_factory.mktemp("photos") / "gravel.png"
    io.imsave(path, data.gravel()[:192, :192], check_contrast=False)
    return path


@pytest.fixture(scope="session")
def small_dpj(photo_path):
    from app.resources import estimate_from_photo
    return estimate_from_photo(photo_path, window=(3, 3), levels=4)


@pytest.fixture
def window(qtbot, small_dpj, photo_path, monkeypatch):
    """The main window on a 64×64 synthesis, with the sample photos pointing at photo_path."""
    from app import resources
    from app.dpj_editor import DPJEditor
    from app.main_window import MainWindow
    from texeditor.recipe.history import History

    monkeypatch.setattr(resources, "sample_images", lambda: [photo_path])
    errors = []      # error dialogs are recorded instead of blocking the test
    monkeypatch.setattr(QtWidgets.QMessageBox, "critical",
                        lambda parent, title, text, *a, **k: errors.append((title, text)))
    win = MainWindow()
    win.errors = errors
    win.resize(1100, 750)
    win.show()
    qtbot.waitExposed(win)
    history = History()
    history.add_dpj(small_dpj)
    win.set_history(history)
    dock = win.synthesis_dock
    dock.width_box.setValue(64)
    dock.height_box.setValue(48)
    dock.seed.set_value(7)
    win.synthesise_from_dock()
    assert win.runner.wait(60_000)
    win.mark_clean()
    yield win
    win.runner.cancel()
    win.runner.wait(10_000)
    if win.isVisible():
        win.mark_clean()
        for editor in win.findChildren(DPJEditor):    # nor ask about a DPJ editor's changes
            editor.undo_stack.setClean()
        win.close()
    win.deleteLater()
