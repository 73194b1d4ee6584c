"""The Relief dock (companion document 003): the texture shaded as a height map, on a plane in
perspective and on a sphere, with the light dragged on a small ball; and File ▸ Export ▸ Height
map… / Normal map…, written by the engine (texeditor.relief).

Views and exports, not changes of the document: no Action. The settings are a ReliefSettings
held by a SettingsModel and kept in the user's settings (QSettings) from one session to the next.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.relief import (light_direction, plane_preview, sphere_preview, write_height_map,
                              write_normal_map)
from texeditor.relief.shading import MAX_STRENGTH, lambert

from .files import settings
from .images import qimage_from_rgb
from .tool_settings import SettingsModel
from .widgets import scrolled

PREVIEWS = (96, 256)         # the smallest and largest side of a preview: half the dock's width
BALL = 96                    # side of the light ball, pixels
OPENGL_FILTER = "Normal map, OpenGL: green up (*.png)"
DIRECTX_FILTER = "Normal map, DirectX: green down (*.png)"
HEIGHT_FILTER = "Height map, 16-bit grey (*.png)"


@dataclass(frozen=True)
class ReliefSettings:
    """The light (degrees), the height scale and the shading coefficients of the previews and
    the normal map; the last normal map convention chosen and whether it wraps."""

    azimuth: float = 135.0
    elevation: float = 45.0
    strength: float = 4.0
    ambient: float = 0.3
    diffuse: float = 0.7
    directx: bool = False
    wrap: bool = True

    def lighting(self) -> dict:
        """The previews' keyword arguments."""
        return {"strength": self.strength, "azimuth": self.azimuth,
                "elevation": self.elevation, "ambient": self.ambient, "diffuse": self.diffuse}


LIMITS = {"azimuth": (-180.0, 180.0), "elevation": (0.0, 90.0), "strength": (0.0, 20.0),
          "ambient": (0.0, 1.0), "diffuse": (0.0, 1.5)}
assert LIMITS["strength"][1] <= MAX_STRENGTH


def load_settings() -> ReliefSettings:
    """The settings kept last time; a value missing, of the wrong type or out of range (a
    settings file edited by hand) is the default."""
    store, default = settings(), ReliefSettings()
    values = {}
    for field in dataclasses.fields(ReliefSettings):
        raw = store.value(f"relief/{field.name}")
        if raw is None:
            continue
        if isinstance(field.default, bool):
            values[field.name] = str(raw).lower() in ("true", "1")
            continue
        try:
            value = float(raw)
        except (TypeError, ValueError):
            continue
        lo, hi = LIMITS[field.name]
        if math.isfinite(value) and lo <= value <= hi:
            values[field.name] = value
    return dataclasses.replace(default, **values)


def save_settings(value: ReliefSettings) -> None:
    store = settings()
    for field in dataclasses.fields(value):
        store.setValue(f"relief/{field.name}", getattr(value, field.name))


