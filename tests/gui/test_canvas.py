"""The canvas alone: palette display, wheel zoom around the cursor, pan, grid and tiled preview."""

import numpy as np
import pytest
from PySide6 import QtCore, QtGui

from app.canvas import GRID_MIN_ZOOM, CanvasView

from .support import drag, wheel


def make_canvas(qtbot, shape=(40, 60)):
    canvas = CanvasView()
    qtbot.addWidget(canvas)
    canvas.resize(600, 400)
    canvas.show()
    qtbot.waitExposed(canvas)
    levels = (np.arange(shape[0] * shape[1]) % 4).reshape(shape).astype(np.uint8)
    palette = np.array([[0, 0, 0], [255, 0, 0], [0, 255, 0], [0, 0, 255]], np.uint8)
    canvas.set_image(levels, palette)
    return canvas, levels


def test_shows_levels_through_palette(qtbot):
    canvas, levels = make_canvas(qtbot)
    assert canvas.displayed_colour(1, 0) == (255, 0, 0)
    canvas.set_palette(np.array([[9, 9, 9]] * 4, np.uint8))
    assert canvas.displayed_colour(1, 0) == (9, 9, 9)


def test_wheel_zooms_around_cursor(qtbot):
    canvas, _ = make_canvas(qtbot)
    before = canvas.zoom()
    pos = QtCore.QPoint(200, 150)
    cell_before = canvas.view.mapSceneToView(canvas.mapToScene(pos))
    wheel(canvas.viewport(), pos, 3)
    assert canvas.zoom() > before * 1.5
    cell_after = canvas.view.mapSceneToView(canvas.mapToScene(pos))
    assert abs(cell_after.x() - cell_before.x()) < 0.5 and abs(cell_after.y() - cell_before.y()) < 0.5
    wheel(canvas.viewport(), pos, -3)
    assert abs(canvas.zoom() - before) / before < 0.01


def test_middle_drag_pans_and_left_drag_does_not(qtbot):
    canvas, _ = make_canvas(qtbot)
    canvas.set_zoom(20)
    start = canvas.view.viewRect().center()
    drag(canvas.viewport(), QtCore.Qt.MouseButton.LeftButton, (300, 200), (200, 200))
    assert canvas.view.viewRect().center() == start
    drag(canvas.viewport(), QtCore.Qt.MouseButton.MiddleButton, (300, 200), (200, 200))
    moved = canvas.view.viewRect().center() - start
    assert moved.x() > 3  # dragged left by 100 px = 5 cells at 20 px/cell: the view moves right


def test_space_drag_pans(qtbot):
    canvas, _ = make_canvas(qtbot)
    canvas.set_zoom(20)
    canvas.setFocus()
    start = canvas.view.viewRect().center()
    qtbot.keyPress(canvas, QtCore.Qt.Key.Key_Space)
    drag(canvas.viewport(), QtCore.Qt.MouseButton.LeftButton, (300, 200), (300, 100))
    qtbot.keyRelease(canvas, QtCore.Qt.Key.Key_Space)
    assert canvas.view.viewRect().center().y() - start.y() > 3
    assert not canvas.view.pan_key_held


def test_tiled_preview_and_grid(qtbot):
    canvas, _ = make_canvas(qtbot)
    canvas.set_tiled(True)
    assert canvas.echo.isVisible()
    rect = canvas.view.viewRect()
    assert rect.width() >= 3 * 60 and rect.height() >= 3 * 40 * 0.99
    # a cell of the left neighbour tile folds back into the texture
    scene = canvas.view.mapViewToScene(QtCore.QPointF(-59.5, 0.5))
    assert canvas.cell_at(scene) == (0, 0)
    canvas.set_tiled(False)
    assert not canvas.echo.isVisible()
    canvas.set_zoom(GRID_MIN_ZOOM * 2)
    assert canvas.zoom() > GRID_MIN_ZOOM


def test_hover_reports_cell_and_level(qtbot):
    canvas, levels = make_canvas(qtbot)
    seen = []
    canvas.hovered.connect(seen.append)
    scene = canvas.view.mapViewToScene(QtCore.QPointF(5.5, 2.5))
    pos = canvas.mapFromScene(scene)
    qtbot.mouseMove(canvas.viewport(), pos)
    qtbot.wait(20)
    assert seen and seen[-1] == (5, 2, int(levels[2, 5]))


# -- zoomed out: mip levels (issue 16) ---------------------------------------------------------------

GREYS = np.array([[0, 0, 0], [255, 255, 255], [255, 0, 0], [0, 0, 255]], np.uint8)


