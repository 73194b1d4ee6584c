"""The Relief dock in a session: opened from the View menu, the light dragged on its ball, a
brush stroke and its undo seen in the previews, the sliders, the dock hidden and shown again,
and both maps exported from File ▸ Export and read back (issue 20)."""

import imageio.v3 as iio
import numpy as np
from PySide6 import QtCore, QtWidgets

from app.relief_dock import BALL, DIRECTX_FILTER, OPENGL_FILTER, ReliefSettings, load_settings
from texeditor.relief import plane_preview, sphere_preview

from .support import LEFT, cell_pos, drag, press_key, settle

Key = QtCore.Qt.Key


def view_action(window, title):
    return next(a for a in window.menu("ViewMenu").actions() if a.text() == title)


def export_action(window, text):
    return next(a for a in window.menu("ExportMenu").actions() if a.text() == text)


def expected(window, dock):
    """Both previews drawn by the engine from the document and the dock's settings."""
    doc, side = window.document, dock.previews.side
    lighting = dock.model.value.lighting()
    return (plane_preview(doc.levels, doc.palette, size=side, **lighting),
            sphere_preview(doc.levels, doc.palette, size=side, **lighting))


def at(window, x, y) -> tuple[int, int]:
    """The canvas viewport position of cell (x, y), for a drag."""
    p = cell_pos(window.canvas, x, y)
    return p.x(), p.y()


def same(a, b) -> bool:
    return all(np.array_equal(x, y) for x, y in zip(a, b))


def save_as(monkeypatch, path, chosen=""):
    monkeypatch.setattr(QtWidgets.QFileDialog, "getSaveFileName",
                        lambda *a, **k: (str(path), chosen))


def test_a_relief_session(window, qtbot, tmp_path, monkeypatch):
    dock = window.relief_dock
    assert not dock.isVisible() and dock.model.value == ReliefSettings()     # hidden at first
    view_action(window, "Relief").trigger()
    qtbot.waitUntil(dock.isVisible)
    assert dock.shown is not None and same(dock.shown, expected(window, dock))
    qtbot.waitUntil(lambda: not dock.visibleRegion().isEmpty())    # in front of its tabs
    settle(window)
    assert dock.width() > 200 and dock.height() > 300, dock.size()  # sized as a dock in front
    assert not dock.widget().horizontalScrollBar().isVisible()      # it fits its column
    assert not dock.widget().verticalScrollBar().isVisible()
    first = dock.shown

    # the light dragged to the right rim of the ball: from the right, grazing
    drag(dock.ball, LEFT, (BALL // 2, BALL // 2), (BALL - 2, BALL // 2))
    light = dock.model.value
    assert abs(light.azimuth) <= 1 and light.elevation < 20
    assert dock.azimuth.value() == round(light.azimuth)
    assert not same(dock.shown, first) and same(dock.shown, expected(window, dock))
    # then to the top of the ball, half-way up: from the top of the picture
    drag(dock.ball, LEFT, (BALL - 2, BALL // 2), (BALL // 2, BALL // 4))
    light = dock.model.value
    assert abs(light.azimuth - 90) <= 1 and 55 <= light.elevation <= 65     # acos(0.5) = 60°
    lit = dock.shown
    assert same(lit, expected(window, dock))

    # a brush stroke: the previews follow the document; undo brings the same pictures back
    press_key(window, Key.Key_B)
    window.palette_dock.swatches.current = 3
    before = window.document.levels.copy()
    drag(window.canvas.viewport(), LEFT, at(window, 4, 10), at(window, 60, 30), steps=8)
    assert not np.array_equal(window.document.levels, before)
    assert not same(dock.shown, lit) and same(dock.shown, expected(window, dock))
    window.undo()
    assert np.array_equal(window.document.levels, before) and same(dock.shown, lit)

    # the sliders: a stronger relief, more ambient light
    dock.strength.setFocus()
    qtbot.keyClick(dock.strength, Key.Key_PageUp)
    assert dock.model.value.strength > light.strength
    assert not same(dock.shown, lit) and same(dock.shown, expected(window, dock))
    brighter = dock.shown
    dock.ambient.setValue(dock.ambient.value() + 20)
    assert abs(dock.model.value.ambient - light.ambient - 0.2) < 1e-9
    assert all((new.astype(int) >= old).all() and (new > old).any()
               for new, old in zip(dock.shown, brighter))
    dock.strength.setValue(60)
    assert dock.model.value.strength == 6.0

    # hidden, the dock does not draw; shown again, it draws the document as it is now
    view_action(window, "Relief").trigger()
    qtbot.waitUntil(lambda: not dock.isVisible())
    shown = dock.shown
    drag(window.canvas.viewport(), LEFT, at(window, 10, 5), at(window, 10, 40), steps=6)
    assert dock.shown is shown
    view_action(window, "Relief").trigger()
    qtbot.waitUntil(dock.isVisible)
    assert same(dock.shown, expected(window, dock)) and not same(dock.shown, shown)

    # File ▸ Export ▸ Height map… and Normal map… (OpenGL, then DirectX), read back
    doc, log = window.document, window.history.actions
    save_as(monkeypatch, tmp_path / "height")                          # .png is added
    export_action(window, "&Height map…").trigger()
    height = iio.imread(tmp_path / "height.png")
    assert height.dtype == np.uint16
    assert np.array_equal(height, doc.palette[doc.levels, 0].astype(np.uint16) * 257)
    save_as(monkeypatch, tmp_path / "gl.png", OPENGL_FILTER)
    export_action(window, "&Normal map…").trigger()
    save_as(monkeypatch, tmp_path / "dx.png", DIRECTX_FILTER)
    export_action(window, "&Normal map…").trigger()
    gl, dx = iio.imread(tmp_path / "gl.png"), iio.imread(tmp_path / "dx.png")
    assert gl.shape == doc.shape + (3,) and gl.dtype == np.uint8
    assert np.array_equal(dx[..., 1], 255 - gl[..., 1])
    assert np.array_equal(dx[..., ::2], gl[..., ::2])
    # the normal map's strength is the dock's: the slopes of the greys × 6, wrapped
    grey = doc.palette[doc.levels, 0] / 255 * 6.0
    du = (np.roll(grey, -1, 1) - np.roll(grey, 1, 1)) / 2
    assert np.abs(gl[..., 0] / 255 * 2 - 1 + du / np.sqrt(1 + du ** 2 + (
        (np.roll(grey, 1, 0) - np.roll(grey, -1, 0)) / 2) ** 2)).max() <= 1 / 255 + 1e-9
    assert window.history.actions == log and window.errors == []     # views and exports only

    # the settings are kept for the next session, the DirectX choice included
    kept = load_settings()
    assert kept == dock.model.value and kept.directx and kept.strength == 6.0


def test_a_failed_export_says_why_and_writes_nothing(window, qtbot, tmp_path, monkeypatch):
    view_action(window, "Relief").trigger()
    qtbot.waitUntil(window.relief_dock.isVisible)
    target = tmp_path / "missing" / "n.png"
    save_as(monkeypatch, target, OPENGL_FILTER)
    export_action(window, "&Normal map…").trigger()
    assert window.errors and "normal map" in window.errors[-1][0] and not target.exists()
    save_as(monkeypatch, "", "")                                       # the dialog cancelled
    export_action(window, "&Height map…").trigger()
    assert len(window.errors) == 1
