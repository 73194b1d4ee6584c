"""Photo models: acquired, drawn with the photo's tone, saved as format-2 .dpj, hostile files."""

import dataclasses
import io
import threading
import zipfile

import numpy as np
import pytest
import skimage as ski
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import texeditor
from texeditor import DPJ
from texeditor.errors import FormatError, InputError
from texeditor.markov.particles import MAX_PARTICLES, PARTICLES
from texeditor.photo import acquire_model, load_model, model_from_bytes, tone
from texeditor.markov.multiscale import (COARSE_ROW_REDRAWS, GIVEN_REDRAWS, NO_ROW_LIMIT,
                                         SCALES_CLOSURE)
from texeditor.recipe.actions import SynthesizeScales
from texeditor.recipe.texturefile import render_texture, save_texture, synthesize_scales_texture
from tests.support.photo import speckle


@pytest.fixture(scope="module")
def model():
    return acquire_model(speckle(), scales=2)


def test_resynthesize_gives_the_picture_and_the_levels():
    r = texeditor.resynthesize(speckle(), (60, 90), seed=4, scales=2)
    assert r.image.shape == (60, 90) and r.image.dtype == np.uint8
    assert r.levels.shape == (60, 90) and r.levels.max() < 4
    again = texeditor.resynthesize(speckle(), (60, 90), seed=4, scales=2)
    assert np.array_equal(r.image, again.image) and np.array_equal(r.levels, again.levels)


def test_resynthesize_auto_scales_fit_a_small_texture():
    """Without ``scales``, a texture too small for the photo's scales is drawn on fewer (its
    levels the same as with those scales asked for); with them, it is refused."""
    photo = ski.data.gravel()[:256, :256]
    assert texeditor.photo.auto_scales(photo, (512, 512)) == 3
    assert [texeditor.photo.auto_scales(photo, s) for s in ((17, 17), (16, 32), (4, 8), (1, 1))] \
        == [3, 2, 1, 1]
    r = texeditor.resynthesize(photo, (16, 32), seed=2)
    assert r.image.shape == (16, 32)
    assert np.array_equal(r.levels, texeditor.resynthesize(photo, (16, 32), seed=2,
                                                           scales=2).levels)
    with pytest.raises(texeditor.InputError, match="or fewer scales"):
        texeditor.resynthesize(photo, (16, 32), scales=3)


def test_resynthesize_reads_a_photo_given_by_its_path(tmp_path):
    """A path (text or pathlib) is read with load_image: it failed with "min() arg is an empty
    sequence"; a missing file is an ImageError naming it."""
    photo = speckle((64, 64), colour=True)
    ski.io.imsave(tmp_path / "p.png", photo, check_contrast=False)
    want = texeditor.resynthesize(photo, (24, 24), seed=1, scales=2)
    for path in (str(tmp_path / "p.png"), tmp_path / "p.png"):
        got = texeditor.resynthesize(path, (24, 24), seed=1, scales=2)
        assert np.array_equal(got.image, want.image) and np.array_equal(got.levels, want.levels)
    with pytest.raises(texeditor.ImageError, match="gone.png: no such file"):
        texeditor.resynthesize(str(tmp_path / "gone.png"), (24, 24))


@pytest.mark.parametrize("colour", [False, True])
def test_an_int64_photo_resynthesizes_as_the_file_reader_reads_it(colour, tmp_path):
    """``np.array(picture, dtype=int)`` (int64, values 0..255) was read on int64's scale and
    refused as "constant: a single grey (0)": it is read by its own range, as load_image reads
    a TIFF of the same samples; a grey one draws what its uint8 photo draws."""
    import tifffile
    photo = speckle((64, 64), colour=colour)
    wide = photo.astype(np.int64)
    tifffile.imwrite(tmp_path / "wide.tif", wide, photometric="rgb" if colour else "minisblack")
    got = texeditor.resynthesize(wide, (24, 24), seed=3, scales=2)
    for want in (texeditor.resynthesize(str(tmp_path / "wide.tif"), (24, 24), seed=3, scales=2),
                 *([] if colour else [texeditor.resynthesize(photo, (24, 24), seed=3, scales=2)])):
        assert np.array_equal(got.image, want.image) and np.array_equal(got.levels, want.levels)
    assert np.array_equal(acquire_model(wide, scales=2).tone.colour,
                          acquire_model(photo, scales=2).tone.colour)


def test_tone_draws_each_point_from_photo_points_of_its_level(model):
    """Every grey drawn is a grey the photo has at that level (the 3×3 context backs off to
    the level itself at worst), so flat levels become the photo's own shading (then finished:
    tests/photo/test_finish.py)."""
    r = model.synthesize((80, 80), seed=1, tone_finish=False)
    photo_levels, photo_grey = model.tone.levels, model.tone.grey
    for level in range(model.levels):
        allowed = set(np.unique(photo_grey[photo_levels == level]).tolist())
        assert set(np.unique(r.image[r.levels == level]).tolist()) <= allowed
    assert len(np.unique(r.image)) > 4 * model.levels      # shaded, not four flat greys


@pytest.mark.parametrize("photo", ["model", "brick"])
def test_a_balanced_tone_keeps_each_levels_greys_as_the_photo_has_them(model, photo):
    """BALANCED (new syntheses): a bin of greys a level has drawn more often than the photo's
    share of that level's greys weighs its matches more, so each level's grey histogram comes
    closer to the photo's (and the 32-grey co-occurrences of issue 19 with it)."""
    if photo == "brick":
        model = acquire_model(ski.data.brick())
    levels = model.synthesize((200, 240), seed=1).levels
    args = (levels, 4, model.tone.levels, model.tone.grey)
    shares = tone._grey_shares(model.tone.levels, model.tone.grey, 4)

    def off(way):
        got = tone._grey_shares(levels, tone.render(*args, seed=1, wrap=way)[0], 4)
        return np.abs(got - shares).sum(axis=1).mean() / 2
    assert off(tone.BALANCED) < 0.7 * off(tone.PLAIN)


def test_tone_off_is_the_palette_view(model):
    r = model.synthesize((40, 40), seed=2, tone=False)
    assert np.array_equal(r.image, model.palette[r.levels][..., 0])


def test_colour_photos_give_colour_textures():
    """Drawn with the photo's own colours; finished, each point's colour moves by its grey's
    change, the same on every channel (a colour picture's pixel noise is in its lightness)."""
    photo = speckle(colour=True)
    model = acquire_model(photo, scales=2)
    drawn = model.synthesize((50, 50), seed=0, tone_finish=False)
    r = texeditor.resynthesize(photo, (50, 50), seed=0, scales=2)
    assert r.image.shape == drawn.image.shape == (50, 50, 3)
    assert np.array_equal(r.levels, drawn.levels)
    colours = {tuple(c) for c in photo.reshape(-1, 3)}
    assert all(tuple(c) in colours for c in drawn.image.reshape(-1, 3)[::37])
    change = r.image.astype(int) - drawn.image
    unclipped = ((drawn.image > 20) & (drawn.image < 235)).all(axis=2)
    assert np.abs(change).max() > 0
    assert np.array_equal(change[unclipped][:, 0], change[unclipped][:, 1])
    assert np.array_equal(change[unclipped][:, 0], change[unclipped][:, 2])


def test_a_saved_model_draws_the_same_texture(model, tmp_path):
    path = tmp_path / "m.dpj"
    model.save(path)
    again = load_model(path)
    a, b = model.synthesize((64, 64), seed=9), again.synthesize((64, 64), seed=9)
    assert np.array_equal(a.image, b.image) and np.array_equal(a.levels, b.levels)
    assert again.to_bytes() == model.to_bytes()
    assert path.stat().st_size <= 2 * 2**20


def test_single_dpj_files_still_open(tmp_path):
    dpj = texeditor.estimate_dpj(np.indices((20, 20)).sum(0) % 3, (2, 2), 3)
    dpj.save(tmp_path / "old.dpj")
    assert isinstance(load_model(tmp_path / "old.dpj"), DPJ)
    with pytest.raises(FormatError, match="photo model"):
        DPJ.from_bytes(acquire_model(speckle(), scales=2, tone=False).to_bytes())


def test_a_texture_file_replays_a_multiscale_synthesis(model, tmp_path):
    history = synthesize_scales_texture(model.scales.dpjs, 70, 50, seed=3)
    save_texture(tmp_path / "t.texture", history)
    doc = render_texture(tmp_path / "t.texture")
    want = model.synthesize((50, 70), seed=3).levels
    assert np.array_equal(doc.levels, want)
    assert doc.actions[-1].TYPE == "synthesize_scales"


