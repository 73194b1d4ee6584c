"""Render screenshots of the application's main states into docs/img/ (offscreen, no display).

    python3 docs/make_screenshots.py [--out docs/img]

Each state is reached through the same code paths a user triggers (dialogs, docks, actions).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
# a fresh texture bank holding only the built-ins, so the pictures never show a user's own entries;
# and fresh user data and settings, so no dialog opens on the settings a user left (nor a crash
# journal of theirs is offered)
os.environ.setdefault("TEXEDITOR_BANK", tempfile.mkdtemp(prefix="texeditor-screenshots-"))
os.environ.setdefault("TEXEDITOR_DATA", tempfile.mkdtemp(prefix="texeditor-screenshots-data-"))

from PySide6 import QtCore, QtGui, QtWidgets  # noqa: E402

QtCore.QSettings.setDefaultFormat(QtCore.QSettings.Format.IniFormat)
QtCore.QSettings.setPath(QtCore.QSettings.Format.IniFormat, QtCore.QSettings.Scope.UserScope,
                         tempfile.mkdtemp(prefix="texeditor-screenshots-settings-"))

SIZE = (1280, 800)


def settle(app, ms: int = 150) -> None:
    deadline = QtCore.QDeadlineTimer(ms)
    while not deadline.hasExpired():
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 20)


def blank_figure(width: int, height: int):
    """(QImage, QPainter on it): a light-grey figure for captioned panels, 10-point text."""
    figure = QtGui.QImage(width, height, QtGui.QImage.Format.Format_RGB888)
    figure.fill(QtGui.QColor(250, 250, 250))
    painter = QtGui.QPainter(figure)
    font = painter.font()
    font.setPointSize(10)
    painter.setFont(font)
    return figure, painter

def synthesised(app, window, dpj_name: str, size: int, seed: int) -> None:
    """The window on a new history: one synthesis of ``size``² points from a bundled DPJ."""
    from texeditor.markov.dpj import DPJ
    from texeditor.recipe.history import History
    from texeditor.resources import bundled_dpj

    history = History()
    history.add_dpj(DPJ.load(bundled_dpj(dpj_name)))
    window.set_history(history)
    window.synthesise(size, size, seed)
    window.runner.wait()
    settle(app)



def save(widget, path: Path) -> None:
    widget.grab().save(str(path))
    print(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img")
    args = parser.parse_args(argv)
    out = args.out.resolve()
    out.mkdir(parents=True, exist_ok=True)

    import numpy as np

    from app.main_window import MainWindow
    from texeditor.recipe.actions import SetPalette

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    app.setApplicationName("texeditor")
    window = MainWindow()
    window.headless = True
    window.resize(*SIZE)
    window.show()
    window.start_default()
    window.runner.wait()
    settle(app)
    for _ in range(600):                # the entry shown from its stored picture is checked
        if window.bank_dock._to_confirm is None and not window.runner.busy:   # once the
            break                                                   # kernels are ready
        settle(app, 100)
    window.runner.wait()
    settle(app)

    # 1. the window as it opens: the built-in "Gravel with tone", in its photo's greys
    save(window, out / "main-window.png")

    # the rest show the plain "Gravel" (its four levels in the palette's greys)
    dock = window.bank_dock
    while dock._to_confirm is not None or window.runner.busy:   # the start entry's check
        window.runner.wait()
        settle(app)
    dock.open_entry(next(e.id for e in dock.bank.search("gravel") if e.name == "Gravel"))
    window.runner.wait()
    settle(app)
    assert window.history.actions[0].TYPE == "synthesize", "the plain Gravel did not open"

    # 2. the 3×3 tiled preview, to judge the seams
    window.act_tiled.trigger()
    settle(app)
    save(window, out / "tiled-preview.png")
    window.act_tiled.trigger()

    # 3. zoomed in far: the pixel grid and the cursor read-out
    canvas = window.canvas
    canvas.set_zoom(22, center=QtCore.QPointF(40, 40))
    settle(app)
    target = canvas.mapFromScene(canvas.view.mapViewToScene(QtCore.QPointF(40.5, 40.5)))
    canvas.hovered.emit((40, 40, int(window.history.document.levels[40, 40])))
    QtWidgets.QApplication.sendEvent(canvas.viewport(), _move_event(canvas.viewport(), target))
    settle(app)
    save(window, out / "zoom-grid.png")
    canvas.fit()

    # 4. the acquisition dialog on a sample photo, set for the thesis's one DPJ (it opens set
    #    for a photo model: auto unticked, 1 scale, a 3×3 window)
    dialog = window.acquire()
    dialog.auto_scales.setChecked(False)
    dialog.scales.setValue(1)
    dialog.v.setValue(3)
    dialog.levels.setValue(5)
    dialog.recompute()
    dialog.wait()                       # the photo is quantised and counted in the background
    settle(app, 300)
    save(dialog, out / "acquire-dialog.png")
    dialog.ok_button.click()
    window.runner.wait()
    settle(app)

    # 5. a coloured palette, then a past step selected with an edited seed (non-destructive)
    g = window.history.document.num_levels
    colours = np.array([[38, 30, 22], [112, 74, 44], [170, 120, 70], [214, 180, 120],
                        [245, 230, 200], [90, 110, 60], [60, 80, 110], [200, 90, 60]])[:g]
    window.submit(SetPalette(colours))
    window.palette_dock.swatches.current = min(2, g - 1)
    window.palette_dock._level_clicked(window.palette_dock.swatches.current)
    settle(app)
    save(window, out / "palette.png")
    dock = window.history_dock
    dock.view.clicked.emit(dock.model.index(1))       # as a click on step 2 does
    dock.form.editor("seed").set_value(2024)
    settle(app)
    save(window, out / "history-edit.png")
    dock.apply_button.click()
    window.runner.wait()
    settle(app)

    # 6. a long synthesis in progress: the progress bar and Cancel, the window still live
    window.synthesis_dock.width_box.setValue(4096)
    window.synthesis_dock.height_box.setValue(4096)
    window.synthesise_from_dock()
    while window.runner.busy and window.progress.value() < 250:
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 20)
    settle(app, 50)
    save(window, out / "synthesising.png")
    window.runner.cancel()
    window.runner.wait()
    window.synthesis_dock.width_box.setValue(256)      # later shots show the usual size
    window.synthesis_dock.height_box.setValue(256)

    for shoot in MORE_SHOTS:      # each capability adds its own screenshots below
        shoot(app, window, out)
        settle(app)

    window.mark_clean()
    window.close()
    return 0


def shot_extract(app, window, out: Path) -> None:
    """The Extract tool: a region selected and turned by its rotation knob, the drag still under
    way so that the ghost shows the result; Esc then cancels it, the document unchanged."""
    import math

    from skimage.measure import label, regionprops

    from app.tools.regions import ExtractTool

    tool = next(t for t in window.tools if isinstance(t, ExtractTool))
    window.set_tool(tool)
    tool.opts.kind.setCurrentIndex(tool.opts.kind.findData("region"))
    levels = window.document.levels
    h, w = levels.shape
    inner = [r for r in regionprops(label(levels == 0, connectivity=1))
             if r.bbox[0] > 0 and r.bbox[1] > 0 and r.bbox[2] < h and r.bbox[3] < w]
    y, x = max(inner, key=lambda r: r.area).coords[0]
    tool.click((int(x), int(y)), QtCore.Qt.KeyboardModifier.NoModifier)
    settle(app)
    canvas, frame = window.canvas, tool.frame
    centre, knob = frame.box.center(), frame.knob()[1]
    viewport, Type = canvas.viewport(), QtCore.QEvent.Type
    for k in range(7):           # press on the knob, then turn 24° counter-clockwise
        t = math.radians(4 * k)
        d = knob - centre
        p = centre + QtCore.QPointF(d.x() * math.cos(t) + d.y() * math.sin(t),
                                    -d.x() * math.sin(t) + d.y() * math.cos(t))
        pos = canvas.mapFromScene(canvas.view.mapViewToScene(p))
        _send(viewport, _mouse_event(viewport, Type.MouseMove if k else Type.MouseButtonPress,
                                     pos))
        settle(app, 40)
    save(window, out / "extract-tool.png")
    _send(canvas, QtGui.QKeyEvent(Type.KeyPress, QtCore.Qt.Key.Key_Escape,
                                  QtCore.Qt.KeyboardModifier.NoModifier))
    _send(viewport, _mouse_event(viewport, Type.MouseButtonRelease, pos))
    window.set_tool(window.tools[0])


MORE_SHOTS = [shot_extract]


def _mouse_event(widget, kind, pos):
    """A left-button press, move (the button held) or release at ``pos``."""
    left, none = QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.MouseButton.NoButton
    button = none if kind == QtCore.QEvent.Type.MouseMove else left
    buttons = none if kind == QtCore.QEvent.Type.MouseButtonRelease else left
    return QtGui.QMouseEvent(kind, QtCore.QPointF(pos), QtCore.QPointF(widget.mapToGlobal(pos)),
                             button, buttons, QtCore.Qt.KeyboardModifier.NoModifier)


def _send(widget, event) -> None:
    QtWidgets.QApplication.sendEvent(widget, event)


def _move_event(widget, pos):
    none = QtCore.Qt.MouseButton.NoButton
    return QtGui.QMouseEvent(QtCore.QEvent.Type.MouseMove, QtCore.QPointF(pos),
                             QtCore.QPointF(widget.mapToGlobal(pos)), none, none,
                             QtCore.Qt.KeyboardModifier.NoModifier)


def shot_spots(app, window, out: Path) -> None:
    """Spots (issue 7): a stone texture made only with spots — two scatters of the Stone and
    Pebble envelopes, under the stones already placed, shaded in relief — with the Spot tool's
    ghost and the spot editor; the editor alone; the texture itself."""
    from app.tools.spot import SpotTool
    from texeditor.recipe.actions import NewCanvas
    from texeditor.export import write_png
    from texeditor.recipe.history import History

    previous = window.history
    stones = [(38, 33, 30), (78, 68, 58), (112, 98, 84), (142, 127, 108), (170, 156, 136),
              (198, 186, 166), (226, 218, 202)]
    history = History()
    history.apply(NewCanvas(320, 224, len(stones), stones))
    window.set_history(history)
    tool = next(t for t in window.tools if isinstance(t, SpotTool))
    window.set_tool(tool)
    settle(app, 400)
    editor, opts = tool.editor, tool.opts
    opts.mode.setCurrentIndex(opts.mode.findData("scatter"))
    opts.blend.setCurrentIndex(opts.blend.findData("under"))
    opts.wrap.setChecked(True)
    for name, count, sizes, levels, depth in [("Stone", 400, (0.5, 1.0), (2, 5), 0.4),
                                              ("Pebble", 500, (0.18, 0.35), (1, 4), 0.5)]:
        editor.load(editor.library.get(name))
        editor.interior.setCurrentIndex(editor.interior.findData("relief"))
        editor.density.set_value(depth)
        editor.seed.set_value(11 if name == "Stone" else 12)
        opts.count.setValue(count)
        opts.scale_box.setValue(sizes[0])
        opts.scale_max.setValue(sizes[1])
        window.palette_dock.swatches.current = levels[0]
        window.palette_dock._level_clicked(levels[0])
        opts.level_max.setValue(levels[1])
        tool.scatter()
        window.runner.wait()
    editor.load(editor.library.get("Stone"))
    editor.interior.setCurrentIndex(editor.interior.findData("relief"))
    editor.density.set_value(0.4)
    editor.seed.set_value(2024)
    window.palette_dock.swatches.current = 4
    window.palette_dock._level_clicked(4)
    opts.mode.setCurrentIndex(opts.mode.findData("place"))
    opts.scale_box.setValue(1.3)
    opts.angle.setValue(20)
    settle(app, 300)
    canvas = window.canvas
    target = canvas.mapFromScene(canvas.view.mapViewToScene(QtCore.QPointF(150.5, 100.5)))
    QtWidgets.QApplication.sendEvent(canvas.viewport(), _move_event(canvas.viewport(), target))
    editor.view.selected = ("m", 1, "left")
    window.statusBar().clearMessage()
    settle(app)
    save(window, out / "spot-stones.png")
    save(tool.dock, out / "spot-editor.png")
    doc = window.document
    texture = out / "spot-texture.png"
    write_png(texture, doc.levels, doc.palette, scale=2)
    print(texture.relative_to(ROOT) if texture.is_relative_to(ROOT) else texture)
    window.set_tool(window.tools[0])
    window.set_history(previous)


MORE_SHOTS.append(shot_spots)


def shot_paint(app, window, out: Path) -> None:
    """Brushes and grains (issue 6): a texture painted by hand — spray clouds of random levels,
    pebbles along paths, hexagon grains, a duplicated zone — with the Spray tool mid-stroke,
    the Grain tool's ghost, the Scramble tool's band, the grain editor and the Peano dialog."""
    import numpy as np

    from app.tools.brush import SprayTool
    from app.tools.grain import GrainTool
    from app.tools.zone import ScrambleTool, Zone
    from texeditor.recipe.actions import NewCanvas
    from texeditor.recipe.history import History
    from texeditor.paint.actions import DuplicateZone, PlaceGrains, Stroke

    previous = window.history
    earth = [(34, 30, 26), (84, 66, 48), (122, 96, 66), (158, 128, 88), (196, 168, 122),
             (232, 214, 176)]
    history = History()
    history.apply(NewCanvas(256, 176, len(earth), earth))
    rng = np.random.default_rng(6)
    for k in range(7):                       # a ground of sprayed clouds, levels at random
        y = 12 + 24 * k
        history.apply(Stroke(points=((y, -10), (y + 9, 90), (y - 6, 180), (y + 4, 270)),
                             level=1, size=30, distribution="cloud", density=0.35,
                             concentration=1.0, level_choices="1, 1, 2, 3", seed=k, wrap=True))
    for k in range(5):                       # pebbles along paths
        y = 20 + 34 * k
        history.apply(PlaceGrains(points=((y, 4), (y + 14, 120), (y, 250)), level=0,
                                  shape="bitmap", size=7, own_levels=True, spacing=11.0,
                                  jitter=3.0, seed=k, wrap=True,
                                  bitmap="0123210/1344431/2345432/2345432/1344431/0123210"))
    centres = tuple(map(tuple, rng.integers([0, 0], [176, 256], size=(40, 2))))
    history.apply(PlaceGrains(points=centres, level=5, shape="hexagon", size=6))
    history.apply(DuplicateZone(points=((10, 10), (70, 90)), offset_row=95, offset_col=150,
                                wrap=True))
    window.set_history(history)
    canvas = window.canvas

    # 1. the Spray tool in the middle of a stroke: the preview, then the Brushes dock
    spray = next(t for t in window.tools if isinstance(t, SprayTool))
    window.set_tool(spray)
    spray.set_brush(next(b for b in window.brush_dock.brushes if b.name == "Soft spray 24"))
    spray.opts.random.setChecked(True)
    spray.opts.choices.setText("4, 5")
    settle(app, 300)
    gesture = spray.drag((30, 150), QtCore.Qt.KeyboardModifier.NoModifier)
    next(gesture)
    for x in range(34, 200, 6):
        gesture.send((x, int(150 - 40 * np.sin(x / 40))))
    window.statusBar().clearMessage()
    settle(app)
    save(window, out / "brush-spray.png")
    gesture.close()
    settle(app)

    # 2. the Grain tool: the library dock, and the ghost of a hexagon under the pointer
    grains = next(t for t in window.tools if isinstance(t, GrainTool))
    grains.pick("Hexagon 12")
    window.palette_dock.swatches.current = 5
    window.palette_dock._level_clicked(5)
    settle(app, 300)
    canvas.set_zoom(4.0, center=QtCore.QPointF(120, 70))
    settle(app)
    target = canvas.mapFromScene(canvas.view.mapViewToScene(QtCore.QPointF(120.5, 70.5)))
    QtWidgets.QApplication.sendEvent(canvas.viewport(), _move_event(canvas.viewport(), target))
    window.statusBar().clearMessage()
    settle(app)
    save(window, out / "grain-tool.png")

    canvas.fit()

    # 3. the grain editor on a grain drawn point by point
    grains.pick("Pebble 6")
    editor = grains.edit()
    editor.move(window.geometry().center() - editor.rect().center())
    settle(app, 300)
    save(editor, out / "grain-editor.png")
    editor.close()

    # 4. the Scramble tool on the duplicated zone: the band that will change
    scramble = next(t for t in window.tools if isinstance(t, ScrambleTool))
    scramble.zone = Zone("rectangle", ((105, 160), (165, 240)))
    window.set_tool(scramble)
    scramble.opts.band.setValue(6)
    window.statusBar().clearMessage()
    settle(app, 300)
    save(window, out / "scramble-band.png")
    scramble.scramble()
    settle(app)

    # 5. Peano sub-regions: the thesis's example on cells of 16 points
    dialog = window.open_peano()
    dialog.cell.setValue(16)
    settle(app, 300)
    save(dialog, out / "peano-dialog.png")
    dialog.close()

    window.set_tool(window.tools[0])
    window.set_history(previous)


MORE_SHOTS.append(shot_paint)


def shot_bank(app, window, out: Path) -> None:
    """The texture bank (issue 10): the browser with an edited built-in open on the canvas; the
    browser filtered by attribute ranges, then "more like this"; the Save to bank dialog."""
    dock = window.bank_dock
    if dock.bank is None:
        dock.load()
        window.runner.wait()
    previous = window.history
    dock.raise_()                                     # its tab, if tabified with others
    target = next(e.id for e in dock.bank.search("filled copied"))
    dock.open_entry(target)
    window.runner.wait()
    dock._take_height()                               # as at start-up, after the other tools
    window.statusBar().clearMessage()
    settle(app, 300)
    save(window, out / "bank-browser.png")

    dock.filter_button.click()
    dock.filters.set_range("density", 0.0, 0.9)
    dock.filters.set_range("coarseness", 2.5, 10.0)
    dock.refresh()
    dock.select(dock.model.ids[0])
    settle(app, 300)
    save(dock, out / "bank-filters.png")
    for use, _lo, _hi in dock.filters.rows.values():
        use.setChecked(False)
    dock.filter_button.click()

    dock.set_like(next(e.id for e in dock.bank.search("gravel") if e.name == "Gravel"))
    settle(app, 300)
    save(dock, out / "bank-like.png")
    dock.set_like(None)

    dialog = dock.save_current()
    dialog.name.setText("Warm gravel, centre filled")
    dialog.tags.setText("gravel, warm, regions, mine")
    dialog.description.setPlainText("The built-in in warm colours, kept as my own version.")
    settle(app, 200)
    save(dialog, out / "bank-save.png")
    dialog.reject()
    window.mark_clean()
    window.set_history(previous)


MORE_SHOTS.append(shot_bank)



def shot_grains(app, window, out: Path) -> None:
    """Grains, density and composition (issue 9): one texture in square, circle and hexagon grains,
    expanded and compressed (the thesis's Fig. 5.5–5.7), each panel made with the Grain & density
    dock; the dock itself; the composition and doubling dialogs."""
    import numpy as np

    from app.images import qimage_from_rgb
    from texeditor import DPJ
    from texeditor.recipe.actions import SetPalette
    from texeditor.resources import bundled_dpj
    from texeditor.texture.actions import RenderGrains

    previous = window.history
    synthesised(app, window, "gravel-3x3-g4", 48, 3)
    window.submit(SetPalette(((236, 230, 218), (176, 132, 86), (112, 74, 44), (42, 30, 22))))
    dock = window.density_dock
    dock.show()
    dock.raise_()
    panels = [("Square grains, 8 px", RenderGrains("square", 8)),
              ("Circle grains, 8 px", RenderGrains("circle", 8)),
              ("Hexagons, 10 px, honeycomb", RenderGrains("hexagon", 10)),
              ("Explosion 2× across", RenderGrains("circle", 8, explosion_x=2.0)),
              ("Explosion 1.6× both ways", RenderGrains("square", 6, explosion_x=1.6,
                                                        explosion_y=1.6)),
              ("Compression 0.5, max level", RenderGrains("circle", 10, compression=0.5,
                                                          overlap="max"))]
    side, caption, gap = 240, 26, 12
    figure, painter = blank_figure(3 * side + 4 * gap, 2 * (side + caption) + 3 * gap)
    for k, (text, action) in enumerate(panels):
        dock.show_action(action)
        dock.commit()                       # as a slider's release does
        window.runner.wait()
        doc = window.document
        rgb = np.asarray(doc.palette)[doc.levels[:side, :side]]
        x, y = gap + (k % 3) * (side + gap), gap + (k // 3) * (side + caption + gap)
        painter.drawImage(x, y, qimage_from_rgb(rgb))
        painter.setPen(QtGui.QColor(40, 40, 40))
        painter.drawText(QtCore.QRect(x, y + side, side, caption),
                         QtCore.Qt.AlignmentFlag.AlignCenter, text)
    painter.end()
    path = out / "grains-density.png"
    figure.save(str(path))
    print(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)

    dock.show_action(RenderGrains("hexagon", 12, explosion_x=1.25, explosion_y=1.25))
    dock.commit()
    window.runner.wait()
    window.canvas.actual_pixels()
    settle(app, 300)
    window.statusBar().clearMessage()
    save(window, out / "grain-dock.png")

    window.act_undo.trigger()               # back to the normalised texture
    window.synthesis_dock.width_box.setValue(160)
    window.synthesis_dock.height_box.setValue(160)
    window.synthesise_from_dock()
    window.runner.wait()
    grass = window.document.store_dpj(DPJ.load(bundled_dpj("grass-2x2-g8")))
    window.act_compose.trigger()
    dialog = window.composition_dialog
    dialog.source.reload()
    dialog.source.dpj.setCurrentIndex(dialog.source.dpj.findData(grass))
    dialog.mask_kind.setCurrentIndex(dialog.mask_kind.findData("texture"))
    dialog.mask_source.seed.set_value(77)
    dialog.mask_levels.setText("3")
    settle(app, 300)
    window.runner.wait()
    settle(app, 300)
    save(dialog, out / "composition.png")
    dialog.close()
    window.act_double.trigger()
    doubling = window.doubling_dialog
    doubling.wait()                     # the table is learnt in the background
    settle(app, 300)
    save(doubling, out / "doubling.png")
    doubling.reject()
    window.mark_clean()
    window.set_history(previous)


MORE_SHOTS.append(shot_grains)


def shot_trees_and_orders(app, window, out: Path) -> None:
    """Issue 21: the Dominance tree tool with one tree finished and a second being built; a
    synthesis laid along the fill orders (§3.3.1); the Grain rendering dock with a grain per
    level (§5.3)."""
    import numpy as np

    from app.images import qimage_from_rgb
    from app.tools.grain import GrainTool
    from app.tools.tree import TreeTool
    from texeditor.paint.actions import LayAlongOrder
    from texeditor.recipe.actions import NewCanvas, SetPalette
    from texeditor.recipe.history import History
    from texeditor.texture.actions import RenderGrains

    previous = window.history
    canvas = window.canvas
    earth = [(24, 22, 20), (70, 60, 50), (120, 100, 78), (170, 146, 110), (214, 192, 150),
             (246, 234, 206)]

    # 1. the Dominance tree tool: a finished tree, and a second one under construction
    history = History()
    history.apply(NewCanvas(96, 64, len(earth), earth))
    window.set_history(history)
    tree = next(t for t in window.tools if isinstance(t, TreeTool))
    grains = next(t for t in window.tools if isinstance(t, GrainTool))
    window.set_tool(tree)
    canvas.fit()
    settle(app, 200)

    def place(grain, cells, parent=None):
        grains.pick(grain)
        if parent is not None:
            tree.click(parent, QtCore.Qt.KeyboardModifier.NoModifier)
        for cell in cells:
            tree.click(cell, QtCore.Qt.KeyboardModifier.NoModifier)

    place("Circle 9", [(20, 20)])
    place("Hexagon 8", [(12, 34), (30, 36)])
    place("Square 3", [(6, 44), (16, 46)], parent=(12, 34))
    place("Point", [(40, 44), (32, 50)], parent=(30, 36))
    tree.finish()
    place("Diamond 7", [(64, 26)])
    place("Pentagon 9", [(74, 16), (80, 34)])
    place("Square 5", [(88, 20)], parent=(74, 16))
    target = canvas.mapFromScene(canvas.view.mapViewToScene(QtCore.QPointF(86.5, 8.5)))
    QtWidgets.QApplication.sendEvent(canvas.viewport(), _move_event(canvas.viewport(), target))
    window.statusBar().clearMessage()
    settle(app, 300)
    save(window, out / "tree-tool.png")
    tree.drop()
    window.set_tool(window.tools[0])

    # 2. one synthesis laid along each fill order (a knot of wood from a spiral)
    synthesised(app, window, "grass-2x2-g8", 160, 5)
    panels = [("TV scan (synthesised)", None), ("Spiral", "spiral"), ("Polar", "polar"),
              ("Peano (Hilbert)", "peano")]
    side, caption, gap = 160, 26, 12
    figure, painter = blank_figure(4 * side + 5 * gap, side + caption + 2 * gap)
    for k, (text, order) in enumerate(panels):
        if order is not None:
            window.submit(LayAlongOrder(order))
        doc = window.document
        x = gap + k * (side + gap)
        painter.drawImage(x, gap, qimage_from_rgb(np.asarray(doc.palette)[doc.levels]))
        painter.setPen(QtGui.QColor(40, 40, 40))
        painter.drawText(QtCore.QRect(x, gap + side, side, caption),
                         QtCore.Qt.AlignmentFlag.AlignCenter, text)
        if order is not None:
            window.act_undo.trigger()
    painter.end()
    path = out / "fill-orders.png"
    figure.save(str(path))
    print(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)

    # 3. the Grain rendering dock: squares for most levels, circles and needles for two
    synthesised(app, window, "gravel-3x3-g4", 48, 3)
    window.submit(SetPalette(((236, 230, 218), (176, 132, 86), (112, 74, 44), (42, 30, 22))))
    dock = window.density_dock
    dock.show()
    dock.raise_()
    dock.show_action(RenderGrains("square", 6, level_grains="1: line 9 angle=45, "
                                                            "3: circle 10"))
    dock.commit()
    window.runner.wait()
    window.canvas.actual_pixels()
    settle(app, 300)
    dock.widget().ensureWidgetVisible(dock.per_level)
    window.statusBar().clearMessage()
    settle(app)
    save(window, out / "grain-per-level.png")
    window.mark_clean()
    window.set_history(previous)


MORE_SHOTS.append(shot_trees_and_orders)


def motifs():
    """A 60×60 grid of motifs of three levels (an L, a bar, a T), as the thesis's figures of the
    global operators draw them."""
    import numpy as np

    levels = np.zeros((60, 60), np.uint8)
    shapes = [np.array([[1, 0, 0], [1, 0, 0], [1, 1, 1]]), np.array([[1, 1, 1, 1, 1]]),
              np.array([[1, 1, 1], [0, 1, 0], [0, 1, 0]])]
    for i in range(5):
        for j in range(5):
            shape = shapes[(i + j) % 3]
            h, w = shape.shape
            top, left = 12 * i + 4, 12 * j + 4
            levels[top:top + h, left:left + w][shape > 0] = 1 + (i + j) % 3
    return levels


def shot_regions21(app, window, out: Path) -> None:
    """Issue 21: the random manipulation of every region (a grid of motifs scattered through
    the Global operators dialog), one neighbour isolated by the Extract tool, a mix of four
    textures in one expression."""
    import numpy as np

    from app.images import qimage_from_rgb
    from app.tools.regions import ExtractTool
    from texeditor.recipe.actions import NewCanvas, SetLevels, SetPalette
    from texeditor.recipe.history import History

    previous = window.history
    window.set_history(History())
    window.submit(NewCanvas(60, 60, 4))
    for (r, c), v in np.ndenumerate(motifs()):
        if v:
            window.submit(SetLevels(r, c, 1, 1, int(v)))
    window.submit(SetPalette(((244, 240, 228), (176, 60, 40), (40, 110, 160), (60, 50, 40))))
    start = len(window.history.actions)
    dialog = window.global_operators()
    dialog.operator.setCurrentIndex(dialog.operator.findData("scatter"))
    panels = [("The motifs", None),
              ("Quarter turns, moves within 3", dict(rotation="quarter", radius=3, lo=1, hi=1)),
              ("Any angle, zoom 0.8–1.6, moves ≤ 4", dict(rotation="any", radius=4, lo=0.8,
                                                            hi=1.6))]
    side, caption, gap = 240, 26, 12
    figure = QtGui.QImage(3 * side + 4 * gap, side + caption + 2 * gap,
                          QtGui.QImage.Format.Format_RGB888)
    figure.fill(QtGui.QColor(250, 250, 250))
    painter = QtGui.QPainter(figure)
    for k, (text, fields) in enumerate(panels):
        if fields is not None:
            while len(window.history.applied) > start:
                window.undo()
            dialog.rotation.setCurrentIndex(dialog.rotation.findData(fields["rotation"]))
            dialog.radius.setValue(fields["radius"])
            dialog.scale_min.setValue(fields["lo"])
            dialog.scale_max.setValue(fields["hi"])
            dialog.seed.set_value(21)
            dialog.apply_button.click()
        doc = window.document
        rgb = np.repeat(np.repeat(np.asarray(doc.palette)[doc.levels], 4, axis=0), 4, axis=1)
        x, y = gap + k * (side + gap), gap
        painter.drawImage(x, y, qimage_from_rgb(np.ascontiguousarray(rgb)))
        painter.setPen(QtGui.QColor(40, 40, 40))
        painter.drawText(QtCore.QRect(x, y + side, side, caption),
                         QtCore.Qt.AlignmentFlag.AlignCenter, text)
    painter.end()
    path = out / "scatter-regions.png"
    figure.save(str(path))
    print(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)
    settle(app, 200)
    save(dialog, out / "scatter-dialog.png")
    dialog.close()

    window.set_history(History())                  # a block with three neighbours
    window.submit(NewCanvas(28, 20, 4))
    for rect in ((4, 5, 4, 6, 2), (4, 11, 4, 2, 1), (8, 5, 1, 6, 3), (12, 16, 5, 7, 3)):
        window.submit(SetLevels(*rect))
    window.submit(SetPalette(((244, 240, 228), (40, 110, 160), (176, 60, 40), (60, 50, 40))))
    tool = next(t for t in window.tools if isinstance(t, ExtractTool))
    window.set_tool(tool)
    tool.opts.kind.setCurrentIndex(tool.opts.kind.findData("neighbours"))
    tool.click((7, 5), None)
    tool.step_neighbour(1)
    tool.step_neighbour(1)
    window.canvas.fit()
    settle(app, 300)
    window.statusBar().clearMessage()
    save(window, out / "extract-neighbours.png")
    window.set_tool(window.tools[0])

    synthesised(app, window, "gravel-3x3-g4", 128, 5)
    window.act_compose.trigger()
    compose = window.composition_dialog
    compose.tabs.setCurrentIndex(2)
    compose.add_texture.click()
    compose.expression_preset.setCurrentIndex(compose.expression_preset.findText("Darkest (min)"))
    settle(app, 300)
    window.runner.wait()
    settle(app, 300)
    save(compose, out / "composition-more.png")
    compose.close()
    window.mark_clean()
    window.set_history(previous)


MORE_SHOTS.append(shot_regions21)


def shot_dpj_editor(app, window, out: Path) -> None:
    """The DPJ editor (issue 8): a 2×2, G = 3 DPJ drawn from a seed, its empty configuration
    set to 0.3 and made stationary, one entry loaded into the painter; then the two
    vertical-stripe configurations entered by hand, and the charts."""
    import numpy as np

    from app.dpj_editor import open_editor

    editor = open_editor(window, new=True)
    editor.headless = True
    editor.resize(1400, 900)
    dialog = editor.new_dialog
    dialog.u.setValue(2)
    dialog.v.setValue(2)
    dialog.levels.setValue(3)
    dialog.accept()
    gen = editor.generators
    gen.seed.set_value(3)
    gen.sparsity.setValue(55)
    gen.evenness.setValue(0.4)
    gen.generate()
    editor.runner.wait()
    gen.set_extremes(0.3, editor.dpj.prob(np.full((2, 2), 2)))
    editor.checks.stationaryRequested.emit()
    editor.runner.wait()
    view = editor.table.view
    view.selectRow(2)
    settle(app, 300)
    editor.preview.preview.wait()
    settle(app, 300)
    save(editor, out / "dpj-editor.png")

    editor.act_new.trigger()
    editor.new_dialog.levels.setValue(2)
    editor.new_dialog.accept()
    for config in ([[0, 1], [0, 1]], [[1, 0], [1, 0]]):
        editor.painter.load(np.array(config, np.uint8), 0.5)
        editor.painter.request_set()
    editor.preview.preview.wait()
    editor.charts.setCurrentIndex(2)
    settle(app, 300)
    save(editor.docks["Configuration painter"], out / "dpj-painter.png")
    save(editor.docks["Charts"], out / "dpj-transitions.png")
    editor.stop()
    editor.close()


MORE_SHOTS.append(shot_dpj_editor)


def shot_photo_model(app, window, out: Path) -> None:
    """A photo model (issue 19): the acquisition dialog on 3 scales with each scale's levels,
    then a 256×256 texture drawn from the scales and shown with the photo's tone. Last: the
    model stays attached to the window."""
    dialog = window.acquire()
    dialog.set_image_path(ROOT / "resources" / "images" / "brick.png")
    dialog.levels.setValue(4)           # the dialog opens on the last acquisition's G (5)
    dialog.v.setValue(2)
    dialog.scales.setValue(3)
    dialog.wait()
    settle(app, 300)
    save(dialog, out / "acquire-scales.png")
    dialog.synthesise_now.setChecked(False)
    dialog.ok_button.click()
    window.synthesise(256, 256, 1984)
    window.runner.wait()
    window.canvas.fit()
    settle(app)
    save(window, out / "photo-tone.png")


MORE_SHOTS.append(shot_photo_model)


def shot_optimise(app, window, out: Path) -> None:
    """The History dock's Optimise log… (issue 21): what the log optimiser would drop, move and
    merge in a log of fills, palettes and crops, before it is done."""
    from texeditor.recipe.actions import CropCanvas, NewCanvas, SetLevels, SetPalette
    from texeditor.recipe.history import History

    previous = window.history
    grey = ((30, 30, 30), (110, 100, 90), (180, 170, 150), (240, 235, 225))
    warm = ((30, 20, 10), (140, 90, 50), (200, 150, 90), (250, 230, 200))
    history = History()
    for action in (NewCanvas(128, 96, 4, grey), SetLevels(8, 8, 24, 40, 1), SetPalette(warm),
                   SetLevels(60, 70, 20, 20, 2), SetLevels(8, 48, 24, 40, 1),
                   CropCanvas(0, 0, 96, 112), SetLevels(70, 20, 12, 12, 3),
                   CropCanvas(4, 4, 88, 100), SetPalette(grey)):
        history.apply(action)
    window.set_history(history)
    dialog = window.history_dock.optimise()
    settle(app)
    save(dialog, out / "history-optimise.png")
    dialog.reject()
    window.set_history(previous)


MORE_SHOTS.append(shot_optimise)


def shot_relief(app, window, out: Path) -> None:
    """Relief (issue 20): a gravel texture in earth colours with the Relief dock open, the
    light dragged to the upper left, the previews on a plane and a sphere."""
    from texeditor.recipe.actions import SetPalette

    previous = window.history
    synthesised(app, window, "gravel-3x3-g4", 256, 1984)
    settle(app)
    window.submit(SetPalette([[62, 48, 36], [118, 92, 66], [166, 138, 102], [214, 194, 160]]))
    dock = window.relief_dock
    dock.show()
    dock.raise_()
    window.resizeDocks([dock], [400], QtCore.Qt.Orientation.Horizontal)
    dock.model.update(azimuth=125, elevation=40, strength=6.0)
    window.canvas.fit()
    settle(app, 300)
    save(window, out / "relief.png")
    dock.hide()
    window.set_history(previous)


MORE_SHOTS.append(shot_relief)


def shot_colour_plates(app, window, out: Path) -> None:
    """Colour plates (issue 20): a gravel texture laid on plates taken from a colour photo
    (scikit-image's coffee cup, blurred) and a stroke of the lightest plate painted across
    them, the plate colours in the palette dock."""
    from skimage import data, io

    from app.resources import estimate_from_photo
    from texeditor.paint.actions import Stroke
    from texeditor.recipe.history import History

    history = History()
    history.add_dpj(estimate_from_photo(ROOT / "resources" / "images" / "gravel.png",
                                        window=(3, 3), levels=4))
    window.set_history(history)
    window.synthesise(384, 256, 1984)
    window.runner.wait()
    settle(app)
    with tempfile.TemporaryDirectory() as folder:
        photo = Path(folder) / "coffee.png"
        io.imsave(photo, data.coffee())
        window.plates_from_photo(6, 0.03, photo)
        window.runner.wait()            # the photo is read in the background
    window.act_plates_dock.trigger()
    window.act_paint_plates.setChecked(True)
    window.submit(Stroke(points=((200, 20), (150, 120), (190, 230)), level=5, size=14))
    window.palette_dock.swatches.current = 5
    window.palette_dock.set_palette(window.paint_palette())
    window.canvas.fit()
    settle(app, 300)
    save(window, out / "colour-plates.png")


MORE_SHOTS.append(shot_colour_plates)

def shot_tileable(app, window, out: Path) -> None:
    """Tileable synthesis (issue 20): a gravel texture drawn on the torus, in the 3×3 tiled
    preview at 400 % around a corner where four copies meet; the same with Tileable off."""

    previous = window.history
    for tileable, name in ((True, "tileable.png"), (False, "tileable-off.png")):
        window.synthesis_dock.tileable_box.setChecked(tileable)
        synthesised(app, window, "gravel-3x3-g4", 128, 3)
        window.canvas.set_tiled(True)
        settle(app)
        view = window.canvas.view                     # a corner of the middle copy, at 400 %
        width, height = (s / 4 for s in view.screenGeometry().getRect()[2:])
        view.setRange(xRange=(128 - width / 2, 128 + width / 2),
                      yRange=(128 - height / 2, 128 + height / 2), padding=0)
        settle(app, 300)
        save(window, out / name)
    window.canvas.set_tiled(False)
    window.synthesis_dock.tileable_box.setChecked(False)
    window.set_history(previous)


MORE_SHOTS.append(shot_tileable)


def shot_tileable_photo(app, window, out: Path) -> None:
    """A tileable texture from gravel's photo model (the current closure: its tone drawn on two
    lanes, the seam columns last), in the 3×3 tiled preview at 400 % around a corner."""
    from texeditor.markov.levels import load_image
    from texeditor.photo import acquire_model
    from texeditor.recipe.history import History

    previous = window.history
    window.set_history(History())
    window.attach_model(acquire_model(load_image(ROOT / "resources" / "images" / "gravel.png")))
    window.synthesis_dock.tileable_box.setChecked(True)
    window.synthesise(256, 256, 5)
    window.runner.wait()
    window.canvas.set_tiled(True)
    settle(app)
    view = window.canvas.view
    width, height = (s / 4 for s in view.screenGeometry().getRect()[2:])
    view.setRange(xRange=(256 - width / 2, 256 + width / 2),
                  yRange=(256 - height / 2, 256 + height / 2), padding=0)
    settle(app, 300)
    save(window, out / "tileable-photo.png")
    window.canvas.set_tiled(False)
    window.synthesis_dock.tileable_box.setChecked(False)
    window.mark_clean()
    window.set_history(previous)


MORE_SHOTS.append(shot_tileable_photo)


def shot_recovery(app, window, out: Path) -> None:
    """Crash recovery: the one dialog that offers every texture a crash left unsaved (three
    journals, as a crash of three windows leaves, each with its thumbnail: textures from
    scikit-image's grass, brick and gravel), one of them unticked."""
    import time

    import skimage as ski

    from app.recovery import RecoveryDialog
    from texeditor import resynthesize
    from texeditor.recipe.journal import Recovered, thumbnail_of

    now = time.time()
    found = [Recovered(Path(f"{k}.journal"), (None,) * steps, {}, source, now - age, steps,
                       thumbnail=thumbnail_of(resynthesize(photo(), (160, 160), seed=k).image))
             for k, (steps, source, age, photo) in enumerate(
                 [(58, None, 600, ski.data.grass),
                  (12, "/home/me/textures/brick wall.texture", 3600, ski.data.brick),
                  (4, None, 7200, ski.data.gravel)])]
    dialog = RecoveryDialog(window, found)
    dialog.list.item(2).setCheckState(QtCore.Qt.CheckState.Unchecked)
    dialog.show()
    settle(app)
    save(dialog, out / "recovery-dialog.png")
    dialog.close()


MORE_SHOTS.append(shot_recovery)


if __name__ == "__main__":
    sys.exit(main())
