"""The bank browser (issue 10), driven with real mouse and key events: start-up on a built-in,
search, filters, open into the canvas, delete and undo, the trash, tags, save and new versions."""

import dataclasses

import numpy as np
import pytest
from PySide6 import QtCore, QtGui, QtTest, QtWidgets

from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.bank.store import Bank, make_record
from texeditor.recipe.history import History

from .support import cell_pos, click

CTRL = QtCore.Qt.KeyboardModifier.ControlModifier


def drawn(rects, size=(32, 32)) -> History:
    history = History()
    history.apply(NewCanvas(*size, 2))
    for rect in rects:
        history.apply(SetLevels(*rect))
    return history


def noise(seed: int) -> History:
    levels = np.random.default_rng(seed).integers(0, 2, (24, 24))
    return drawn([(r, c, 1, 1, 1) for (r, c), v in np.ndenumerate(levels) if v], (24, 24))


@pytest.fixture
def bank_path(tmp_path):
    """A hand-made bank: two stripe textures and two noises."""
    path = tmp_path / "bank.sqlite"
    with Bank(path, builtins=False) as bank:
        bank.add(drawn([(0, c, 32, 2, 1) for c in range(2, 32, 4)]), "Thin stripes",
                 tags=["lines", "regular"], description="vertical lines")
        bank.add(drawn([(0, c, 32, 4, 1) for c in range(4, 32, 8)]), "Wide stripes",
                 tags=["lines", "regular"])
        bank.add(noise(1), "Noise one", tags=["granular"], description="salt and pepper")
        bank.add(noise(2), "Noise two", tags=["granular"])
    return path


@pytest.fixture
def dock(window, bank_path, qtbot):
    dock = window.bank_dock
    assert dock.load(bank_path)
    assert window.runner.wait(60_000)
    return dock


def shown(dock) -> list:
    return [dock.bank.get(i).name for i in dock.model.ids]


def item_pos(dock, name: str) -> QtCore.QPoint:
    """The centre of an entry's tile in the grid (scrolled into view)."""
    row = shown(dock).index(name)
    index = dock.model.index(row)
    dock.view.scrollTo(index)
    return dock.view.visualRect(index).center()


def double_click(widget, pos: QtCore.QPoint) -> None:
    """Press, release, press, double-click, release — what a mouse sends (QTest's mouseDClick
    skips the first press, and an item view only opens what was pressed)."""
    Type, left, none = QtCore.QEvent.Type, QtCore.Qt.MouseButton.LeftButton, \
        QtCore.Qt.MouseButton.NoButton
    for kind in (Type.MouseButtonPress, Type.MouseButtonRelease, Type.MouseButtonPress,
                 Type.MouseButtonDblClick, Type.MouseButtonRelease):
        held = none if kind == Type.MouseButtonRelease else left
        QtWidgets.QApplication.sendEvent(widget, QtGui.QMouseEvent(
            kind, QtCore.QPointF(pos), QtCore.QPointF(widget.mapToGlobal(pos)), left, held,
            QtCore.Qt.KeyboardModifier.NoModifier))


def type_search(qtbot, dock, text: str) -> None:
    dock.search.selectAll()
    QtTest.QTest.keyClick(dock.search, QtCore.Qt.Key.Key_Backspace)
    QtTest.QTest.keyClicks(dock.search, text)
    qtbot.waitUntil(lambda: not dock._search_timer.isActive(), timeout=3000)


# -- start-up -----------------------------------------------------------------------------------

def test_the_application_opens_on_a_builtin_entry_of_the_bank(window, qtbot):
    window.start_default()                   # as `texeditor` with no file does
    assert window.runner.wait(120_000)
    dock = window.bank_dock
    assert dock.bank is not None and len(dock.model.ids) >= 6
    gravel = dock.bank.find("gravel")
    entry = dock.bank.get(dock.selected())
    assert entry.name == "Gravel with tone" and entry.builtin and entry.id in gravel
    assert window.document.result_hash() == entry.sha256
    assert np.array_equal(window.canvas.levels, window.document.levels)
    from texeditor.photo import document_tone       # shown in the photo's greys, not 4 flat ones
    tone = document_tone(window.document)
    assert tone is not None and np.array_equal(window.canvas.picture[..., 0], tone)
    history = window.history_dock                   # its long step title does not widen the
    label = f"Step 1: {window.history.actions[0].label()}"     # docks (the canvas keeps room)
    assert history.group.title() != label and history.group.toolTip() == label
    assert history.minimumSizeHint().width() <= 360 and history.width() <= 360
    qtbot.waitUntil(lambda: history.row_rect(0).width() > 0, timeout=3000)
    assert history.view.horizontalScrollBar().maximum() == 0        # elided in the list too
    assert history.row_rect(0).width() <= history.view.viewport().width()
    assert dock.bank.pending() == [] and not window.errors
    assert not window.is_modified()
    dock.raise_()                            # (its tab, when tabified with other docks)
    qtbot.waitUntil(lambda: all(i in dock.model.pixmaps for i in dock.model.ids[:6]),
                    timeout=5000)            # the visible thumbnails are read once painted


