"""The bank picker (issues 7 and 9): choose an entry with real clicks and keys, then fill spots
with its texture or compose with it; an empty bank and an unusable one say so."""

import numpy as np
from PySide6 import QtCore, QtTest

from app.bank_picker import EMPTY, BankPicker
from texeditor.actions import NewCanvas, SetLevels, Synthesize
from texeditor.bank import Bank, default_path
from texeditor.composition import fit
from texeditor.history import History
from texeditor.spot_actions import PlaceSpot
from texeditor.texture_actions import Incrust

from .events import cell_pos, click, press_key
from .test_spot_tools import spot_tool

LEFT = QtCore.Qt.MouseButton.LeftButton
Key = QtCore.Qt.Key


def add_entry(history, name: str) -> int:
    """Store a texture in the test's own default bank (its built-ins come with it)."""
    with Bank() as bank:
        return bank.add(history, name)


def pebbles(dpj) -> History:
    """A G = 4 texture like the window's: a synthesis of its DPJ with a rectangle drawn on it."""
    history = History()
    ref = history.add_dpj(dpj)
    history.apply(Synthesize(ref, 24, 20, 3))
    history.apply(SetLevels(2, 2, 5, 6, 3))
    return history


def entry_levels(entry_id: int) -> np.ndarray:
    with Bank() as bank:
        return bank.render(entry_id).levels


def search_and_pick(qtbot, picker, words: str) -> None:
    """Type the words, click the only thumbnail found, click OK."""
    qtbot.waitExposed(picker)
    QtTest.QTest.keyClicks(picker.search, words)
    qtbot.waitUntil(lambda: picker.grid.model().rowCount() == 1, timeout=3000)
    rect = picker.grid.visualRect(picker.grid.model().index(0))
    QtTest.QTest.mouseClick(picker.grid.viewport(), LEFT, pos=rect.center())
    assert picker.ok_button.isEnabled()
    QtTest.QTest.mouseClick(picker.ok_button, LEFT)


def choose_fill(tool, value: str) -> None:
    """Pick a fill in the tool options' combo box with the keyboard."""
    combo = tool.opts.fill
    combo.setFocus()
    while combo.currentData() != value:
        press_key(combo, Key.Key_Down)


def test_choose_an_entry_then_place_a_spot_filled_with_its_texture(window, qtbot, small_dpj):
    entry = add_entry(pebbles(small_dpj), "Pebbles")
    tool = spot_tool(window)
    tool.editor.load(tool.editor.library.get("Ellipse"))
    choose_fill(tool, "texture")
    picker = tool.picker
    assert isinstance(picker, BankPicker) and picker.isModal()
    search_and_pick(qtbot, picker, "pebb")
    qtbot.waitUntil(lambda: tool.texture is not None, timeout=30_000)
    assert window.runner.wait(30_000)
    assert tool.opts.texture_label.text() == "Pebbles" and "as it is" in tool.opts.hint.text()

    click(window.canvas.viewport(), cell_pos(window.canvas, 30, 20))
    action = window.history.actions[-1]
    assert isinstance(action, PlaceSpot) and action.fill == "texture"
    stamp = action.stamp(0, window.document.shape)
    rows, cols = np.nonzero(stamp.mask)
    rows, cols = rows + stamp.top, cols + stamp.left
    texture = entry_levels(entry)
    assert np.array_equal(window.document.levels[rows, cols],
                          texture[rows % texture.shape[0], cols % texture.shape[1]])
    assert action.dpj in window.document.dpjs


def test_a_texture_of_another_g_says_its_levels_are_mapped(window, qtbot):
    two = History()
    two.apply(NewCanvas(8, 8, 2))
    two.apply(SetLevels(0, 0, 4, 8, 1))
    add_entry(two, "Two levels")
    tool = spot_tool(window)
    choose_fill(tool, "texture")
    search_and_pick(qtbot, tool.picker, "two")
    qtbot.waitUntil(lambda: tool.texture is not None, timeout=30_000)
    assert "G = 2 levels, the document 4" in tool.opts.hint.text()
    assert "mapped" in tool.opts.hint.text()


def test_compose_with_a_bank_entry_chosen_with_the_keyboard(window, qtbot, small_dpj):
    entry = add_entry(pebbles(small_dpj), "Pebbles")
    window.act_compose.trigger()
    dialog = window._composition_dialog
    qtbot.waitExposed(dialog)
    assert window.runner.wait(30_000)
    source = dialog.source
    source.kind.setCurrentIndex(source.kind.findData("bank"))
    QtTest.QTest.mouseClick(source.bank_button, LEFT)
    picker = source.findChild(BankPicker)
    qtbot.waitExposed(picker)
    QtTest.QTest.keyClicks(picker.search, "pebbles")
    qtbot.waitUntil(lambda: picker.grid.model().rowCount() == 1, timeout=3000)
    press_key(picker.search, Key.Key_Return)        # the first entry found is selected: OK
    qtbot.waitUntil(lambda: source.bank_source is not None, timeout=30_000)
    assert source.bank_label.text() == "Pebbles"

    dialog.tabs.setCurrentIndex(0)
    dialog.mask_kind.setCurrentIndex(dialog.mask_kind.findData("levels"))
    dialog.mask_levels.setText("0-3")               # every point: T3 is T2
    dialog.update_preview()
    assert window.runner.wait(30_000)
    assert "bank entry “Pebbles”" in dialog.status.text()
    dialog.apply_button.click()
    assert window.runner.wait(30_000)
    action = window.history.actions[-1]
    assert isinstance(action, Incrust) and action.source == source.bank_source.recipe
    expected = fit(entry_levels(entry), window.document.shape)
    assert np.array_equal(window.document.levels, expected)
    dialog.close()


def test_an_empty_bank_says_so(qtbot, tmp_path):
    with Bank(tmp_path / "empty.sqlite", builtins=False) as bank:
        picker = BankPicker(bank)
        qtbot.addWidget(picker)
        assert picker.status.text() == EMPTY and not picker.ok_button.isEnabled()
        QtTest.QTest.keyClicks(picker.search, "x")
        qtbot.waitUntil(lambda: "No entry matches" in picker.status.text(), timeout=3000)


def test_an_unusable_bank_is_explained_and_the_fill_goes_back(window, qtbot):
    default_path().write_bytes(b"not a bank at all" * 100)
    tool = spot_tool(window)
    choose_fill(tool, "texture")
    picker = tool.picker
    qtbot.waitExposed(picker)
    assert "cannot be used" in picker.status.text() and "not a texture bank" in \
        picker.status.text()
    assert not picker.ok_button.isEnabled() and not picker.grid.isEnabled()
    press_key(picker, Key.Key_Escape)
    qtbot.waitUntil(lambda: tool.opts.fill.currentData() == "level", timeout=3000)
    assert tool.texture is None
