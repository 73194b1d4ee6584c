"""Issue 21 items 4–6 with real mouse and key events: dominance trees built vertex by vertex on
the canvas, a zone laid along a scan order, Peano cells numbered along another order, and a
grain per level in the Grain rendering dock — asserting on the document's levels."""

import numpy as np
import pytest
from PySide6 import QtCore, QtTest, QtWidgets

from app.tools.grain import GrainTool
from app.tools.tree import TreeTool
from app.tools.zone import OrderTool
from texeditor.paint.actions import DominanceTree, LayAlongOrder, PeanoLevels
from texeditor.texture.actions import RenderGrains

from .support import cell_pos, click, mouse, move, press_key

Key = QtCore.Qt.Key
LEFT = QtCore.Qt.MouseButton.LeftButton
NO_MOD = QtCore.Qt.KeyboardModifier.NoModifier
CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier


@pytest.fixture(autouse=True)
def user_data(tmp_path, monkeypatch):
    """Grain and brush libraries in a temporary folder, never the user's own."""
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path / "data"))


def blank(window):
    """The canvas cleared to level 0 by one step (the test's hand-made answers start there)."""
    window.submit(PeanoLevels(cell=64, expression="1", low=0, high=0))
    assert not window.document.levels.any()


def at(window, x, y):
    """Click the canvas at cell (x, y)."""
    QtTest.QTest.qWait(20)
    click(window.canvas.viewport(), cell_pos(window.canvas, x, y))


def stroke(window, cells):
    """Press, move and release through cells (x, y), each placed once the view has settled."""
    canvas = window.canvas
    Type, none = QtCore.QEvent.Type, QtCore.Qt.MouseButton.NoButton
    for k, cell in enumerate(cells):
        QtTest.QTest.qWait(30)
        kind = Type.MouseButtonPress if k == 0 else Type.MouseMove
        mouse(canvas.viewport(), kind, cell_pos(canvas, *cell), LEFT if k == 0 else none, LEFT)
    mouse(canvas.viewport(), Type.MouseButtonRelease, cell_pos(canvas, *cells[-1]), LEFT, none)


def key(window, k, modifiers=NO_MOD):
    QtTest.QTest.keyClick(window.canvas, k, modifiers)


def pick_grain(window, name):
    """Click a grain in the Grain stamps dock."""
    dock = window.grain_dock
    grains = next(t for t in window.tools if isinstance(t, GrainTool))
    item = dock.list.item([g.name for g in grains.grains].index(name))
    dock.list.scrollToItem(item)
    QtTest.QTest.mouseClick(dock.list.viewport(), LEFT, NO_MOD,
                            dock.list.visualItemRect(item).center())
    assert grains.grain.name == name


def square(levels, row, col, side, level):
    """A square grain of ``side`` placed at (row, col) by its anchor (below-right of centre)."""
    a = side // 2
    levels[row - a:row - a + side, col - a:col - a + side] = level


# -- dominance trees -------------------------------------------------------------------------------

def test_two_trees_placed_on_screen_then_undo_one_and_redo(window, qtbot):
    blank(window)
    start = window.history.index
    QtTest.QTest.keyClick(window, Key.Key_G, SHIFT)
    tree = window.tool
    assert isinstance(tree, TreeTool) and window.grain_dock.isVisible()
    top = window.document.num_levels - 1                       # G = 4: levels 1..3

    # tree 1: a root square of 5 with two point children, grains picked between clicks
    pick_grain(window, "Square 5")
    assert window.tool is tree                                  # picking keeps the tree tool
    at(window, 10, 10)
    pick_grain(window, "Point")
    at(window, 20, 10)
    at(window, 10, 20)
    assert tree.parents == [-1, 0, 0] and window.history.index == start
    assert window.canvas.overlay.isVisible()                    # the grains, previewed
    key(window, Key.Key_Return)
    action = window.history.actions[-1]
    assert isinstance(action, DominanceTree) and action.expression == "1(2,3)"
    assert action.points == ((10, 10), (10, 20), (20, 10))
    one = np.zeros_like(window.document.levels)
    square(one, 10, 10, 5, top)
    one[10, 20] = one[20, 10] = 1
    assert np.array_equal(window.document.levels, one)
    assert not tree.points and window.history.index == start + 1

    # tree 2: root, a child, a vertex taken back, a grandchild under the child picked by a click
    pick_grain(window, "Square 3")
    at(window, 40, 30)
    at(window, 50, 30)
    at(window, 40, 40)
    key(window, Key.Key_Backspace)                              # takes back (40, 40)
    key(window, Key.Key_Z, CTRL)                                # so does Ctrl+Z while building
    assert tree.points == [(30, 40)] and window.history.index == start + 1
    at(window, 50, 30)
    at(window, 50, 30)                                          # near vertex 2: its parent now
    assert tree.current_parent == 1 and len(tree.points) == 2
    pick_grain(window, "Point")
    at(window, 56, 36)
    assert tree.parents == [-1, 0, 1]
    key(window, Key.Key_Enter)
    assert window.history.actions[-1].expression == "1(2(3))"
    two = one.copy()
    square(two, 30, 40, 3, 3)                                   # ranks 2, 1, 0 → levels 3, 2, 1
    square(two, 30, 50, 3, 2)
    two[36, 56] = 1
    assert np.array_equal(window.document.levels, two)

    key(window, Key.Key_Z, CTRL)                                # nothing being built: undo
    assert np.array_equal(window.document.levels, one)
    key(window, Key.Key_Z, CTRL | SHIFT)
    assert np.array_equal(window.document.levels, two)
    window.act_undo.trigger()
    window.act_undo.trigger()
    assert window.history.index == start and not window.document.levels.any()


