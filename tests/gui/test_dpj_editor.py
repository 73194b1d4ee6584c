"""The DPJ editor through its real widgets: paint, set, check, normalise, preview, table edits,
generators, files, undo, and a hand-made DPJ handed to the main window."""

import numpy as np
import pytest
from PySide6 import QtCore, QtWidgets
from PySide6.QtTest import QTest

from app.dpj_editor import DPJEditor
from app.dpj_editor.checks import BAD, OK, WARN
from app.dpj_editor.table import CHAIN, PROB
from texeditor import DPJ, resources
from texeditor.markov import dpj_edit as E
from texeditor.markov.estimation import estimate_dpj
from texeditor.markov.levels import load_image, quantize

from .support import choose_level, drag, new_dpj, paint, set_probability

LEFT = QtCore.Qt.MouseButton.LeftButton
NONE = QtCore.Qt.KeyboardModifier.NoModifier
CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
Key = QtCore.Qt.Key
V_STRIPES = np.array([[[0, 1], [0, 1]], [[1, 0], [1, 0]]], np.uint8)


@pytest.fixture
def editor(qtbot, monkeypatch):
    errors = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "critical",
                        lambda parent, title, text, *a, **k: errors.append((title, text)))
    ed = DPJEditor()
    ed.errors = errors
    qtbot.addWidget(ed)
    ed.show()
    qtbot.waitExposed(ed)
    yield ed
    ed.stop()


def table_click(qtbot, editor, row, modifier=NONE, column=0):
    view = editor.table.view
    rect = view.visualRect(editor.table.proxy.index(row, column))
    QTest.mouseClick(view.viewport(), LEFT, modifier, rect.center())


def test_paint_set_normalise_and_undo(qtbot, editor):
    new_dpj(qtbot, editor, 2, 2, 2)
    assert editor.checks.sum.state == BAD and not editor.act_use.isEnabled()
    paint(editor, V_STRIPES[0])
    set_probability(qtbot, editor, "0.3")
    assert editor.dpj.prob(V_STRIPES[0]) == 0.3 and editor.table.model.rowCount() == 1
    paint(editor, V_STRIPES[1])
    assert "Not in the DPJ" in editor.painter.entry_label.text()
    set_probability(qtbot, editor, "0.3")
    assert len(editor.dpj) == 2 and np.isclose(editor.dpj.total, 0.6)
    assert editor.checks.sum.state == BAD and "must be 1" in editor.checks.sum.text.text()
    assert editor.checks.sum.button.isEnabled()

    QTest.mouseClick(editor.checks.sum.button, LEFT)               # Normalise
    assert editor.checks.sum.state == OK and editor.report.is_valid
    assert np.allclose(editor.dpj.probs, 0.5) and editor.act_use.isEnabled()
    assert editor.checks.stationarity.state == OK and "Ready" in editor.checks.verdict.text()
    # 01 then 10 then 01...: the columns alternate, a chain of period 2 (flagged, nothing to drop)
    chain = editor.checks.chain
    assert chain.state == WARN and "period 2" in chain.text.text() and not chain.button.isEnabled()

    editor.activateWindow()
    qtbot.keyClick(editor, Key.Key_Z, CTRL)                         # undo the normalisation
    assert np.isclose(editor.dpj.total, 0.6) and editor.checks.sum.state == BAD
    qtbot.keyClick(editor, Key.Key_Z, CTRL | QtCore.Qt.KeyboardModifier.ShiftModifier)
    assert editor.checks.sum.state == OK


def test_dragging_paints_every_cell_crossed_and_right_click_picks(qtbot, editor):
    new_dpj(qtbot, editor, 4, 1, 3)
    grid = editor.painter.grid
    choose_level(editor, 2)
    a, b = grid.cell_rect(0, 0).center(), grid.cell_rect(0, 3).center()
    drag(grid, LEFT, (a.x(), a.y()), (b.x(), b.y()), steps=6)
    assert grid.config.tolist() == [[2, 2, 2, 2]]
    choose_level(editor, 0)
    QTest.mouseClick(grid, QtCore.Qt.MouseButton.RightButton, NONE, grid.cell_rect(0, 1).center())
    assert editor.painter.grid.level == 2