def test_the_bank_is_not_opened_until_asked(window):
    assert window.bank_dock.bank is None and window.bank_dock.open_bank_button.isVisible()


# -- search -------------------------------------------------------------------------------------

def test_typing_in_the_search_box_filters_the_grid(dock, qtbot):
    assert shown(dock) == ["Noise two", "Noise one", "Wide stripes", "Thin stripes"]
    type_search(qtbot, dock, "stripes")
    assert sorted(shown(dock)) == ["Thin stripes", "Wide stripes"]
    assert "2 of 4 entries" in dock.status.text()
    type_search(qtbot, dock, "tag:granular")
    assert sorted(shown(dock)) == ["Noise one", "Noise two"]
    type_search(qtbot, dock, "pepp")
    assert shown(dock) == ["Noise one"]
    type_search(qtbot, dock, "")
    assert len(shown(dock)) == 4


def test_attribute_filters(dock, qtbot):
    qtbot.mouseClick(dock.filter_button, QtCore.Qt.MouseButton.LeftButton)
    assert dock.filters.isVisible()
    use, low, high = dock.filters.rows["directivity"]
    use.click()
    low.selectAll()
    QtTest.QTest.keyClicks(low, "0.9")
    qtbot.waitUntil(lambda: not dock._search_timer.isActive(), timeout=3000)
    assert sorted(shown(dock)) == ["Thin stripes", "Wide stripes"]
    use.click()
    qtbot.waitUntil(lambda: not dock._search_timer.isActive(), timeout=3000)
    assert len(shown(dock)) == 4


def test_more_like_this(dock, qtbot):
    click(dock.view.viewport(), item_pos(dock, "Thin stripes"))
    qtbot.mouseClick(dock.like_button, QtCore.Qt.MouseButton.LeftButton)
    assert shown(dock)[0] == "Wide stripes" and "Thin stripes" not in shown(dock)
    assert dock.like_bar.isVisible()
    dock.set_like(None)
    assert len(shown(dock)) == 4


# -- open, edit tags, delete --------------------------------------------------------------------

def test_double_click_opens_the_entry_into_the_canvas(dock, window, qtbot):
    expected = dock.bank.render(dock.bank.find("thin")[0])
    double_click(dock.view.viewport(), item_pos(dock, "Thin stripes"))
    assert window.runner.wait(30_000)
    assert np.array_equal(window.document.levels, expected.levels)
    assert window.document.result_hash() == expected.result_hash()
    assert window.history.actions == expected.actions
    assert np.array_equal(window.canvas.levels, expected.levels) and not window.errors


def test_a_damaged_entry_is_an_error_and_the_document_stays(dock, window, qtbot):
    import sqlite3
    before = window.document.levels.copy()
    with sqlite3.connect(dock.bank.path) as conn:
        conn.execute("UPDATE entries SET sha256 = ? WHERE name = 'Noise one'", ("0" * 64,))
    click(dock.view.viewport(), item_pos(dock, "Noise one"))
    QtTest.QTest.keyClick(dock.view, QtCore.Qt.Key.Key_Return)
    assert window.runner.wait(30_000)
    assert window.errors and "damaged" in window.errors[-1][1]
    assert np.array_equal(window.document.levels, before)


def test_tags_are_edited_in_the_details(dock, qtbot):
    click(dock.view.viewport(), item_pos(dock, "Noise two"))
    assert dock.tags_edit.text() == "granular"
    click(dock.tags_edit, dock.tags_edit.rect().center())
    assert dock.tags_edit.hasFocus()
    dock.tags_edit.selectAll()
    QtTest.QTest.keyClicks(dock.tags_edit, "granular, fine, Mine")
    QtTest.QTest.keyClick(dock.tags_edit, QtCore.Qt.Key.Key_Return)
    entry = dock.bank.get(dock.selected())
    assert entry.name == "Noise two" and entry.tags == ("fine", "granular", "mine")
    type_search(qtbot, dock, "#mine")
    assert shown(dock) == ["Noise two"]


