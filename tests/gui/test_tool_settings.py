"""Tools keep their settings as data (app.tool_settings) and the main window is built from its
declared docks and menus: sessions that switch tools, change settings through widgets and
through the dataclasses, then paint and check the document."""

import dataclasses

import numpy as np
import pytest
from PySide6 import QtCore, QtWidgets

from app.main_window import DOCKS, MENUS
from app.tools.brush import BrushSettings, BrushTool, SprayTool
from app.tools.grain import GrainTool
from app.tools.regions import ExtractTool, FillTool, TranslateTool
from app.tools.spot import SpotTool
from app.tools.zone import ScrambleTool
from texeditor.paint.actions import Stroke
from texeditor.recipe.actions import NewCanvas, SetLevels

from .support import cell_pos, click, press_key

Key = QtCore.Qt.Key
# The layouts users saved name docks by these: they must never change.
SAVED_DOCK_NAMES = {"ToolOptionsDock", "SynthesisDock", "PaletteDock", "HistoryDock", "BankDock",
                    "BrushDock", "GrainDock", "GrainDensityDock", "ReliefDock", "PlatesDock"}


@pytest.fixture(autouse=True)
def user_data(tmp_path, monkeypatch):
    """Grain and brush libraries in a temporary folder, never the user's own."""
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path / "data"))


@pytest.fixture
def board(window):
    """A 40×30 canvas, G = 4: two separate blocks of level 2 and one of level 3."""
    window.submit(NewCanvas(40, 30, 4))
    window.submit(SetLevels(4, 5, 4, 6, 2))
    window.submit(SetLevels(20, 30, 3, 3, 2))
    window.submit(SetLevels(10, 25, 5, 5, 3))
    window.canvas.fit()
    return window


def tool_of(window, kind):
    return next(t for t in window.tools if type(t) is kind)


def test_tools_keep_their_settings_when_the_user_switches_and_back(board, qtbot):
    """Each tool's settings, changed in its options panel, survive a round of every other tool
    (read from the dataclass and shown again by the panel) and are the ones it paints with."""
    press_key(board, Key.Key_F)
    fill = board.tool
    assert isinstance(fill, FillTool)
    fill.opts.scope.setCurrentIndex(fill.opts.scope.findData("global"))
    press_key(board, Key.Key_B)
    brush = board.tool
    brush.opts.size_box.setValue(5)
    brush.opts.shape_box.setCurrentIndex(brush.opts.shape_box.findData("square"))
    press_key(board, Key.Key_G)
    grain = board.tool
    grain.opts.spacing.setValue(13)
    grain.opts.wrap.setChecked(True)
    press_key(board, Key.Key_M)
    move = board.tool
    move.opts.fill.setValue(3)
    move.opts.kind.setCurrentIndex(move.opts.kind.findData("neighbours"))
    press_key(board, Key.Key_S)
    spot = board.tool
    spot.opts.mode.setCurrentIndex(spot.opts.mode.findData("scatter"))
    spot.opts.count.setValue(7)
    scramble = tool_of(board, ScrambleTool)
    board.set_tool(scramble)
    scramble.opts.band.setValue(6)
    scramble.opts.density.setValue(45)

    expected = {fill: {"scope": "global", "connectivity": 4},
                brush: {"size": 5, "shape": "square"},
                grain: {"spacing": 13, "jitter": 2, "wrap": True},
                move: {"fill": 3, "kind": "neighbours", "wrap": False},
                spot: {"mode": "scatter", "count": 7},
                scramble: {"band": 6, "density": 0.45, "grain": 2}}
    for key in (Key.Key_H, Key.Key_E, Key.Key_C, Key.Key_A, Key.Key_D, Key.Key_F, Key.Key_B,
                Key.Key_G, Key.Key_M, Key.Key_S):
        press_key(board, key)
        qtbot.wait(5)
    board.set_tool(scramble)
    for tool, fields in expected.items():
        for name, value in fields.items():
            assert getattr(tool.settings, name) == pytest.approx(value), (tool.NAME, name)
    assert move.opts.fill.value() == 3 and scramble.opts.density.value() == 45
    assert spot.opts.scatter_box.isVisibleTo(spot.opts)      # the panel follows its mode

    # the settings are what the tools paint with
    press_key(board, Key.Key_F)
    board.palette_dock.swatches.current = 1
    click(board.canvas.viewport(), cell_pos(board.canvas, 7, 5))
    levels = board.document.levels
    assert (levels[4:8, 5:11] == 1).all() and (levels[20:23, 30:33] == 1).all()   # global
    assert (levels[10:15, 25:30] == 3).all()
    press_key(board, Key.Key_B)
    click(board.canvas.viewport(), cell_pos(board.canvas, 20, 25))
    stroke = board.history.actions[board.history.index - 1]
    assert isinstance(stroke, Stroke) and (stroke.size, stroke.shape) == (5, "square")
    assert (board.document.levels[23:28, 18:23] == 1).all()     # a 5×5 square dab
    board.undo()
    board.undo()
    assert (board.document.levels[4:8, 5:11] == 2).all()
    assert brush.settings.size == 5 and fill.settings.scope == "global"   # undo keeps them