def test_a_tileable_texture_of_the_previous_closure_replays_and_shows_its_tone_as_it_did():
    """A file written before closure 3 (tests/data/scales-v2): its levels and its tone picture
    come out bit-identical (closure 2, the first tiling tone); a new step records closure 4."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_tone, step_wrap
    expected = json.loads((DATA / "scales-v2" / "expected.json").read_text())
    doc = render_texture(DATA / "scales-v2" / "tileable-tone.texture")
    step = doc.actions[-1]
    assert step.closure == expected["closure"] == 2 and step_wrap(step) == tone.TILED
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    new = SynthesizeScales(step.dpjs, 80, 60, seed=7, tileable=True,
                           tone_photo=step.tone_photo, tone_levels=step.tone_levels)
    assert new.to_json()["version"] == SynthesizeScales.VERSION and new.tone_balance
    assert new.closure == SCALES_CLOSURE
    assert new.particles == PARTICLES and step.particles == 0
    assert new.rebalance and not step.rebalance
    assert step_wrap(new) == tone.TILED_LANES | tone.BALANCED | tone.FINISHED


@pytest.mark.parametrize("closure", range(1, 9))
def test_a_tileable_step_of_one_dpj_shows_a_models_tone_whatever_its_closure(closure):
    """A single-DPJ synthesis is shown with an attached photo model's tone: its step names
    closures the scales do not have (8, the last rows pulled at full strength), and its tone
    tiles as a multi-scale step's of closure 3 on does (a tileable photo-model walk once
    stopped there: "seam closure 7 does not exist")."""
    from texeditor.photo import step_wrap
    from texeditor.photo.model import tone_wrap
    from texeditor.recipe.actions import Synthesize
    step = Synthesize("0123456789abcdef", 30, 20, 1, True, closure=closure)
    assert step_wrap(step) & (tone.TILED_LANES if closure >= 3 else tone.TILED)
    with pytest.raises(InputError):
        tone_wrap(True, 9)


@pytest.mark.parametrize("name", ["plain", "tileable"])
def test_textures_of_version_3_replay_with_16_coarse_redraws_as_they_did(name):
    """Files written by SynthesizeScales version 3 (tests/data/scales-v3: brick, a coarsest law
    that meets dead ends) come out bit-identical, levels and tone: their steps keep 16 redraws
    at a coarsest dead end. A new step tries COARSE_REDRAWS times, so the same seed draws
    another texture, as its model does."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    from texeditor.markov.multiscale import COARSE_REDRAWS
    expected = json.loads((DATA / "scales-v3" / "expected.json").read_text())[name]
    doc = render_texture(DATA / "scales-v3" / f"{name}.texture")
    step = doc.actions[-1]
    assert step.coarse_redraws == 16 and step.tileable == expected["tileable"]
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    new = dataclasses.replace(step, coarse_redraws=COARSE_REDRAWS, particles=PARTICLES)
    assert new.to_json()["version"] == SynthesizeScales.VERSION and new.to_json()["coarse_redraws"] == COARSE_REDRAWS
    redrawn = new.prepare(doc)
    assert not np.array_equal(redrawn, doc.levels)
    model = document_model(doc, step)
    assert np.array_equal(redrawn, model.synthesize((120, 160), seed=7, tileable=step.tileable,
                                                    closure=step.closure, tone=False,
                                                    rebalance=False, steer=False,
                                                    more_drafts=False, given_redraws=16,
                                                    free_moves=False, forced_moves=False).levels)


@pytest.mark.parametrize("name", ["scales-plain", "scales-tileable"])
def test_textures_of_version_5_replay_drawing_a_coarse_scale_again_whole(name):
    """Files written by SynthesizeScales version 5 (tests/data/scales-v5: a crop of coffee, whose
    coarse scales seldom come out at their level shares at once) come out bit-identical, levels
    and tone: their steps draw such a scale again whole (particles 0). A new step draws it as
    particles, so the same seed draws another texture, nearer the photo's level shares."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    expected = json.loads((DATA / "scales-v5" / "expected.json").read_text())[name]
    doc = render_texture(DATA / "scales-v5" / f"{name}.texture")
    step = doc.actions[-1]
    assert step.particles == 0 and step.closure == expected["closure"] == 4
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    new = dataclasses.replace(step, particles=PARTICLES)
    assert new.to_json()["version"] == SynthesizeScales.VERSION and new.to_json()["particles"] == PARTICLES
    redrawn = new.prepare(doc)
    assert not np.array_equal(redrawn, doc.levels)
    model = document_model(doc, step)
    assert np.array_equal(redrawn, model.synthesize((100, 140), seed=step.seed,
                                                    tileable=step.tileable, tone=False,
                                                    closure=step.closure, rebalance=False,
                                                    steer=False, more_drafts=False,
                                                    given_redraws=16, free_moves=False,
                                                    forced_moves=False).levels)


def test_a_tileable_texture_of_version_6_replays_with_closure_4():
    """A file written by SynthesizeScales version 6 (tests/data/scales-v6: tileable, closure 4,
    particles 6) comes out bit-identical, levels and tone. A new step of it records closure 5
    (version 7) and draws what the model draws with it."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    expected = json.loads((DATA / "scales-v6" / "expected.json").read_text())["scales-tileable"]
    doc = render_texture(DATA / "scales-v6" / "scales-tileable.texture")
    step = doc.actions[-1]
    assert step.closure == expected["closure"] == 4 and step.particles == PARTICLES
    assert step.tileable and expected["version"] == 6
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    new = dataclasses.replace(step, closure=5)
    assert new.to_json()["version"] == SynthesizeScales.VERSION and new.to_json()["closure"] == 5
    model = document_model(doc, step)
    assert np.array_equal(new.prepare(doc), model.synthesize((100, 140), seed=step.seed,
                                                             tileable=True, closure=5, tone=False,
                                                             rebalance=False, steer=False,
                                                             more_drafts=False,
                                                             given_redraws=16,
                                                             free_moves=False,
                                                             forced_moves=False).levels)


def test_a_texture_of_version_7_replays_without_rebalancing():
    """A file written by SynthesizeScales version 7 (tests/data/scales-v7: a crop of chelsea whose
    finest level shares come out 0.14 off the model's) comes out bit-identical, levels and tone:
    its step keeps the shares as drawn. A new step (version 8) of it rebalances them: the same
    seed draws the same texture with region borders moved, within TRIGGER of the shares."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.markov.balance import TRIGGER
    from texeditor.photo import document_model, document_tone
    expected = json.loads((DATA / "scales-v7" / "expected.json").read_text())["scales-plain"]
    doc = render_texture(DATA / "scales-v7" / "scales-plain.texture")
    step = doc.actions[-1]
    assert not step.rebalance and step.closure == expected["closure"] == 5
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    model = document_model(doc, step)
    shares = np.bincount(doc.levels.ravel(), minlength=4) / doc.levels.size
    assert np.abs(shares - model.frequencies()).max() > 0.1
    new = dataclasses.replace(step, rebalance=True)
    assert new.to_json()["version"] == SynthesizeScales.VERSION and new.to_json()["rebalance"] is True
    redrawn = new.prepare(doc)
    moved = redrawn != doc.levels
    assert 0 < moved.mean() < 0.25
    shares = np.bincount(redrawn.ravel(), minlength=4) / redrawn.size
    assert np.abs(shares - model.frequencies()).max() <= TRIGGER
    drawn = model.synthesize((100, 140), seed=step.seed, steer=False, more_drafts=False,
                             given_redraws=16, free_moves=False, forced_moves=False)
    assert np.array_equal(drawn.levels, redrawn) and drawn.moved >= moved.sum()   # moves
    assert np.array_equal(drawn.image, model.render(redrawn, seed=step.seed))


def test_a_texture_of_version_8_replays_unsteered():
    """Files written by SynthesizeScales version 8 (tests/data/scales-v8: a crop of chelsea,
    plain and tileable) come out bit-identical, levels and tone: their steps draw every scale
    unsteered. A new step (version 9) of the plain one steers them: the same seed draws another
    texture, the one the model draws, and its shares come out closer to the model's."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    expected = json.loads((DATA / "scales-v8" / "expected.json").read_text())
    for name in ("scales-plain", "scales-tileable"):
        doc = render_texture(DATA / "scales-v8" / f"{name}.texture")
        step = doc.actions[-1]
        assert not step.steer and step.rebalance and expected[name]["version"] == 8
        assert step.tileable == (name == "scales-tileable")
        assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected[name]["levels_sha256"]
        assert (hashlib.sha256(document_tone(doc).tobytes()).hexdigest()
                == expected[name]["tone_sha256"])
    doc = render_texture(DATA / "scales-v8" / "scales-plain.texture")
    step = doc.actions[-1]
    new = dataclasses.replace(step, steer=True)
    assert new.to_json()["version"] == SynthesizeScales.VERSION and new.to_json()["steer"] is True
    redrawn = new.prepare(doc)
    model = document_model(doc, step)
    assert np.array_equal(redrawn, model.synthesize((100, 140), seed=step.seed, tone=False,
                                                    more_drafts=False, given_redraws=16,
                                                    free_moves=False, forced_moves=False).levels)
    assert not np.array_equal(redrawn, doc.levels)


