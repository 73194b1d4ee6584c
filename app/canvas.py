"""The canvas: the document's level matrix shown through its palette, with zoom, pan and a 3×3 tiled preview.

It sits at the end of the data flow (levels + palette -> screen). It only displays and reports the
cursor; edits reach the document as Actions submitted by the main window, never from here.
"""

from __future__ import annotations

import math
import weakref

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtGui

from .mip import box_average, box_average_rgb, mip_level

GRID_MIN_ZOOM = 12.0          # screen pixels per cell before the pixel grid is drawn
ZOOM_STEP = math.sqrt(2.0)    # one +/- key press
MIN_ZOOM, MAX_ZOOM = 1 / 32, 128.0
BACKGROUND = "#2b2b2b"        # a neutral dark surround, as in Krita and GIMP
UNUSED_LEVEL = (255, 0, 255)  # a level beyond the palette shows up magenta instead of passing unseen


def palette_lut(palette) -> np.ndarray:
    """A 256-entry RGB lookup table: the palette's G colours, then magenta for impossible levels."""
    pal = np.asarray(palette, dtype=np.uint8).reshape(-1, 3)
    lut = np.empty((256, 3), dtype=np.uint8)
    lut[:] = UNUSED_LEVEL
    lut[: len(pal)] = pal
    return lut


def colourize(levels: np.ndarray, palette) -> np.ndarray:
    """(H, W, 3) uint8 RGB of a level matrix seen through a palette (for export and previews)."""
    return palette_lut(palette)[np.asarray(levels, dtype=np.uint8)]


def view_zoom(view: pg.ViewBox) -> float:
    """Screen pixels per cell, from the view's requested range (never a stale paint matrix)."""
    span = view.viewRect().width()
    return view.width() / span if span > 0 and view.width() > 0 else 1.0


class CanvasViewBox(pg.ViewBox):
    """A ViewBox with editor habits: wheel zooms around the cursor, middle-drag or space-drag pans.

    The left button belongs to the current tool (see CanvasView.tool_drag), except for the
    hand tool, which pans; the right button is left to a future context menu.
    """

    def __init__(self, canvas):
        super().__init__(lockAspect=True, invertY=True, enableMenu=False, defaultPadding=0.02)
        self.pan_key_held = False
        self._canvas = weakref.ref(canvas)  # weak: a cycle with the view crashes Qt at close

    def mouseDragEvent(self, ev, axis=None):
        button = ev.button()
        left = button == QtCore.Qt.MouseButton.LeftButton
        if left and self._canvas().in_gesture() and not ev.isStart():
            ev.accept()              # a stroke under way stays one until its release: Space or
            self._canvas().tool_drag(ev)   # the hand tool chosen mid-stroke pans the next drag
            return
        tool = self._canvas().tool
        panning = button == QtCore.Qt.MouseButton.MiddleButton or (
            left and (self.pan_key_held or (tool is not None and tool.PANS)))
        if panning:
            super().mouseDragEvent(ev, axis)
        elif left and tool is not None:
            ev.accept()
            self._canvas().tool_drag(ev)
        else:
            ev.ignore()

    def mouseClickEvent(self, ev):
        tool = self._canvas().tool
        if ev.button() == QtCore.Qt.MouseButton.LeftButton and tool is not None and not tool.PANS:
            ev.accept()
            self._canvas().tool_click(ev)
        else:
            ev.ignore()


class CanvasImage(pg.ImageItem):
    """The texture's image item: the level matrix through the palette at 100 % and above, a mip
    level below (set by the canvas, always placed on the cells it covers). ``smooth`` (zoomed
    out) draws it with bilinear filtering, so the last factor of less than 2 left by the mip
    level does not drop cells either; zoomed in, cells stay crisp squares."""

    def __init__(self):
        super().__init__(axisOrder="row-major")
        self.smooth = False

    def paint(self, painter, *args):
        painter.save()
        painter.setRenderHint(QtGui.QPainter.RenderHint.SmoothPixmapTransform, self.smooth)
        super().paint(painter, *args)
        painter.restore()


