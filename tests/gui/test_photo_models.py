"""Photo models in the window, as sessions: acquire one with several scales (or open a format-2
`.dpj`), synthesise from its scales in the Synthesis dock, look at it with and without the
photo's tone, paint, undo to the start and redo, edit a scale's DPJ, save and reopen; asserts are
on the document, the log and the picture on the canvas."""

import imageio.v3 as iio
import numpy as np
from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.markov.dpj import DPJ
from texeditor.markov.levels import load_image
from texeditor.photo import PhotoModel, acquire_model, tone
from texeditor.recipe.actions import SynthesizeScales

from tests.support import ROOT

from .support import (edit_and_apply, fill_a_cell, press_key, recipe,
                      synthesise, type_into, undo_to_start)

CTRL = QtCore.Qt.KeyboardModifier.ControlModifier
SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier
LEFT = QtCore.Qt.MouseButton.LeftButton
Key = QtCore.Qt.Key


def rgb(picture):
    return np.repeat(picture[..., None], 3, axis=2) if picture.ndim == 2 else picture


def tone_of(window, seed):
    """What the canvas must show with tone on: the document's levels in the photo's tone."""
    return rgb(window.photo_model.render(window.document.levels, seed=seed))


def palette_shown(window):
    """With tone off the canvas draws each level in its palette colour."""
    doc = window.document
    assert window.canvas.picture is None
    h, w = doc.shape
    for x, y in ((0, 0), (w - 1, h - 1), (w // 2, h // 3)):
        level = doc.levels[y, x]
        assert window.canvas.displayed_colour(x, y) == tuple(int(c) for c in doc.palette[level])


def redo_to_end(qtbot, window):
    while window.history.can_redo:
        qtbot.keyClick(window, Key.Key_Z, CTRL | SHIFT)


def test_acquire_scales_synthesise_tone_undo_edit_save_reopen(qtbot, window, tmp_path):
    start = window.document.levels.copy()
    start_seed = window.history.actions[0].seed

    # File ▸ Acquire with 3 scales, a 3×2 window, tone on
    qtbot.keyClick(window, Key.Key_I, CTRL)
    dialog = window.acquire_dialog
    assert dialog.wait() and dialog.model is not None      # first a photo model, auto scales
    qtbot.mouseClick(dialog.auto_scales, LEFT)             # unticked, and 1 scale: a DPJ
    type_into(qtbot, dialog.scales, "1")
    assert dialog.wait() and dialog.model is None
    assert not dialog.tone.isEnabled() and dialog.scale_strip.isHidden()
    type_into(qtbot, dialog.v, "2")
    type_into(qtbot, dialog.scales, "3")
    assert dialog.wait()
    model = dialog.model
    assert isinstance(model, PhotoModel) and model.scales.scales == 3 and model.tone is not None
    assert dialog.tone.isEnabled() and not dialog.wrap.isEnabled()
    captions = [dialog.findChild(QtWidgets.QLabel, f"scale{k}caption").text() for k in range(3)]
    assert captions == ["1/4", "1/2", "1/1"] and dialog.scale_strip.isVisibleTo(dialog)
    h, w = dialog.scale_levels[-1].shape
    assert [lv.shape for lv in dialog.scale_levels] == [(h // 4, w // 4), (h // 2, w // 2), (h, w)]
    assert "3 scales" in dialog.info.text() and dialog.ok_button.isEnabled()
    assert "1/2: 3×2, G = 4 given 2 and the row's phase" in dialog.info.text()
    assert "1/1: 3×2, G = 4 given 4," in dialog.info.text()
    dialog.synthesise_now.setChecked(False)
    qtbot.mouseClick(dialog.ok_button, LEFT)
    window.activateWindow()                # the window manager's part, offscreen
    qtbot.waitUntil(lambda: QtWidgets.QApplication.activeWindow() is window, timeout=3000)

    doc = window.document
    names = [d.meta["name"] for d in model.scales.dpjs]
    stem = dialog.path.stem
    assert names == [f"{stem} scale {k}/3" for k in (1, 2, 3)]
    refs = tuple(d.ref for d in model.scales.dpjs)
    assert all(r in doc.dpjs for r in refs) and doc.dpj_ref == refs[-1]
    finest = doc.dpjs[refs[-1]]
    assert finest.window == (3, 2) and finest.levels == 16
    assert window.photo_model is model and window.scale_refs() == refs
    dock = window.synthesis_dock
    assert dock.scales_box.isEnabled() and dock.scale_count() == 3
    assert "3 scales" in dock.dpj_label.text()
    assert np.array_equal(doc.levels, start)           # adding DPJs adds no step
    assert np.array_equal(window.canvas.picture, tone_of(window, start_seed))

    # Synthesise 128×128 on 3 scales from the dock
    synthesise(qtbot, window, 128, 128, 5)
    doc = window.document
    step = window.history.actions[-1]
    assert step.TYPE == "synthesize_scales" and step.dpjs == refs and step.seed == 5
    assert doc.shape == (128, 128) and doc.num_levels == 4 and int(doc.levels.max()) < 4
    expected = SynthesizeScales(refs, 128, 128, 5).render_result(
        [doc.dpjs[r] for r in refs]).levels
    assert np.array_equal(doc.levels, expected)
    assert np.array_equal(doc.palette, model.palette)
    assert np.array_equal(window.canvas.levels, doc.levels)
    toned = tone_of(window, 5)
    assert np.array_equal(window.canvas.picture, toned)
    after_synthesis = doc.levels.copy()

    # tone off with its key (with the focus off the seed field typed last), on again with the
    # dock's box
    window.canvas.setFocus()
    press_key(window, Key.Key_T)
    assert not window.act_tone.isChecked() and not dock.tone_box.isChecked()
    palette_shown(window)
    qtbot.mouseClick(dock.tone_box, LEFT)
    assert window.act_tone.isChecked()
    assert np.array_equal(window.canvas.picture, toned)

    # a fill: the tone picture follows the document
    fill_a_cell(qtbot, window)
    filled = window.document.levels.copy()
    assert not np.array_equal(filled, after_synthesis)
    assert np.array_equal(window.canvas.picture, tone_of(window, 5))

    # undo to the start, redo to the end
    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start)
    assert window.document.shape == (48, 64) and dock.width_box.value() == 64
    assert np.array_equal(window.canvas.picture, tone_of(window, start_seed))
    redo_to_end(qtbot, window)
    assert np.array_equal(window.document.levels, filled)
    assert (dock.width_box.value(), dock.seed.value(), dock.scale_count()) == (128, 5, 3)
    assert np.array_equal(window.canvas.picture, tone_of(window, 5))

    # again with another seed on 2 scales: the coarser scales' texture
    synthesise(qtbot, window, 128, 128, 6, scales=2)
    step = window.history.actions[-1]
    assert step.TYPE == "synthesize_scales" and step.dpjs == refs[:2] and step.seed == 6
    assert window.document.shape == (128, 128) and window.document.num_levels == 4
    assert window.document.dpj_ref == refs[1]
    assert not np.array_equal(window.document.levels, filled)
    assert window.scale_refs() == refs and dock.scale_count() == 2
    assert np.array_equal(window.canvas.picture, tone_of(window, 6))
    qtbot.keyClick(window, Key.Key_Z, CTRL)                   # the dock shows the step's values
    assert (dock.seed.value(), dock.scale_count()) == (5, 3)
    qtbot.keyClick(window, Key.Key_Z, CTRL | SHIFT)
    assert (dock.seed.value(), dock.scale_count()) == (6, 2)

    # Edit DPJ opens the current scale's DPJ: composite levels (4 given 2 parent levels and
    # the row's phase), its name in the title
    qtbot.keyClick(window, Key.Key_J, CTRL)
    editor = window.dpj_editor
    assert editor.dpj is window.document.dpj and editor.dpj.levels == 16
    assert editor.dpj.window == (3, 2) and "scale 2/3" in editor.windowTitle()
    assert editor.report is not None or editor.checked_report() is not None
    editor.close()
    window.activateWindow()
    qtbot.waitUntil(lambda: QtWidgets.QApplication.activeWindow() is window, timeout=3000)

    # export shows what is on screen; save, reopen: the scales travel in the file
    png = tmp_path / "toned.png"
    assert window.export_to(png)
    assert np.array_equal(rgb(iio.imread(png)), window.canvas.picture)
    levels = window.document.levels.copy()
    path = tmp_path / "scales.texture"
    assert window.save_to(path)
    window.open_file(path)
    assert window.runner.wait(120_000) and not window.errors
    doc = window.document
    assert np.array_equal(doc.levels, levels)
    assert [a.TYPE for a in window.history.actions][-3:] == ["synthesize_scales", "fill",
                                                             "synthesize_scales"]
    assert all(r in doc.dpjs for r in refs) and window.scale_refs() == refs
    assert window.photo_model is model                  # its scales are in the texture
    assert np.array_equal(window.canvas.picture, tone_of(window, 6))
    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start)
    redo_to_end(qtbot, window)
    assert np.array_equal(window.document.levels, levels)


def test_open_a_photo_model_file_then_a_single_dpj(qtbot, window, photo_path, tmp_path,
                                                  monkeypatch):
    start = window.document.levels.copy()
    model_path = tmp_path / "brick-model.dpj"
    acquire_model(load_image(photo_path), scales=3).save(model_path)
    chosen = [str(model_path)]
    monkeypatch.setattr(QtWidgets.QFileDialog, "getOpenFileName",
                        lambda *a, **k: (chosen[0], ""))

    # File ▸ Open DPJ or photo model… on a format-2 file
    qtbot.keyClick(window, Key.Key_O, CTRL | SHIFT)
    model = window.photo_model
    assert isinstance(model, PhotoModel) and model.scales.scales == 3 and not window.errors
    refs = window.scale_refs()
    assert len(refs) == 3 and window.document.dpj_ref == refs[-1]
    assert [window.document.dpjs[r].meta["name"] for r in refs] == \
        [f"brick-model scale {k}/3" for k in (1, 2, 3)]
    assert window.act_tone.isEnabled()

    synthesise(qtbot, window, 96, 80, 3)
    step = window.history.actions[-1]
    assert step.TYPE == "synthesize_scales" and step.dpjs == refs
    assert window.document.shape == (80, 96)
    assert np.array_equal(window.canvas.picture, tone_of(window, 3))
    window.act_tone.trigger()                                # View ▸ Photographic tone
    palette_shown(window)
    window.act_tone.trigger()
    assert np.array_equal(window.canvas.picture, tone_of(window, 3))
    made = window.document.levels.copy()

    # the step's seed edited in the History dock: replayed in the worker, undone with Ctrl+Z
    before = edit_and_apply(qtbot, window, 1, "seed", "31")
    step = window.history.actions[1]
    assert step.TYPE == "synthesize_scales" and step.seed == 31 and step.dpjs == refs
    expected = SynthesizeScales(refs, 96, 80, 31).render_result(
        [window.document.dpjs[r] for r in refs]).levels
    assert np.array_equal(window.document.levels, expected)
    assert np.array_equal(window.canvas.picture, tone_of(window, 31))
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert recipe(window) == before and np.array_equal(window.document.levels, made)
    assert np.array_equal(window.canvas.picture, tone_of(window, 3))

    # the DPJ editor's own Open says where a photo model opens
    qtbot.keyClick(window, Key.Key_J, CTRL)
    editor = window.dpj_editor
    assert not editor.open_file(model_path)
    assert window.errors and "photo model" in window.errors[-1][1]
    window.errors.clear()
    editor.close()
    window.activateWindow()
    qtbot.waitUntil(lambda: QtWidgets.QApplication.activeWindow() is window, timeout=3000)

    # a format-1 file: the current DPJ, no scales; its synthesis is a plain one, and its 8
    # levels are more than the model's 4: shown with the palette
    single = tmp_path / "grass.dpj"
    DPJ.load(ROOT / "resources" / "dpj" / "grass-2x2-g8.dpj").save(single)
    chosen[0] = str(single)
    window.act_open_dpj.trigger()
    assert window.scale_refs() == () and not window.synthesis_dock.scales_box.isEnabled()
    assert window.document.dpj.levels == 8 and window.document.dpj.window == (2, 2)
    assert "grass" in window.synthesis_dock.dpj_label.text()
    synthesise(qtbot, window, 40, 30, 4)
    assert window.history.actions[-1].TYPE == "synthesize"
    assert window.document.num_levels == 8
    assert not window.act_tone.isEnabled() and not window.synthesis_dock.tone_box.isEnabled()
    palette_shown(window)

    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start)
    redo_to_end(qtbot, window)
    assert window.document.shape == (30, 40)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.document.levels, made)
    # 4 levels again: the photo's tone is back, and the dock offers the scales exactly when the
    # current DPJ (which the history restores) is one of them
    assert np.array_equal(window.canvas.picture, tone_of(window, 3))
    dock = window.synthesis_dock
    scaled = window.document.dpj_ref in refs
    assert window.scale_refs() == (refs if scaled else ())
    assert dock.scales_box.isEnabled() == scaled and dock.scale_count() == (3 if scaled else 1)


