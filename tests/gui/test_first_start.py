"""A first start (issue 16): the window shows the start entry's stored picture while the numba
kernels compile in the background; steps that need them wait in the worker, then work."""

import threading

import numpy as np
import pytest

from texeditor.bank import store as bk
from texeditor import warmup
from texeditor.recipe.actions import Synthesize
from texeditor.bank.store import Bank, picture_bytes

from .support import cell_pos, click


@pytest.fixture
def slow_compile(monkeypatch, tmp_path):
    """A fresh bank, and a warm-up whose compile waits for ``gate`` (as a long first compile)."""
    monkeypatch.setenv("TEXEDITOR_BANK", str(tmp_path / "first.sqlite"))
    assert warmup.wait(timeout=120)
    warmup._reset()
    gate = threading.Event()
    monkeypatch.setattr(warmup, "_compile", lambda: gate.wait(120))
    yield gate
    gate.set()
    assert warmup.wait(timeout=30)


def test_the_start_entry_shows_before_the_kernels_are_ready(window, qtbot, slow_compile,
                                                            monkeypatch):
    from texeditor.photo import PhotoModel, document_tone
    gate = slow_compile
    monkeypatch.setattr(Bank, "open", lambda *a, **k: pytest.fail("the start entry was replayed"))
    monkeypatch.setattr(Bank, "render", lambda *a, **k: pytest.fail("a built-in was replayed"))
    toned_on, rendering = [], PhotoModel.rendering
    monkeypatch.setattr(PhotoModel, "rendering", lambda self, *a, **k: (
        toned_on.append(threading.current_thread() is threading.main_thread()),
        rendering(self, *a, **k))[1])
    window.start_default()
    dock = window.bank_dock
    qtbot.waitUntil(lambda: dock.opened is not None, timeout=10_000)
    assert warmup.pending()
    entry = dock.bank.get(dock.opened[0])
    picture = dock.bank.stored_picture(entry)
    assert entry.name == "Gravel with tone" and picture is not None
    assert np.array_equal(window.document.levels, picture[0])
    assert np.array_equal(window.canvas.levels, picture[0])
    assert window.document.result_hash() == entry.sha256
    assert [a.TYPE for a in window.history.actions] == ["synthesize_scales"]
    assert "stored picture" in window.statusBar().currentMessage()
    # its photo's tone is drawn off the GUI thread while the kernels may still compile
    qtbot.waitUntil(lambda: window.canvas.picture is not None, timeout=20_000)
    assert toned_on and not any(toned_on) and warmup.pending("tone")
    assert np.array_equal(window.canvas.picture[..., 0], document_tone(window.document))
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=20_000)   # thumbnails, no replay
    assert dock.bank.pending() == [] and warmup.pending()
    qtbot.waitUntil(lambda: dock.engine_note.isVisible(), timeout=5000)
    assert "first start only" in dock.engine_note.text()

    # a step that needs the kernels waits in the worker, with the busy bar, and is not lost
    ref = window.history.actions[0].dpjs[0]         # the coarsest scale: a plain DPJ
    assert not window.submit(Synthesize(ref, 40, 30, 5))
    assert window.runner.busy and "synthesis engine" in window.task_label.text()
    assert window.progress.isVisible() and window.history.index == 1
    qtbot.wait(200)
    assert window.runner.busy and window.history.index == 1            # still waiting
    gate.set()
    qtbot.waitUntil(lambda: window.history.index == 2, timeout=20_000)
    assert window.document.shape == (30, 40)
    qtbot.waitUntil(lambda: not dock.engine_note.isVisible() and not window.runner.busy,
                    timeout=20_000)          # the note goes; the start entry is checked
    assert dock._to_confirm is None and not window.errors

    # synthesis works; undo goes back to the stored picture
    window.synthesise(64, 48, 9)
    assert window.runner.wait(60_000) and window.document.shape == (48, 64)
    assert window.history.actions[-1].TYPE == "synthesize_scales"
    window.undo()
    window.undo()
    assert np.array_equal(window.document.levels, picture[0]) and window.history.index == 1
    assert not window.errors


def test_a_forged_picture_is_refused_and_the_entry_replayed(window, qtbot, tmp_path,
                                                            monkeypatch):
    """A picture that is not the recorded texture never shows: the entry is replayed."""
    monkeypatch.setenv("TEXEDITOR_BANK", str(tmp_path / "forged.sqlite"))
    forged = tmp_path / "pictures"
    forged.mkdir()
    for path in bk.PICTURES_DIR.glob("*.npz"):
        with np.load(path, allow_pickle=False) as z:
            levels, palette = z["levels"].copy(), z["palette"]
        levels[0, 0] = (int(levels[0, 0]) + 1) % len(palette)
        (forged / path.name).write_bytes(picture_bytes(levels, palette))
    monkeypatch.setattr(bk, "PICTURES_DIR", forged)
    opened, real_open = [], Bank.open
    monkeypatch.setattr(Bank, "open", lambda self, i, **k: opened.append(i) or real_open(self, i, **k))
    window.start_default()
    assert window.runner.wait(120_000)
    dock = window.bank_dock
    entry = dock.bank.get(dock.opened[0])
    assert entry.name == "Gravel with tone" and window.document.result_hash() == entry.sha256
    assert dock.bank.pending() == [] and not window.errors        # replayed, not refused
    assert opened == [entry.id] and dock._to_confirm is None