def test_esc_drops_a_tree_and_a_tool_change_finishes_one(window, qtbot):
    blank(window)
    window.set_tool(next(t for t in window.tools if isinstance(t, TreeTool)))
    tree = window.tool
    pick_grain(window, "Square 3")
    at(window, 12, 12)
    at(window, 20, 12)
    key(window, Key.Key_Escape)
    assert not tree.points and not window.document.levels.any()
    assert not window.canvas.overlay.isVisible()
    at(window, 30, 20)
    stroke(window, [(30, 20), (32, 22), (34, 24)])
    assert tree.points == [(24, 34)]                            # the vertex dragged along
    press_key(window, Key.Key_B)                                # another tool: the tree lands
    assert isinstance(window.history.actions[-1], DominanceTree)
    expected = np.zeros_like(window.document.levels)
    square(expected, 24, 34, 3, window.document.num_levels - 1)
    assert np.array_equal(window.document.levels, expected)


def test_a_tree_deeper_than_the_levels_stays_on_screen_to_be_mended(window, qtbot):
    blank(window)
    window.set_tool(next(t for t in window.tools if isinstance(t, TreeTool)))
    tree = window.tool
    pick_grain(window, "Point")
    tree.opts.low.setValue(2)                                   # levels 2..3: two ranks at most
    for x in (5, 15, 25):                                       # a chain 1 ⊃ 2 ⊃ 3
        at(window, x, 5)
        at(window, x, 5)                                        # picks it as the parent
    assert tree.parents == [-1, 0, 1]
    assert "use more levels" in tree.opts.status.text()
    key(window, Key.Key_Return)
    assert window.errors and len(tree.points) == 3             # refused, nothing lost
    assert not window.document.levels.any()
    errors = len(window.errors)
    press_key(window, Key.Key_B)                # another tool: kept, said in the status bar,
    assert window.tool is not tree and len(window.errors) == errors     # no dialog
    assert "kept, not drawn" in window.statusBar().currentMessage()
    assert len(tree.points) == 3 and not window.document.levels.any()
    window.set_tool(tree)                       # back: the tree is there to be mended
    assert "use more levels" in tree.opts.status.text()
    tree.opts.low.setValue(1)
    key(window, Key.Key_Return)
    assert window.document.levels[5, [5, 15, 25]].tolist() == [3, 2, 1]


# -- the Scan order tool -----------------------------------------------------------------------------

def walked_spiral(shape, centre):
    """The square spiral as a walk (an independent statement of the order): right 1, down 1,
    left 2, up 2, right 3, … from the centre, keeping the cells on the canvas."""
    h, w = shape
    (r, c), cells = centre, [centre]
    moves, run = [(0, 1), (1, 0), (0, -1), (-1, 0)], 1
    k = 0
    while len(cells) < h * w:
        for _ in range(2):
            dr, dc = moves[k % 4]
            for _ in range(run):
                r, c = r + dr, c + dc
                if 0 <= r < h and 0 <= c < w:
                    cells.append((r, c))
            k += 1
        run += 1
    return cells


