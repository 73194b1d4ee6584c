"""A 1280×800 laptop (issue 16): every dock and dialog usable — the History list keeps its rows
and shows the current step, nothing scrolls sideways, the spot editor leaves the right-hand docks
alone, the Brushes dock shows only with the tools that use it, dialogs fit on the screen — and the
acquisition dialog says what the DPJ's chain means in a user's words."""

import numpy as np
import pytest
from PySide6 import QtCore, QtGui, QtWidgets

from app.widgets import DECORATIONS
from texeditor.recipe.actions import SetPalette

SCREEN = QtCore.QSize(1280, 800)
USABLE = SCREEN - DECORATIONS          # what a window may take once the window manager framed it


@pytest.fixture
def laptop(window, qtbot):
    window.resize(SCREEN)
    qtbot.wait(50)
    return window


def tool(window, name: str):
    return next(t for t in window.tools if t.NAME.split()[0] == name)


def palette_steps(window, n: int) -> None:
    base = np.array(window.history.document.palette)
    for k in range(n):
        p = base.copy()
        p[0] = (k * 7 % 256, 20, 20)
        assert window.submit(SetPalette(p))


def shown_rows(dock) -> int:
    """The steps wholly inside the History list's viewport."""
    viewport = dock.view.viewport().rect()
    return sum(viewport.contains(dock.row_rect(r)) for r in range(dock.model.rowCount()))


def horizontal_bars(widget) -> list:
    return [b for b in widget.findChildren(QtWidgets.QScrollBar)
            if b.orientation() == QtCore.Qt.Orientation.Horizontal and b.isVisible()]


@pytest.mark.parametrize("tool_name", ["Hand", "Spot", "Grain", "Extract"])
def test_history_keeps_eight_rows_and_shows_the_current_step(laptop, qtbot, tool_name):
    laptop.set_tool(tool(laptop, tool_name))
    palette_steps(laptop, 30)
    qtbot.wait(100)
    dock = laptop.history_dock
    assert shown_rows(dock) >= 8
    current = laptop.history.index - 1
    assert dock.view.viewport().rect().contains(dock.row_rect(current))
    # a step with a long form (the synthesis: DPJ, size, seed) keeps the list's rows
    qtbot.mouseClick(dock.view.viewport(), QtCore.Qt.MouseButton.LeftButton,
                     pos=dock.row_rect(0).center())
    qtbot.wait(50)
    assert dock.form.editors and shown_rows(dock) >= 8
    assert not horizontal_bars(dock)


def test_the_step_form_never_scrolls_sideways(laptop, qtbot):
    """Every kind of field fits the dock's width: a narrow dock wraps, it does not scroll."""
    dock = laptop.history_dock
    laptop.resizeDocks([dock], [300], QtCore.Qt.Orientation.Horizontal)
    palette_steps(laptop, 1)
    for step in (0, 1):
        qtbot.mouseClick(dock.view.viewport(), QtCore.Qt.MouseButton.LeftButton,
                         pos=dock.row_rect(step).center())
        qtbot.wait(50)
        assert not horizontal_bars(dock), step
        viewport = dock.form_area.viewport().width()
        assert dock.form.minimumSizeHint().width() <= viewport, step
        for w in dock.form.findChildren(QtWidgets.QWidget):
            if w.isVisible():
                right = w.mapTo(dock.form_area.viewport(), w.rect().topRight()).x()
                assert right <= viewport, (step, w)


def test_brushes_dock_only_with_the_tools_that_use_a_brush(laptop, qtbot):
    brushes, stamps, bank = laptop.brush_dock, laptop.grain_dock, laptop.bank_dock
    for name, brush_shown, stamps_shown in (
            ("Brush", True, False), ("Fill", False, False), ("Spray", True, False),
            ("Extract", False, False), ("Grain", False, True), ("Spot", False, False),
            ("Brush", True, False), ("Translate", False, False), ("Copy", False, False),
            ("Duplicate", False, False), ("Hand", False, False)):
        laptop.set_tool(tool(laptop, name))
        qtbot.wait(20)
        assert brushes.toggleViewAction().isChecked() == brush_shown, name
        assert stamps.toggleViewAction().isChecked() == stamps_shown, name
        if brush_shown:
            assert not brushes.visibleRegion().isEmpty(), name        # its tab is the front one
    assert not bank.visibleRegion().isEmpty()      # the bank's tab came back to the front
    # opened by the user (View ▸ Brushes), it stays open whatever the tool
    brushes.toggleViewAction().trigger()
    laptop.set_tool(tool(laptop, "Brush"))
    laptop.set_tool(tool(laptop, "Fill"))
    assert brushes.toggleViewAction().isChecked()


def test_the_spot_editor_leaves_the_right_docks_their_room(laptop, qtbot):
    right = [laptop.synthesis_dock, laptop.palette_dock, laptop.history_dock]
    before = [d.geometry() for d in right]
    laptop.set_tool(tool(laptop, "Spot"))
    dock = tool(laptop, "Spot").dock
    qtbot.waitUntil(lambda: dock.isVisible() and dock.height() > 200)
    qtbot.wait(50)
    for d, was in zip(right, before):
        assert d.width() >= 300 and d.height() >= was.height() - 2, (d.windowTitle(), was)
    assert dock.geometry().right() < laptop.history_dock.geometry().left()   # under the canvas
    assert not horizontal_bars(dock)                                          # and whole
    assert dock.editor.width() >= dock.editor.minimumSizeHint().width()
    assert shown_rows(laptop.history_dock) >= 8 or laptop.history_dock.model.rowCount() < 8


