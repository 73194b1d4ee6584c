"""The main window driven like a user would: keys, clicks, the wheel; asserts are on the document."""

import numpy as np
import pytest
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.recipe.actions import SetPalette, Synthesize

from .support import move, type_into, wheel

CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier
LEFT = QtCore.Qt.MouseButton.LeftButton


def test_starts_on_a_synthesis_from_the_dpj(window):
    doc = window.history.document
    assert doc.shape == (48, 64)
    assert isinstance(window.history.actions[0], Synthesize)
    assert window.canvas.levels.shape == (48, 64)
    assert "repairs" in window.repairs_label.text()


def test_synthesise_button_applies_a_synthesize_action(qtbot, window):
    dock = window.synthesis_dock
    type_into(qtbot, dock.width_box, "80")
    type_into(qtbot, dock.height_box, "40")
    type_into(qtbot, dock.seed.edit, "12345")
    qtbot.mouseClick(dock.button, LEFT)
    assert window.runner.wait(60_000)
    doc = window.history.document
    assert doc.shape == (40, 80)
    last = window.history.actions[-1]
    assert isinstance(last, Synthesize) and last.seed == 12345
    assert np.array_equal(window.canvas.levels, doc.levels)
    assert "repairs" in window.statusBar().currentMessage()


def test_new_seed_button_gives_another_texture(qtbot, window):
    before = window.history.document.levels.copy()
    qtbot.mouseClick(window.synthesis_dock.seed.button, LEFT)
    assert window.synthesis_dock.seed.value() != 7
    qtbot.keyClick(window, QtCore.Qt.Key.Key_R, CTRL)
    assert window.runner.wait(60_000)
    assert not np.array_equal(before, window.history.document.levels)


def test_cancel_midway_leaves_the_document_unchanged(qtbot, window):
    before = window.history.document.levels.copy()
    steps = len(window.history.actions)
    dock = window.synthesis_dock
    dock.width_box.setValue(2048)
    dock.height_box.setValue(2048)
    seen = []
    window.runner.progress.connect(seen.append)
    with qtbot.waitSignal(window.runner.progress, timeout=30_000):
        qtbot.mouseClick(dock.button, LEFT)
    assert window.cancel_button.isVisible() and not dock.button.isEnabled()
    qtbot.mouseClick(window.cancel_button, LEFT)
    assert window.runner.wait(30_000)
    assert seen and seen[-1] < 1.0               # it really stopped midway
    assert len(window.history.actions) == steps
    assert np.array_equal(window.history.document.levels, before)
    assert "cancelled" in window.statusBar().currentMessage()
    assert not window.cancel_button.isVisible() and dock.button.isEnabled()


def test_the_same_seed_again_says_no_step_was_added_then_a_new_seed_adds_one(qtbot, window):
    """Ctrl+R with the dock's size and seed unchanged draws the same texture: no step, and the
    status bar says so (not "Synthesised"); a new seed then adds a step, twice in a row."""
    steps = len(window.history.actions)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_R, CTRL)
    assert window.runner.wait(60_000)
    assert len(window.history.actions) == steps
    assert "no step was added" in window.statusBar().currentMessage()
    for seed in (8, 9):
        window.synthesis_dock.seed.set_value(seed)
        qtbot.keyClick(window, QtCore.Qt.Key.Key_R, CTRL)
        assert window.runner.wait(60_000)
        assert window.history.actions[-1].seed == seed
        assert "Synthesised" in window.statusBar().currentMessage()
    assert len(window.history.actions) == steps + 2


def test_commands_while_a_synthesis_runs_say_to_wait(qtbot, window, tmp_path):
    """File ▸ Open and Ctrl+R while a long synthesis runs: each says to wait and changes
    nothing; the synthesis, cancelled, leaves the document as it was."""
    before = window.history.document.levels.copy()
    steps = len(window.history.actions)
    window.synthesis_dock.width_box.setValue(2048)
    window.synthesis_dock.height_box.setValue(2048)
    with qtbot.waitSignal(window.runner.progress, timeout=30_000):
        qtbot.keyClick(window, QtCore.Qt.Key.Key_R, CTRL)
    window.statusBar().clearMessage()
    window.open_file(tmp_path / "any.texture")
    assert "Busy" in window.statusBar().currentMessage()
    window.statusBar().clearMessage()
    qtbot.keyClick(window, QtCore.Qt.Key.Key_R, CTRL)
    assert "Busy" in window.statusBar().currentMessage()
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Escape)
    assert window.runner.wait(30_000)
    assert len(window.history.actions) == steps
    assert np.array_equal(window.history.document.levels, before)