def test_a_toned_texture_reopened_in_a_fresh_session_shows_its_tone(qtbot, window, photo_path,
                                                                    tmp_path, monkeypatch):
    """The tone travels in the `.texture`: reopened with no photo model at hand (another
    texture opened between, which lets the model go), the canvas still shows the photo's
    greys, toggles to the palette and back, and undo/redo walk the reopened log."""
    from texeditor.photo import document_tone
    other = tmp_path / "other.texture"
    assert window.save_to(other)
    model_path = tmp_path / "brick-model.dpj"
    acquire_model(load_image(photo_path), scales=2).save(model_path)
    monkeypatch.setattr(QtWidgets.QFileDialog, "getOpenFileName",
                        lambda *a, **k: (str(model_path), ""))
    qtbot.keyClick(window, Key.Key_O, CTRL | SHIFT)
    synthesise(qtbot, window, 72, 56, 9)
    step = window.history.actions[-1]
    assert step.TYPE == "synthesize_scales" and step.tone_photo in window.document.exemplars
    toned = window.canvas.picture.copy()
    assert np.array_equal(toned, tone_of(window, 9))
    path = tmp_path / "toned.texture"
    assert window.save_to(path)

    window.open_file(other)                                   # the model is let go
    assert window.runner.wait(60_000) and not window.errors
    assert window.photo_model is None and window.canvas.picture is None
    window.open_file(path)
    assert window.runner.wait(60_000) and not window.errors
    assert window.photo_model is None and window.act_tone.isEnabled()
    assert np.array_equal(window.canvas.picture, toned)
    assert np.array_equal(toned, rgb(document_tone(window.document)))
    window.act_copy_picture.trigger()                         # Edit ▸ Copy picture: the tone
    copied = QtWidgets.QApplication.clipboard().image().convertToFormat(
        QtGui.QImage.Format.Format_RGB888)
    h, w = toned.shape[:2]
    assert np.array_equal(np.frombuffer(copied.constBits(), np.uint8).reshape(
        h, copied.bytesPerLine())[:, :3 * w].reshape(h, w, 3), toned)
    window.act_tone.trigger()
    palette_shown(window)
    window.act_tone.trigger()
    assert np.array_equal(window.canvas.picture, toned)

    fill_a_cell(qtbot, window)                                # a step after: tone follows
    assert not np.array_equal(window.canvas.picture, toned)
    undo_to_start(qtbot, window)
    redo_to_end(qtbot, window)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.canvas.picture, toned)