def open_dialogs(window):
    yield "Acquire", window.acquire()
    yield "New", window.new_document()
    yield "Global operators", window.global_operators()
    yield "Composition", window.open_composition()
    yield "Doubling", window.open_doubling()
    yield "Peano", window.open_peano()
    yield "Grain editor", window.grain_dock.tool.edit()
    window.bank_dock.act_save.trigger()
    yield "Save to bank", next(w for w in QtWidgets.QApplication.topLevelWidgets()
                               if type(w).__name__ == "SaveToBankDialog" and w.isVisible())


def test_every_dialog_fits_a_1280x800_screen(laptop, qtbot):
    for name, dialog in open_dialogs(laptop):
        qtbot.waitExposed(dialog)
        qtbot.wait(30)
        for what, size in (("size", dialog.size()), ("hint", dialog.sizeHint()),
                           ("minimum", dialog.minimumSizeHint())):
            assert size.width() <= USABLE.width() and size.height() <= USABLE.height(), \
                (name, what, size)
        dialog.close()


def test_the_dpj_editor_opens_within_the_screen(laptop, qtbot, monkeypatch):
    from app import dpj_editor
    monkeypatch.setattr(QtGui.QScreen, "availableGeometry",
                        lambda self: QtCore.QRect(QtCore.QPoint(0, 0), SCREEN))
    editor = dpj_editor.open_editor(laptop)
    qtbot.waitExposed(editor)
    qtbot.wait(50)
    assert editor.width() <= USABLE.width() and editor.height() <= USABLE.height()
    minimum = editor.minimumSizeHint()
    assert minimum.width() <= USABLE.width() and minimum.height() <= USABLE.height()
    for title in ("Checks", "Live preview", "Configuration painter"):    # no dock squashed
        assert not editor.docks[title].visibleRegion().isEmpty(), title
    preview = editor.preview.use_button                      # the preview's buttons in view
    assert preview.visibleRegion().boundingRect().size() == preview.size()
    assert editor.preview.preview.wait() and editor.analysis.wait()   # no job outlives the test


def test_the_acquire_dialog_explains_the_chain_with_a_remedy(laptop, qtbot):
    from types import SimpleNamespace

    from app.acquire_dialog import chain_advice
    dead_ends = SimpleNamespace(states=1570, closed_classes=0, transient_states=1570,
                                dead_ends=8967, period=0)
    text, detail, warn = chain_advice(dead_ends, wrap=False)
    assert warn and "dead ends" in text and "Wrap around the edges" in text
    assert "fewer levels" in text and "smaller window" in text
    assert "closed class" not in text and "transient" not in text       # the jargon is detail
    assert "closed class" in detail and "transient" in detail and "1,570" in detail
    assert "Wrap" not in chain_advice(dead_ends, wrap=True)[0]            # already on
    families = SimpleNamespace(states=40, closed_classes=3, transient_states=2, dead_ends=0,
                               period=1)
    assert "3 separate families" in chain_advice(families, wrap=True)[0]
    fine = SimpleNamespace(states=40, closed_classes=1, transient_states=2, dead_ends=3, period=1)
    assert not chain_advice(fine, wrap=True)[2]
    beat = SimpleNamespace(states=4, closed_classes=1, transient_states=0, dead_ends=0, period=2)
    text, detail, warn = chain_advice(beat, wrap=True)
    assert warn and "cycle through 2 families" in text and "period 2" in detail

    dialog = laptop.acquire()
    assert dialog.wait()
    dialog.auto_scales.setChecked(False)              # one DPJ: its chain is explained
    dialog.scales.setValue(1)
    assert dialog.wait()
    text = dialog.info.text()
    assert "non-zero configurations" in text and "transient" not in text
    assert "closed class" in dialog.info.toolTip()
    dialog.reject()


def test_the_acquire_dialog_grown_for_a_photo_models_scales_stays_on_the_screen(laptop, qtbot):
    """Ticking "auto" scales grows the acquisition dialog by the scales' previews and the
    model's report; grown downwards, its Acquire and Cancel went below a 1280×800 screen's
    bottom. It moves up to stay on the screen; on a screen shorter than it, its big previews
    shrink. Then Acquire: a texture drawn from the photo model."""
    dialog = laptop.acquire()
    qtbot.waitExposed(dialog)
    assert dialog.wait()
    dialog.auto_scales.setChecked(False)             # one DPJ: no scales to show
    dialog.scales.setValue(1)
    assert dialog.wait()
    dialog.resize(dialog.width(), dialog.minimumSizeHint().height())
    dialog.move(dialog.x(), 300)                     # where a window manager may have put it
    dialog.auto_scales.setChecked(True)
    assert dialog.wait()
    qtbot.waitUntil(lambda: dialog.scale_strip.isVisible())
    room = dialog.screen().availableGeometry()
    qtbot.waitUntil(lambda: room.contains(dialog.frameGeometry()), timeout=3000)
    ok = dialog.findChild(QtWidgets.QDialogButtonBox) or dialog
    assert room.contains(ok.mapToGlobal(ok.rect().bottomRight()))
    dialog.accept()
    qtbot.waitUntil(lambda: type(laptop.history.actions[-1]).__name__ == "SynthesizeScales",
                    timeout=60_000)
    assert laptop.runner.wait(60_000) and len(laptop.synthesis_dock.scale_dpjs) > 1
    laptop.mark_clean()