def test_escape_cancels(qtbot, window):
    steps = len(window.history.actions)
    window.synthesis_dock.width_box.setValue(2048)
    window.synthesis_dock.height_box.setValue(2048)
    with qtbot.waitSignal(window.runner.progress, timeout=30_000):
        qtbot.keyClick(window, QtCore.Qt.Key.Key_R, CTRL)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Escape)
    assert window.runner.wait(30_000)
    assert len(window.history.actions) == steps


def test_undo_redo_with_keys_and_history_clicks(qtbot, window):
    first = window.history.document.levels.copy()
    window.synthesis_dock.seed.set_value(99)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_R, CTRL)
    assert window.runner.wait(60_000)
    second = window.history.document.levels.copy()
    assert not np.array_equal(first, second)

    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)
    assert np.array_equal(window.history.document.levels, first)
    assert np.array_equal(window.canvas.levels, first)
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL)        # the base step stays
    assert window.history.index == 1
    qtbot.keyClick(window, QtCore.Qt.Key.Key_Z, CTRL | SHIFT)
    assert np.array_equal(window.history.document.levels, second)

    view = window.history_dock.view
    qtbot.mouseClick(view.viewport(), LEFT, pos=window.history_dock.row_rect(0).center())
    assert window.history.index == 1
    assert np.array_equal(window.canvas.levels, first)
    qtbot.mouseClick(view.viewport(), LEFT, pos=window.history_dock.row_rect(1).center())
    assert window.history.index == 2
    assert np.array_equal(window.canvas.levels, second)


def test_edit_a_past_seed_and_replay(qtbot, window):
    # step 1: the synthesis (seed 7); step 2: a palette change that must survive the replay
    red = np.array([[0, 0, 0], [200, 0, 0], [0, 200, 0], [0, 0, 200]], np.uint8)
    window.submit(SetPalette(red))
    before = window.canvas.levels.copy()
    dock = window.history_dock
    qtbot.mouseClick(dock.view.viewport(), LEFT, pos=dock.row_rect(0).center())
    assert window.history.index == 1                  # clicking a step goes there...
    assert dock.group.title().startswith("Step 1")    # ...and shows its parameters
    assert not dock.apply_button.isEnabled()
    type_into(qtbot, dock.form.editor("seed").edit, "4242")
    assert dock.apply_button.isEnabled()
    qtbot.mouseClick(dock.apply_button, LEFT)
    assert window.runner.wait(60_000)
    history = window.history
    assert history.actions[0].seed == 4242
    assert isinstance(history.actions[1], SetPalette) and history.index == 2
    assert not np.array_equal(window.canvas.levels, before)
    assert np.array_equal(history.document.palette, red)
    assert window.canvas.displayed_colour(0, 0) == tuple(red[history.document.levels[0, 0]])


def test_wheel_zoom_and_keyboard_zoom(qtbot, window):
    canvas = window.canvas
    canvas.fit()
    fitted = canvas.zoom()
    wheel(canvas.viewport(), QtCore.QPoint(100, 100), 2)
    assert canvas.zoom() > fitted * 1.3
    assert "zoom" in window.zoom_label.text()
    canvas.setFocus()
    qtbot.keyClick(canvas, QtCore.Qt.Key.Key_0)
    assert abs(canvas.zoom() - fitted) / fitted < 0.02
    qtbot.keyClick(canvas, QtCore.Qt.Key.Key_Plus)
    assert canvas.zoom() > fitted * 1.3
    qtbot.keyClick(canvas, QtCore.Qt.Key.Key_Minus)
    assert abs(canvas.zoom() - fitted) / fitted < 0.02
    qtbot.keyClick(canvas, QtCore.Qt.Key.Key_1)
    assert abs(canvas.zoom() - 1.0) < 0.01


def test_tiled_preview_toggle(qtbot, window):
    canvas = window.canvas
    canvas.setFocus()
    qtbot.keyClick(canvas, QtCore.Qt.Key.Key_W)
    assert canvas.tiled and canvas.echo.isVisible() and window.act_tiled.isChecked()
    assert canvas.view.viewRect().width() >= 3 * 64
    button = window.findChild(QtWidgets.QToolBar).widgetForAction(window.act_tiled)
    qtbot.mouseClick(button, LEFT)
    assert not canvas.tiled and not canvas.echo.isVisible()


