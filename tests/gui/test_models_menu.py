"""Models ▸ Random-phase noise / Texton / Match histogram (issue 22) as a session: each dialog
previews the step it applies; steps follow one another with tools between, and undo goes back
to the start."""

import numpy as np

from app.step_dialog import exemplar_from
from texeditor.markov.levels import load_image, quantize
from texeditor.pyramid import heeger_bergen
from texeditor.spectral import random_phase_noise, texton
from texeditor.spectral.actions import matched_palette

from .support import fill_a_cell, model_ok, open_model_dialog, undo_to_start




def test_models_session(window, qtbot, photo_path):
    start = (window.document.levels.copy(), window.document.palette.copy())
    photo, _ = exemplar_from(load_image(photo_path))
    names = [a.text() for a in window.menu("ModelsMenu").actions()]
    assert names == ["Random-phase &noise from a photo…", "&Texton of a photo…",
                     "&Match histogram to a photo…", "&Heeger–Bergen texture from a photo…",
                     "&Flow texture…", "&Fractal relief…", "&IFS motif…"]

    dialog = open_model_dialog(window, qtbot, "random_phase_noise")
    dialog.width_box.setValue(40)
    dialog.height_box.setValue(30)
    dialog.levels.setValue(5)
    dialog.seed.set_value(3)
    model_ok(dialog, qtbot)
    doc = window.document
    expected = quantize(random_phase_noise(photo, (30, 40), seed=3), 5, "lab")
    assert doc.shape == (30, 40) and doc.num_levels == 5
    assert np.array_equal(doc.levels, expected.levels)
    assert np.array_equal(doc.palette, expected.palette)
    first = doc.levels.copy()

    dialog = open_model_dialog(window, qtbot, "random_phase_noise")      # again, another seed
    dialog.seed.set_value(4)
    model_ok(dialog, qtbot)
    assert doc.shape == (30, 40) and not np.array_equal(doc.levels, first)
    fill_a_cell(qtbot, window)                                     # a tool works on it
    assert window.history.actions[-1].TYPE == "fill"

    levels, palette = doc.levels.copy(), doc.palette.copy()
    dialog = open_model_dialog(window, qtbot, "match_histogram")
    model_ok(dialog, qtbot)
    assert np.array_equal(doc.levels, levels)
    assert np.array_equal(doc.palette, matched_palette(levels, palette, photo))

    dialog = open_model_dialog(window, qtbot, "texton")
    dialog.levels.setValue(4)
    model_ok(dialog, qtbot)
    assert doc.shape == photo.shape[:2] and doc.num_levels == 4
    assert np.array_equal(doc.levels, quantize(texton(photo), 4, "lab").levels)
    assert [a.TYPE for a in window.history.actions[-5:]] == [
        "random_phase_noise", "random_phase_noise", "fill", "match_histogram", "texton"]
    assert not window.errors

    undo_to_start(qtbot, window)
    assert np.array_equal(window.document.levels, start[0])
    assert np.array_equal(window.document.palette, start[1])


def test_match_histogram_previews_then_applies_the_photos_distribution(window, qtbot, photo_path):
    photo, _ = exemplar_from(load_image(photo_path))
    doc = window.document
    levels, palette = doc.levels.copy(), doc.palette.copy()
    dialog = open_model_dialog(window, qtbot, "match_histogram")
    model_ok(dialog, qtbot)
    assert np.array_equal(doc.levels, levels)
    assert np.array_equal(doc.palette, matched_palette(levels, palette, photo))
    window.act_undo.trigger()
    assert np.array_equal(doc.palette, palette)


def test_a_bad_photo_says_why_and_ok_stays_off(window, qtbot, tmp_path):
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"not a picture")
    dialog = open_model_dialog(window, qtbot, "texton")
    dialog.set_photo(bad)
    assert dialog.wait() and not dialog.ok.isEnabled() and dialog.info.text()
    steps = len(window.history.actions)
    dialog.apply()
    assert len(window.history.actions) == steps
    dialog.reject()


def test_heeger_bergen_previews_in_the_background_the_latest_settings_winning(window, qtbot,
                                                                              photo_path):
    photo, _ = exemplar_from(load_image(photo_path))
    start = window.document.levels.copy()
    dialog = open_model_dialog(window, qtbot, "heeger_bergen")
    dialog.width_box.setValue(64)
    dialog.height_box.setValue(48)
    dialog.iterations.setValue(2)
    dialog.levels.setValue(6)
    for seed in (5, 6, 7):                      # typed one after the other: only 7 is shown
        dialog.seed.set_value(seed)
    assert not dialog.ok.isEnabled()            # nothing to apply until the preview is there
    model_ok(dialog, qtbot)
    expected = quantize(heeger_bergen(photo, (48, 64), seed=7, iterations=2), 6, "lab")
    doc = window.document
    assert doc.shape == (48, 64) and np.array_equal(doc.levels, expected.levels)
    assert window.history.actions[-1].seed == 7

    dialog = open_model_dialog(window, qtbot, "heeger_bergen")     # again: Cancel while it computes
    dialog.width_box.setValue(512)
    dialog.height_box.setValue(512)
    dialog.iterations.setValue(20)
    dialog.previews.timer.stop()
    dialog.previews._start()
    qtbot.waitUntil(lambda: dialog.busy.value() > 0, timeout=20_000)
    dialog.reject()
    assert dialog.previews.job is None or dialog.previews.job.is_cancelled()
    assert np.array_equal(doc.levels, expected.levels) and not window.errors
    window.act_undo.trigger()
    assert np.array_equal(window.document.levels, start)
