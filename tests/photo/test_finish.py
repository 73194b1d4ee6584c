"""The tone's finish (photo.finish): a tone picture's pixel-scale power brought to the photo's,
its layout left alone, a tiling picture still tiling."""

from __future__ import annotations

import numpy as np
import pytest
import skimage as ski
from scipy import ndimage as ndi

from texeditor.errors import FormatError
from texeditor.photo import acquire_model, finish, tone


def band(power: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """The rings between lo and hi cycles per point."""
    centre = (np.arange(finish.RINGS) + 0.5) * finish.RING
    return power[(centre > lo) & (centre <= hi)]


def log_off(picture, photo, lo, hi) -> float:
    """Mean log10 power of ``picture`` over ``photo``'s in a band of rings."""
    return float(np.mean(np.log10(band(finish.radial_power(picture), lo, hi))
                         - np.log10(band(finish.radial_power(photo), lo, hi))))


@pytest.mark.parametrize("name", ["gravel", "brick"])
def test_a_finished_tone_has_the_photos_pixel_scale_power(name):
    """A tone drawn on synthetic levels carries too much power at periods 2–2.7 (copies meet
    in sharp steps); finished, it has the photo's, and the layout (periods over 8) is as drawn."""
    photo = getattr(ski.data, name)()[:256, :256]
    model = acquire_model(photo)
    drawn = model.synthesize((256, 256), seed=3, tone_finish=False)
    shown = model.synthesize((256, 256), seed=3)
    assert np.array_equal(drawn.levels, shown.levels)
    before, after = (log_off(x.image, photo, 0.375, 0.5) for x in (drawn, shown))
    assert before > 0.08 and abs(after) < 0.3 * before
    low = [ndi.gaussian_filter(x.image.astype(float), 4) for x in (drawn, shown)]
    assert np.abs(low[0] - low[1]).mean() < 0.2
    assert 0 < np.abs(shown.image.astype(int) - drawn.image).mean() < 3


def test_the_finish_keeps_the_layout_and_only_scales_the_fine_rings():
    """Its filter is 1 on the rings below 1/PERIOD and within GAIN above: a picture with too
    much fine noise loses it, one with too little is sharpened, within GAIN."""
    rng = np.random.default_rng(1)
    smooth = ndi.gaussian_filter(rng.normal(128, 40, (200, 230)), 0.8)
    photo = np.clip(smooth, 0, 255).astype(np.uint8)
    noisy = np.clip(smooth + rng.normal(0, 5, smooth.shape), 0, 255).astype(np.uint8)
    power = finish.radial_power(photo)
    gain = finish.gain(finish.radial_power(noisy), power)
    centre = (np.arange(finish.RINGS) + 0.5) * finish.RING
    assert np.all(gain[centre <= 1 / finish.PERIOD] == 1.0)
    assert np.all((gain >= finish.GAIN[0]) & (gain <= finish.GAIN[1]))
    assert gain[centre > 0.4].max() < 0.9                     # the noise is taken down
    shown, _ = finish.finished(noisy, None, power, False)
    assert abs(log_off(shown, photo, 0.3, 0.5)) < 0.2 * log_off(noisy, photo, 0.3, 0.5)
    blurred = ndi.gaussian_filter(photo.astype(float), 1.0).astype(np.uint8)
    sharpened, _ = finish.finished(blurred, None, power, False)
    assert log_off(sharpened, photo, 0.25, 0.4) > log_off(blurred, photo, 0.25, 0.4) + 0.1


def test_a_tiling_picture_is_finished_on_the_torus():
    """Rolled, a tiling picture is finished the same way (its power is read without a window
    and it is filtered with no margin), so it still tiles: no seam comes from the finish."""
    rng = np.random.default_rng(2)
    photo = np.clip(ndi.gaussian_filter(rng.normal(128, 40, (128, 128)), 1.2), 0, 255)
    tile = np.clip(ndi.gaussian_filter(rng.normal(128, 30, (96, 120)), 0.6, mode="wrap")
                   + rng.normal(0, 8, (96, 120)), 0, 255).astype(np.uint8)
    power = finish.radial_power(photo.astype(np.uint8))
    shown, _ = finish.finished(tile, None, power, True)
    rolled, _ = finish.finished(np.roll(tile, (40, 70), axis=(0, 1)), None, power, True)
    back = np.roll(rolled, (-40, -70), axis=(0, 1)).astype(int)
    assert np.abs(back - shown).max() <= 1 and np.mean(back != shown) < 0.001
    plain, _ = finish.finished(tile, None, power, False)
    assert not np.array_equal(plain, shown)


def test_small_pictures_and_photos_without_power_are_shown_as_drawn():
    grey = np.full((15, 300), 100, np.uint8)
    power = finish.radial_power(np.random.default_rng(0).integers(0, 255, (64, 64)))
    assert finish.finished(grey, None, power, False)[0] is grey
    big = np.random.default_rng(1).integers(0, 255, (40, 40)).astype(np.uint8)
    assert finish.finished(big, None, np.full(finish.RINGS, np.nan), True)[0] is big


def test_old_steps_show_their_tone_unfinished_and_new_ones_finished():
    """step_wrap reads tone_finish: a SynthesizeScales of version 10 or before has none (its
    picture is the one it showed), a new one has it."""
    from texeditor.photo import step_wrap
    from texeditor.recipe.actions import SynthesizeScales
    from texeditor.recipe.codec import action_from_json
    new = SynthesizeScales(("0123456789abcdef",), 30, 20, closure=5)     # version 10's last
    assert new.tone_finish and step_wrap(new) & tone.FINISHED
    before_12 = {k: v for k, v in new.to_json().items()
                 if k not in ("given_redraws", "coarse_row_redraws", "free_moves",
                               "forced_moves", "lean_drafts")}
    with pytest.raises(FormatError):
        action_from_json({**before_12, "version": 10})          # version 10 had no finish
    written = {k: v for k, v in before_12.items() if k != "tone_finish"}
    old = action_from_json({**written, "version": 10})
    assert not old.tone_finish and not step_wrap(old) & tone.FINISHED
    assert old.to_json()["version"] == SynthesizeScales.VERSION


@pytest.mark.parametrize("name", ["scales-plain", "scales-tileable"])
def test_textures_of_version_11_replay_as_they_were_written(name):
    """Files written by SynthesizeScales version 11 (tests/data/scales-v11: gravel plain, chelsea
    tileable in colour) come out bit-identical, levels and finished tone; the same step without
    its finish shows another picture of the same levels."""
    import dataclasses
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone, step_wrap
    from texeditor.recipe.texturefile import render_texture
    expected = json.loads((DATA / "scales-v11" / "expected.json").read_text())[name]
    doc = render_texture(DATA / "scales-v11" / f"{name}.texture")
    step = doc.actions[-1]
    assert expected["version"] == 11 and step.tone_finish and step.given_redraws == 16
    assert step.tileable == expected["tileable"] and step.closure == expected["closure"]
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    shown = document_tone(doc)
    assert hashlib.sha256(shown.tobytes()).hexdigest() == expected["tone_sha256"]
    unfinished = document_model(doc, step).render(
        doc.levels, seed=step.seed, wrap=step_wrap(dataclasses.replace(step, tone_finish=False)))
    assert unfinished.shape == shown.shape and not np.array_equal(unfinished, shown)