def zoomed_out(qtbot, levels, zoom=0.25, palette=GREYS):
    canvas = CanvasView()
    qtbot.addWidget(canvas)
    canvas.resize(600, 400)
    canvas.show()
    qtbot.waitExposed(canvas)
    canvas.set_image(levels, palette)
    canvas.set_zoom(zoom)
    canvas.view.setRange(QtCore.QRectF(0, 0, 10, 10), padding=0)   # top-left corner in view
    canvas.set_zoom(zoom)
    qtbot.wait(20)
    return canvas


def screen(canvas) -> np.ndarray:
    """The canvas as rendered on screen: (h, w, 3) uint8 from a grab."""
    image = canvas.grab().toImage().convertToFormat(QtGui.QImage.Format.Format_RGB888)
    w, h, stride = image.width(), image.height(), image.bytesPerLine()
    return np.frombuffer(image.constBits(), np.uint8).reshape(h, stride)[:, :3 * w].reshape(
        h, w, 3).copy()


def texture_pixels(canvas, shot: np.ndarray, margin: int = 3) -> np.ndarray:
    """The screen pixels that show the texture (a margin inside its edges)."""
    rect = canvas.mapFromScene(canvas.view.mapViewToScene(
        QtCore.QRectF(0, 0, canvas.levels.shape[1], canvas.levels.shape[0]))).boundingRect()
    rect = rect.intersected(QtCore.QRect(0, 0, shot.shape[1], shot.shape[0]))
    return shot[rect.top() + margin:rect.bottom() - margin, rect.left() + margin:
                rect.right() - margin]