class TileEcho(pg.GraphicsObject):
    """The eight neighbours of the 3×3 tiled preview, painted from the image item's own QImage.

    Sharing the rendered image keeps a tiled 2048² preview at the memory cost of one tile; the
    image may be a mip level, so it is drawn where the item sits (its rect in cell coordinates)
    and repeated every ``tile_size`` cells.
    """

    def __init__(self, source: CanvasImage):
        super().__init__()
        self.source = source
        self.tile_size = (0, 0)      # (w, h) of the texture in cells, set by the canvas

    def boundingRect(self) -> QtCore.QRectF:
        w, h = self.tile_size
        return QtCore.QRectF(-w, -h, 3 * w, 3 * h)

    def paint(self, painter, *args):
        w, h = self.tile_size
        if not w or self.source.image is None:
            return
        if self.source.qimage is None or self.source._renderRequired:
            self.source.render()
        qimage = self.source.qimage
        if qimage is None:
            return
        rect = self.source.mapRectToParent(self.source.boundingRect())
        painter.save()
        painter.setRenderHint(QtGui.QPainter.RenderHint.SmoothPixmapTransform, self.source.smooth)
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                if dx or dy:
                    painter.drawImage(rect.translated(dx * w, dy * h), qimage)
        painter.restore()


class PixelGrid(pg.GraphicsObject):
    """Thin lines between cells, drawn only over the visible part and only when zoomed in far."""

    def __init__(self, view: CanvasViewBox):
        super().__init__()
        self.view = view
        self.bounds = QtCore.QRectF()
        self.pen = QtGui.QPen(QtGui.QColor(128, 128, 128, 120))
        self.pen.setCosmetic(True)
        self.pen.setWidth(1)

    def set_bounds(self, rect: QtCore.QRectF) -> None:
        self.prepareGeometryChange()
        self.bounds = QtCore.QRectF(rect)
        self.update()

    def boundingRect(self) -> QtCore.QRectF:
        return self.bounds

    def paint(self, painter, *args):
        if view_zoom(self.view) < GRID_MIN_ZOOM:
            return
        visible = self.view.viewRect().intersected(self.bounds)
        if visible.isEmpty():
            return
        painter.setPen(self.pen)
        x0, x1 = math.ceil(visible.left()), math.floor(visible.right())
        y0, y1 = math.ceil(visible.top()), math.floor(visible.bottom())
        lines = [QtCore.QLineF(x, visible.top(), x, visible.bottom()) for x in range(x0, x1 + 1)]
        lines += [QtCore.QLineF(visible.left(), y, visible.right(), y) for y in range(y0, y1 + 1)]
        painter.drawLines(lines)


def _drawn_from(qimage: QtGui.QImage | None, array: np.ndarray) -> bool:
    """Whether the image item's QImage shows ``array``'s own memory: pyqtgraph makes it on the
    memory of the array it renders where it can (an indexed or RGB picture), so a change of
    the array shows without a new render."""
    if qimage is None or qimage.isNull():
        return False
    pixels = np.frombuffer(qimage.constBits(), np.uint8, count=qimage.sizeInBytes())
    return np.may_share_memory(pixels, array)