def test_the_preview_follows_edits_and_the_latest_change_wins(qtbot, editor):
    new_dpj(qtbot, editor, 2, 2, 2)
    preview = editor.preview
    assert preview.preview.wait()
    assert preview.levels is None and "no usable" in preview.status.text()   # nothing yet
    for config in V_STRIPES:
        paint(editor, config)
        set_probability(qtbot, editor, "0.5")
    assert preview.preview.wait()
    levels = preview.levels
    assert levels.shape == (128, 128)
    assert np.all(levels == levels[0]) and np.all(levels[0, 1:] != levels[0, :-1])   # stripes
    started = preview.preview.started
    for k in range(6):                        # a burst of changes: one synthesis, the last
        editor.edit(E.set_entry(editor.dpj, V_STRIPES[0], 0.5 + k / 100), f"burst {k}")
    assert preview.preview.wait()
    assert preview.preview.started - started <= 2
    assert preview.preview.shown == preview.preview.generation


def test_table_select_delete_and_undo(qtbot, editor):
    editor.start(E.random_dpj((2, 1), 3, seed=1), "seeded")
    model = editor.table.model
    assert model.rowCount() == 9
    first, third = (int(model.data(model.index(r, 0), QtCore.Qt.ItemDataRole.UserRole + 1))
                    for r in (0, 2))
    table_click(qtbot, editor, 0)
    table_click(qtbot, editor, 2, CTRL)
    assert sorted(editor.table.selected_codes()) == sorted([first, third])
    qtbot.keyClick(editor.table.view, Key.Key_Delete)
    assert len(editor.dpj) == 7 and not np.isin([first, third], editor.dpj.codes).any()
    assert "7 configurations" in editor.table.count_label.text()
    editor.undo_stack.undo()
    assert len(editor.dpj) == 9


def test_clicking_a_row_loads_the_painter_and_edit_in_place(qtbot, editor):
    editor.start(E.random_dpj((2, 2), 2, seed=3), "seeded")
    model = editor.table.model
    table_click(qtbot, editor, 4)
    i = int(model.rows[4])
    assert np.array_equal(editor.painter.config(), editor.dpj.configs[i])
    assert np.isclose(editor.painter.probability.value(), editor.dpj.probs[i], atol=1e-8)
    code = int(editor.dpj.codes[i])
    view = editor.table.view
    rect = view.visualRect(editor.table.proxy.index(4, PROB))
    QTest.mouseClick(view.viewport(), LEFT, NONE, rect.center())   # a real double click's
    QTest.mouseDClick(view.viewport(), LEFT, NONE, rect.center())  # first press, then this
    line = view.findChild(QtWidgets.QLineEdit)
    assert line is not None
    line.selectAll()
    qtbot.keyClicks(line, "2.5e-3")
    qtbot.keyClick(line, Key.Key_Return)
    j = int(np.searchsorted(editor.dpj.codes, code))
    qtbot.waitUntil(lambda: editor.dpj.probs[j] == 0.0025)
    assert editor.checks.sum.state == BAD


def test_sorting_and_filtering_the_table(qtbot, editor):
    editor.start(E.random_dpj((2, 2), 3, seed=5), "seeded")
    model, view = editor.table.model, editor.table.view
    shown = lambda: editor.dpj.probs[model.rows]                        # noqa: E731
    assert np.all(np.diff(shown()) <= 0)                                 # largest first
    header = view.horizontalHeader()
    QTest.mouseClick(header.viewport(), LEFT, NONE,
                     QtCore.QPoint(header.sectionViewportPosition(PROB) + 20, 5))
    assert np.all(np.diff(shown()) >= 0)
    button = editor.table._level_buttons[2]
    QTest.mouseClick(button, LEFT)
    editor.table.filter_timer.timeout.emit()
    configs = editor.dpj.configs[model.rows]
    assert len(configs) and all((c == 2).any() for c in configs)
    assert len(configs) == sum((c == 2).any() for c in editor.dpj.configs)
    editor.table.mode.setCurrentIndex(2)                                 # uses only level 2
    editor.table.apply_filter()
    assert model.rowCount() == 1
    qtbot.keyClicks(editor.table.pmin, "0.02")
    editor.table.clear_filter()
    assert model.rowCount() == 81