def test_status_bar_follows_the_cursor(qtbot, window):
    canvas = window.canvas
    qtbot.wait(50)                       # let the layout and the view range settle
    target = canvas.mapFromScene(canvas.view.mapViewToScene(QtCore.QPointF(10.5, 5.5)))
    move(canvas.viewport(), target + QtCore.QPoint(40, 40))
    qtbot.wait(40)                       # pyqtgraph drops moves closer than its rate limit
    move(canvas.viewport(), target)
    qtbot.waitUntil(lambda: window.cursor_label.text() == "x 10, y 5")
    level = window.history.document.levels[5, 10]
    assert window.level_label.text() == f"level {level}"


def test_acquire_from_a_photo(qtbot, window, photo_path):
    qtbot.keyClick(window, QtCore.Qt.Key.Key_I, CTRL)
    dialog = window.acquire_dialog
    qtbot.waitExposed(dialog)
    assert dialog.wait()                    # read, quantised and counted in the worker
    assert dialog.path == photo_path and dialog.dpj is not None
    assert dialog.model is not None                 # first a photo model, as `resynth` makes
    qtbot.mouseClick(dialog.auto_scales, LEFT)      # unticked, and 1 scale: one DPJ, the
    type_into(qtbot, dialog.scales, "1")            # thesis's
    type_into(qtbot, dialog.u, "2")
    type_into(qtbot, dialog.v, "2")
    type_into(qtbot, dialog.levels, "5")
    dialog.method.setFocus()
    qtbot.keyClick(dialog.method, QtCore.Qt.Key.Key_Up)     # Lloyd–Max, above colour classes
    qtbot.mouseClick(dialog.wrap, LEFT)
    assert dialog.wait()
    assert dialog.dpj.window == (2, 2) and dialog.dpj.levels == 5
    assert dialog.dpj.meta["quantiser"] == "lloyd" and dialog.dpj.meta["wrap"] is True
    assert "non-zero configurations" in dialog.info.text()
    assert f"{len(dialog.dpj):,}" in dialog.info.text()
    assert not dialog.photo_view.pixmap().isNull() and not dialog.levels_view.pixmap().isNull()
    acquired = dialog.dpj
    qtbot.mouseClick(dialog.ok_button, LEFT)
    assert window.runner.wait(60_000)
    doc = window.history.document
    assert doc.dpj == acquired
    assert doc.num_levels == 5 and doc.levels.max() < 5
    assert isinstance(window.history.actions[-1], Synthesize)
    assert "2×2" in window.synthesis_dock.dpj_label.text()


def test_the_acquisition_dialog_keeps_its_settings_for_next_time(qtbot, window):
    from app.files import settings
    dialog = window.acquire()                       # first: a photo model, as `resynth` makes
    assert dialog.wait() and (dialog.u.value(), dialog.v.value()) == (3, 2)
    assert dialog.method.currentData() == "lab" and dialog.auto_scales.isChecked()
    assert dialog.model is not None and not dialog.scales.isEnabled()
    type_into(qtbot, dialog.levels, "3")
    dialog.method.setCurrentIndex(dialog.method.findData("lloyd"))
    dialog.auto_scales.setChecked(False)            # one DPJ, the thesis's
    dialog.scales.setValue(1)
    dialog.synthesise_now.setChecked(False)
    assert dialog.wait() and dialog.model is None
    qtbot.mouseClick(dialog.ok_button, LEFT)
    assert window.history.document.dpj == dialog.dpj
    again = window.acquire()                        # opened again: as it was left
    assert again.wait()
    assert again.levels.value() == 3 and again.method.currentData() == "lloyd"
    assert not again.auto_scales.isChecked() and again.scales.isEnabled()
    assert not again.synthesise_now.isChecked() and again.model is None
    again.reject()
    store = settings()                              # a settings file edited by hand
    for key, junk in (("levels", "99"), ("u", "three"), ("quantiser", "magic"), ("auto", "maybe")):
        store.setValue(f"acquire/{key}", junk)
    store.sync()
    third = window.acquire()
    assert third.levels.value() == 4 and third.u.value() == 3       # the defaults
    assert third.method.currentData() == "lab"
    assert third.auto_scales.isChecked() and not third.scales.isEnabled()
    assert third.wait() and third.dpj is not None and third.model is not None
    third.reject()