class LightBall(QtWidgets.QWidget):
    """A lit ball: drag on it to put the light where the pointer is (the centre: straight
    above the texture; the rim: grazing). Emits ``moved(azimuth, elevation)`` in degrees."""

    moved = QtCore.Signal(float, float)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setFixedSize(BALL, BALL)
        self.setCursor(QtCore.Qt.CursorShape.CrossCursor)
        self.setToolTip("Drag to move the light: the centre is straight above the texture, the "
                        "rim grazing")
        self.light = light_direction(135, 45)
        s = (np.arange(BALL) + 0.5) / BALL * 2 - 1
        x, y = np.meshgrid(s, -s)
        self._inside = x * x + y * y < 1
        self._normals = np.dstack([x, y, np.sqrt(np.clip(1 - x * x - y * y, 0, 1))])

    def set_light(self, azimuth: float, elevation: float) -> None:
        self.light = light_direction(azimuth, elevation)
        self.update()

    def light_at(self, pos: QtCore.QPointF) -> tuple[float, float]:
        """(azimuth, elevation) of the light over the ball's point under ``pos``; beyond the
        rim, on the rim."""
        x = (pos.x() / self.width()) * 2 - 1
        y = 1 - (pos.y() / self.height()) * 2
        r = math.hypot(x, y)
        if r > 1:
            x, y, r = x / r, y / r, 1.0
        azimuth = math.degrees(math.atan2(y, x)) if r > 1e-9 else 0.0
        return azimuth, math.degrees(math.acos(min(1.0, r)))

    def picture(self) -> np.ndarray:
        """The ball lit by the light, as (BALL, BALL, 3) uint8."""
        grey = 255 * lambert(self._normals @ self.light, 0.12, 0.88)
        rgb = np.where(self._inside, np.clip(grey, 0, 255), 0)
        return np.repeat(rgb[..., None], 3, axis=2).astype(np.uint8)

    def paintEvent(self, ev) -> None:
        p = QtGui.QPainter(self)
        p.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing)
        path = QtGui.QPainterPath()
        path.addEllipse(QtCore.QRectF(0.5, 0.5, BALL - 1, BALL - 1))
        p.setClipPath(path)
        p.drawImage(0, 0, qimage_from_rgb(self.picture()))
        p.setClipping(False)
        lx, ly = self.light[0], self.light[1]
        centre = QtCore.QPointF((lx + 1) / 2 * BALL, (1 - ly) / 2 * BALL)
        p.setPen(QtGui.QPen(QtGui.QColor(20, 20, 20), 1.5))
        p.setBrush(QtGui.QColor(255, 214, 64))
        p.drawEllipse(centre, 5, 5)
        p.end()

    def mousePressEvent(self, ev) -> None:
        if ev.button() == QtCore.Qt.MouseButton.LeftButton:
            self.moved.emit(*self.light_at(ev.position()))

    def mouseMoveEvent(self, ev) -> None:
        if ev.buttons() & QtCore.Qt.MouseButton.LeftButton:
            self.moved.emit(*self.light_at(ev.position()))


