"""The tool framework: the Tools bar, shortcuts, options dock, and gestures routed to the tool."""

from PySide6 import QtCore

from app.tools import HandTool, Tool
from texeditor.recipe.actions import SetLevels

from .support import cell_pos, click, drag, press_key


class StampTool(Tool):
    """A test tool: a click sets one point, a drag sets every cell it passes."""

    NAME = "Stamp"
    SHORTCUT = "Q"

    def click(self, cell, modifiers):
        level = self.main_window.current_level
        self.main_window.submit(SetLevels(cell[1], cell[0], 1, 1, level))

    def drag(self, cell, modifiers):
        cells = [cell]
        while True:
            try:
                cells.append((yield))
            except GeneratorExit:
                for x, y in dict.fromkeys(cells):
                    level = self.main_window.current_level
                    self.main_window.submit(SetLevels(y, x, 1, 1, level))
                raise


def test_the_hand_tool_is_current_at_start_and_pans_without_editing(window, qtbot):
    canvas = window.canvas
    assert isinstance(window.tool, HandTool) and window.tool.qaction.isChecked()
    assert window.tool_dock.title.text().startswith("Hand")
    before = window.document.levels.copy()
    x0 = canvas.view.viewRange()[0][0]
    drag(canvas.viewport(), QtCore.Qt.MouseButton.LeftButton,
         (cell_pos(canvas, 30, 20).x(), cell_pos(canvas, 30, 20).y()),
         (cell_pos(canvas, 20, 20).x(), cell_pos(canvas, 20, 20).y()))
    assert canvas.view.viewRange()[0][0] > x0 + 5          # the view moved right
    assert (window.document.levels == before).all() and window.history.index == 1


def test_a_tool_gets_clicks_and_drags_as_cells_and_submits_actions(window, qtbot):
    canvas = window.canvas
    window.set_tool(StampTool(window))
    level = window.current_level
    a = cell_pos(canvas, 3, 2)
    click(canvas.viewport(), a)
    assert window.document.levels[2, 3] == level and window.history.index == 2
    b, c = cell_pos(canvas, 10, 7), cell_pos(canvas, 14, 7)
    drag(canvas.viewport(), QtCore.Qt.MouseButton.LeftButton, (b.x(), b.y()), (c.x(), c.y()),
         steps=16)       # small steps: every cell crossed gets a move
    assert (window.document.levels[7, 10:15] == level).all()
    steps = window.history.index
    assert steps == 2 + 5            # this test tool makes one step per cell crossed
    window.undo()
    assert window.history.index == steps - 1


def test_tool_shortcut_switches_back_to_the_hand(window, qtbot):
    window.set_tool(StampTool(window))
    press_key(window, QtCore.Qt.Key.Key_H)
    assert isinstance(window.tool, HandTool)