def test_acquire_refuses_an_unreadable_file_in_place(qtbot, window, tmp_path, monkeypatch):
    bad = tmp_path / "not-a-photo.png"
    bad.write_bytes(b"hello")
    dialog = window.acquire()
    monkeypatch.setattr(QtWidgets.QFileDialog, "getOpenFileName", lambda *a, **k: (str(bad), ""))
    qtbot.mouseClick(dialog.browse, LEFT)
    assert dialog.wait()
    assert dialog.dpj is None and not dialog.ok_button.isEnabled()
    assert "not-a-photo" in dialog.info.text()
    dialog.reject()


def test_new_document_dialog(qtbot, window):
    qtbot.keyClick(window, QtCore.Qt.Key.Key_N, CTRL)
    dialog = window.new_dialog
    type_into(qtbot, dialog.width_box, "30")
    type_into(qtbot, dialog.height_box, "20")
    type_into(qtbot, dialog.levels_box, "4")
    qtbot.keyClick(dialog, QtCore.Qt.Key.Key_Return)
    doc = window.history.document
    assert doc.shape == (20, 30) and not doc.levels.any()
    assert len(window.history.actions) == 1
    assert doc.dpj is not None            # the DPJ carries over: Synthesise still works


@pytest.mark.parametrize("answer, closes", [("Cancel", False), ("Discard", True)])
def test_unsaved_changes_prompt_on_close(qtbot, window, monkeypatch, answer, closes):
    window.submit(SetPalette(np.full((4, 3), 50, np.uint8)))
    assert window.is_modified() and window.windowTitle().startswith("Untitled*")
    asked = []
    button = getattr(QtWidgets.QMessageBox.StandardButton, answer)
    monkeypatch.setattr(QtWidgets.QMessageBox, "question",
                        lambda *a, **k: asked.append(a) or button)
    assert window.close() is closes
    assert asked
    assert window.isVisible() is not closes


def test_tabbed_left_docks_show_whole_titles_and_scroll_to_the_last(qtbot, window):
    """Four docks tabbed in the left column at 1280×800: every title whole (scroll arrows
    instead of "Bru…"), and the last tab reached with the arrow and a click raises its dock."""
    window.resize(1280, 800)
    for dock in (window.brush_dock, window.grain_dock):
        dock.show()
    bars = lambda: [b for b in window.findChildren(QtWidgets.QTabBar)
                    if b.isVisible() and b.count() == 4]
    qtbot.waitUntil(lambda: len(bars()) == 1)
    bar = bars()[0]
    assert bar.elideMode() == QtCore.Qt.TextElideMode.ElideNone
    fm = bar.fontMetrics()
    for i in range(bar.count()):
        assert bar.tabRect(i).width() >= fm.horizontalAdvance(bar.tabText(i).replace("&&", "&"))
    last = next(i for i in range(bar.count()) if bar.tabText(i) == "Grain rendering")
    arrows = [b for b in bar.findChildren(QtWidgets.QToolButton) if b.isVisible()]
    right = max(arrows, key=lambda b: b.x()) if arrows else None
    for _ in range(8):                       # scroll until the tab is wholly in view
        if bar.rect().contains(bar.tabRect(last)) or right is None:
            break
        qtbot.mouseClick(right, LEFT)
    assert bar.rect().contains(bar.tabRect(last))
    qtbot.mouseClick(bar, LEFT, pos=bar.tabRect(last).center())
    qtbot.waitUntil(lambda: not window.density_dock.visibleRegion().isEmpty())
    assert window.brush_dock.visibleRegion().isEmpty()


def test_status_bar_shows_a_busy_bar_until_a_task_reports_progress(qtbot, window):
    """A task that computes for a while before its first progress (a first start compiling the
    kernels) shows a busy bar, then the fraction it reports; Cancel stays available."""
    import threading
    go = threading.Event()

    def work(progress, cancel):
        go.wait(10)
        progress(0.25)
        while not cancel():
            threading.Event().wait(0.01)
        return None

    window.runner.run("Working…", work, lambda result: None)
    qtbot.waitUntil(window.progress.isVisible)
    assert window.progress.maximum() == 0 and window.task_label.text() == "Working…"
    go.set()
    qtbot.waitUntil(lambda: window.progress.maximum() == 1000 and window.progress.value() == 250)
    qtbot.mouseClick(window.cancel_button, LEFT)
    assert window.runner.wait(10_000) and not window.progress.isVisible()


