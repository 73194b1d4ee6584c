"""Offscreen Qt for the GUI tests, with settings kept away from the user's own."""

import os

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

import PySide6  # noqa: E402
import pytest  # noqa: E402
from PySide6 import QtCore  # noqa: E402

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