def test_textures_of_version_9_replay_as_they_were_written():
    """Files written by SynthesizeScales version 9 (tests/data/scales-v9: the crop of chelsea,
    plain and tileable, steered) come out bit-identical, levels and tone: their steps draft
    every scale as 6 particles."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    expected = json.loads((DATA / "scales-v9" / "expected.json").read_text())
    for name in ("scales-plain", "scales-tileable"):
        doc = render_texture(DATA / "scales-v9" / f"{name}.texture")
        step = doc.actions[-1]
        assert step.steer and step.rebalance and expected[name]["version"] == 9
        assert not step.more_drafts and step.to_json()["version"] == SynthesizeScales.VERSION
        assert step.tileable == (name == "scales-tileable")
        assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected[name]["levels_sha256"]
        assert (hashlib.sha256(document_tone(doc).tobytes()).hexdigest()
                == expected[name]["tone_sha256"])
        new = dataclasses.replace(step, more_drafts=True)
        assert new.to_json()["version"] == SynthesizeScales.VERSION and new.to_json()["more_drafts"] is True
        assert np.array_equal(new.prepare(doc), document_model(doc, step).synthesize(
            (100, 140), seed=step.seed, tileable=step.tileable, closure=step.closure,
            tone=False, given_redraws=16, free_moves=False, forced_moves=False).levels)


@pytest.mark.parametrize("name", ["scales-plain", "scales-tileable"])
def test_textures_of_version_12_replay_as_they_were_written(name):
    """Files written by SynthesizeScales version 12 (tests/data/scales-v12: gravel plain, chelsea
    tileable in colour) come out bit-identical, levels and tone: 8 tries at a finer dead end;
    the same step with 16, as steps before it tried, draws another texture."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    expected = json.loads((DATA / "scales-v12" / "expected.json").read_text())[name]
    doc = render_texture(DATA / "scales-v12" / f"{name}.texture")
    step = doc.actions[-1]
    assert expected["version"] == 12 and step.given_redraws == expected["given_redraws"] == 8
    assert step.tileable == expected["tileable"] and step.closure == expected["closure"]
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    sixteen = dataclasses.replace(step, given_redraws=16).prepare(doc)
    assert not np.array_equal(sixteen, doc.levels)
    assert np.array_equal(sixteen, document_model(doc, step).synthesize(
        (step.height, step.width), seed=step.seed, tileable=step.tileable, tone=False,
        closure=step.closure, given_redraws=16, free_moves=False, forced_moves=False).levels)


@pytest.mark.parametrize("name", ["scales-plain", "scales-tileable"])
def test_textures_of_version_13_replay_as_they_were_written(name):
    """Files written by SynthesizeScales version 13 (tests/data/scales-v13: gravel plain, coffee
    tileable in colour) come out bit-identical, levels and tone: a row of the coarsest scale
    redraws at most 0.5 times a point; the same step without that limit, as steps before it,
    draws another texture."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    expected = json.loads((DATA / "scales-v13" / "expected.json").read_text())[name]
    doc = render_texture(DATA / "scales-v13" / f"{name}.texture")
    step = doc.actions[-1]
    assert expected["version"] == 13 and step.coarse_row_redraws == 0.5
    assert step.tileable == expected["tileable"] and step.closure == expected["closure"]
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    free = dataclasses.replace(step, coarse_row_redraws=NO_ROW_LIMIT).prepare(doc)
    assert not np.array_equal(free, doc.levels)
    assert np.array_equal(free, document_model(doc, step).synthesize(
        (step.height, step.width), seed=step.seed, tileable=step.tileable, tone=False,
        closure=step.closure, coarse_row_redraws=NO_ROW_LIMIT, free_moves=False, forced_moves=False).levels)


SHARE_SWITCHES = (   # a version, the switch it brought, how far off its fixtures are without it
    (14, "free_moves", 0.08), (15, "forced_moves", 0.2))


@pytest.mark.parametrize("version, switch, without", SHARE_SWITCHES)
@pytest.mark.parametrize("name", ["scales-plain", "scales-tileable"])
def test_textures_of_versions_14_and_15_replay_as_they_were_written(name, version, switch,
                                                                      without):
    """Files written by SynthesizeScales version 14 (tests/data/scales-v14: chelsea plain, coffee
    tileable in colour) and 15 (scales-v15: a moon crop, plain and tileable) come out
    bit-identical, levels and tone, within 0.03 of the model's level shares: the moves free of
    the parents (14) and forced moves (15, a level the free moves could not bring back)
    brought them back; the same step without them, as steps before it, draws a texture
    0.08 (14) and 0.2 (15) off."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    folder = DATA / f"scales-v{version}"
    expected = json.loads((folder / "expected.json").read_text())[name]
    doc = render_texture(folder / f"{name}.texture")
    step = doc.actions[-1]
    assert expected["version"] == version and getattr(step, switch)
    assert step.seed == expected["seed"] and step.forced_moves == (version >= 15)
    assert step.tileable == expected["tileable"] and step.closure == expected["closure"]
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    model = document_model(doc, step)

    def off(levels):
        return np.abs(np.bincount(levels.ravel(), minlength=model.levels) / levels.size
                      - model.frequencies()).max()
    switched = dataclasses.replace(step, **{switch: False}).prepare(doc)
    assert off(doc.levels) <= 0.03 < without < off(switched)
    assert np.array_equal(switched, model.synthesize(
        (step.height, step.width), seed=step.seed, tileable=step.tileable, tone=False,
        closure=step.closure, free_moves=switch != "free_moves", forced_moves=False).levels)


@pytest.mark.parametrize("name", ["scales-plain", "scales-tileable"])
def test_textures_of_version_16_replay_as_they_were_written(name):
    """Files written by SynthesizeScales version 16 (tests/data/scales-v16: a coffee crop, plain
    and tileable) come out bit-identical, levels and tone: a scale whose plain draws are off
    about as far as its parents was not drafted (lean_drafts); the same step without it, as
    steps before it, drafts that scale and draws another texture. Both within 0.03 of the
    model's level shares."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    expected = json.loads((DATA / "scales-v16" / "expected.json").read_text())[name]
    doc = render_texture(DATA / "scales-v16" / f"{name}.texture")
    step = doc.actions[-1]
    assert expected["version"] == 16 and step.lean_drafts and step.seed == expected["seed"]
    assert step.tileable == expected["tileable"] and step.closure == expected["closure"]
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    model = document_model(doc, step)
    drafted = dataclasses.replace(step, lean_drafts=False).prepare(doc)
    assert not np.array_equal(drafted, doc.levels)
    assert np.array_equal(drafted, model.synthesize((step.height, step.width), seed=step.seed,
                                                    tileable=step.tileable, tone=False,
                                                    closure=step.closure,
                                                    lean_drafts=False).levels)
    for levels in (doc.levels, drafted):
        assert np.abs(np.bincount(levels.ravel(), minlength=model.levels) / levels.size
                      - model.frequencies()).max() <= 0.03


def test_a_texture_of_version_17_replays_with_its_closure_6():
    """A file written by SynthesizeScales version 17 (tests/data/scales-v17: a coffee crop,
    tileable, closure 6) comes out bit-identical, levels and tone: its step reads closure 6
    (version 17 had closures 1 to 6). A step naming closure 7 pulls
    the last rows of the finer scales towards the first, so the same seed draws another
    texture, as its model does; version 17 cannot name closure 7."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    from texeditor.recipe.codec import action_from_json
    expected = json.loads((DATA / "scales-v17" / "expected.json").read_text())["scales-tileable"]
    doc = render_texture(DATA / "scales-v17" / "scales-tileable.texture")
    step = doc.actions[-1]
    assert expected["version"] == 17 and step.closure == expected["closure"] == 6
    assert step.tileable and step.seed == expected["seed"]
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    new = dataclasses.replace(step, closure=7)
    assert SynthesizeScales.VERSION == 19 and SynthesizeScales(step.dpjs, 8, 8).closure == 8
    pulled = new.prepare(doc)
    assert not np.array_equal(pulled, doc.levels)
    model = document_model(doc, step)
    assert np.array_equal(pulled, model.synthesize((step.height, step.width), seed=step.seed,
                                                   tileable=True, closure=7,
                                                   tone=False).levels)
    written = step.to_json()
    with pytest.raises(FormatError):
        action_from_json({**written, "version": 17, "closure": 7})
    assert action_from_json({**written, "version": 17}).closure == 6


