"""The bank picker (issues 7 and 9): choose an entry with real clicks and keys, then fill spots
with its texture or compose with it (an entry made from two DPJs too); an empty bank and an
unusable one say so, and a fill whose entry fails to load goes back to the previous fill."""

import sqlite3

import numpy as np
from PySide6 import QtCore, QtTest, QtWidgets

from app.bank_picker import EMPTY, BankPicker
from tests.support import REFS, TINY_DPJS
from texeditor.recipe.actions import NewCanvas, SetLevels, Synthesize
from texeditor.bank.store import Bank, default_path
from texeditor.texture.composition import fit
from texeditor.recipe.document import dpj_ref
from texeditor.recipe.history import History
from texeditor.spots.actions import PlaceSpot
from texeditor.texture.actions import Incrust, Mix, MixTextures
from texeditor.recipe.sources import synthesis_recipe
from texeditor.recipe.texturefile import load_texture, save_texture

from .support import cell_pos, click, press_key, spot_tool

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


def pick_in_popup(qtbot, combo, value) -> None:
    """Open a combo box's list, move to ``value`` and press Return: the combo goes straight
    there (stepping with the closed combo's arrows makes every item on the way current)."""
    combo.setFocus()
    press_key(combo, Key.Key_F4)
    view = combo.view()
    qtbot.waitUntil(view.isVisible, timeout=3000)
    press_key(view, Key.Key_Home)
    while view.currentIndex().data(QtCore.Qt.ItemDataRole.UserRole) != value:
        press_key(view, Key.Key_Down)
    press_key(view, Key.Key_Return)
    assert combo.currentData() == value


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
    assert action.texture_dpjs and set(action.texture_dpjs) <= set(window.document.dpjs)


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


def open_composition_on_the_bank(window, qtbot):
    """Image ▸ Composition…, source "a bank entry", its Choose button clicked: (dialog, source)."""
    window.act_compose.trigger()
    dialog = window.composition_dialog
    qtbot.waitExposed(dialog)
    assert window.runner.wait(30_000)
    source = dialog.source
    choose(source.kind, "bank")
    QtTest.QTest.mouseClick(source.bank_button, LEFT)
    return dialog, source


def test_compose_with_a_bank_entry_chosen_with_the_keyboard(window, qtbot, small_dpj):
    entry = add_entry(pebbles(small_dpj), "Pebbles")
    dialog, source = open_composition_on_the_bank(window, qtbot)
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
    pick_in_popup(qtbot, tool.opts.fill, "texture")
    picker = tool.picker
    qtbot.waitExposed(picker)
    assert "cannot be used" in picker.status.text() and "not a texture bank" in \
        picker.status.text()
    assert not picker.ok_button.isEnabled() and not picker.grid.isEnabled()
    press_key(picker, Key.Key_Escape)
    qtbot.waitUntil(lambda: tool.opts.fill.currentData() == "level", timeout=3000)
    assert tool.texture is None


def two_dpjs(dpj) -> History:
    """A G = 4 texture made from two DPJs: pebbles mixed with a synthesis of another DPJ."""
    history = pebbles(dpj)
    history.document.store_dpj(TINY_DPJS[0])
    history.apply(Mix(synthesis_recipe(REFS[0], 6, 5, 2), (REFS[0],), op2="xor"))
    return history


def choose(combo, value) -> None:
    """Pick an item of a combo box with the keyboard."""
    combo.setFocus()
    press_key(combo, Key.Key_Home)
    while combo.currentData() != value:
        press_key(combo, Key.Key_Down)


def test_compose_with_a_bank_entry_of_two_dpjs(window, qtbot, small_dpj, tmp_path):
    entry = add_entry(two_dpjs(small_dpj), "Two DPJs")
    dialog, source = open_composition_on_the_bank(window, qtbot)
    search_and_pick(qtbot, source.findChild(BankPicker), "two")
    qtbot.waitUntil(lambda: source.bank_source is not None, timeout=30_000)
    assert window.errors == [] and source.bank_label.text() == "Two DPJs"

    bar = dialog.tabs.tabBar()
    QtTest.QTest.mouseClick(bar, LEFT, pos=bar.tabRect(0).center())
    choose(dialog.mask_kind, "levels")
    dialog.mask_levels.selectAll()
    QtTest.QTest.keyClicks(dialog.mask_levels, "0-3")          # every point: T3 is T2
    qtbot.waitUntil(lambda: "points change" in dialog.status.text()
                    and "levels 0-3" in dialog.status.text() and not window.runner.busy,
                    timeout=30_000)
    assert "bank entry “Two DPJs”" in dialog.status.text()
    QtTest.QTest.mouseClick(dialog.apply_button, LEFT)
    assert window.runner.wait(30_000)
    action = window.history.actions[-1]
    assert isinstance(action, Incrust) and window.errors == []
    assert set(action.source_dpjs) == {dpj_ref(small_dpj), REFS[0]}
    assert set(action.source_dpjs) <= set(window.document.dpjs)
    assert np.array_equal(window.document.levels, fit(entry_levels(entry), window.document.shape))
    dialog.close()

    dock = window.history_dock
    qtbot.mouseClick(dock.view.viewport(), LEFT, pos=dock.row_rect(window.history.index - 1)
                     .center())
    shown = [w.text() for w in dock.form.findChildren(QtWidgets.QLabel)]
    assert any(t.startswith("2 DPJs: ") for t in shown)         # read-only, not an editor
    assert "source_dpjs" not in dock.form.editors

    path = tmp_path / "composed.texture"
    save_texture(path, window.history)
    with Bank() as bank:
        bank.trash(entry)
        bank.purge()
    again, _ = load_texture(path)
    assert again.document.result_hash() == window.document.result_hash()