def test_the_scan_order_tool_lays_the_canvas_then_a_zone_along_a_spiral(window, qtbot):
    press_key(window, Key.Key_O)
    tool = window.tool
    assert isinstance(tool, OrderTool) and tool.settings.order == "spiral"
    before = window.document.levels.copy()
    move(window.canvas.viewport(), cell_pos(window.canvas, 30, 20))
    overlay = window.canvas.overlay                             # the order as a ramp
    rect = overlay.mapRectToView(overlay.boundingRect())
    assert overlay.isVisible() and (rect.width(), rect.height()) == (64, 48)
    ramp = overlay.image
    assert ramp[20, 30, 0] == ramp[:, :, 0].min() and ramp[20, 35, 0] < ramp[20, 50, 0]
    at(window, 30, 20)                                          # no zone: the whole canvas
    action = window.history.actions[-1]
    assert action == LayAlongOrder("spiral", centre_row=20, centre_col=30)
    expected = np.zeros_like(before)
    for (r, c), v in zip(walked_spiral(before.shape, (20, 30)), before.ravel()):
        expected[r, c] = v
    assert np.array_equal(window.document.levels, expected)

    laid = window.document.levels.copy()
    stroke(window, [(4, 6), (8, 8), (12, 10)])                  # a 9×5 zone
    assert tool.zone.points == ((6, 4), (10, 12))
    tool.opts.order.setCurrentIndex(tool.opts.order.findData("polar"))
    at(window, 8, 8)
    assert window.history.actions[-1].zone == "rectangle"
    now = window.document.levels
    outside = np.ones(now.shape, bool)
    outside[6:11, 4:13] = False
    assert np.array_equal(now[outside], laid[outside])
    polar = sorted(((r, c) for r in range(6, 11) for c in range(4, 13)),     # angle, radius
                   key=lambda p: (round(np.mod(np.arctan2(8 - p[0], p[1] - 8), 2 * np.pi), 9)
                                  if p != (8, 8) else -1, (p[0] - 8) ** 2 + (p[1] - 8) ** 2))
    assert [now[p] for p in polar] == laid[6:11, 4:13].ravel().tolist()
    window.act_undo.trigger()
    window.act_undo.trigger()
    assert np.array_equal(window.document.levels, before)


# -- Peano cells along another order ----------------------------------------------------------------

def test_the_peano_dialog_numbers_cells_in_a_spiral(window, qtbot):
    dialog = window.open_peano()
    qtbot.waitExposed(dialog)
    dialog.cell.setValue(16)                                    # 4 × 3 cells of 16 points
    dialog.expression.setText("2(1)")
    dialog.order.setCurrentIndex(dialog.order.findData("spiral"))
    assert "spiral" in dialog.summary.text()
    QtTest.QTest.mouseClick(dialog.apply_button, LEFT)
    action = window.history.actions[-1]
    assert isinstance(action, PeanoLevels) and action.order == "spiral"
    levels = window.document.levels
    top = window.document.num_levels - 1
    assert (levels[16:32, 16:32] == 1).all()                    # cell 1: the middle one (1, 1)
    assert (levels[16:32, 32:48] == top).all()                  # cell 2: its right neighbour
    dialog.close()


# -- a grain per level -------------------------------------------------------------------------------

def test_a_level_drawn_with_its_own_grain_and_undo_back_to_normal(window, qtbot):
    dock = window.density_dock
    dock.show()
    dock.raise_()
    QtWidgets.QApplication.processEvents()
    normal = window.document.levels.copy()
    start = window.history.index
    assert len(dock._level_widgets) == window.document.num_levels - 1
    _, shape, size = dock._level_widgets[1]                     # level 2's row
    assert not size.isEnabled()
    shape.setCurrentIndex(shape.findData("diamond"))            # a diamond of 1: one pixel,
    assert size.isEnabled() and window.history.index == start   # as before: no step
    size.setValue(5)
    qtbot.waitUntil(lambda: window.history.index == start + 1, timeout=5000)
    assert window.runner.wait(60_000)
    action = window.history.actions[-1]
    assert action == RenderGrains("square", 1, level_grains="2: diamond 5")
    assert window.document.shape == (48 * 5, 64 * 5)            # the diamond sets the pitch
    levels = window.document.levels
    diamond = (np.abs(np.arange(5)[:, None] - 2) + np.abs(np.arange(5) - 2) <= 2) * 2
    point = np.zeros((5, 5), np.uint8)
    point[2, 2] = 1
    for (r, c), v in np.ndenumerate(normal):
        cell = levels[5 * r:5 * r + 5, 5 * c:5 * c + 5]
        expected = diamond if v == 2 else point * v             # 1 and 3: a one-pixel square
        assert np.array_equal(cell, expected), (r, c)
    assert "own grains for levels 2" in dock.info.text()
    window.act_undo.trigger()
    assert window.runner.wait(60_000)
    assert np.array_equal(window.document.levels, normal)
    assert dock._level_widgets[1][1].currentData() is None     # the controls follow the log
    window.act_redo.trigger()
    assert window.runner.wait(60_000)
    assert dock._level_widgets[1][1].currentData() == "diamond"
    assert dock._level_widgets[1][2].value() == 5
