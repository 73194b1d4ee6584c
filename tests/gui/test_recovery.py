"""Crash recovery end to end: a real app process is killed after N actions; the next start
offers its work back and restores exactly those N actions."""

import os
import subprocess
import sys
import textwrap

import numpy as np
from PySide6 import QtWidgets

from app.recovery import offer_recovery
from texeditor.recipe.journal import orphans

N = 6
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHILD = textwrap.dedent(f"""
    import os, signal
    from PySide6 import QtWidgets
    app = QtWidgets.QApplication([])
    from app.main_window import MainWindow
    from texeditor.recipe.actions import NewCanvas, SetLevels
    from texeditor.recipe.history import History
    window = MainWindow()
    window.show()
    window.set_history(History())
    window.submit(NewCanvas(40, 30, 4))
    for k in range({N} - 1):
        window.submit(SetLevels(k, 2 * k, 3, 5, 1 + k % 3))
        app.processEvents()
    os.kill(os.getpid(), signal.SIGKILL)    # a crash: no close, no cleanup
""")


def expected_levels():
    levels = np.zeros((30, 40), np.uint8)
    for k in range(N - 1):
        levels[k:k + 3, 2 * k:2 * k + 5] = 1 + k % 3
    return levels


def test_a_killed_app_is_restored_exactly_up_to_its_last_action(window, monkeypatch, qtbot):
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    proc = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True,
                          timeout=120, cwd=ROOT)
    assert proc.returncode == -9, proc.stderr.decode()[-2000:]
    assert len(orphans()) == 1
    asked = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "question",
                        lambda *a, **k: asked.append(a[2]) or QtWidgets.QMessageBox.StandardButton.Yes)
    assert offer_recovery(window) == 1
    assert asked and f"{N} steps" in asked[0]
    assert len(window.history.applied) == N
    assert np.array_equal(window.document.levels, expected_levels())
    assert window.is_modified() and "*" in window.windowTitle()
    assert orphans() == []                     # offered once, then gone


def test_declining_forgets_the_journal(window, monkeypatch):
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True, timeout=120,
                   cwd=ROOT)
    before = window.history.applied
    monkeypatch.setattr(QtWidgets.QMessageBox, "question",
                        lambda *a, **k: QtWidgets.QMessageBox.StandardButton.No)
    assert offer_recovery(window) == 0
    assert window.history.applied == before and orphans() == []