def test_a_fill_whose_entry_fails_to_load_goes_back_to_the_previous_fill(window, qtbot,
                                                                         small_dpj):
    entry = add_entry(pebbles(small_dpj), "Pebbles")
    with sqlite3.connect(default_path()) as conn:          # damaged: its replay will not match
        conn.execute("UPDATE entries SET sha256 = ? WHERE id = ?", ("0" * 64, entry))
    tool = spot_tool(window)
    pick_in_popup(qtbot, tool.opts.fill, "document")
    pick_in_popup(qtbot, tool.opts.fill, "texture")
    search_and_pick(qtbot, tool.picker, "pebb")
    qtbot.waitUntil(lambda: tool.opts.fill.currentData() == "document", timeout=30_000)
    assert window.runner.wait(30_000)
    assert tool.texture is None and not tool.opts.texture_row.isVisible()
    assert any("Pebbles" in title and "damaged" in text for title, text in window.errors)


def test_a_cancelled_pick_goes_back_to_the_previous_fill(window, qtbot):
    tool = spot_tool(window)
    pick_in_popup(qtbot, tool.opts.fill, "document")
    pick_in_popup(qtbot, tool.opts.fill, "texture")
    picker = tool.picker
    qtbot.waitExposed(picker)
    press_key(picker, Key.Key_Escape)
    qtbot.waitUntil(lambda: tool.opts.fill.currentData() == "document", timeout=3000)
    assert tool.texture is None


def test_mix_three_textures_two_of_them_from_the_bank_in_one_expression(window, qtbot,
                                                                        small_dpj):
    """More textures: T2 and T3 bank entries, T4 a synthesis; the brightest of the four, then
    a typed expression with brackets; undo back to the start (issue 21 item 9)."""
    pebbled = add_entry(pebbles(small_dpj), "Pebbles")
    striped = History()
    striped.apply(NewCanvas(6, 4, 4))
    striped.apply(SetLevels(0, 0, 4, 2, 2))                 # columns 0-1 of every 6: level 2
    stripes = add_entry(striped, "Stripes")
    start = window.document.levels.copy()
    dialog, source = open_composition_on_the_bank(window, qtbot)
    search_and_pick(qtbot, source.findChild(BankPicker), "pebbles")
    qtbot.waitUntil(lambda: source.bank_source is not None, timeout=30_000)
    QtTest.QTest.mouseClick(dialog.tabs.tabBar(), LEFT,
                            pos=dialog.tabs.tabBar().tabRect(2).center())
    assert dialog.tabs.currentIndex() == 2 and len(dialog.extra) == 1
    t3 = dialog.extra[0]
    choose(t3.kind, "bank")
    QtTest.QTest.mouseClick(t3.bank_button, LEFT)
    search_and_pick(qtbot, t3.findChild(BankPicker), "stripes")
    qtbot.waitUntil(lambda: t3.bank_source is not None, timeout=30_000)
    QtTest.QTest.mouseClick(dialog.add_texture, LEFT)         # T4: a synthesis, seed 4
    assert len(dialog.extra) == 2 and dialog.extra[1].seed.value() == 4
    dialog.expression_preset.setCurrentIndex(dialog.expression_preset.findText(
        "Brightest (max)"))
    assert dialog.expression.text() == "T1 max T2 max T3 max T4"
    dialog.update_preview()
    assert window.runner.wait(30_000)
    assert "points change" in dialog.status.text(), dialog.status.text()
    QtTest.QTest.mouseClick(dialog.apply_button, LEFT)
    assert window.runner.wait(30_000)
    action = window.history.actions[-1]
    assert isinstance(action, MixTextures) and len(action.sources) == 3
    shape = window.document.shape
    t2, t3_levels = (fit(entry_levels(e), shape) for e in (pebbled, stripes))
    t4 = fit(replay_one(action.sources[2], window), shape)
    expected = np.maximum.reduce([start, t2, t3_levels, t4])       # all G = 4: levels are greys
    assert np.array_equal(window.document.levels, expected)

    QtTest.QTest.mouseClick(dialog.remove_texture, LEFT)      # back to T1…T3, typed
    dialog.expression.setFocus()
    dialog.expression.selectAll()
    QtTest.QTest.keyClicks(dialog.expression, "T1 min (T2 max T3)")
    assert dialog.expression_preset.currentText() == "Custom"
    dialog.update_preview()
    assert window.runner.wait(30_000)
    QtTest.QTest.mouseClick(dialog.apply_button, LEFT)
    assert window.runner.wait(30_000)
    assert window.history.actions[-1].expression == "T1 min (T2 max T3)"
    assert np.array_equal(window.document.levels, np.minimum(expected, np.maximum(t2, t3_levels)))
    window.act_undo.trigger()
    window.act_undo.trigger()
    assert np.array_equal(window.document.levels, start)
    dialog.close()


def replay_one(recipe: str, window) -> np.ndarray:
    from texeditor.recipe.sources import source_levels
    return source_levels(window.document, recipe, (window.document.dpj_ref,))[0]