def test_a_tileable_texture_of_scales_version_18_replays_as_it_did():
    """A file written by SynthesizeScales version 18 (tests/data/scales-v18: a camera crop,
    120×136, tileable, closure 7) comes out bit-identical, levels and tone: its step reads
    closure 7 (version 18 had closures 1 to 7). A new step closes the scales by closure 8,
    whose finer scales are pulled at full strength and redrawn at the bottom seam only where
    they do not close, so the same seed draws another texture, as its model does; version 18
    cannot name closure 8."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_model, document_tone
    from texeditor.recipe.codec import action_from_json
    expected = json.loads((DATA / "scales-v18" / "expected.json").read_text())["scales-tileable"]
    doc = render_texture(DATA / "scales-v18" / "scales-tileable.texture")
    step = doc.actions[-1]
    assert expected["version"] == 18 and step.closure == expected["closure"] == 7
    assert step.tileable and step.seed == expected["seed"] and doc.levels.shape == (136, 120)
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == expected["tone_sha256"]
    new = dataclasses.replace(step, closure=8)
    assert new.to_json()["version"] == 19
    pulled = new.prepare(doc)
    assert not np.array_equal(pulled, doc.levels)
    model = document_model(doc, step)
    assert np.array_equal(pulled, model.synthesize((step.height, step.width), seed=step.seed,
                                                   tileable=True, tone=False).levels)
    written = step.to_json()
    with pytest.raises(FormatError):
        action_from_json({**written, "version": 18, "closure": 8})
    assert action_from_json({**written, "version": 18}).closure == 7


FLAGS = (("rebalance", 8), ("steer", 9), ("more_drafts", 10),    # the multiscale step's switches,
         ("tone_finish", 11), ("free_moves", 14),                # with the version each came with
         ("forced_moves", 15), ("lean_drafts", 16))


def flag_cases():
    for name, since in FLAGS:
        yield name, since - 1, {}, False             # an older step draws without it ...
        yield name, 2, {}, False
        yield name, since - 1, {name: True}, None    # ... and cannot name it
        yield name, since, {}, True                  # its own version: on by default,
        yield name, since, {name: False}, False      # off when it says so,
        yield name, since, {name: 1}, None           # and a switch is a bool


@pytest.mark.parametrize("name, version, obj, value", list(flag_cases()))
def test_a_multiscale_step_keeps_its_switches_as_its_version_has_them(name, version, obj, value):
    """Rebalancing (version 8), steering (9), more drafts of small scales (10), the tone's
    finish (11), moves free of the parents (14), forced moves (15) and drafts only past the
    parents' error (16): an older step draws without them and cannot name them; the version
    that brought one names it, default on."""
    if value is None:
        with pytest.raises(FormatError):
            read_scales_step(version, obj)
    else:
        assert getattr(read_scales_step(version, obj), name) is value


@pytest.mark.parametrize("version, obj, particles", [
    (5, {}, 0), (4, {}, 0), (1, {}, 0), (5, {"particles": 8}, None), (3, {"particles": 0}, None),
    (6, {}, PARTICLES), (6, {"particles": 0}, 0), (6, {"particles": 3}, 3),
    (6, {"particles": MAX_PARTICLES + 1}, None), (6, {"particles": True}, None),
    (7, {}, PARTICLES), (7, {"particles": 0}, 0), (8, {"particles": 2}, 2)])
def test_a_multiscale_step_keeps_how_it_fits_its_level_shares(version, obj, particles):
    """Particles came with SynthesizeScales version 6: an older step draws a scale again whole
    (particles 0) and cannot name them; version 6 names 0 to MAX_PARTICLES, default PARTICLES."""
    if particles is None:
        with pytest.raises(FormatError):
            read_scales_step(version, obj)
    else:
        assert read_scales_step(version, obj).particles == particles


def read_scales_step(version: int, obj: dict):
    """A multi-scale step of ``version`` as a file holds it (closure 2 from version 2 on),
    with ``obj``'s fields, read as today's code reads it."""
    from texeditor.recipe.codec import action_from_json
    step = {"type": "synthesize_scales", "version": version, "dpjs": ["0123456789abcdef"],
            "width": 30, "height": 20, "seed": 1, "tileable": False, **obj}
    if version > 1:
        step["closure"] = 2
    return action_from_json(step)


@pytest.mark.parametrize("obj, closure", [({"closure": 2}, 2), ({"closure": 1}, 1), ({}, 2),
                                          ({"closure": 3}, None), ({"closure": "2"}, None)])
def test_a_version_2_multiscale_step_keeps_its_closure(obj, closure):
    from texeditor.recipe.codec import action_from_json
    step = {"type": "synthesize_scales", "version": 2, "dpjs": ["0123456789abcdef"],
            "width": 30, "height": 20, "seed": 1, "tileable": True, **obj}
    if closure is None:
        with pytest.raises(FormatError):
            action_from_json(step)
    else:
        assert action_from_json(step).closure == closure
        assert action_from_json(step).coarse_redraws == 16


@pytest.mark.parametrize("kind, version, obj, closure", [
    ("synthesize_scales", 3, {}, 3), ("synthesize_scales", 4, {}, 3),
    ("synthesize_scales", 4, {"closure": 2}, 2), ("synthesize_scales", 4, {"closure": 4}, None),
    ("synthesize_scales", 3, {"closure": 4}, None), ("synthesize_scales", 5, {}, 4),
    ("synthesize_scales", 5, {"closure": 3}, 3), ("synthesize_scales", 5, {"closure": 5}, None),
    ("synthesize_scales", 6, {}, 4), ("synthesize_scales", 6, {"closure": 5}, None),
    ("synthesize_scales", 6, {"closure": 3}, 3), ("synthesize_scales", 7, {}, 5),
    ("synthesize_scales", 7, {"closure": 4}, 4), ("synthesize_scales", 7, {"closure": 6}, None),
    ("synthesize_scales", 8, {}, 5), ("synthesize_scales", 8, {"closure": 6}, None),
    ("synthesize_scales", 10, {}, 5), ("synthesize_scales", 10, {"closure": 4}, 4),
    ("synthesize_scales", 10, {"closure": 6}, None), ("synthesize_scales", 11, {}, 5),
    ("synthesize_scales", 11, {"closure": 6}, None), ("synthesize_scales", 12, {}, 5),
    ("synthesize_scales", 12, {"closure": 4}, 4), ("synthesize_scales", 12, {"closure": 6}, None),
    ("synthesize_scales", 13, {}, 5), ("synthesize_scales", 13, {"closure": 6}, None),
    ("synthesize_scales", 14, {}, 5), ("synthesize_scales", 14, {"closure": 6}, None),
    ("synthesize_scales", 15, {}, 5), ("synthesize_scales", 15, {"closure": 6}, None),
    ("synthesize_scales", 16, {}, 5), ("synthesize_scales", 16, {"closure": 6}, None),
    ("synthesize_scales", 17, {}, 6), ("synthesize_scales", 17, {"closure": 5}, 5),
    ("synthesize_scales", 17, {"closure": 7}, None),
    ("synthesize_scales", 18, {}, 7), ("synthesize_scales", 18, {"closure": 6}, 6),
    ("synthesize_scales", 18, {"closure": 8}, None), ("synthesize_scales", 19, {}, 8),
    ("synthesize_scales", 19, {"closure": 7}, 7), ("synthesize_scales", 19, {"closure": 9}, None),
    ("synthesize_scales", 20, {}, None),
    ("synthesize", 2, {}, 2), ("synthesize", 2, {"closure": 1}, 1),
    ("synthesize", 2, {"closure": 3}, None), ("synthesize", 1, {}, 1),
    ("synthesize", 3, {}, 4), ("synthesize", 3, {"closure": 2}, 2),
    ("synthesize", 3, {"closure": 5}, None), ("synthesize", 4, {}, 5),
    ("synthesize", 4, {"closure": 4}, 4), ("synthesize", 4, {"closure": 6}, None),
    ("synthesize", 5, {}, 7), ("synthesize", 5, {"closure": 6}, 6),
    ("synthesize", 5, {"closure": 5}, 5), ("synthesize", 5, {"closure": 8}, None),
    ("synthesize", 6, {}, 8), ("synthesize", 6, {"closure": 7}, 7),
    ("synthesize", 6, {"closure": 9}, None), ("synthesize", 7, {}, None)])
def test_steps_keep_the_closure_of_their_version(kind, version, obj, closure):
    """Closure 4 (seams closed over shorter stretches) came with Synthesize version 3 and
    SynthesizeScales version 5, closure 5 (the coarsest law chosen quicker) with
    SynthesizeScales version 7, closure 5 of one DPJ (its last column read as the others) with
    Synthesize version 4, closure 6 (rows drawn on their ring) with Synthesize version 5 and
    SynthesizeScales version 17, closure 7 (the last rows pulled towards the first) with
    Synthesize version 5 and SynthesizeScales version 18, closure 8 (pulled at full strength,
    the bottom seam redrawn only where it does not close) with Synthesize version 6 and
    SynthesizeScales version 19:
    an older step keeps the closure it names, or its version's default, and cannot name a
    later one."""
    from texeditor.recipe.codec import action_from_json
    step = {"type": kind, "version": version, "width": 30, "height": 20, "seed": 1,
            "tileable": True, **obj,
            **({"dpjs": ["0123456789abcdef"]} if kind == "synthesize_scales" else
               {"dpj": "0123456789abcdef"})}
    if closure is None:
        with pytest.raises(FormatError):
            action_from_json(step)
    else:
        assert action_from_json(step).closure == closure


@pytest.mark.parametrize("version, obj, redraws", [
    (3, {}, 16), (1, {}, 16), (3, {"coarse_redraws": 4}, None), (4, {}, 4),
    (4, {"coarse_redraws": 16}, 16), (4, {"coarse_redraws": 0}, 0),
    (4, {"coarse_redraws": 17}, None), (4, {"coarse_redraws": True}, None),
    (3, {"tone_balance": True}, None), (4, {"tone_balance": False}, 4)])
def test_a_multiscale_step_keeps_its_coarse_redraws(version, obj, redraws):
    """Steps before version 4 tried 16 times at a dead end of the coarsest scale and drew their
    tone without balance (and cannot name either); version 4 names both: 0 to 16 redraws,
    default COARSE_REDRAWS, and balance, default on."""
    if redraws is None:
        with pytest.raises(FormatError):
            read_scales_step(version, obj)
    else:
        step = read_scales_step(version, obj)
        assert step.coarse_redraws == redraws
        assert step.tone_balance == obj.get("tone_balance", version == 4)


@pytest.mark.parametrize("version, obj, redraws", [
    (11, {}, 16), (3, {}, 16), (11, {"given_redraws": 8}, None), (12, {}, GIVEN_REDRAWS),
    (12, {"given_redraws": 16}, 16), (12, {"given_redraws": 0}, 0),
    (12, {"given_redraws": 17}, None), (12, {"given_redraws": True}, None)])
def test_a_multiscale_step_keeps_its_finer_redraws(version, obj, redraws):
    """Steps before version 12 tried 16 times at a dead end of a scale drawn given its parents
    (and cannot name it); version 12 names 0 to 16, default GIVEN_REDRAWS (8)."""
    if redraws is None:
        with pytest.raises(FormatError):
            read_scales_step(version, obj)
    else:
        step = read_scales_step(version, obj)
        assert step.given_redraws == redraws and step.coarse_redraws == (16 if version < 4
                                                                          else 4)


@pytest.mark.parametrize("version, obj, limit", [
    (12, {}, NO_ROW_LIMIT), (4, {}, NO_ROW_LIMIT), (12, {"coarse_row_redraws": 0.5}, None),
    (13, {}, COARSE_ROW_REDRAWS), (13, {"coarse_row_redraws": 16}, 16.0),
    (13, {"coarse_row_redraws": 0}, 0.0), (13, {"coarse_row_redraws": 16.5}, None),
    (13, {"coarse_row_redraws": -1}, None), (13, {"coarse_row_redraws": True}, None),
    (13, {"coarse_row_redraws": "1"}, None)])
def test_a_multiscale_step_keeps_its_coarsest_row_limit(version, obj, limit):
    """Steps before version 13 let a row of the coarsest scale redraw without limit (and
    cannot name one); version 13 names 0 to 16 a point, default COARSE_ROW_REDRAWS (0.5)."""
    if limit is None:
        with pytest.raises(FormatError):
            read_scales_step(version, obj)
    else:
        step = read_scales_step(version, obj)
        assert step.coarse_row_redraws == limit and step.given_redraws == (
            GIVEN_REDRAWS if version >= 12 else 16)
        assert step.to_json()["version"] == SynthesizeScales.VERSION == 19


def _rezip(data: bytes, change) -> bytes:
    src = zipfile.ZipFile(io.BytesIO(data))
    members = {i.filename: src.read(i) for i in src.infolist()}
    change(members)
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as zf:
        for name, content in members.items():
            zf.writestr(name, content)
    return out.getvalue()


def _tone_with(arrays: dict) -> bytes:
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as zf:
        for name, a in arrays.items():
            buf = io.BytesIO()
            np.lib.format.write_array(buf, a, allow_pickle=False)
            zf.writestr(f"{name}.npy", buf.getvalue())
    return out.getvalue()


def _meta_changed(dpj_bytes: bytes, **changes) -> bytes:
    """A DPJ file with its meta's keys changed (the arrays as they were)."""
    import json
    with np.load(io.BytesIO(dpj_bytes), allow_pickle=False) as npz:
        arrays = {k: npz[k] for k in npz.files}
    meta = {**json.loads(str(arrays["meta"])), **changes}
    out = io.BytesIO()
    np.savez(out, **{**arrays, "meta": np.array(json.dumps(meta))})
    return out.getvalue()