def test_a_new_seed_from_a_reopened_toned_texture_keeps_its_tone(qtbot, window):
    """The built-in *Brick with tone* opened as a file (no photo model attached): a new seed
    from the Synthesis dock, twice, then a tileable one, each names the tone its first step
    named and shows it (it came out in the palette's four greys before); a fill after it
    follows the tone; undo to the start shows the opened texture again, redo the last."""
    from texeditor.bank.store import BUILTIN_DIR
    from texeditor.photo import document_tone
    window.open_file(BUILTIN_DIR / "06-brick-with-tone.texture")
    assert window.runner.wait(60_000) and not window.errors
    assert window.photo_model is None
    first = window.history.actions[0]
    opened = window.canvas.picture.copy()
    assert first.tone_photo is not None and np.array_equal(opened, rgb(document_tone(
        window.document)))
    for seed, tile in ((41, False), (42, False), (43, True)):
        if tile != window.synthesis_dock.tileable():
            qtbot.mouseClick(window.synthesis_dock.tileable_box, LEFT)
        synthesise(qtbot, window, 96, 80, seed)
        step = window.history.actions[-1]
        assert (step.TYPE, step.seed, step.tileable) == ("synthesize_scales", seed, tile)
        assert (step.tone_photo, step.tone_levels) == (first.tone_photo, first.tone_levels)
        assert window.act_tone.isEnabled() and window.canvas.picture is not None
        assert np.array_equal(window.canvas.picture, rgb(document_tone(window.document)))
        assert len(np.unique(window.canvas.picture)) > 4 * window.document.num_levels
    last = window.canvas.picture.copy()
    fill_a_cell(qtbot, window)
    assert np.array_equal(window.canvas.picture, rgb(document_tone(window.document)))
    undo_to_start(qtbot, window)
    assert np.array_equal(window.canvas.picture, opened)
    redo_to_end(qtbot, window)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.canvas.picture, last)