def test_generators_seed_extremes_merge(qtbot, editor):
    new_dpj(qtbot, editor, 2, 2, 4)
    gen = editor.generators
    gen.seed.set_value(99)
    gen.sparsity.setValue(0)
    QTest.mouseClick(gen.generate_button, LEFT)
    assert editor.runner.wait()
    assert len(editor.dpj) == 4 ** 4 and np.all(editor.dpj.probs > 0)
    assert editor.dpj == E.random_dpj((2, 2), 4, 99, palette=editor.dpj.palette)

    start = gen.empty.value()                  # the seeded weight, rounded to the slider
    assert start == round(editor.dpj.prob(np.zeros((2, 2))) * 1000)
    gen.empty.setFocus()
    for _ in range(3):
        qtbot.keyClick(gen.empty, Key.Key_PageUp)                    # 3 × 10 steps of 0.001
    assert editor.dpj.prob(np.zeros((2, 2))) == (start + 30) / 1000     # exactly
    assert abs(editor.dpj.total - 1) < 1e-12

    gen.pairs_button.click()
    assert gen.mapping() == [0, 0, 1, 1]
    before = editor.dpj
    QTest.mouseClick(gen.merge_button, LEFT)
    assert editor.runner.wait()
    assert editor.dpj.levels == 2 and editor.dpj == E.merge_levels(before, [0, 0, 1, 1])
    assert len(editor.painter.swatches.palette_rgb) == 2