HOSTILE = {
    "no scale": lambda m: m.pop("scale-1.dpj"),
    "parents mark not a bool": lambda m: m.__setitem__(
        "scale-1.dpj", _meta_changed(m["scale-1.dpj"], parents_under="yes")),
    "extra member": lambda m: m.__setitem__("evil.py", b"print(1)"),
    "bad version": lambda m: m.__setitem__("model.json", b'{"format_version": 3, "scales": 2}'),
    "scales not int": lambda m: m.__setitem__("model.json",
                                              b'{"format_version": 2, "scales": "2"}'),
    "json bomb": lambda m: m.__setitem__("model.json", b"[" * 100000),
    "scale not a dpj": lambda m: m.__setitem__("scale-0.dpj", b"not a zip"),
    "scales swapped": lambda m: m.update({"scale-0.dpj": m["scale-1.dpj"],
                                          "scale-1.dpj": m["scale-0.dpj"]}),
    "tone levels too high": lambda m: m.__setitem__("tone.npz", _tone_with(
        {"levels": np.full((8, 8), 9, np.uint8), "grey": np.zeros((8, 8), np.uint8)})),
    "tone shapes differ": lambda m: m.__setitem__("tone.npz", _tone_with(
        {"levels": np.zeros((8, 8), np.uint8), "grey": np.zeros((8, 9), np.uint8)})),
    "tone grey not uint8": lambda m: m.__setitem__("tone.npz", _tone_with(
        {"levels": np.zeros((8, 8), np.uint8), "grey": np.zeros((8, 8), np.float64)})),
    "tone not a zip": lambda m: m.__setitem__("tone.npz", b"\x00" * 50),
}


@pytest.mark.parametrize("case", sorted(HOSTILE))
def test_hostile_model_files_are_refused_with_a_reason(model, case):
    data = _rezip(model.to_bytes(), HOSTILE[case])
    with pytest.raises(FormatError):
        model_from_bytes(data, "hostile.dpj")


def _deflated_npy(zf, name: str, shape) -> None:
    """A member holding a uint8 .npy of zeros of ``shape``, deflated as it is written."""
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "|u1", "fortran_order": False,
                                                  "shape": shape})
    with zf.open(name, "w") as f:
        f.write(header.getvalue())
        f.write(bytes(int(np.prod(shape))))