def test_a_large_tone_is_drawn_in_the_background_and_each_edit_shows_at_once(
        qtbot, window, photo_path, monkeypatch, tmp_path):
    """A picture of a million points or more has its tone drawn on a thread: after an edit
    the canvas shows at once the last tone with the changed points in their palette colours,
    then the new tone; edits made meanwhile are drawn next, undo and closing stay safe."""
    import threading
    window.attach_model(acquire_model(load_image(photo_path), scales=2))
    start = window.document.levels.copy()
    start_seed = window.history.actions[0].seed
    synthesise(qtbot, window, 160, 120, 4)
    assert np.array_equal(window.canvas.picture, tone_of(window, 4))   # small: drawn at once

    gate, real = threading.Event(), PhotoModel.rendering
    drawn_on = []

    def gated(self, *args, **kwargs):
        if threading.current_thread() is not threading.main_thread():
            drawn_on.append(threading.current_thread().name)
            assert gate.wait(30)
        return real(self, *args, **kwargs)
    monkeypatch.setattr(PhotoModel, "rendering", gated)
    window.TONE_IN_BACKGROUND = 0                    # every picture counts as large

    def meanwhile(before_levels, before_picture):
        doc = window.document
        changed = doc.levels != before_levels
        assert changed.any()
        picture = window.canvas.picture
        assert np.array_equal(picture[~changed], before_picture[~changed])
        assert np.array_equal(picture[changed], doc.palette[doc.levels[changed]])

    toned_levels, toned = window.document.levels.copy(), window.canvas.picture.copy()
    fill_a_cell(qtbot, window)
    meanwhile(toned_levels, toned)                   # the tone is held at the gate
    fill_a_cell(qtbot, window)                       # a second edit while it is drawn
    meanwhile(toned_levels, toned)
    assert drawn_on == ["tone"]                      # one drawing at a time
    gate.set()
    qtbot.waitUntil(lambda: np.array_equal(window.canvas.picture, tone_of(window, 4)),
                    timeout=30_000)
    assert len(drawn_on) == 2                        # the second edit's tone came next
    filled = window.document.levels.copy()

    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start)
    qtbot.waitUntil(lambda: np.array_equal(window.canvas.picture, tone_of(window, start_seed)),
                    timeout=30_000)
    redo_to_end(qtbot, window)
    assert np.array_equal(window.document.levels, filled)
    qtbot.waitUntil(lambda: np.array_equal(window.canvas.picture, tone_of(window, 4)),
                    timeout=30_000)

    # an export while the tone is drawn writes the tone, not the picture shown meanwhile
    gate.clear()
    fill_a_cell(qtbot, window)
    png = tmp_path / "exported-meanwhile.png"
    assert window.export_to(png)
    assert np.array_equal(rgb(iio.imread(png)), tone_of(window, 4))
    gate.set()
    qtbot.waitUntil(lambda: not window._tone_drawing, timeout=30_000)
    gate.clear()
    fill_a_cell(qtbot, window)                       # closed with a tone being drawn
    window.mark_clean()
    window.close()
    gate.set()
    qtbot.waitUntil(lambda: not window._tone_drawing, timeout=30_000)
    assert not window.errors


