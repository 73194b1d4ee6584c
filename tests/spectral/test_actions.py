"""The model steps (random-phase noise, texton, histogram matching) as Actions on documents
that hold exemplar photos: computed as the engine functions say, replayed identical from files
and the bank, undone, and every stored exemplar checked."""

import hashlib
import io
import json
import struct
import zipfile

import numpy as np
import pytest
from skimage.exposure import match_histograms

from texeditor.bank.store import Bank
from texeditor.errors import FormatError, InputError, ReplayError
from texeditor.markov.levels import quantize
from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.recipe.document import Document
from texeditor.recipe.exemplars import exemplar_png
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.recipe.texturefile import load_texture, parse_texture, save_texture, texture_bytes
from texeditor.spectral import random_phase_noise, texton
from texeditor.spectral.actions import MatchHistogram, RandomPhaseNoise, Texton

from tests.support.spectral import COLOUR, GREY, colour_photo, grey_photo, history


def test_an_exemplars_reference_hashes_tag_shape_and_pixels():
    photo = colour_photo()
    digest = hashlib.sha256(b"texeditor-exemplar-v1" + struct.pack("<3I", 24, 32, 3)
                            + photo.tobytes()).hexdigest()
    doc = Document()
    assert doc.add_exemplar(photo) == COLOUR == digest[:16]
    assert doc.add_exemplar(grey_photo()) == GREY
    assert not doc.exemplars[COLOUR].flags.writeable


@pytest.mark.parametrize("bad", [np.zeros((8, 8), np.float32), np.zeros((8, 8, 4), np.uint8),
                                 np.zeros((1025, 4), np.uint8), np.zeros((1, 9), np.uint8)])
def test_bad_exemplars_are_refused(bad):
    with pytest.raises(InputError):
        Document().add_exemplar(bad)


def test_an_exemplar_under_another_reference_is_refused():
    with pytest.raises(InputError):
        Document().add_exemplar(grey_photo(), ref=COLOUR)


@pytest.mark.parametrize("ref, photo", [(COLOUR, colour_photo()), (GREY, grey_photo())])
def test_random_phase_noise_is_the_models_output_cut_into_levels(ref, photo):
    h = history()
    h.apply(RandomPhaseNoise(ref, 50, 36, seed=4, levels=6))
    q = quantize(random_phase_noise(photo, (36, 50), seed=4), 6, "lab")
    doc = h.document
    assert doc.shape == (36, 50) and doc.num_levels == 6
    assert np.array_equal(doc.levels, q.levels) and np.array_equal(doc.palette, q.palette)
    h.apply(RandomPhaseNoise(ref, 50, 36, seed=5, levels=6))
    assert not np.array_equal(h.document.levels, q.levels)
    h.undo()
    h.undo()
    assert doc.shape == (8, 12) and doc.num_levels == 3                 # the drawn texture again


def test_the_texton_is_at_the_exemplars_size_and_peaks_in_the_middle():
    h = history()
    h.apply(Texton(GREY, levels=4))
    expected = quantize(texton(grey_photo()), 4, "lab")
    assert np.array_equal(h.document.levels, expected.levels)
    assert h.document.shape == (20, 20) and h.document.levels[10, 10] == 3   # the brightest


def displayed_matched(doc, reference):
    """scikit-image's match_histograms on the picture shown, as floats, rounded."""
    shown = doc.palette[doc.levels].astype(np.float64)
    ref = reference if reference.ndim == 3 else np.repeat(reference[..., None], 3, axis=2)
    return np.round(match_histograms(shown, ref.astype(np.float64), channel_axis=-1))


@pytest.mark.parametrize("ref, photo", [(COLOUR, colour_photo()), (GREY, grey_photo())])
def test_match_histogram_is_phi_on_the_picture_shown(ref, photo):
    h = history()
    h.apply(RandomPhaseNoise(GREY, 30, 20, seed=1, levels=5))
    levels = h.document.levels.copy()
    expected = displayed_matched(h.document, photo)
    h.apply(MatchHistogram(ref))
    doc = h.document
    assert np.array_equal(doc.levels, levels)
    assert np.array_equal(doc.palette[doc.levels], expected)
    h.undo()
    assert not np.array_equal(h.document.palette[h.document.levels], expected)


def test_match_histogram_by_hand():
    """Two levels, 3 points dark and 1 bright; reference values 0, 10, 20, 30: the dark level
    is at cumulative share 3/4 → 20, the bright one at 1 → 30 (φ = c_f⁻¹ ∘ c_g)."""
    doc = Document()
    doc.add_exemplar(np.array([[0, 10], [20, 30]], np.uint8))
    doc.apply(NewCanvas(2, 2, 2))
    doc.apply(SetLevels(0, 0, 1, 1, 1))
    ref = next(iter(doc.exemplars))
    doc.apply(MatchHistogram(ref))
    assert doc.palette.tolist() == [[20, 20, 20], [30, 30, 30]]


def test_a_step_without_its_exemplar_is_refused_and_does_not_replay():
    h = History()
    with pytest.raises(InputError, match="exemplar"):
        h.apply(RandomPhaseNoise(COLOUR, 10, 10))
    assert h.document.shape == (0, 0) and not h.actions
    with pytest.raises(ReplayError):
        replay([RandomPhaseNoise(COLOUR, 10, 10)], {})