class CanvasView(pg.GraphicsView):
    """The central widget. ``hovered`` carries (x, y, level) under the cursor, or None outside."""

    hovered = QtCore.Signal(object)
    zoomChanged = QtCore.Signal(float)

    def __init__(self, parent=None):
        self._levels: np.ndarray | None = None
        self._lut: np.ndarray | None = None      # the palette's 256-entry table
        self._picture: np.ndarray | None = None  # (H, W, 3) shown instead of lut[levels]: tone
        self._mips: dict[int, np.ndarray] = {}   # mip level k -> its picture, for this image
        self._shown_level: int | None = None     # the level the image item holds (None: stale)
        self._tiled = False
        self._last_zoom = 0.0
        super().__init__(parent, background=BACKGROUND)
        self.setFocusPolicy(QtCore.Qt.FocusPolicy.StrongFocus)
        self.setMouseTracking(True)
        self.tool = None            # the current tool (app.tools.Tool); set by the main window
        self._gesture = None        # the running drag generator
        self.view = CanvasViewBox(self)
        self.setCentralItem(self.view)
        self.image = CanvasImage()
        self.overlay = pg.ImageItem(axisOrder="row-major")   # tool previews: ghosts, selections
        self.stroke_preview = None  # the painting tools' StrokePreview, made on their first use
        self.echo = TileEcho(self.image)
        self.echo.setVisible(False)
        self.grid = PixelGrid(self.view)
        self.view.addItem(self.echo)
        self.view.addItem(self.image)
        self.view.addItem(self.grid)
        self.view.addItem(self.overlay)
        self.overlay.setZValue(5)
        self.grid.setZValue(10)
        self.view.sigRangeChanged.connect(self._range_changed)
        self.scene().sigMouseMoved.connect(self._mouse_moved)

    # -- content ----------------------------------------------------------------------------------
    def set_image(self, levels: np.ndarray, palette, picture: np.ndarray | None = None) -> None:
        """Show a level matrix through a palette; a new shape fits the view to it. ``picture``
        (uint8, grey (H, W) or RGB (H, W, 3), the levels' shape): shown instead of the palette's
        colours — the levels drawn with a photo's tone — while the cursor still reads levels."""
        new_shape = self._levels is None or self._levels.shape != levels.shape
        if picture is not None:
            picture = np.asarray(picture, dtype=np.uint8)
            if picture.shape[:2] != levels.shape:
                raise ValueError(f"a {picture.shape} picture for {levels.shape} levels")
            if picture.ndim == 2:
                picture = np.repeat(picture[..., None], 3, axis=2)
        self._picture = picture
        self._levels = levels
        self._lut = palette_lut(palette)
        self._mips.clear()
        self._shown_level = None
        self.echo.tile_size = (levels.shape[1], levels.shape[0])
        self.echo.prepareGeometryChange()
        self.grid.set_bounds(self.content_rect())
        if new_shape:
            self.fit()
        self._show_level()

    def update_box(self, levels: np.ndarray, box) -> bool:
        """Redraw only ``box`` (top, left, height, width) of a matrix of the shape shown, through
        the palette shown: the cells (or their mip) in that box are written into the canvas's
        own picture (a copy of the cells, or the mip), whose memory the QImage on screen is made
        on; nothing else is uploaded. Never into the QImage itself: until the next paint it may
        still be made on the matrix shown before, which a History keeps as an undo record.
        False (nothing done) when a full ``set_image`` is needed: another shape, no picture yet,
        or a picture not the canvas's own (a photo's tone)."""
        if (self._levels is None or levels.shape != self._levels.shape or box is None
                or self._picture is not None
                or self._shown_level is None or self.image.qimage is None
                or self.image.image is None):
            return False
        top, left, h, w = (int(v) for v in box)
        if h <= 0 or w <= 0:
            return True
        k = self._shown_level
        f = 1 << k
        r0, c0 = top >> k, left >> k
        r1, c1 = (top + h - 1) // f + 1, (left + w - 1) // f + 1
        if k == 0:
            patch = levels[r0:r1, c0:c1]
        else:
            patch = box_average(np.ascontiguousarray(levels[r0 * f:r1 * f, c0 * f:c1 * f]),
                                self._lut, k)
        shown = self.image.image               # the canvas's own cells or mip, never the matrix
        if not shown.flags.writeable:
            return False
        shown[r0:r1, c0:c1] = patch
        if not _drawn_from(self.image.qimage, shown):
            self.image.updateImage()           # a QImage of another array (not painted since)
        self._levels = levels
        for other in [j for j in self._mips if j != k]:
            del self._mips[other]
        self.image.update(QtCore.QRectF(c0 * f, r0 * f, (c1 - c0) * f, (r1 - r0) * f))
        self.echo.update()
        return True

    def set_palette(self, palette) -> None:
        """Recolour without touching the matrix (used by the palette dock's live preview); a
        picture shown instead of the palette's colours (tone) stays as it is."""
        self._lut = palette_lut(palette)
        if self._picture is not None:
            return
        self._mips.clear()
        if self._shown_level == 0:
            self.image.setLookupTable(self._lut)
            self.echo.update()
        elif self._shown_level is not None:
            self._shown_level = None
            self._show_level()

    def mip(self, k: int) -> np.ndarray:
        """Mip level k of the shown picture (box averages of 2^k × 2^k cells), built once per
        image or palette change and kept until the next."""
        mip = self._mips.get(k)
        if mip is None and self._picture is not None:
            mip = self._mips[k] = box_average_rgb(self._picture, k)
        elif mip is None:
            mip = self._mips[k] = box_average(self._levels, self._lut, k)
        return mip

    @property
    def shown_level(self) -> int | None:
        """The mip level on screen (0: the cells themselves)."""
        return self._shown_level

    def _show_level(self) -> None:
        """Put the picture for the current zoom in the image item: the cells at 100 % and
        above, below it the mip level of the largest power of two ≤ 1/zoom (device pixels),
        its rect kept on the cells it averages so picking and overlays line up."""
        if self._levels is None or (self._shown_level is not None and self.image.image is None):
            return       # no texture, or the main window cleared the picture (an empty document)
        zoom = self.zoom() * self.devicePixelRatioF()
        self.image.smooth = zoom < 1.0
        k = mip_level(zoom, self._levels.shape)
        if k == self._shown_level:
            return
        h, w = self._levels.shape
        if k == 0 and self._picture is not None:
            self.image.setImage(self._picture, lut=None, levels=(0, 255), autoLevels=False)
            self.image.setRect(QtCore.QRectF(0, 0, w, h))
        elif k == 0:                 # a copy: the QImage is made on its memory, and update_box
            cells = np.array(self._levels)          # writes there, never into the document's
            self.image.setImage(cells, lut=self._lut, levels=(0, 255), autoLevels=False)
            self.image.setRect(QtCore.QRectF(0, 0, w, h))
        else:
            mip, f = self.mip(k), 1 << k
            self.image.setImage(mip, lut=None, levels=(0, 255), autoLevels=False)
            self.image.setRect(QtCore.QRectF(0, 0, mip.shape[1] * f, mip.shape[0] * f))
        self._shown_level = k
        self.echo.update()

    @property
    def levels(self) -> np.ndarray | None:
        return self._levels

    @property
    def picture(self) -> np.ndarray | None:
        """The (H, W, 3) picture shown instead of the palette's colours (tone), or None."""
        return self._picture

    def shown_crop(self, side: int) -> np.ndarray | None:
        """The middle side × side (at most) of the picture shown, (h, w, 3) uint8: the tone or
        plates when they show, else the levels in the palette's colours; None when empty."""
        if self._levels is None or not self._levels.size:
            return None
        h, w = self._levels.shape
        top, left = max(0, (h - side) // 2), max(0, (w - side) // 2)
        box = (slice(top, top + side), slice(left, left + side))
        if self._picture is not None:
            return np.ascontiguousarray(self._picture[box][..., :3])
        return np.ascontiguousarray(self._lut[self._levels[box]][..., :3])

    def displayed_colour(self, x: int, y: int) -> tuple[int, int, int]:
        """The colour the canvas shows at cell (x, y) — what the user sees, for checks."""
        if self._picture is not None:
            return tuple(int(c) for c in self._picture[y, x])
        return tuple(int(c) for c in self._lut[self._levels[y, x]][:3])

    # -- tiled preview ----------------------------------------------------------------------------
    @property
    def tiled(self) -> bool:
        return self._tiled

    def set_tiled(self, on: bool) -> None:
        """Show the texture as a 3×3 tiling so seams at its borders can be judged."""
        if on == self._tiled:
            return
        self._tiled = bool(on)
        self.echo.setVisible(self._tiled)
        self.grid.set_bounds(self.content_rect())
        self.fit()

    def content_rect(self) -> QtCore.QRectF:
        if self._levels is None:
            return QtCore.QRectF()
        h, w = self._levels.shape
        if self._tiled:
            return QtCore.QRectF(-w, -h, 3 * w, 3 * h)
        return QtCore.QRectF(0, 0, w, h)

    # -- zoom ---------------------------------------------------------------------------------------
    def zoom(self) -> float:
        """Screen pixels per cell (1.0 = 100 %)."""
        return view_zoom(self.view)

    def set_zoom(self, zoom: float, center: QtCore.QPointF | None = None) -> None:
        zoom = min(max(zoom, MIN_ZOOM), MAX_ZOOM)
        factor = self.zoom() / zoom
        self.view.scaleBy((factor, factor), center=center)

    def zoom_in(self) -> None:
        self.set_zoom(self.zoom() * ZOOM_STEP)

    def zoom_out(self) -> None:
        self.set_zoom(self.zoom() / ZOOM_STEP)

    def actual_pixels(self) -> None:
        self.set_zoom(1.0)

    def fit(self) -> None:
        rect = self.content_rect()
        if not rect.isEmpty():
            self.view.setRange(rect, padding=0.02)

    def resizeEvent(self, ev):
        fitted = self._is_fitted()
        super().resizeEvent(ev)
        if fitted:
            self.fit()

    def _is_fitted(self) -> bool:
        rect = self.content_rect()
        if rect.isEmpty():
            return False
        view = self.view.viewRect()
        return view.contains(rect) and (
            view.width() < rect.width() * 1.1 or view.height() < rect.height() * 1.1)

    def _range_changed(self, *args):
        self.grid.update()
        self._show_level()
        zoom = self.zoom()
        if not math.isclose(zoom, self._last_zoom, rel_tol=1e-6):
            self._last_zoom = zoom
            self.zoomChanged.emit(zoom)

    # -- cursor -------------------------------------------------------------------------------------
    def cell_at(self, scene_pos) -> tuple[int, int] | None:
        """The (x, y) cell under a scene position, folded back into the texture in tiled mode."""
        if self._levels is None:
            return None
        p = self.view.mapSceneToView(scene_pos)
        x, y = math.floor(p.x()), math.floor(p.y())
        h, w = self._levels.shape
        lo_x, lo_y, span = (-w, -h, 3) if self._tiled else (0, 0, 1)
        if not (lo_x <= x < lo_x + span * w and lo_y <= y < lo_y + span * h):
            return None
        return x % w, y % h

    def point_at(self, scene_pos) -> tuple[int, int]:
        """The (x, y) cell under a scene position, even outside the canvas (a drag may leave
        it); folded back into the texture in tiled mode, so strokes wrap around."""
        p = self.view.mapSceneToView(scene_pos)
        x, y = math.floor(p.x()), math.floor(p.y())
        if self._tiled and self._levels is not None:
            h, w = self._levels.shape
            if -w <= x < 2 * w and -h <= y < 2 * h:
                return x % w, y % h
        return x, y

    # -- tools --------------------------------------------------------------------------------------
    def tool_click(self, ev) -> None:
        if self._levels is not None:
            self.tool.click(self.point_at(ev.scenePos()), ev.modifiers())

    def tool_drag(self, ev) -> None:
        """Run the tool's gesture generator: start on the first event, send each move, close on
        release (a tool error never leaves a gesture half-open)."""
        if self._levels is None:
            return
        if ev.isStart():
            self.end_gesture()
            self._gesture = self.tool.drag(self.point_at(ev.buttonDownScenePos()), ev.modifiers())
            if not self._next(None):
                return
        if self._gesture is not None:
            self._next(self.point_at(ev.scenePos()))
            if ev.isFinish():
                gesture, self._gesture = self._gesture, None
                gesture.close()

    def in_gesture(self) -> bool:
        return self._gesture is not None

    def end_gesture(self) -> None:
        """Close a drag left open (its release never came), so that its step lands now, in the
        document it was drawn on — not in whatever document the next drag finds."""
        if self._gesture is not None:
            gesture, self._gesture = self._gesture, None
            gesture.close()

    def _next(self, cell) -> bool:
        try:
            if cell is None:
                next(self._gesture)
            else:
                self._gesture.send(cell)
            return True
        except StopIteration:
            self._gesture = None
            return False

    def set_overlay(self, rgba: np.ndarray | None, origin: tuple[int, int] = (0, 0)) -> None:
        """Show an (h, w, 4) uint8 picture over the texture with its top-left cell at ``origin``
        (x, y) — a tool's preview, often just the bounding box of what moves — or nothing."""
        if rgba is None:
            self.overlay.clear()
            self.overlay.setVisible(False)
            return
        self.overlay.setImage(rgba, autoLevels=False, levels=(0, 255))
        h, w = rgba.shape[:2]
        self.overlay.setRect(QtCore.QRectF(origin[0], origin[1], w, h))
        self.overlay.setVisible(True)

    def _mouse_moved(self, scene_pos):
        cell = self.cell_at(scene_pos)
        if self.tool is not None and self._gesture is None:
            self.tool.hover(cell)
        if cell is None:
            self.hovered.emit(None)
        else:
            x, y = cell
            self.hovered.emit((x, y, int(self._levels[y, x])))

    # -- space-drag pan -----------------------------------------------------------------------------
    def keyPressEvent(self, ev):
        if ev.key() == QtCore.Qt.Key.Key_Space and not ev.isAutoRepeat():
            self.view.pan_key_held = True
            self.viewport().setCursor(QtCore.Qt.CursorShape.OpenHandCursor)
            ev.accept()
            return
        super().keyPressEvent(ev)

    def keyReleaseEvent(self, ev):
        if ev.key() == QtCore.Qt.Key.Key_Space and not ev.isAutoRepeat():
            self.view.pan_key_held = False
            self.viewport().unsetCursor()
            ev.accept()
            return
        super().keyReleaseEvent(ev)

    def leaveEvent(self, ev):
        self.hovered.emit(None)
        super().leaveEvent(ev)

    def focusOutEvent(self, ev):
        self.view.pan_key_held = False
        self.viewport().unsetCursor()
        super().focusOutEvent(ev)
