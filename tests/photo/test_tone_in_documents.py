"""A photo model's tone travels with the textures drawn from it: a multi-scale synthesis names
the photo and its finest levels (two exemplars), so a `.texture`, a bank entry and `texeditor
render` show the texture as it was made, not in four flat palette colours."""

import io
import json
import zipfile

import numpy as np
import pytest
from PIL import Image

from texeditor import Bank
from texeditor.bank.store import THUMB, document_thumbnail, thumbnail_png
from texeditor.cli import main as cli
from texeditor.errors import FormatError, InputError, TexeditorError
from texeditor.photo import acquire_model, document_model, document_tone
from texeditor.recipe.actions import SynthesizeScales
from texeditor.recipe.texturefile import render_texture, save_texture, synthesize_scales_texture
from tests.support.photo import speckle


@pytest.fixture(scope="module", params=["grey", "colour"])
def model(request):
    return acquire_model(speckle((96, 112), seed=2, colour=request.param == "colour"), scales=2)


def made(model, tmp_path, tileable=False):
    history = synthesize_scales_texture(model.scales.dpjs, 70, 50, seed=3, tileable=tileable,
                                        tone=model.tone_pictures())
    path = tmp_path / "t.texture"
    save_texture(path, history)
    return path


@pytest.mark.parametrize("tileable", [False, True])
def test_a_reopened_texture_shows_the_picture_the_model_drew(model, tmp_path, tileable):
    doc = render_texture(made(model, tmp_path, tileable))
    want = model.synthesize((50, 70), seed=3, tileable=tileable)
    assert np.array_equal(doc.levels, want.levels)
    assert np.array_equal(document_tone(doc), want.image)      # tone, colour and seed kept
    assert len(np.unique(want.image)) > 2 * model.levels       # shaded, not the palette


def test_without_a_tone_the_palette_shows(model, tmp_path):
    history = synthesize_scales_texture(model.scales.dpjs, 40, 30, seed=1)
    save_texture(tmp_path / "p.texture", history)
    doc = render_texture(tmp_path / "p.texture")
    assert doc.actions[-1].tone_photo is None and document_tone(doc) is None


def test_an_older_log_without_tone_parameters_still_reads(model, tmp_path):
    """Logs written before the tone parameters existed lack them: they read, with no tone."""
    path = tmp_path / "old.texture"
    save_texture(path, synthesize_scales_texture(model.scales.dpjs, 40, 30, seed=1))
    members = {i.filename: zipfile.ZipFile(path).read(i) for i in zipfile.ZipFile(path).infolist()}
    log = json.loads(members["actions.json"])
    steps = log["actions"] if isinstance(log, dict) else log
    assert all(step.pop("tone_photo", 0) is None and step.pop("tone_levels", 0) is None
               for step in steps if step["type"] == "synthesize_scales")
    members["actions.json"] = json.dumps(log).encode()
    with zipfile.ZipFile(path, "w") as zf:
        for name, data in members.items():
            zf.writestr(name, data)
    doc = render_texture(path)
    assert doc.actions[-1].tone_levels is None and document_tone(doc) is None


def test_a_tone_names_both_its_pictures(model):
    refs = tuple(d.ref for d in model.scales.dpjs)
    with pytest.raises(InputError, match="both"):
        SynthesizeScales(refs, 8, 8, 0, tone_photo="0123456789abcdef")
    with pytest.raises(InputError, match="exemplar reference"):
        SynthesizeScales(refs, 8, 8, 0, tone_photo="no", tone_levels="0123456789abcdef")


def test_a_tone_whose_pictures_are_missing_does_not_replay(model):
    history = synthesize_scales_texture(model.scales.dpjs, 20, 20, seed=1)
    step = history.actions[-1]
    bad = SynthesizeScales(step.dpjs, 20, 20, 1, tone_photo="0123456789abcdef",
                           tone_levels="fedcba9876543210")
    with pytest.raises(TexeditorError, match="not part of this document"):
        history.apply(bad)


def test_levels_that_are_not_the_models_are_refused_and_the_thumbnail_falls_back(model):
    """A hostile entry may name pictures that hash right but do not fit the scales: the tone is
    refused (FormatError) and the bank's thumbnail shows the palette instead of failing."""
    history = synthesize_scales_texture(model.scales.dpjs, 30, 30, seed=1)
    photo, levels = model.tone_pictures()
    wrong = history.add_exemplar(np.full_like(levels, 200))
    step = SynthesizeScales(history.actions[-1].dpjs, 30, 30, 1,
                            tone_photo=history.add_exemplar(photo), tone_levels=wrong)
    history.apply(step)
    with pytest.raises(FormatError):
        document_model(history.document)
    assert document_thumbnail(history.document) == thumbnail_png(history.document.levels,
                                                                 history.document.palette)


def test_a_bank_entry_keeps_the_tone_and_its_thumbnail_shows_it(model, tmp_path):
    bank = Bank(tmp_path / "bank")
    history = synthesize_scales_texture(model.scales.dpjs, 70, 50, seed=3,
                                        tone=model.tone_pictures())
    entry = bank.add(history, "toned")
    reopened = bank.open(entry).document
    want = model.synthesize((50, 70), seed=3).image
    assert np.array_equal(document_tone(reopened), want)
    png = bank.thumbnails([entry])[entry]
    assert png == document_thumbnail(reopened)
    shown = np.asarray(Image.open(io.BytesIO(png)))
    flat = np.asarray(Image.open(io.BytesIO(thumbnail_png(reopened.levels, reopened.palette,
                                                          THUMB))))
    assert shown.shape[:2] == flat.shape[:2] and not np.array_equal(shown, flat)


def test_the_command_line_renders_a_texture_as_resynth_drew_it(tmp_path, capsys):
    photo = tmp_path / "photo.png"
    Image.fromarray(speckle((80, 80), seed=5, colour=True)).save(photo)
    args = ["resynth", str(photo), "--size", "48x40", "--seed", "7", "--scales", "2"]
    assert cli(args + ["-o", str(tmp_path / "direct.png")]) == 0
    assert cli(args + ["-o", str(tmp_path / "t.texture")]) == 0
    assert cli(["render", str(tmp_path / "t.texture"), "-o", str(tmp_path / "again.png")]) == 0
    assert "with its photo's tone" in capsys.readouterr().out
    direct = np.asarray(Image.open(tmp_path / "direct.png"))
    assert direct.shape == (40, 48, 3)
    assert np.array_equal(np.asarray(Image.open(tmp_path / "again.png")), direct)
    assert cli(["render", str(tmp_path / "t.texture"), "--no-tone",
                "-o", str(tmp_path / "flat.png")]) == 0
    flat = np.asarray(Image.open(tmp_path / "flat.png"))
    assert len(np.unique(flat.reshape(-1, flat.shape[-1]), axis=0)) <= 4