def test_a_tone_bomb_is_refused_from_its_header_before_it_is_inflated(model):
    """tone.npz is stored in the model, so the model's 512 MiB limit sees only its compressed
    size: levels declared just past MAX_TONE_PIXELS, deflated to a few KB, are refused from
    their .npy header, the array never inflated (a 57 KB model of two 40000² such arrays took
    3.3 GB before it was refused)."""
    import tracemalloc
    from texeditor.photo import model as photo_model
    shape = (photo_model.MAX_TONE_PIXELS // 4096 + 1, 4096)
    tone_npz = io.BytesIO()
    with zipfile.ZipFile(tone_npz, "w", zipfile.ZIP_DEFLATED) as zf:
        _deflated_npy(zf, "levels.npy", shape)
        _deflated_npy(zf, "grey.npy", (8, 8))
    data = _rezip(model.to_bytes(), lambda m: m.__setitem__("tone.npz", tone_npz.getvalue()))
    assert len(data) < 2**20
    tracemalloc.start()
    try:
        with pytest.raises(FormatError, match=r"tone levels of 4096x4097 points, more than the "
                                              r"limit of 16777216"):
            model_from_bytes(data, "bomb.dpj")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 4 * 2**20


@pytest.mark.parametrize("picture", [("grey", np.zeros((8, 9), np.uint8)),
                                     ("colour", np.zeros((8, 8, 3), np.float32)),
                                     ("grey", np.zeros((8, 8, 4), np.uint8))])
def test_a_tones_photo_is_checked_from_its_header_before_any_array_is_read(model, monkeypatch,
                                                                           picture):
    """The photo's declared shape and dtype must fit the levels' before either is read."""
    arrays = {"levels": np.zeros((8, 8), np.uint8), picture[0]: picture[1]}
    data = _rezip(model.to_bytes(), lambda m: m.__setitem__("tone.npz", _tone_with(arrays)))
    read, real = [], np.lib.format.read_array

    def spy(*args, **kwargs):
        array = real(*args, **kwargs)
        read.append(array.shape)
        return array
    monkeypatch.setattr(np.lib.format, "read_array", spy)
    with pytest.raises(FormatError, match="the tone's photo must be uint8 grey or colour"):
        model_from_bytes(data, "hostile.dpj")
    assert read and not [shape for shape in read if shape[:2] == (8, 8)]   # DPJs' only


def test_tone_refuses_levels_it_cannot_show(model):
    with pytest.raises(InputError):
        tone.render(np.full((4, 4), 7, np.uint8), 4, model.tone.levels, model.tone.grey)


@pytest.mark.parametrize("colour, shape, seed", [(False, (300, 170), 5), (True, (97, 260), 7),
                                               (True, (97, 260), 5)])
def test_tone_drawn_beside_the_synthesis_is_the_tone_of_the_finished_levels(colour, shape, seed):
    """The tone runs on a second thread behind the synthesis, on rows said to be final: the
    picture is the one rendered from the finished levels, and no final row changes after;
    or, when the shares were brought back by moves (the last seed), the last call (all rows
    final) is not made and the picture is rendered again from the moved levels."""
    model = acquire_model(speckle((256, 256), seed=2, colour=colour), scales=3)
    result = model.synthesize(shape, seed=seed)
    assert np.array_equal(result.image, model.render(result.levels, seed=seed))

    seen = []
    from texeditor.markov.multiscale import synthesize_scales
    drawn = synthesize_scales(model.scales, shape, seed=seed,
                              rows_final=lambda lv, n: seen.append(lv[:n].copy()))
    final = drawn.levels
    assert np.array_equal(final, result.levels) and seen
    assert (drawn.moved > 0) == (seed == 5 and colour)
    if drawn.moved:
        assert len(seen[-1]) < shape[0]
        return
    assert len(seen[-1]) == shape[0]
    assert all(np.array_equal(rows, final[:len(rows)]) for rows in seen)


@pytest.mark.parametrize("balanced", [False, True])
def test_a_tone_beside_a_synthesis_keeps_to_one_lane_then_takes_two(monkeypatch, balanced):
    """While beside() says the levels are being drawn, rows go on one lane (the synthesis
    keeps its core); after, the rest on two lanes; the picture is the one of two lanes."""
    model = acquire_model(speckle((256, 256), seed=3), scales=2)
    levels = model.synthesize((300, 260), seed=4, tone=False).levels
    wrap = tone.PLAIN | (tone.BALANCED if balanced else 0)
    expected = model.rendering(levels, seed=4, wrap=wrap).grey
    lanes, two = [], tone._two_lanes
    monkeypatch.setattr(tone, "_two_lanes", lambda run, rows, width: (
        lanes.append(rows), two(run, rows, width)))
    drawing = [True]
    renderer = tone.Renderer(levels.shape, model.levels, model.tone.levels, model.tone.grey,
                             seed=4, wrap=wrap)
    renderer.beside = lambda: drawing[0]
    renderer.advance(levels, 150)
    assert lanes == [] and renderer.done == 149             # one lane beside the synthesis
    drawing[0] = False
    renderer.advance(levels, 300)
    assert lanes == [(149, 300)]                            # then both lanes
    assert np.array_equal(renderer.result()[0], expected)


def test_a_fresh_models_tone_index_is_built_on_the_tone_thread(monkeypatch):
    """The tone's index of the photo is built on the tone's thread while the levels are drawn
    (the first synthesis of a model does not wait for it first); the picture is the same."""
    from texeditor.photo import model as model_module
    built_on = []
    real = model_module.tone_index
    monkeypatch.setattr(model_module, "tone_index", lambda *a: built_on.append(
        threading.current_thread().name) or real(*a))
    fresh = acquire_model(speckle((128, 128), seed=3), scales=3)
    result = fresh.synthesize((80, 90), seed=2)
    assert len(built_on) == 1 and built_on[0].startswith("tone")
    assert threading.current_thread().name not in built_on
    assert np.array_equal(result.image, fresh.render(result.levels, seed=2))
    assert len(built_on) == 1            # kept with the model


@pytest.mark.parametrize("colour, shape", [(False, (300, 170)), (True, (97, 260))])
def test_a_tiling_tone_drawn_beside_the_synthesis_is_the_tone_of_the_closed_torus(colour, shape):
    """Closure 3: the tone follows the rows of a torus before it is closed (the closure may
    change them after) and still gives the tone of the closed levels, drawn TILED_LANES
    (balanced: its counts of the rows drawn again start over from them; and without)."""
    model = acquire_model(speckle((256, 256), seed=2, colour=colour), scales=3)
    for size in (shape, (900, 100)):             # the second told of rows before it closes
        result = model.synthesize(size, seed=5, tileable=True)
        finished = tone.TILED_LANES | tone.BALANCED | tone.FINISHED
        assert np.array_equal(result.image, model.render(result.levels, seed=5, wrap=finished))
        unbalanced = model.synthesize(size, seed=5, tileable=True, tone_balance=False,
                                      tone_finish=False)
        assert np.array_equal(unbalanced.image, model.render(result.levels, seed=5,
                                                             wrap=tone.TILED_LANES))
        assert not np.array_equal(unbalanced.image, result.image)
    told = []
    from texeditor.markov.multiscale import synthesize_scales
    final = synthesize_scales(model.scales, (900, 100), seed=5, tileable=True,
                              rows_final=lambda lv, n: told.append(n)).levels
    assert len(told) > 1 and told[-1] == 900
    assert np.array_equal(final, result.levels)
    older = model.synthesize(shape, seed=5, tileable=True, closure=2, tone_balance=False,
                             tone_finish=False)
    assert np.array_equal(older.image, model.render(older.levels, seed=5, wrap=tone.TILED))


def seam_jumps(picture):
    """Mean grey jump across the bottom-top and the right-left seams over that inside."""
    g = picture.astype(float)
    return [np.abs(np.take(g, 0, axis=a) - np.take(g, -1, axis=a)).mean()
            / np.abs(np.diff(g, axis=a)).mean() for a in (0, 1)]


def test_a_tiling_tone_on_two_lanes_shows_no_seam(model):
    """Its seam columns, drawn last, match the points on both sides: the jumps across both
    seams are those of the first tiling tone, well under a tone that does not tile."""
    jumps = {wrap: [] for wrap in (tone.PLAIN, tone.TILED, tone.TILED_LANES)}
    for seed in range(4):
        levels = model.synthesize((96, 128), seed=seed, tileable=True).levels
        for wrap in jumps:
            picture = tone.render(levels, 4, model.tone.levels, model.tone.grey, seed=seed,
                                  wrap=wrap)[0]
            jumps[wrap].append(seam_jumps(picture))
    plain, tiled, lanes = (np.mean(jumps[w], axis=0) for w in jumps)
    assert np.all(lanes < 0.7 * plain) and np.all(lanes < 1.25 * tiled)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(h=st.integers(1, 30), w=st.integers(1, 290), seed=st.integers(0, 2 ** 32),
       told_rows=st.integers(0, 30), balanced=st.booleans(), finished=st.booleans())
def test_a_tiling_tone_on_two_lanes_is_exact_at_any_size(model, h, w, seed, told_rows, balanced,
                                                         finished):
    """Any canvas (narrower than the seam columns, one row, one point): drawn after an edit
    from the last rendering, or band by band from levels that change at the end, the picture
    is the one drawn at once."""
    rng = np.random.default_rng(seed)
    levels = rng.integers(0, 4, (h, w)).astype(np.uint8)
    edited = levels.copy()
    edited[rng.integers(h), rng.integers(w)] ^= 1
    args = (4, model.tone.levels, model.tone.grey)
    way = tone.TILED_LANES | (tone.BALANCED if balanced else 0) | (tone.FINISHED if finished else 0)
    fresh = tone.rendering(edited, *args, seed=seed, wrap=way)
    before = tone.rendering(levels, *args, seed=seed, wrap=way)
    again = tone.rendering(edited, *args, seed=seed, wrap=way, before=before)
    assert np.array_equal(again.grey, fresh.grey) and np.array_equal(again.source, fresh.source)
    assert np.array_equal(again.picture, fresh.picture)
    renderer = tone.Renderer((h, w), *args, seed=seed, wrap=way)
    renderer.advance(levels, min(h - 1, told_rows))
    renderer.advance(edited, h)
    assert np.array_equal(renderer.result()[0], fresh.grey)


@pytest.mark.parametrize("way", [tone.TILED_LANES, tone.TILED_LANES | tone.BALANCED])
@pytest.mark.parametrize("change, redrawn_from", [("seam columns", None), ("last rows", 88),
                                                  ("a middle row", 49), ("row 99", 97),
                                                  ("row 0", 0)])
def test_a_tiling_tone_drawn_before_the_closure_draws_again_only_what_it_changed(
        model, monkeypatch, change, redrawn_from, way):
    """Levels told of, then changed where a torus's closure changes them: the picture is that
    of the final levels; changes in the seam columns leave the rest as drawn, a change in a
    row has the rows from the one above it drawn again (drawing order: picture row k + 1)."""
    final = model.synthesize((100, 300), seed=1, tileable=True).levels
    told = final.copy()
    if change == "seam columns":
        told[:, -5:] = (told[:, -5:] + 1) % 4
    elif change == "last rows":
        told[90:] = (told[90:] + 1) % 4
    elif change == "a middle row":
        told[51, 100:140] = (told[51, 100:140] + 1) % 4
    else:                                            # row 0 is drawn last, row 1 first
        row = int(change.split()[1])
        told[row, :30] = (told[row, :30] + 1) % 4
    fresh = tone.rendering(final, 4, model.tone.levels, model.tone.grey, seed=6, wrap=way)
    renderer = tone.Renderer(final.shape, 4, model.tone.levels, model.tone.grey, seed=6,
                             wrap=way)
    for n in range(10, 100, 30):
        renderer.advance(told, n)
    assert 0 < renderer.done < 100
    starts = []
    real = tone.Renderer._rows
    monkeypatch.setattr(tone.Renderer, "_rows",
                        lambda self, codes, stop, width: starts.append(self.done)
                        or real(self, codes, stop, width))
    renderer.advance(told, 100)                        # told rows drawn to the end first
    starts.clear()
    renderer.advance(final, 100)
    assert np.array_equal(renderer.result()[0], fresh.grey)
    assert np.array_equal(renderer.sources(), fresh.source)
    assert starts == ([] if redrawn_from is None else [redrawn_from])
    renderer.advance(final, 100)                       # the same levels again: nothing drawn
    assert starts == ([] if redrawn_from is None else [redrawn_from])


def test_cancel_stops_the_synthesis_and_its_tone(model):
    from texeditor.errors import Cancelled
    calls = []
    with pytest.raises(Cancelled):
        model.synthesize((600, 600), seed=1, progress=calls.append,
                         cancel=lambda: len(calls) >= 3)
    assert model.synthesize((40, 40), seed=1).image.shape == (40, 40)   # nothing left stuck


@pytest.mark.parametrize("way", [tone.PLAIN | tone.BALANCED, tone.TILED_LANES])
def test_a_tone_told_to_stop_stops_between_chunks(model, way):
    """A rendering whose levels went stale (rebalanced after their rows were told final) is
    stopped at its next chunk of rows, wherever it is."""
    from texeditor.errors import Cancelled
    levels = model.synthesize((160, 300), seed=1, tone=False).levels
    stop, chunks = [False], []
    renderer = tone.Renderer(levels.shape, 4, model.tone.levels, model.tone.grey, seed=6,
                             wrap=way, cancel=lambda: chunks.append(1) or stop[0])
    renderer.advance(levels, 60)
    assert chunks and renderer.done > 0
    stop[0] = True
    with pytest.raises(Cancelled):
        renderer.advance(levels, 160)


def test_a_colour_photo_gives_colour_classes_at_every_scale():
    """Red and green of one grey: a grey quantiser cannot tell them apart, the default (CIELAB
    classes) keeps them as levels of their own, and the texture draws each from its class."""
    rng = np.random.default_rng(3)
    blobs = ski.filters.gaussian(rng.random((256, 256)), 6) > 0.5
    red, green = np.array([200, 60, 60]), np.array([40, 110, 40])     # one luminance, 90
    noise = rng.integers(-12, 13, (256, 256, 1))
    photo = np.clip(np.where(blobs[..., None], red, green) + noise, 0, 255).astype(np.uint8)
    lab = acquire_model(photo, scales=2, levels=2)
    grey = acquire_model(photo, scales=2, levels=2, quantizer="lloyd")
    hue = lambda c: int(np.argmax(c[:2]))        # 0: red wins, 1: green wins
    assert sorted(hue(c) for c in lab.palette) == [0, 1]
    assert len({hue(c) for c in grey.palette}) == 1 or np.abs(
        grey.palette[0].astype(int) - grey.palette[1]).max() < 40
    out = lab.synthesize((96, 96), seed=2)
    for level in range(2):
        pixels = out.image[out.levels == level].astype(int)
        assert np.all(np.argmax(pixels[:, :2], axis=1) == hue(lab.palette[level]))


@pytest.mark.parametrize("way", [tone.PLAIN, tone.BALANCED, tone.TILED_LANES,
                                 tone.TILED_LANES | tone.BALANCED])
@pytest.mark.parametrize("rows, columns", [(8, 128), (3, 5), (2, 1)])
def test_two_lanes_render_the_picture_of_one_scan(model, monkeypatch, rows, columns, way):
    """The tone's two-lane wavefront (strips on two threads, each chunk waiting for the strip
    above) gives the picture of one scan in order, whatever the strip and chunk sizes; with
    balance too (each strip's weights count rows the other lane has finished), and on a tiling
    picture (TILED_LANES: the seam columns after the rest)."""
    tiling = way & ~tone.BALANCED == tone.TILED_LANES
    levels = model.synthesize((150, 301), seed=3, tileable=tiling).levels
    args = (levels, 4, model.tone.levels, model.tone.grey)
    monkeypatch.setattr(tone, "LANE_ROWS", 10 ** 6)          # one strip: the plain scan
    one = tone.render(*args, seed=8, wrap=way)[0]
    monkeypatch.setattr(tone, "LANE_ROWS", rows)
    monkeypatch.setattr(tone, "LANE_COLUMNS", columns)
    lanes = []
    real = tone._two_lanes
    monkeypatch.setattr(tone, "_two_lanes", lambda *a: lanes.append(1) or real(*a))
    two = tone.render(*args, seed=8, wrap=way)[0]
    assert lanes and np.array_equal(one, two)
    assert not np.array_equal(two, tone.render(*args, seed=9, wrap=way)[0])
    assert not np.array_equal(two, tone.render(*args, seed=8, wrap=way ^ tone.BALANCED)[0])
    if tiling:
        assert not np.array_equal(two, tone.render(*args, seed=8, wrap=tone.TILED)[0])


@pytest.mark.parametrize("width", [128, 256, 1000])
def test_the_second_lane_starts_before_the_first_strip_ends(width):
    """Each strip is cut into LANE_CHUNKS chunks or more, so the lane below starts while the
    strip above is still drawn (with two chunks a strip, as 256² pictures had, the two lanes
    took turns: one core)."""
    started = threading.Event()
    chunks = []

    def run(rows, columns):
        chunks.append((rows, columns))
        if rows[0] == tone.LANE_ROWS:
            started.set()
        elif rows[0] == 0 and columns[1] > width:       # the first strip's last chunk
            assert started.wait(10), "the second lane waited for the whole first strip"
    tone._two_lanes(run, (0, 4 * tone.LANE_ROWS), width)
    first = [c for r, c in chunks if r[0] == 0]
    assert len(first) >= tone.LANE_CHUNKS and first[0][0] == 0
    assert all(a[1] == b[0] for a, b in zip(first, first[1:]))      # they cover the row


def test_an_error_in_a_tone_lane_reaches_the_caller(monkeypatch):
    calls = []

    def run(rows, columns):
        calls.append(rows)
        if len(calls) == 5:
            raise MemoryError("lane")
    with pytest.raises(MemoryError):
        tone._two_lanes(run, (0, 64), 1000)
    assert len(calls) < 64 // tone.LANE_ROWS * 8         # the other lane stopped too


@pytest.mark.parametrize("wrap", [False, True, tone.TILED_LANES, tone.BALANCED,
                                  tone.TILED_LANES | tone.BALANCED,
                                  tone.BALANCED | tone.FINISHED,
                                  tone.TILED_LANES | tone.BALANCED | tone.FINISHED])
@pytest.mark.parametrize("colour", [False, True])
def test_a_rendering_after_an_edit_keeps_the_rows_above_and_matches_a_fresh_one(wrap, colour,
                                                                                 monkeypatch):
    """The window draws the tone again after each edit from the previous rendering: the rows
    above the first changed one are kept, and the picture is the one drawn from scratch."""
    model = acquire_model(speckle((200, 200), seed=4, colour=colour), scales=2)
    levels = model.synthesize((90, 140), seed=2, tileable=bool(wrap & 3)).levels
    drawn = model.rendering(levels, seed=2, wrap=wrap)
    starts = []
    real = tone.Renderer.resume
    monkeypatch.setattr(tone.Renderer, "resume",
                        lambda self, before, start: starts.append(start) or real(self, before, start))
    expected = {False: (59, 29, 1, 0, 88), True: (59, 29, 1, 0, 0),
                tone.TILED_LANES: (58, 28, 0, 0, 87)}[wrap & 3]  # the last: picture row 0 first
    for top, expected_start in zip((60, 30, 2, 0, 89), expected):
        edited = drawn.levels.copy()
        edited[top:top + 1, 20:70] = (edited[top:top + 1, 20:70] + 1) % 4
        again = model.rendering(edited, seed=2, wrap=wrap, before=drawn)
        fresh = model.rendering(edited, seed=2, wrap=wrap)
        assert np.array_equal(again.picture, fresh.picture)
        assert np.array_equal(again.source, fresh.source)
        assert tone.first_row_to_draw(drawn, edited, 2, wrap) == expected_start
        drawn = again
    assert starts == [start for start in expected if start]   # from 0: everything drawn
    assert model.rendering(drawn.levels, seed=2, wrap=wrap, before=drawn) is drawn
    other_seed = model.rendering(drawn.levels, seed=3, wrap=wrap, before=drawn)
    assert np.array_equal(other_seed.picture, model.render(drawn.levels, seed=3, wrap=wrap))


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 12), st.integers(1, 12))
def test_a_match_is_the_sum_over_the_causal_neighbourhood_inside_both_pictures(seed, h, w):
    """tone._distance is the sum of squared grey differences over the 12 causal neighbours that
    lie in both pictures, before ``limit``; so is _distance_near, from the gathered greys, where
    they all do (most points)."""
    rng = np.random.default_rng(seed)
    grey = rng.integers(0, 256, (h, w), dtype=np.uint8)
    photo = rng.integers(0, 256, (rng.integers(1, 12), rng.integers(1, 12)), dtype=np.uint8)
    i, j = rng.integers(0, h), rng.integers(0, w)
    pi, pj = rng.integers(0, photo.shape[0]), rng.integers(0, photo.shape[1])
    limit = rng.integers(j, w + 1)
    expected = 0
    for di in range(-tone.HALF, 1):
        for dj in range(-tone.HALF, tone.HALF + 1 if di < 0 else 0):
            y, x, py, px = i + di, j + dj, pi + di, pj + dj
            if 0 <= y and 0 <= x < limit and 0 <= py and 0 <= px < photo.shape[1]:
                expected += (int(grey[y, x]) - int(photo[py, px])) ** 2
    assert tone._distance(grey, i, j, photo, pi, pj, np.inf, limit) == expected
    early = tone._distance(grey, i, j, photo, pi, pj, expected - 1, limit)
    assert early > expected - 1 if expected else early == 0
    half = tone.HALF
    if half <= min(i, j, pi) and j + half < limit and half <= pj < photo.shape[1] - half:
        near = np.empty(tone.NEIGHBOURS, np.int32)
        tone._gather(grey, i, j, near)
        assert tone._distance_near(near, photo, pi, pj) == expected


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([2, 4, 64, 3**9, 2**22 + 1]))
def test_the_tone_index_groups_points_as_a_stable_sort_would(seed, space):
    """tone._grouped (a counting sort below GROUPED_SPACE, a sort above) gives the codes
    present, where each starts and the points in code order, ties in index order."""
    rng = np.random.default_rng(seed)
    code = rng.integers(0, min(space, 50), rng.integers(1, 3000)) * (space // 50 or 1)
    code = np.minimum(code, space - 1).astype(np.int64)
    order = np.argsort(code, kind="stable")
    unique, first = np.unique(code[order], return_index=True)
    got = tone._grouped(code, space)
    assert np.array_equal(got[0], unique) and np.array_equal(got[1], first)
    assert np.array_equal(got[2], order)


@pytest.mark.parametrize("g", [2, 4, 5, 6, 11])
def test_the_tone_finds_a_context_by_table_or_by_search_alike(g, monkeypatch):
    """Below DIRECT_SPACE (G ≤ 5) a 3×3 context finds its photo points in a look-up table, else
    by a binary search: both give the same pictures (plain, balanced, tiling, colour). From
    G = 11 the codes no longer fit int32 (tone._code_type): the search runs on int64 codes."""
    photo = ski.data.coffee()[:90, :120]
    levels = texeditor.quantize(photo, g, "lab").levels
    grey = (ski.color.rgb2gray(photo) * 255).astype(np.uint8)
    out = np.ascontiguousarray(np.rot90(levels)[:70, :80])
    out[10:20, 5:40] = np.random.default_rng(g).integers(0, g, (10, 35))   # unseen contexts
    table = tone.tone_index(levels, g)
    assert (len(table.direct) == g ** 9) is (g ** 9 <= tone.DIRECT_SPACE)
    monkeypatch.setattr(tone, "DIRECT_SPACE", 0)
    searched = tone.tone_index(levels, g)
    assert len(searched.direct) == 0
    for way in (tone.PLAIN, tone.PLAIN | tone.BALANCED, tone.TILED, tone.TILED_LANES):
        args = (out, g, levels, grey, photo)
        a = tone.render(*args, seed=3, wrap=way, index=table)
        b = tone.render(*args, seed=3, wrap=way, index=searched)
        assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert table.codes[0].dtype == (np.int32 if g <= 10 else np.int64)


def test_int32_context_codes_draw_the_pictures_int64_codes_drew(monkeypatch):
    """The tone reads its codes as int32 when they fit (a tenth off its time): the pictures
    are those of the int64 codes before (plain, balanced, tiling, both tilings' lanes)."""
    photo = ski.data.gravel()[:96, :96]
    levels = texeditor.quantize(photo, 4, "lloyd").levels
    out = np.ascontiguousarray(np.rot90(levels)[:80, :150])    # wide enough for two lanes
    ways = (tone.PLAIN, tone.PLAIN | tone.BALANCED | tone.FINISHED, tone.TILED,
            tone.TILED_LANES | tone.BALANCED)
    narrow = tone.tone_index(levels, 4, photo)
    assert narrow.codes[0].dtype == np.int32 and narrow.points[0].dtype == np.int32
    now = [tone.render(out, 4, levels, photo, seed=5, wrap=w, index=narrow)[0] for w in ways]
    monkeypatch.setattr(tone, "_code_type", lambda g: np.int64)
    wide = tone.tone_index(levels, 4, photo)
    wide = wide._replace(points=tuple(p.astype(np.int64) for p in wide.points))   # as before
    assert wide.codes[0].dtype == np.int64
    for way, picture in zip(ways, now):
        before = tone.render(out, 4, levels, photo, seed=5, wrap=way, index=wide)[0]
        assert np.array_equal(picture, before)


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 2**20), st.integers(0, 2**40 - 1))
def test_a_photo_point_splits_into_row_and_column_as_a_division_would(pw, s):
    assert tone._split(np.int64(s), np.int64(pw), 1.0 / pw) == divmod(s, pw)
    k = s // pw * pw                                # the multiples, where a float quotient
    for t in (k, k + pw - 1, max(k - 1, 0)):        # may round to either side
        assert tone._split(np.int64(t), np.int64(pw), 1.0 / pw) == divmod(t, pw)