def test_the_start_entry_is_toned_at_once_from_its_stored_tone(window, qtbot, slow_compile,
                                                               monkeypatch):
    """Before the tone's kernels are ready (its rendering held here), the built-in shows its
    stored tone picture, not the palette's greys; the tone drawn later is the same pixels."""
    from texeditor.photo import PhotoModel, document_tone
    release, rendering = threading.Event(), PhotoModel.rendering

    def held(self, *args, **kwargs):
        assert release.wait(60)
        return rendering(self, *args, **kwargs)
    monkeypatch.setattr(PhotoModel, "rendering", held)
    window.start_default()
    dock = window.bank_dock
    qtbot.waitUntil(lambda: dock.opened is not None, timeout=10_000)
    stored = dock.bank.stored_tone(dock.bank.get(dock.opened[0]))
    assert stored is not None and window._tone_cache is None      # nothing rendered yet
    assert window.canvas.picture is not None
    assert np.array_equal(window.canvas.picture[..., 0], stored)
    release.set()
    slow_compile.set()
    qtbot.waitUntil(lambda: window._tone_cache is not None, timeout=60_000)
    assert np.array_equal(window.canvas.picture[..., 0], stored)
    assert np.array_equal(stored, document_tone(window.document))
    qtbot.waitUntil(lambda: not window.runner.busy, timeout=60_000)
    window.submit(Synthesize(window.history.actions[0].dpjs[0], 40, 30, 5))    # levels of its
    assert window.runner.wait(60_000) and window.document.shape == (30, 40)   # own: no stored
    assert window.canvas.picture is None or window.canvas.picture.shape[:2] == (30, 40)


def test_commands_before_the_first_texture_is_there_say_to_wait(qtbot, small_dpj):
    """A window whose first texture is still opening in the worker (a first start, or a
    crash's journals being read) has no document yet: Undo, Redo, Synthesise, an export, a
    model, the grain editor, the relief's height map raised "'NoneType' object has no
    attribute …" in the event loop (an exception, which fails this test). Now Undo and Redo
    are greyed (until the texture is there) and the others say in the status bar to wait,
    changing nothing; the Extract tool chosen meanwhile works once the texture
    is there: it follows the document (a synthesis, undo)."""
    from PySide6 import QtCore
    from app.main_window import MainWindow
    from texeditor.recipe.history import History
    win = MainWindow()
    qtbot.addWidget(win)
    win.resize(1280, 800)
    win.show()
    qtbot.waitExposed(win)
    assert win.history is None
    started = threading.Event()               # Esc cancels work even before the texture
    win.runner.run("Opening…", lambda progress, cancel: (started.set(), cancel_wait(cancel)),
                   lambda _r: None)
    assert started.wait(10) and win.act_cancel.isEnabled()
    win.act_cancel.trigger()
    assert win.runner.wait(10_000) and "still opening" not in win.statusBar().currentMessage()
    assert not win.act_undo.isEnabled() and not win.act_redo.isEnabled()   # nothing to undo
    for action in (win.act_synth, win.act_export, win.act_global):
        win.statusBar().clearMessage()
        action.trigger()                      # its menu entry, toolbar button or shortcut
        assert "still opening" in win.statusBar().currentMessage(), action.text()
        assert win.history is None and not win.runner.busy
    models = [a for a in win.findChildren(QtCore.QObject) if a.objectName() == "act_texton"]
    models[0].trigger()
    assert "still opening" in win.statusBar().currentMessage()
    assert win.relief_dock.export_height() is False
    extract = next(t for t in win.tools if t.NAME.startswith("Extract"))
    win.set_tool(extract)
    assert win.grain_dock.tool.edit() is None
    history = History()
    history.add_dpj(small_dpj)
    win.set_history(history)
    win.synthesis_dock.width_box.setValue(48)
    win.synthesis_dock.height_box.setValue(40)
    win.act_synth.trigger()
    assert win.runner.wait(60_000) and win.document.shape == (40, 48)
    assert not win.act_undo.isEnabled()       # the first step is the base texture
    assert win.canvas.tool is extract and "No selection" in extract.status.text()
    win.canvas.fit()
    click(win.canvas.viewport(), cell_pos(win.canvas, 10, 10))     # it follows the document
    qtbot.waitUntil(lambda: "No selection" not in extract.status.text())
    win.act_undo.trigger()
    assert not win.runner.busy
    first = win.history                       # another texture opened with the tool chosen:
    second = History()                        # the tool follows the new document, and
    second.add_dpj(small_dpj)                 # nothing listens to the old one any more
    win.set_history(second)
    win.act_synth.trigger()
    assert win.runner.wait(60_000) and not first._subscribers
    assert len(second._subscribers) == 2      # the window's and the tool's
    click(win.canvas.viewport(), cell_pos(win.canvas, 20, 20))
    qtbot.waitUntil(lambda: "No selection" not in extract.status.text())
    win.mark_clean()


def cancel_wait(cancel) -> None:
    """Work that runs until it is cancelled (10 s at most)."""
    import time
    deadline = time.monotonic() + 10
    while not cancel() and time.monotonic() < deadline:
        time.sleep(0.005)