def test_a_settings_dataclass_and_its_widgets_mirror_each_other(board, qtbot):
    spray = tool_of(board, SprayTool)
    board.set_tool(spray)
    opts = spray.opts
    changes = []
    spray.model.changed.connect(changes.append)

    # the dataclass set as a whole: the widgets follow, with one notification and no echo
    spray.settings = dataclasses.replace(spray.settings, size=9, density=0.4, wrap=True,
                                         random_levels=True, choices="2, 3")
    assert changes == [""]
    assert (opts.size_box.value(), opts.density.value()) == (9, 40)
    assert opts.wrap.isChecked() and opts.random.isChecked() and opts.choices.text() == "2, 3"
    assert spray.settings.size == 9 and spray.settings.density == pytest.approx(0.4)

    # a widget changed: the dataclass follows (a percentage becomes a fraction)
    opts.density.setValue(60)
    opts.concentration.setValue(1.5)
    assert spray.settings.density == pytest.approx(0.6)
    assert spray.settings.concentration == pytest.approx(1.5)
    assert changes[1:] == ["density", "concentration"]
    assert isinstance(spray.settings, BrushSettings)
    brush = spray.brush
    assert (brush.size, brush.distribution, brush.density) == (9, "cloud", pytest.approx(0.6))

    # a preset keeps the level and wrap choices; [ and ] go through the dataclass too
    board.brush_dock.choose(next(i for i, b in enumerate(board.brush_dock.brushes)
                                 if b.name == "Soft spray 24"))
    assert spray.settings.preset == "Soft spray 24" and opts.size_box.value() == 24
    assert opts.preset.text() == "Preset: Soft spray 24" and spray.settings.wrap
    press_key(board, Key.Key_BracketRight)
    assert spray.settings.size == 26 and opts.size_box.value() == 26

    # a tool whose panel was never built keeps settings all the same, and shows them once built
    brush_tool = tool_of(board, BrushTool)
    extract = tool_of(board, ExtractTool)
    extract.settings = dataclasses.replace(extract.settings, factor=1.5, dx=-4, wrap=True)
    board.set_tool(extract)
    assert extract.panel.factor.value() == 1.5 and extract.panel.dx.value() == -4
    assert extract.opts.wrap.isChecked()
    extract.model.update(angle=45.0)
    assert extract.panel.angle.value() == 45.0
    extract.panel.ny.setValue(3)
    assert extract.settings.ny == 3 and brush_tool.settings.size == 3

    # the grain chosen in the Grain stamps dock is a setting the panel shows
    grain_tool = tool_of(board, GrainTool)
    grain_tool.pick("Hexagon 8")
    assert grain_tool.settings.grain.name == "Hexagon 8"
    assert "Hexagon 8" in grain_tool.opts.current.text()

    # a spot mode set as data updates the panel (its scatter box) as a click on it would
    spot = tool_of(board, SpotTool)
    board.set_tool(spot)
    spot.model.update(mode="scatter")
    assert spot.opts.mode.currentData() == "scatter"
    assert spot.opts.scatter_box.isVisibleTo(spot.opts)
    spot.model.update(mode="place")
    assert not spot.opts.scatter_box.isVisibleTo(spot.opts)

    # Translate's settings move a region by a drag of the tool as set in data
    move = tool_of(board, TranslateTool)
    board.set_tool(move)
    move.model.update(fill=1)
    assert move.opts.fill.value() == 1
    steps = board.history.index
    gesture = move.drag((6, 5), QtCore.Qt.KeyboardModifier.NoModifier)
    next(gesture)
    gesture.send((6, 15))
    gesture.close()
    assert board.history.index == steps + 1
    levels = board.document.levels
    assert (levels[4:8, 5:11] == 1).all() and (levels[14:18, 5:11] == 2).all()