@pytest.mark.parametrize("shape", [(64, 96), (37, 53), (9, 1)])
def test_a_toned_picture_s_mip_levels_are_its_block_means(shape):
    """A texture shown with its tone is reduced in one pass over its RGB pixels: each pixel of
    level k the rounded mean of its 2^k × 2^k block (partial blocks at the edges: the cells they
    have), exactly as the levels' own mip through their palette."""
    from app.mip import box_average, box_average_rgb
    rng = np.random.default_rng(sum(shape))
    rgb = rng.integers(0, 256, shape + (3,), dtype=np.uint8)
    for k in range(4):
        f = 1 << k
        got = box_average_rgb(rgb, k)
        h, w = -(-shape[0] // f), -(-shape[1] // f)
        assert got.shape == (h, w, 3)
        for i, j in ((0, 0), (h - 1, w - 1), (h // 2, w // 3)):
            block = rgb[i * f:(i + 1) * f, j * f:(j + 1) * f].reshape(-1, 3).astype(int)
            assert np.array_equal(got[i, j], (block.sum(0) + len(block) // 2) // len(block))
        grey = rgb[..., 1]                               # the levels' path agrees
        ramp = np.repeat(np.arange(256, dtype=np.uint8)[:, None], 3, axis=1)
        assert np.array_equal(box_average(grey, ramp, k)[..., 0],
                              box_average_rgb(np.dstack([grey] * 3), k)[..., 0])


@pytest.mark.parametrize("pattern", ["checkerboard", "stripes", "pairs"])
def test_zoomed_out_shows_area_averages_not_moire(qtbot, pattern):
    y, x = np.indices((1024, 1536))
    levels = {"checkerboard": (x + y) % 2, "stripes": x % 2,
              "pairs": (x // 2) % 2}[pattern].astype(np.uint8)
    canvas = zoomed_out(qtbot, levels, 0.25)
    assert abs(canvas.zoom() - 0.25) < 0.01 and canvas.shown_level == 2
    seen = texture_pixels(canvas, screen(canvas)).astype(int)
    assert seen.size > 3 * 100 * 100
    # half black, half white cells: every screen pixel is their mean, a mid-grey
    assert np.all(np.abs(seen - 127.5) <= 3), (seen.min(), seen.max())


def test_zoom_between_levels_and_back_to_cells(qtbot):
    y, x = np.indices((1024, 1536))
    canvas = zoomed_out(qtbot, ((x + y) % 2).astype(np.uint8), 0.3)
    assert canvas.shown_level == 1                     # 2 ≤ 1/0.3 < 4
    seen = texture_pixels(canvas, screen(canvas)).astype(int)
    assert np.all(np.abs(seen - 127.5) <= 3)
    canvas.set_zoom(4)
    qtbot.wait(10)
    assert canvas.shown_level == 0
    shot = screen(canvas)                              # zoomed in: crisp black and white cells
    centre = canvas.mapFromScene(canvas.view.mapViewToScene(QtCore.QPointF(5.5, 5.5)))
    assert tuple(shot[centre.y(), centre.x()]) in ((0, 0, 0), (255, 255, 255))


def block_texture():
    levels = np.zeros((1024, 1536), np.uint8)
    levels[::2, ::2] = 1                                # a fine pattern everywhere
    levels[300:420, 500:700] = 2                        # a red block somewhere
    return levels


def test_picking_and_picture_line_up_when_zoomed_out(qtbot):
    levels = block_texture()
    canvas = zoomed_out(qtbot, levels, 0.3)
    canvas.fit()
    qtbot.wait(20)
    assert canvas.zoom() < 0.5 and canvas.shown_level >= 1
    shot = screen(canvas).astype(int)
    red = (shot[..., 0] > 200) & (shot[..., 1] < 60) & (shot[..., 2] < 60)
    ys, xs = np.nonzero(red)
    assert len(ys) > 50
    seen = []
    canvas.hovered.connect(seen.append)
    # the red block on screen is the block's cells under the pointer: its centre and corners
    # (within two screen pixels: the edges are blends of a mip level drawn smoothly)
    tol = 2 / canvas.zoom() + 1
    for px, py, (cx, cy) in (((xs.min() + xs.max()) // 2, (ys.min() + ys.max()) // 2, (600, 360)),
                             (xs.min() + 1, ys.min() + 1, (500, 300)),
                             (xs.max() - 1, ys.max() - 1, (699, 419))):
        qtbot.mouseMove(canvas.viewport(), QtCore.QPoint(int(px), int(py)))
        qtbot.wait(20)
        x, y, level = seen[-1]
        assert level == 2
        assert abs(x - cx) <= tol and abs(y - cy) <= tol, ((x, y), (cx, cy), canvas.zoom())


def test_tiled_preview_zoomed_out_repeats_the_averaged_picture(qtbot):
    levels = block_texture()
    canvas = zoomed_out(qtbot, levels, 0.3)
    canvas.set_tiled(True)
    qtbot.wait(20)
    assert canvas.shown_level >= 2
    shot = screen(canvas).astype(int)
    for dx in (-1, 0, 1):                               # the block's centre in three tiles
        p = canvas.mapFromScene(canvas.view.mapViewToScene(QtCore.QPointF(600 + dx * 1536, 360)))
        r, g, b = shot[p.y(), p.x()]
        assert r > 200 and g < 60 and b < 60, (dx, r, g, b)
    p = canvas.mapFromScene(canvas.view.mapViewToScene(QtCore.QPointF(100 - 1536, 100)))
    assert np.all(np.abs(shot[p.y() - 2:p.y() + 3, p.x() - 2:p.x() + 3] - 64) <= 3)


def test_zoomed_out_picture_follows_edits_and_palette(qtbot):
    levels = block_texture()
    canvas = zoomed_out(qtbot, levels, 0.25)
    centre = canvas.mapFromScene(canvas.view.mapViewToScene(QtCore.QPointF(40, 40)))
    assert np.all(np.abs(screen(canvas)[centre.y(), centre.x()].astype(int) - 64) <= 3)
    painted = levels.copy()
    painted[20:60, 20:60] = 3                           # an edit lands: the new picture shows
    canvas.set_image(painted, GREYS)
    qtbot.wait(10)
    assert tuple(screen(canvas)[centre.y(), centre.x()]) == (0, 0, 255)
    canvas.set_palette(np.array([[0, 0, 0], [255, 255, 255], [255, 0, 0], [0, 200, 0]],
                                np.uint8))             # the palette preview recolours the mip
    qtbot.wait(10)
    assert tuple(screen(canvas)[centre.y(), centre.x()]) == (0, 200, 0)
    assert canvas.displayed_colour(30, 30) == (0, 200, 0)


def _shown_pixels(canvas) -> np.ndarray:
    """The picture item's pixels as painted (a paint renders only what is out of date)."""
    canvas.grab()
    q = canvas.image.qimage
    return np.frombuffer(q.constBits(), np.uint8, count=q.sizeInBytes()).copy()


def _fresh_pixels(qtbot, canvas, doc) -> np.ndarray:
    fresh = CanvasView()
    qtbot.addWidget(fresh)
    fresh.resize(canvas.size())
    fresh.show()
    fresh.set_image(doc.levels, doc.palette)
    fresh.set_zoom(canvas.zoom())
    fresh._show_level()
    fresh.image.render()
    assert fresh.shown_level == canvas.shown_level
    return _shown_pixels(fresh)


def test_edits_redraw_only_their_box_and_the_picture_stays_exact(window, qtbot, monkeypatch):
    """Issue 18: a step that touches a box re-uploads only that box (no full set_image), at
    100 % and zoomed out; undo, redo and a new palette too; the picture on screen is exactly a
    full redraw's after each, and a new canvas shape still redraws everything."""
    from texeditor.recipe.actions import ResizeCanvas, SetLevels, SetPalette
    canvas = window.canvas
    full = []
    real_set_image = canvas.set_image
    monkeypatch.setattr(canvas, "set_image", lambda *a: full.append(1) or real_set_image(*a))
    for zoom in (4.0, 0.3):
        canvas.set_zoom(zoom)
        qtbot.wait(20)
        _shown_pixels(canvas)
        for step in (SetLevels(3, 4, 5, 6, 1), SetLevels(40, 50, 30, 30, 2),
                     SetLevels(0, 0, 2, 2, 0)):
            assert window.submit(step)
            qtbot.wait(10)
            assert np.array_equal(_shown_pixels(canvas),
                                  _fresh_pixels(qtbot, canvas, window.document))
        window.undo()
        window.undo()
        window.redo()
        assert np.array_equal(_shown_pixels(canvas), _fresh_pixels(qtbot, canvas, window.document))
    assert full == []                                  # six steps, undo and redo: boxes only
    palette = window.document.palette.copy()
    palette[1] = (250, 10, 10)
    assert window.submit(SetPalette(palette))             # a recolouring, not a re-upload
    assert full == []
    assert np.array_equal(_shown_pixels(canvas), _fresh_pixels(qtbot, canvas, window.document))
    assert window.submit(ResizeCanvas(70, 30, 0))
    assert len(full) == 1 and window.canvas.levels.shape == (70, 30)
    assert np.array_equal(_shown_pixels(canvas), _fresh_pixels(qtbot, canvas, window.document))


def test_a_box_redrawn_before_the_next_paint_leaves_the_matrix_drawn_last_alone(qtbot):
    """Monkey seed 1: the picture item's QImage is made on the memory of the array it is drawn
    from. A box redrawn after a new matrix, before the paint that draws it, was written into
    the QImage of the matrix drawn last — an array a History keeps as an undo record — so undo
    and redo gave back another document. The canvas writes only into pictures of its own."""
    canvas, old = make_canvas(qtbot)
    palette = np.array([[0, 0, 0], [255, 0, 0], [0, 255, 0], [0, 0, 255]], np.uint8)
    _shown_pixels(canvas)                       # painted: the picture is made from ``old``
    kept = old.copy()
    old.flags.writeable = False                 # as the document hands its levels out
    new = (kept + 1) % 4
    canvas.set_image(new, palette)              # a new matrix, not painted yet...
    new[10:20, 5:25] = 3
    assert canvas.update_box(new, (10, 5, 10, 20))     # ...and a box of it at once
    assert np.array_equal(old, kept)
    doc = type("Doc", (), {"levels": new, "palette": palette})
    assert np.array_equal(_shown_pixels(canvas), _fresh_pixels(qtbot, canvas, doc))
    new[0:3, 0:3] = 0                           # a box after a paint: drawn where it is
    assert canvas.update_box(new, (0, 0, 3, 3))
    assert np.array_equal(_shown_pixels(canvas), _fresh_pixels(qtbot, canvas, doc))


def test_undo_and_redo_after_a_box_edit_made_before_a_paint_give_the_replayed_documents(
        window, qtbot):
    """The window's side of the test above: a new matrix, then at once a box edit; undo and
    redo then step through exactly the documents the log replays to."""
    from texeditor.recipe.actions import NewCanvas, SetLevels
    from texeditor.recipe.replay import replay
    canvas, history = window.canvas, window.history
    canvas.set_zoom(4.0)
    qtbot.wait(20)
    assert window.submit(SetLevels(3, 4, 5, 6, 1))
    _shown_pixels(canvas)
    assert window.submit(NewCanvas(64, 48, 4))          # drawn whole at the next paint...
    assert window.submit(SetLevels(3, 4, 5, 6, 2))      # ...and a box edit before that paint
    assert window.submit(SetLevels(20, 30, 4, 4, 3))

    def replayed():
        doc = replay(history.applied, history.document.dpjs)
        return (np.array_equal(doc.levels, history.document.levels)
                and np.array_equal(doc.palette, history.document.palette))

    for _ in range(4):
        window.undo()
        assert replayed(), f"undo to step {history.index}"
    assert history.index == 1
    for _ in range(4):
        window.redo()
        assert replayed(), f"redo to step {history.index}"
    assert history.index == 5