def synthesised_twice(qtbot, window, photo, scales: int, seeds):
    """A model of ``photo`` attached, then two 160×120 syntheses (``seeds``) from the Synthesis
    dock: (the model, the canvas before them, the last one's levels — checked against the
    model's own — and the index of its step)."""
    model = acquire_model(photo, scales=scales)
    window.attach_model(model)
    start = window.document.levels.copy()
    for seed in seeds:
        synthesise(qtbot, window, 160, 120, seed)
    step = window.history.actions[-1]
    new = window.document.levels.copy()
    assert step.seed == seeds[-1] and np.array_equal(new, model.synthesize(
        (120, 160), seed=seeds[-1], tone=False).levels)
    return model, start, new, len(window.history.actions) - 1


def edited_draw(qtbot, window, model, step: int, name: str, value):
    """Type ``value`` for step ``step``'s parameter ``name`` in the History form, Apply &
    replay: the canvas holds what the model draws with that value (returned)."""
    edit_and_apply(qtbot, window, step, name, str(value))
    done = window.history.actions[-1]
    assert not window.errors and getattr(done, name) == value
    drawn = model.synthesize((done.height, done.width), seed=done.seed, tone=False,
                             **{name: value}).levels
    assert np.array_equal(window.document.levels, drawn)
    return drawn