def test_delete_then_undelete_then_the_trash(dock, qtbot):
    click(dock.view.viewport(), item_pos(dock, "Wide stripes"))
    wide = dock.selected()
    QtTest.QTest.keyClick(dock.view, QtCore.Qt.Key.Key_Delete)
    assert "Wide stripes" not in shown(dock) and dock.bank.find(trash=True) == [wide]
    qtbot.mouseClick(dock.undo_button, QtCore.Qt.MouseButton.LeftButton)
    assert "Wide stripes" in shown(dock) and dock.bank.find(trash=True) == []
    assert dock.selected() == wide

    qtbot.mouseClick(dock.delete_button, QtCore.Qt.MouseButton.LeftButton)
    assert "Wide stripes" not in shown(dock)
    dock.act_trash.trigger()                 # ⋯ ▸ Show the trash
    assert shown(dock) == ["Wide stripes"] and dock.restore_button.isVisible()
    click(dock.view.viewport(), item_pos(dock, "Wide stripes"))
    qtbot.mouseClick(dock.restore_button, QtCore.Qt.MouseButton.LeftButton)
    assert shown(dock) == []
    dock.act_trash.trigger()
    assert "Wide stripes" in shown(dock) and dock.bank.count() == 4


def test_duplicate(dock, qtbot):
    click(dock.view.viewport(), item_pos(dock, "Thin stripes"))
    qtbot.mouseClick(dock.duplicate_button, QtCore.Qt.MouseButton.LeftButton)
    copy = dock.bank.get(dock.selected())
    assert copy.name == "Thin stripes (copy)" and shown(dock)[0] == copy.name
    assert copy.sha256 == dock.bank.get(dock.bank.find("thin")[-1]).sha256


# -- save to the bank ---------------------------------------------------------------------------

def fill_dialog(qtbot, dialog, name=None, tags=None) -> None:
    if name is not None:
        dialog.name.selectAll()
        QtTest.QTest.keyClicks(dialog.name, name)
    if tags is not None:
        dialog.tags.selectAll()
        QtTest.QTest.keyClicks(dialog.tags, tags)
    qtbot.mouseClick(dialog.ok_button, QtCore.Qt.MouseButton.LeftButton)
    window = dialog.parent()
    window.activateWindow()                # the window manager's part, offscreen
    qtbot.waitUntil(lambda: QtWidgets.QApplication.activeWindow() is window, timeout=3000)


def test_save_find_by_tag_open_edit_and_save_a_new_version(dock, window, qtbot):
    original = window.document.copy()
    qtbot.keyClick(window, QtCore.Qt.Key.Key_B, CTRL)            # File ▸ Save to bank…
    dialog = dock.save_dialog
    assert dialog.isVisible() and not dialog.version.isVisible()
    fill_dialog(qtbot, dialog, "My gravel", "mine, warm")
    assert window.runner.wait(30_000)
    first = dock.bank.get(dock.selected())
    assert (first.name, first.tags) == ("My gravel", ("mine", "warm"))
    assert first.sha256 == original.result_hash()

    type_search(qtbot, dock, "tag:warm")                          # find it by tag
    assert shown(dock) == ["My gravel"]
    double_click(dock.view.viewport(), item_pos(dock, "My gravel"))
    assert window.runner.wait(30_000)
    assert np.array_equal(window.document.levels, original.levels)
    assert window.windowTitle().startswith("“My gravel” from the bank (")

    fill = next(t for t in window.tools if t.NAME == "Fill")      # edit: the fill tool
    button = window.tool_dock.buttons[id(fill)]
    click(button, button.rect().center())
    assert window.tool is fill
    canvas = window.canvas
    level = int(window.document.levels[10, 10])
    target = 1 if level == 0 else 0
    window.palette_dock.swatches.current = target
    click(canvas.viewport(), cell_pos(canvas, 10, 10))
    assert window.document.levels[10, 10] == target and window.is_modified()
    edited = window.document.copy()

    qtbot.keyClick(window, QtCore.Qt.Key.Key_B, CTRL)
    dialog = dock.save_dialog
    assert dialog.version.isVisible() and dialog.version.isChecked()
    assert dialog.name.text() == "My gravel" and dialog.tags.text() == "mine, warm"
    fill_dialog(qtbot, dialog)
    assert window.runner.wait(30_000)
    second = dock.bank.get(dock.selected())
    assert second.parent == first.id and second.id != first.id
    assert second.sha256 == edited.result_hash() != first.sha256
    assert dock.bank.open(second.id).document.result_hash() == edited.result_hash()
    assert dock.bank.open(first.id).document.result_hash() == original.result_hash()
    assert not window.errors