def test_a_flat_exemplar_is_a_clear_error():
    h = History()
    ref = h.add_exemplar(np.full((8, 8), 90, np.uint8))
    with pytest.raises(InputError, match="levels"):
        h.apply(RandomPhaseNoise(ref, 16, 16))
    with pytest.raises(InputError):
        RandomPhaseNoise(ref, 5000, 16)                    # beyond a model's canvas


def test_a_texture_file_keeps_the_exemplars_its_log_uses(tmp_path):
    h = history()
    h.apply(RandomPhaseNoise(COLOUR, 40, 30, seed=3))
    h.apply(MatchHistogram(COLOUR))
    manifest = save_texture(tmp_path / "t.texture", h)
    assert manifest.exemplars == (COLOUR,)          # GREY is held but not used: not saved
    with zipfile.ZipFile(tmp_path / "t.texture") as zf:
        assert f"exemplars/{COLOUR}.png" in zf.namelist()
    again, _ = load_texture(tmp_path / "t.texture")
    assert again.document.result_hash() == h.document.result_hash()
    assert np.array_equal(again.document.exemplars[COLOUR], colour_photo())
    again.undo()
    again.apply(RandomPhaseNoise(COLOUR, 40, 30, seed=3, levels=4))       # edits go on


def test_a_file_without_exemplars_has_the_manifest_of_before():
    doc = Document.new(4, 4, 2)
    data, _ = texture_bytes(doc, doc.actions)
    with zipfile.ZipFile(io.BytesIO(data)) as zf:
        assert "exemplars" not in json.loads(zf.read("manifest.json"))


def rewritten(data: bytes, change) -> bytes:
    """The archive with its members passed through ``change(name, bytes) -> (name, bytes)``."""
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(data)) as zin, zipfile.ZipFile(out, "w") as zout:
        for info in zin.infolist():
            item = change(info.filename, zin.read(info))
            if item is not None:
                zout.writestr(item[0], item[1])
    return out.getvalue()


def forged_png(name, data):
    if name.endswith(".png"):
        image = colour_photo().copy()
        image[0, 0] ^= 1
        return name, exemplar_png(image)
    return name, data


def big_png(name, data):
    return (name, exemplar_png(np.zeros((4, 1100), np.uint8))) if name.endswith(".png") else \
        (name, data)


def dropped_png(name, data):
    return None if name.endswith(".png") else (name, data)


def not_png(name, data):
    return (name, b"GIF89a" + data[6:]) if name.endswith(".png") else (name, data)


@pytest.mark.parametrize("change", [forged_png, big_png, dropped_png, not_png])
def test_a_damaged_exemplar_member_is_refused(change):
    h = history()
    h.apply(Texton(COLOUR))
    data, _ = texture_bytes(h.document, h.applied)
    with pytest.raises(FormatError):
        parse_texture(rewritten(data, change))


def test_the_bank_keeps_exemplars_shared_and_purges_them(tmp_path):
    with Bank(tmp_path / "b.sqlite", builtins=False) as bank:
        h = history()
        h.apply(RandomPhaseNoise(COLOUR, 30, 30, seed=8, levels=4))
        first = bank.add(h, "noise")
        copy = bank.duplicate(first)
        again = bank.open(copy).document
        assert again.result_hash() == h.document.result_hash()
        assert list(again.exemplars) == [COLOUR]
        out = tmp_path / "x.texture"
        bank.export_texture(first, out)
        assert load_texture(out)[0].document.result_hash() == h.document.result_hash()
        bank.trash(first)
        bank.purge()
        assert bank.open(copy).document.exemplars            # still used by the copy
        bank.trash(copy)
        bank.purge()
        assert bank._read("SELECT count(*) FROM exemplars")[0][0] == 0


def test_editing_a_past_model_step_replays_with_its_exemplar():
    h = history()
    h.apply(RandomPhaseNoise(GREY, 20, 20, seed=1, levels=3))
    h.apply(SetLevels(0, 0, 2, 2, 0))
    h.replace(3, RandomPhaseNoise(GREY, 20, 20, seed=2, levels=3))
    expected = quantize(random_phase_noise(grey_photo(), (20, 20), seed=2), 3, "lab").levels
    expected[:2, :2] = 0
    assert np.array_equal(h.document.levels, expected)


def test_a_crash_journal_keeps_the_exemplars_and_recovers_the_model_steps(tmp_path):
    from texeditor.recipe.journal import Journal, recover
    h = history()
    journal = Journal(tmp_path)
    journal.reset(h.applied, h.document.dpjs, exemplars=h.document.exemplars)
    h.apply(RandomPhaseNoise(COLOUR, 24, 20, seed=6, levels=4))
    journal.sync(h.applied, h.document.dpjs, h.document.exemplars)
    h.apply(MatchHistogram(GREY))
    journal.sync(h.applied, h.document.dpjs, h.document.exemplars)
    found = recover(journal.path)
    assert set(found.exemplars) == {COLOUR, GREY}
    again = History.from_log(found.actions, found.dpjs, exemplars=found.exemplars)
    assert again.document.result_hash() == h.document.result_hash()
    journal.discard()