def test_the_coarsest_row_limit_is_edited_in_the_history_form(qtbot, window):
    """From a small gravel crop (its coarsest law dead-ends nearly everywhere), synthesise twice,
    then set the last step's coarsest row limit to 16 (no limit, as steps before version 13)
    and Apply & replay: the older texture, with its tone; then 0 (no redraws at all); undo
    twice gives the version 13 texture back, and undo to the start the blank canvas."""
    import skimage as ski
    model, start, new, last = synthesised_twice(qtbot, window, ski.data.gravel()[:256, :256],
                                                3, (4, 5))
    assert window.history.actions[-1].coarse_row_redraws == 0.5
    free = edited_draw(qtbot, window, model, last, "coarse_row_redraws", 16)
    assert not np.array_equal(free, new)
    qtbot.waitUntil(lambda: np.array_equal(window.canvas.picture, tone_of(window, 5)),
                    timeout=30_000)
    edited_draw(qtbot, window, model, last, "coarse_row_redraws", 0)
    for _ in range(2):
        qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.document.levels, new)
    qtbot.waitUntil(lambda: np.array_equal(window.canvas.picture, tone_of(window, 5)),
                    timeout=30_000)
    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start) and not window.errors


def unticked(qtbot, window, step: int, name: str):
    """Click step ``step`` in the History list, untick its switch ``name`` with the keyboard,
    Apply & replay: the step now done."""
    dock = window.history_dock
    qtbot.mouseClick(dock.view.viewport(), LEFT, pos=dock.row_rect(step).center())
    kind, box = dock.form.editors[name]
    assert kind == "bool" and box.isChecked()
    box.setFocus()
    qtbot.keyClick(box, Key.Key_Space)
    assert not box.isChecked()
    qtbot.mouseClick(dock.apply_button, LEFT)
    assert window.runner.wait(60_000) and not window.errors
    done = window.history.actions[-1]
    assert getattr(done, name) is False
    return done


def test_moves_free_of_the_parents_and_forced_moves_are_unticked_in_the_history_form(qtbot,
                                                                                     window):
    """From a small chelsea crop, synthesise twice (the last draw's finest shares 0.11 off until
    moves free of its parents bring them back), untick "Shares: moves free of the parents" in
    the History form and Apply & replay: forced moves bring the shares back instead (another
    texture); untick "Shares: forced moves at last" too: the texture as steps before version
    14 drew it, off its shares, with its tone; undo twice gives the version 15 texture back, a
    fill after it is one more step, and undo to the start the blank canvas."""
    import skimage as ski
    model, start, new, last = synthesised_twice(qtbot, window,
                                                ski.data.chelsea()[100:292, 200:392], 3, (8, 9))

    def off(levels):
        return np.abs(np.bincount(levels.ravel(), minlength=4) / levels.size
                      - model.frequencies()).max()
    step = window.history.actions[-1]
    assert step.free_moves and step.forced_moves and off(new) <= 0.03
    unticked(qtbot, window, last, "free_moves")
    forced = model.synthesize((120, 160), seed=9, tone=False, free_moves=False).levels
    assert np.array_equal(window.document.levels, forced) and off(forced) <= 0.03
    assert not np.array_equal(forced, new)
    unticked(qtbot, window, last, "forced_moves")
    bound = model.synthesize((120, 160), seed=9, tone=False, free_moves=False,
                             forced_moves=False).levels
    assert np.array_equal(window.document.levels, bound) and off(bound) > 0.05
    qtbot.waitUntil(lambda: np.array_equal(window.canvas.picture, tone_of(window, 9)),
                    timeout=30_000)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.document.levels, forced)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.document.levels, new)
    qtbot.waitUntil(lambda: np.array_equal(window.canvas.picture, tone_of(window, 9)),
                    timeout=30_000)
    fill_a_cell(qtbot, window)                         # a click after the edit: one more step
    assert not window.errors
    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start) and not window.errors