def test_save_without_an_open_bank_opens_it(window, qtbot, tmp_path, monkeypatch):
    monkeypatch.setenv("TEXEDITOR_BANK", str(tmp_path / "fresh.sqlite"))
    qtbot.keyClick(window, QtCore.Qt.Key.Key_B, CTRL)
    dock = window.bank_dock
    fill_dialog(qtbot, dock.save_dialog, "First save")
    assert window.runner.wait(120_000)                            # built-ins are prepared too
    assert dock.bank.find("first") and not window.errors


def test_an_entry_saved_by_another_window_appears(dock, qtbot):
    with Bank(dock.bank.path) as other:           # another window, or the command line
        other.add(noise(9), "From elsewhere", tags=["shared"])
    qtbot.waitUntil(lambda: "From elsewhere" in shown(dock), timeout=10_000)


# -- import, export, many entries -----------------------------------------------------------------

def test_import_and_export_through_the_menu(dock, window, qtbot, tmp_path, monkeypatch):
    out = tmp_path / "wide.texture"
    click(dock.view.viewport(), item_pos(dock, "Wide stripes"))
    monkeypatch.setattr(QtWidgets.QFileDialog, "getSaveFileName",
                        lambda *a, **k: (str(out), ""))
    dock.act_export.trigger()
    assert window.runner.wait(30_000) and out.exists()
    monkeypatch.setattr(QtWidgets.QFileDialog, "getOpenFileName",
                        lambda *a, **k: (str(out), ""))
    dock.act_import.trigger()
    assert window.runner.wait(30_000)
    imported = dock.bank.get(dock.selected())
    assert imported.name == "Wide" and imported.sha256 == dock.bank.get(
        dock.bank.find("stripes wide")[0]).sha256


def test_thumbnails_are_read_lazily(window, qtbot, tmp_path):
    path = tmp_path / "many.sqlite"
    record = make_record(noise(3), "n")
    with Bank(path, builtins=False) as bank:
        bank.insert_many([dataclasses.replace(record, name=f"entry {k}") for k in range(400)])
    dock = window.bank_dock
    assert dock.load(path)
    qtbot.waitUntil(lambda: len(dock.model.pixmaps) > 0, timeout=5000)
    assert len(dock.model.ids) == 400 and len(dock.model.pixmaps) < 100
    dock.view.scrollToBottom()
    qtbot.waitUntil(lambda: dock.model.ids[-1] in dock.model.pixmaps, timeout=5000)
    assert dock.model.ids[0] in dock.model.pixmaps and len(dock.model.pixmaps) < 200


def reachable(view, rows: int) -> None:
    """Every tile either lies in the viewport or the vertical scroll bar is there to reach it;
    the last one, scrolled to, lies wholly in the viewport and a click selects it."""
    viewport = view.viewport().rect()
    model = view.model()
    hidden = [r for r in range(rows) if not viewport.contains(view.visualRect(model.index(r)))]
    assert not hidden or view.verticalScrollBar().isVisible(), (hidden, viewport)
    last = model.index(rows - 1)
    view.scrollTo(last)
    QtTest.QTest.qWait(20)
    rect = view.visualRect(last)
    assert viewport.contains(rect), (rect, viewport)
    click(view.viewport(), rect.center())
    assert view.currentIndex().row() == rows - 1


@pytest.mark.parametrize("results", [3, 14])
def test_every_result_can_be_scrolled_to_and_clicked(window, qtbot, tmp_path, results):
    """"grav" found 3 and showed 2 with no scroll bar (issue 16): at every dock width each
    result is in view or a scroll bar reaches it, and the grid reflows with the width."""
    path = tmp_path / "many.sqlite"
    with Bank(path, builtins=False) as bank:
        for k in range(results):
            bank.add(noise(k), f"Gravel {k}", tags=["granular"])
        bank.add(noise(99), "Stripes")
    window.resize(1280, 800)
    dock = window.bank_dock
    dock.show()
    dock.raise_()
    assert dock.load(path)
    assert window.runner.wait(60_000)
    type_search(qtbot, dock, "grav")
    qtbot.waitUntil(lambda: len(shown(dock)) == results)
    view = dock.view
    columns = {}
    for width in (295, 300, 303, 340, 390, 420):
        window.resizeDocks([dock], [width], QtCore.Qt.Orientation.Horizontal)
        qtbot.wait(60)
        reachable(view, results)
        columns[dock.width()] = len({view.visualRect(view.model().index(r)).left()
                                     for r in range(results)})
    assert columns[max(columns)] > columns[min(columns)] or results <= 3    # it reflows