def test_zoom_is_shown_only_once_there_is_a_texture(qtbot, window):
    from app.main_window import MainWindow
    from texeditor.recipe.actions import NewCanvas
    from texeditor.recipe.history import History
    empty = MainWindow()
    qtbot.addWidget(empty)
    empty.show()
    qtbot.waitExposed(empty)
    assert empty.zoom_label.text() == "zoom –"
    history = History()
    history.apply(NewCanvas(40, 30, 4))
    empty.set_history(history)
    qtbot.waitUntil(lambda: empty.zoom_label.text().endswith(" %"))
    assert window.zoom_label.text().startswith("zoom ") and window.zoom_label.text() != "zoom –"
    empty.mark_clean()


def test_quit_closes_every_window_each_asking_and_a_cancel_stops_it(qtbot, window, monkeypatch):
    from app.main_window import MainWindow
    from texeditor.recipe.actions import NewCanvas, SetLevels
    from texeditor.recipe.history import History
    Button = QtWidgets.QMessageBox.StandardButton
    second = MainWindow()
    second.show()
    second.set_history(History())
    second.submit(NewCanvas(20, 10, 4))
    second.submit(SetLevels(0, 0, 2, 2, 1))
    window.submit(SetLevels(0, 0, 2, 2, 3))
    answers, asked = [Button.Discard, Button.Cancel], []
    monkeypatch.setattr(QtWidgets.QMessageBox, "question",
                        lambda parent, *a, **k: asked.append(parent) or answers.pop(0))
    assert not window.quit_all()                    # Discard here, Cancel in the second window
    assert asked == [window, second]
    assert not window.isVisible() and second.isVisible()
    assert second.document.levels[0, 0] == 1        # the cancelled one kept its work
    answers.append(Button.Discard)
    second.act_quit.trigger()                       # File ▸ Quit (Ctrl+Q) from the one left
    assert not second.isVisible() and asked == [window, second, second]
    second.deleteLater()


def test_copy_picture_puts_what_is_shown_on_the_clipboard_after_each_edit(qtbot, window):
    from texeditor.export import to_rgb
    from texeditor.recipe.actions import SetLevels

    def clipboard_rgb():
        image = QtWidgets.QApplication.clipboard().image().convertToFormat(
            QtGui.QImage.Format.Format_RGB888)
        h, w = image.height(), image.width()
        return np.frombuffer(image.constBits(), np.uint8).reshape(h, image.bytesPerLine())[
            :, :3 * w].reshape(h, w, 3)
    QtWidgets.QApplication.clipboard().clear()
    qtbot.keyClick(window.canvas, QtCore.Qt.Key.Key_C, CTRL)        # Edit ▸ Copy picture
    doc = window.document
    assert np.array_equal(clipboard_rgb(), to_rgb(doc.levels, doc.palette))
    window.submit(SetLevels(0, 0, 5, 5, (int(doc.levels[0, 0]) + 1) % doc.num_levels))
    window.act_copy_picture.trigger()                               # again, after an edit
    doc = window.document
    assert np.array_equal(clipboard_rgb(), to_rgb(doc.levels, doc.palette))
    assert "Copied the picture (64×48" in window.statusBar().currentMessage()
    edit = window.synthesis_dock.seed.edit                  # a text field keeps Ctrl+C
    edit.setFocus()
    edit.selectAll()
    qtbot.keyClick(edit, QtCore.Qt.Key.Key_C, CTRL)
    assert QtWidgets.QApplication.clipboard().text() == edit.text() == "7"