def first_of_column(spec) -> str:
    """The dock a tabbed dock's column starts with (the bank, the synthesis dock)."""
    while spec.tab_with:
        spec = next(s for s in DOCKS if s.attr == spec.tab_with)
    return spec.attr


def test_the_declared_docks_and_menus_are_built_and_found_by_object_name(board, qtbot):
    names = [spec.object_name for spec in DOCKS]
    assert set(names) == SAVED_DOCK_NAMES and len(names) == len(set(names))
    view = board.menu("ViewMenu")
    for spec in DOCKS:
        dock = board.findChild(QtWidgets.QDockWidget, spec.object_name)
        assert dock is getattr(board, spec.attr) and type(dock) is spec.cls
        assert board.dockWidgetArea(dock) == spec.area
        assert dock.toggleViewAction() in view.actions()
        if spec.tab_with:                      # a column of tabs behind its first dock
            dock.show()
            assert dock in board.tabifiedDockWidgets(getattr(board, first_of_column(spec)))
            dock.setHidden(spec.hidden)
    assert [d.objectName() for d in board.docks()] == names

    bar_menus = [a.menu() for a in board.menuBar().actions()]
    assert [(m.objectName(), m.title()) for m in bar_menus] == list(MENUS)
    for name, _title in MENUS:
        assert board.menu(name) is board.findChild(QtWidgets.QMenu, name)
    every = [m for m in bar_menus] + [a.menu() for m in bar_menus for a in m.actions()
                                       if a.menu() is not None]
    assert len(every) > len(MENUS) and all(m.objectName() for m in every)   # submenus too
    assert board.recent_menu is board.menu("RecentMenu")
    with pytest.raises(KeyError):
        board.menu("File")                                    # never by the visible text

    # what the docks offer is wired where declared, shortcuts included
    tools_menu = board.menu("ToolsMenu")
    brushes = board.brush_dock
    assert {brushes.act_smaller, brushes.act_bigger} <= set(tools_menu.actions())
    assert {brushes.act_smaller, brushes.act_bigger} <= set(board.actions())
    image = board.menu("ImageMenu").actions()
    assert {board.act_peano, board.act_compose, board.act_double} <= set(image)
    stamps = board.menu("GrainStampsMenu")
    stamps.aboutToShow.emit()
    entry = next(a for a in stamps.actions() if a.text() == "Hexagon 8")
    entry.trigger()
    assert isinstance(board.tool, GrainTool) and board.tool.grain.name == "Hexagon 8"
    assert board.grain_dock.list.currentItem().text() == "Hexagon 8"

    # the dialogs those entries open are the window's own, kept and shown again
    board.act_peano.trigger()
    peano = board.peano_dialog
    assert peano.isVisible()
    peano.close()
    board.act_peano.trigger()
    assert board.peano_dialog is peano and peano.isVisible()
    peano.close()

    # a saved layout comes back onto the same docks
    state = board.saveState()
    board.brush_dock.show()
    assert board.restoreState(state)
    assert board.brush_dock.isHidden()
    assert np.array_equal(board.document.levels[10:15, 25:30], np.full((5, 5), 3))