def test_a_models_level_shares_are_counted_once_and_cannot_be_changed_from_outside(model):
    shares = model.frequencies()
    shares[:] = 0
    again = model.frequencies()
    counts = np.bincount(model.tone.levels.ravel(), minlength=model.levels)
    assert np.array_equal(again, counts / counts.sum())
    index = model._index()
    assert np.array_equal(index.shares, tone._grey_shares(model.tone.levels, model.tone.grey,
                                                          model.levels))


@pytest.mark.parametrize("photo", [ski.data.astronaut()[::2, ::2], ski.data.camera()[::2, ::2],
                                   (np.random.default_rng(4).random((190, 230, 4)) * 255
                                    ).astype(np.uint8)])
def test_a_model_is_the_same_however_a_large_photo_is_cut_into_bands(photo, monkeypatch):
    """Large photos are converted a band of rows (or a chunk of colours) at a time, and their
    colours counted rather than sorted: the model is the one made in one go."""
    from texeditor.markov import levels, multiscale
    from texeditor.photo import model as model_module

    def fingerprint(m):
        arrays = [m.tone.levels, m.tone.grey] + ([m.tone.colour] if m.tone.colour is not None
                                                 else [])
        for d in m.scales.dpjs:
            arrays += [d.configs, d.probs, np.asarray(d.palette)]
        return arrays
    whole = fingerprint(acquire_model(photo, scales=3))
    for module, name, value in ((multiscale, "PYRAMID_ROWS", 2), (model_module, "TONE_ROWS", 3),
                                (levels, "LAB_CHUNK", 7), (levels, "COUNTED_COLOURS", 1)):
        monkeypatch.setattr(module, name, value)
    banded = fingerprint(acquire_model(photo, scales=3))
    assert len(whole) == len(banded)
    assert all(a.dtype == b.dtype and np.array_equal(a, b) for a, b in zip(whole, banded))