def test_a_step_drawn_with_16_coarse_redraws_again_is_the_older_texture(qtbot, window):
    """Synthesise twice from brick's model (its coarsest law meets dead ends), then set the last
    step's Coarse redraws to 16 in the History form and Apply & replay: the canvas shows what a
    version 3 step drew (16 tries at a coarsest dead end), with its tone; undo goes back to the
    version 4 texture; the same with 16 tries at a finer dead end (before version 12); then
    the tone's switches, and undo to the start."""
    import skimage as ski
    model, start, new, last = synthesised_twice(qtbot, window, ski.data.brick()[:160, :160],
                                                2, (6, 7))
    assert window.history.actions[-1].coarse_redraws == 4
    older = edited_draw(qtbot, window, model, last, "coarse_redraws", 16)
    assert not np.array_equal(older, new)
    assert np.array_equal(window.canvas.picture, tone_of(window, 7))
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.document.levels, new)
    assert np.array_equal(window.canvas.picture, tone_of(window, 7))

    # the finer scale's redraws at a dead end to 16, as steps before version 12 tried; undo
    assert window.history.actions[-1].given_redraws == 8
    edit_and_apply(qtbot, window, last, "given_redraws", "16")
    assert not window.errors and window.history.actions[-1].given_redraws == 16
    sixteen = model.synthesize((120, 160), seed=7, tone=False, given_redraws=16).levels
    assert np.array_equal(window.document.levels, sixteen) and not np.array_equal(sixteen, new)
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.document.levels, new)

    # untick Tone balance in the form, Apply & replay: the same levels, the tone drawn the way
    # of steps before version 4
    unticked(qtbot, window, last, "tone_balance")
    assert np.array_equal(window.document.levels, new)
    unbalanced = rgb(model.render(new, seed=7, wrap=tone.PLAIN | tone.FINISHED))
    assert np.array_equal(window.canvas.picture, unbalanced)
    assert not np.array_equal(unbalanced, tone_of(window, 7))

    # then untick Tone finish: the picture as drawn, every grey one of the photo's own
    step = unticked(qtbot, window, last, "tone_finish")
    assert step.tone_balance is False
    drawn = rgb(model.render(new, seed=7, wrap=tone.PLAIN))
    assert np.array_equal(window.document.levels, new)
    assert np.array_equal(window.canvas.picture, drawn) and not np.array_equal(drawn, unbalanced)
    assert set(np.unique(drawn)) <= set(np.unique(model.tone.grey))
    qtbot.keyClick(window, Key.Key_Z, CTRL)
    assert np.array_equal(window.canvas.picture, unbalanced)
    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start)


def test_an_edited_scale_used_from_the_dpj_editor_stays_a_scale_of_the_model(qtbot, window,
                                                                            photo_path, small_dpj):
    """Edit DPJ on a photo model's finest scale, then Use: the model keeps the edited DPJ in
    that scale's place, so Synthesise draws every scale, the edited one among them, in the
    photo's tone (it was drawn alone, its composite levels as plain levels, without a tone);
    undo and redo go through it; a DPJ that is not that scale's shape is used alone."""
    from app.dpj_editor.window import use_in_main_window
    from texeditor.photo import document_tone
    window.attach_model(acquire_model(load_image(photo_path), scales=2))
    finest = window.document.dpj
    probs = finest.probs.copy()
    probs[0] *= 3
    edited = DPJ(finest.configs, probs / probs.sum(), finest.levels, palette=finest.palette,
                 meta={**finest.meta, "name": "hand-made"})
    use_in_main_window(window, edited)
    assert window.document.dpj_ref == edited.ref and window.scale_refs()[-1] == edited.ref
    assert "scale 2" in window.statusBar().currentMessage()
    synthesise(qtbot, window, 64, 48, 31)
    step = window.history.actions[-1]
    assert isinstance(step, SynthesizeScales) and step.dpjs[-1] == edited.ref
    assert step.dpjs[0] == window.photo_model.scales.dpjs[0].ref and step.tone_photo is not None
    drawn = window.document.levels.copy()
    assert document_tone(window.document) is not None and drawn.max() < window.photo_model.levels
    window.undo()
    window.redo()
    assert np.array_equal(window.document.levels, drawn)

    other = DPJ(small_dpj.configs, small_dpj.probs, small_dpj.levels,    # another window
                meta={**small_dpj.meta, "scale": 1, "scales": 2, "name": "other"})
    use_in_main_window(window, other)
    assert window.scale_refs() == () and window.photo_model.scales.dpjs[-1].ref == edited.ref
    assert not window.errors