def test_at_1280_by_800_the_synthesis_and_palette_docks_show_every_control(qtbot, small_dpj):
    """A first start's window at 1280×800: the Synthesis and Palette docks at their natural
    height, so Synthesise and the grey scale's Reset show without scrolling (the closed Plates
    dock, tabbed with Synthesis, once made Synthesis taller, and the History list's eight rows
    squeezed Palette); the history, its eight rows kept, takes the rest. Then a synthesis,
    Plates opened: Plates and Palette whole, the history's eight rows kept (the Optimise
    button's own row above the list left them short); Plates closed: as at first."""
    from app.main_window import MainWindow
    from texeditor.recipe.history import History
    win = MainWindow()
    qtbot.addWidget(win)
    win.resize(1280, 800)
    history = History()
    history.add_dpj(small_dpj)
    win.set_history(history)
    win.show()
    qtbot.waitExposed(win)

    def whole(dock):
        area = dock.widget()
        return (not area.verticalScrollBar().isVisible()
                and area.viewport().height() >= area.widget().sizeHint().height())
    qtbot.waitUntil(lambda: whole(win.synthesis_dock) and whole(win.palette_dock))
    assert win.history_dock.height() >= win.history_dock.minimumSizeHint().height()
    rows = win.history_dock.view.fontMetrics().lineSpacing() + 2
    assert win.history_dock.view.viewport().height() >= 8 * rows
    button = win.synthesis_dock.button
    assert win.synthesis_dock.widget().viewport().rect().contains(
        button.mapTo(win.synthesis_dock.widget().viewport(), button.rect().bottomRight()))
    win.synthesise_from_dock()
    assert win.runner.wait(60_000)
    win.act_plates_dock.trigger()                 # open: tabbed with Synthesis, in front
    qtbot.waitUntil(lambda: not win.plates_dock.visibleRegion().isEmpty())
    qtbot.waitUntil(lambda: whole(win.plates_dock) and whole(win.palette_dock))
    assert win.history_dock.view.viewport().height() >= 8 * rows
    win.plates_dock.close()
    qtbot.wait(50)
    assert whole(win.synthesis_dock) and whole(win.palette_dock)
    win.mark_clean()


def test_a_window_deleted_just_as_its_task_ends_is_deleted_without_an_error(qtbot, small_dpj):
    """A window closed and deleted as its task ends (Quit, or a second window closed): what
    the task's end schedules must not reach its deleted docks — the Grain rendering dock
    refreshed on a timer (QTimer.singleShot with a bound method, which PySide does not cancel
    when the object goes) and met its deleted labels ("Internal C++ object already deleted",
    an exception in the event loop, which fails this test). Twice, then a window that stays
    and synthesises."""
    from app.main_window import MainWindow
    from texeditor.recipe.history import History

    def new_window():
        win = MainWindow()
        history = History()
        history.add_dpj(small_dpj)
        win.set_history(history)
        win.show()
        qtbot.waitExposed(win)
        return win
    for _ in range(2):
        win = new_window()
        win.mark_clean()
        assert win.close()
        win.runner.finished.emit()           # the task's end, as the window goes
        win.deleteLater()
        QtCore.QCoreApplication.sendPostedEvents(None, QtCore.QEvent.Type.DeferredDelete)
        qtbot.wait(100)                      # any timer after the deletion
    win = new_window()
    qtbot.addWidget(win)
    win.synthesise_from_dock()
    done = win.runner.wait(60_000)
    win.mark_clean()                     # closed at the end without a question
    assert done and win.document.levels.size and len(win.history.actions) == 1


def test_docks_squeezed_by_a_small_window_get_their_height_back_when_it_grows(qtbot, window):
    """Shrunk to its minimum, the window squeezes the Synthesis and Palette docks (their
    Synthesise button and Contrast slider scroll out of sight); grown back, they stayed
    squeezed and the History took the room. Now they get their height back; a dock the user
    made taller than it needs is left as it is."""
    from .support import settle
    synth, palette, history = window.synthesis_dock, window.palette_dock, window.history_dock

    def seen():
        settle(window)
        qtbot.wait(50)
        return (not synth.button.visibleRegion().isEmpty(),
                not palette.contrast.visibleRegion().isEmpty())
    assert seen() == (True, True)
    start = (synth.height(), palette.height(), history.height())
    window.resize(1, 1)                                  # as small as its docks allow
    assert seen() != (True, True)
    window.resize(1100, 750)
    assert seen() == (True, True)
    assert (synth.height(), palette.height()) == start[:2] and history.height() >= 200
    window.resizeDocks([synth, palette, history], [start[0] + 150, start[1], start[2] - 150],
                       QtCore.Qt.Orientation.Vertical)
    settle(window)
    taller = synth.height()
    window.resize(1100, 800)
    settle(window)
    qtbot.wait(50)
    assert taller > start[0] + 30                         # the user's taller dock ...
    assert synth.height() >= taller - 4 and not window.errors     # ... kept (but rounding)