def test_slider_drag_is_one_undo_step(qtbot, editor):
    editor.start(E.random_dpj((2, 2), 2, seed=8), "seeded")
    steps = editor.undo_stack.count()
    slider = editor.generators.full
    start = slider.value()
    opt = QtWidgets.QStyleOptionSlider()
    slider.initStyleOption(opt)
    handle = slider.style().subControlRect(QtWidgets.QStyle.ComplexControl.CC_Slider, opt,
                                           QtWidgets.QStyle.SubControl.SC_SliderHandle, slider)
    a = handle.center()
    drag(slider, LEFT, (a.x(), a.y()), (a.x() + slider.width() // 3, a.y()), steps=5)
    full = editor.dpj.prob(np.ones((2, 2)))
    assert slider.value() > start + 100 and full == slider.value() / 1000
    assert editor.undo_stack.count() == steps + 1


def test_restrict_and_make_stationary_from_the_checks(qtbot, editor):
    configs = np.array([[[0, 1]], [[1, 2]], [[2, 1]], [[1, 1]], [[3, 3]]], np.uint8)
    editor.start(DPJ(configs, [.1, .3, .3, .15, .15], 4), "planted")
    assert editor.checks.chain.state == WARN and "2 unreachable" in editor.checks.chain.text.text()
    model = editor.table.model
    marked = [model.data(model.index(r, CHAIN)) for r in range(5)]
    assert sorted(marked) == ["", "", "", "small closed class", "transient"]
    QTest.mouseClick(editor.checks.chain.button, LEFT)                 # Restrict
    assert editor.runner.wait()
    assert len(editor.dpj) == 3 and editor.checks.chain.state == OK

    editor.start(E.random_dpj((2, 2), 2, seed=4), "seeded")
    assert editor.checks.stationarity.state == WARN
    QTest.mouseClick(editor.checks.stationarity.button, LEFT)          # Make stationary
    assert editor.runner.wait()
    r = editor.dpj.report()
    assert max(r.horizontal_residual, r.vertical_residual) < 1e-9
    assert editor.checks.stationarity.state == OK


def test_a_photo_dpj_without_wrap_restricts_to_its_closed_class_and_undoes(qtbot, editor):
    """Issue 21.1: the border's dead ends are marked, not every entry; Restrict keeps the main
    closed class; Ctrl+Z brings the dead ends back."""
    q = quantize(load_image(resources.sample_images()[0]), 4, "band")
    photo = estimate_dpj(q.levels, (3, 3), 4, wrap=False)
    editor.start(photo, "brick")
    assert editor.analysis.wait()
    chain, model = editor.checks.chain, editor.table.model
    assert chain.state == WARN and "1 closed class," in chain.text.text()
    assert f", {editor.report.dead_ends} dead end" in chain.text.text() and chain.button.isEnabled()
    marks = [model.data(model.index(r, CHAIN)) for r in range(model.rowCount())]
    dead = marks.count("dead end")
    assert 0 < dead == editor.report.dead_ends and marks.count("") >= 0.99 * len(marks)
    QTest.mouseClick(chain.button, LEFT)                               # Restrict
    assert editor.runner.wait() and editor.analysis.wait()
    assert chain.state == OK and len(editor.dpj) == len(photo.restrict())
    assert editor.report.closed_classes == 1 and editor.report.dead_ends == 0
    editor.activateWindow()
    qtbot.keyClick(editor, Key.Key_Z, CTRL)
    assert editor.analysis.wait()
    assert editor.dpj == photo and chain.state == WARN and editor.report.dead_ends == dead


def test_save_open_and_a_damaged_file(qtbot, editor, tmp_path, monkeypatch):
    editor.start(E.random_dpj((3, 1), 2, seed=2), "seeded")
    target = tmp_path / "mine"
    monkeypatch.setattr(QtWidgets.QFileDialog, "getSaveFileName", lambda *a, **k: (str(target), ""))
    editor.act_save.trigger()
    saved = tmp_path / "mine.dpj"
    assert saved.exists() and DPJ.load(saved) == editor.dpj and "*" not in editor.windowTitle()
    kept = editor.dpj
    editor.start(DPJ.empty((2, 2), 2), "other")
    bad = tmp_path / "bad.dpj"
    bad.write_bytes(b"not a dpj")
    assert not editor.open_file(bad)
    assert editor.errors and "bad.dpj" in editor.errors[-1][0] and len(editor.dpj) == 0
    monkeypatch.setattr(QtWidgets.QFileDialog, "getOpenFileName", lambda *a, **k: (str(saved), ""))
    editor.act_open.trigger()
    assert editor.dpj == kept and editor.dpj.meta["name"] == "mine"


def test_hand_made_vertical_stripes_synthesise_stripes(qtbot, window):
    window.act_new_dpj.trigger()
    editor = window.dpj_editor
    new_dpj(qtbot, editor, 2, 2, 2)
    for config in V_STRIPES:                            # only the vertical-stripe windows
        paint(editor, config)
        set_probability(qtbot, editor, "0.5")
    assert editor.report.is_valid
    QTest.mouseClick(editor.preview.use_button, LEFT)             # Use this DPJ
    doc = window.history.document
    assert doc.dpj == editor.dpj and "hand-made" in window.synthesis_dock.dpj_label.text()
    window.synthesise_from_dock()
    assert window.runner.wait(60_000)
    levels = window.history.document.levels
    assert levels.shape == (48, 64)
    assert np.all(levels == levels[0])                              # every column is constant
    assert np.all(levels[0, 1:] != levels[0, :-1])                  # and the columns alternate
    editor.stop()


def test_edit_dpj_opens_the_current_one(qtbot, window):
    window.act_edit_dpj.trigger()
    editor = window.dpj_editor
    assert editor.isVisible() and editor.dpj is window.history.document.dpj
    assert editor.table.model.rowCount() == len(editor.dpj)
    editor.stop()


def test_large_dpjs_are_checked_in_the_background(qtbot, editor, monkeypatch):
    import app.dpj_editor.window as window_module
    monkeypatch.setattr(window_module, "BACKGROUND_CHECKS", 10)
    main = [[[a, b]] for a in (1, 2, 3) for b in (1, 2, 3)]           # a closed class {1, 2, 3}
    configs = np.array(main + [[[0, 1]], [[5, 5]]], np.uint8)        # + transient 0, class {5}
    big = DPJ(configs, np.full(11, 1 / 11), 6)
    editor.start(DPJ(configs[:3], [.5, .25, .25], 6), "small")      # 3 entries: checked at once
    assert editor.report is not None and editor.report.entries == 3
    editor.start(big, "larger")
    assert editor.report is None and editor.checks.verdict.text() == "Checking…"
    assert not editor.act_use.isEnabled()
    assert editor.analysis.wait()
    assert editor.report.entries == 11 and editor.unreachable == 2
    assert editor.act_use.isEnabled()
    model = editor.table.model
    marks = sorted(model.data(model.index(r, CHAIN)) for r in range(model.rowCount()))
    assert marks[-2:] == ["small closed class", "transient"] and marks[:-2] == [""] * 9


def test_the_new_dpj_dialog_refuses_a_window_it_cannot_index_then_makes_one(qtbot, editor):
    """The largest window and G have too many configurations to index: the dialog says so and
    its OK (and Return) does nothing; a smaller window is accepted, twice in a row."""
    before = editor.dpj
    editor.act_new.trigger()
    dialog = editor.new_dialog
    ok = dialog.buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Ok)
    for box in (dialog.u, dialog.v, dialog.levels):
        box.setValue(box.maximum())
    assert not ok.isEnabled() and "too many" in dialog.info.text()
    qtbot.keyClick(dialog, Key.Key_Return)
    assert dialog.isVisible() and editor.dpj is before
    dialog.levels.setValue(3)
    dialog.u.setValue(2)
    assert ok.isEnabled() and "possible configurations" in dialog.info.text()
    qtbot.keyClick(dialog, Key.Key_Return)
    assert editor.dpj.window == (2, 6) and editor.dpj.levels == 3 and len(editor.dpj) == 0
    new_dpj(qtbot, editor, 3, 3, 4)
    assert not editor.errors