class PreviewPair(QtWidgets.QWidget):
    """The plane and the sphere side by side, each half the width (within PREVIEWS); says
    ``resized`` when that side changes, for the pictures to be drawn again at the new size."""

    resized = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        self.side = PREVIEWS[0]
        grid = QtWidgets.QGridLayout(self)
        grid.setContentsMargins(0, 0, 0, 0)
        self.labels = []
        for col, (title, tip) in enumerate((
                ("Plane", "The texture repeated on a plane seen in perspective, lit in the "
                          "plane's own frame"),
                ("Sphere", "The texture wrapped round a ball; the light is set as seen from "
                           "the viewer"))):
            label = QtWidgets.QLabel()
            label.setToolTip(tip)
            label.setSizePolicy(QtWidgets.QSizePolicy.Policy.Ignored,
                                QtWidgets.QSizePolicy.Policy.Fixed)
            label.setFixedHeight(self.side)
            label.setMinimumWidth(PREVIEWS[0])
            label.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
            grid.addWidget(QtWidgets.QLabel(title), 0, col)
            grid.addWidget(label, 1, col)
            self.labels.append(label)

    def resizeEvent(self, ev) -> None:
        super().resizeEvent(ev)
        spacing = self.layout().horizontalSpacing()
        side = max(PREVIEWS[0], min(PREVIEWS[1], (self.width() - spacing) // 2))
        if side != self.side:
            self.side = side
            for label in self.labels:
                label.setFixedHeight(side)
            self.resized.emit()

    def show_pictures(self, pictures) -> None:
        for label, rgb in zip(self.labels, pictures or (None, None)):
            if rgb is None:
                label.clear()
            else:
                label.setPixmap(QtGui.QPixmap.fromImage(qimage_from_rgb(rgb)))


class ReliefDock(QtWidgets.QDockWidget):
    """The light, the strength and the shading; the previews follow the document (its change
    events, through the main window) and the settings; the export actions."""

    def __init__(self, window):
        super().__init__("Relief", window)
        self.main_window = window
        self.model = SettingsModel(load_settings())
        self._stale = True
        self.shown: tuple[np.ndarray, np.ndarray] | None = None    # the previews on show
        body = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(body)
        layout.addLayout(self._light_row())
        form = QtWidgets.QFormLayout()
        self.strength = self._slider(form, "Strength", "strength", 10,
                                     "Height of the relief: heights are the greys (0..1) "
                                     "times this")
        self.ambient = self._slider(form, "Ambient", "ambient", 100,
                                    "k_a: light everywhere, even in the shadows")
        self.diffuse = self._slider(form, "Diffuse", "diffuse", 100,
                                    "k_d: light on the faces turned towards the lamp")
        self.wrap = QtWidgets.QCheckBox("Seamless normal map")
        self.wrap.setToolTip("Differences taken across the edges, so that a texture that tiles "
                             "gives a normal map that tiles; off: one-sided at the border")
        self.model.bind("wrap", self.wrap)
        form.addRow(self.wrap)
        layout.addLayout(form)
        self.previews = PreviewPair()
        self.previews.resized.connect(self.document_changed)
        layout.addWidget(self.previews)
        self.act_height = QtGui.QAction("&Height map…", self)
        self.act_height.setStatusTip("Write the texture's greys as a 16-bit grey PNG")
        self.act_height.triggered.connect(self.export_height)
        self.act_normal = QtGui.QAction("&Normal map…", self)
        self.act_normal.setStatusTip("Write the tangent-space normal map of the relief as an RGB "
                                     "PNG (OpenGL or DirectX green)")
        self.act_normal.triggered.connect(self.export_normal)
        layout.addLayout(self._export_row())
        layout.addStretch(1)
        self.setWidget(scrolled(body))
        self.model.changed.connect(self._settings_changed)
        self._settings_changed()

    # -- building -----------------------------------------------------------------------------------
    def _light_row(self) -> QtWidgets.QHBoxLayout:
        row = QtWidgets.QHBoxLayout()
        self.ball = LightBall()
        self.ball.moved.connect(lambda az, el: self.model.update(azimuth=az, elevation=el))
        row.addWidget(self.ball)
        form = QtWidgets.QFormLayout()
        self.azimuth = QtWidgets.QSpinBox()
        self.azimuth.setRange(-180, 180)
        self.azimuth.setWrapping(True)
        self.azimuth.setSuffix("°")
        self.azimuth.setToolTip("Where the light comes from, counter-clockwise from the right: "
                                "90° from the top of the picture")
        self.elevation = QtWidgets.QSpinBox()
        self.elevation.setRange(0, 90)
        self.elevation.setSuffix("°")
        self.elevation.setToolTip("Height of the light above the texture: 90° straight above")
        self.model.bind("azimuth", self.azimuth)
        self.model.bind("elevation", self.elevation)
        form.addRow("Azimuth", self.azimuth)
        form.addRow("Elevation", self.elevation)
        row.addLayout(form, 1)
        return row

    def _slider(self, form, label: str, name: str, scale: int, tip: str) -> QtWidgets.QSlider:
        """A slider for a decimal setting (value × scale), with its value beside it."""
        lo, hi = LIMITS[name]
        slider = QtWidgets.QSlider(QtCore.Qt.Orientation.Horizontal)
        slider.setRange(round(lo * scale), round(hi * scale))
        slider.setToolTip(tip)
        value = QtWidgets.QLabel()
        value.setMinimumWidth(QtGui.QFontMetrics(value.font()).horizontalAdvance("20.00") + 4)
        value.setAlignment(QtCore.Qt.AlignmentFlag.AlignRight
                           | QtCore.Qt.AlignmentFlag.AlignVCenter)
        slider.valueChanged.connect(lambda v: value.setText(f"{v / scale:.2f}"))
        self.model.bind(name, slider, scale=scale)
        value.setText(f"{slider.value() / scale:.2f}")
        box = QtWidgets.QHBoxLayout()
        box.addWidget(slider, 1)
        box.addWidget(value)
        form.addRow(label, box)
        return slider

    def _export_row(self) -> QtWidgets.QHBoxLayout:
        row = QtWidgets.QHBoxLayout()
        row.addWidget(QtWidgets.QLabel("Export"))
        for action, text in ((self.act_height, "Height map…"), (self.act_normal, "Normal map…")):
            button = QtWidgets.QPushButton(text)
            button.setToolTip(action.statusTip())
            button.clicked.connect(action.trigger)
            row.addWidget(button)
        return row

    def menu_entries(self) -> list[tuple[str, QtGui.QAction | None]]:
        """(menu objectName, action or None for a separator) the window adds for this dock."""
        return [("ExportMenu", None), ("ExportMenu", self.act_height),
                ("ExportMenu", self.act_normal)]

    # -- showing ------------------------------------------------------------------------------------
    def showEvent(self, ev) -> None:
        """Shown (View ▸ Relief, its tab chosen): the previews of the document as it is now."""
        super().showEvent(ev)
        if self._stale:
            self.refresh()

    def _settings_changed(self, _name: str = "") -> None:
        value = self.model.value
        self.ball.set_light(value.azimuth, value.elevation)
        save_settings(value)
        self.document_changed()

    def document_changed(self) -> None:
        """The document's levels or palette (or the settings) changed: draw the previews again,
        at once when the dock is on show, else when it is next shown."""
        self._stale = True
        if self.isVisible():
            self.refresh()

    def refresh(self) -> None:
        """Draw both previews of the document (10–20 ms each, whatever its size)."""
        history = self.main_window.history
        levels = history.document.levels if history is not None else np.zeros((0, 0))
        self._stale = False
        if not levels.size:
            self.shown = None
            self.previews.show_pictures(None)
            return
        palette, lighting = history.document.palette, self.model.value.lighting()
        self.shown = tuple(draw(levels, palette, size=self.previews.side, **lighting)
                           for draw in (plane_preview, sphere_preview))
        self.previews.show_pictures(self.shown)

    # -- exports ------------------------------------------------------------------------------------
    def export_height(self) -> bool:
        """Ask where, then write the height map."""
        if not self._has_texture():
            return False
        path, _ = self._ask("Export the height map", "height", HEIGHT_FILTER, HEIGHT_FILTER)
        return bool(path) and self._write(path, "height map", "", write_height_map)

    def export_normal(self) -> bool:
        """Ask where, then write the normal map with the dock's strength and wrap; the file
        dialog's type chooses OpenGL or DirectX (remembered for next time)."""
        if not self._has_texture():
            return False
        chosen = DIRECTX_FILTER if self.model.value.directx else OPENGL_FILTER
        path, picked = self._ask("Export the normal map", "normal",
                                 f"{OPENGL_FILTER};;{DIRECTX_FILTER}", chosen)
        if not path:
            return False
        if (picked == DIRECTX_FILTER) != self.model.value.directx:
            self.model.update(directx=picked == DIRECTX_FILTER)
        value = self.model.value
        return self._write(path, "normal map", f" ({'DirectX' if value.directx else 'OpenGL'})",
                           lambda p, levels, palette: write_normal_map(
                               p, levels, palette, strength=value.strength,
                               directx=value.directx, wrap=value.wrap))

    def _has_texture(self) -> bool:
        if self.main_window.still_opening():
            return False
        if self.main_window.history.document.levels.size:
            return True
        self.main_window.statusBar().showMessage("Nothing to export: the canvas is empty.", 5000)
        return False

    def _ask(self, title: str, what: str, filters: str, chosen: str) -> tuple[str, str]:
        window = self.main_window
        folder, stem = (window.path.parent, window.path.stem) if window.path is not None \
            else (Path.home(), "texture")
        start = str(folder / f"{stem}-{what}.png")
        return QtWidgets.QFileDialog.getSaveFileName(window, title, start, filters, chosen)

    def _write(self, path, what: str, detail: str, write) -> bool:
        """``write(path, levels, palette)`` the document's map (atomic: no half-written file);
        a failure is a dialog."""
        path = Path(path)
        if path.suffix.lower() != ".png":
            path = path.with_name(path.name + ".png")
        doc = self.main_window.history.document
        levels, palette = doc.levels.copy(), doc.palette.copy()     # edits may follow
        h, w = doc.shape
        return self.main_window.write_export(h * w, path, lambda: write(path, levels, palette),
                                             f"Cannot export the {what}",
                                             f"Exported the {what}{detail} {path} ({w}×{h}).")
