"""Stored pictures (issue 16): a first start shows and indexes the built-ins without the synthesis
kernels. A picture stands for a replay only when it is the recorded texture; anything else is
refused and the entry is replayed as before. Also the kernels' background warm-up."""

import dataclasses
import io
import zipfile
from pathlib import Path

import numpy as np
import pytest

from texeditor.bank import store as bk
from texeditor import warmup
from texeditor.markov import synthesis
from texeditor.recipe.actions import SetLevels, SetPalette, Synthesize
from texeditor.recipe.codec import log_text
from texeditor.bank.store import Bank, picture_bytes, read_picture, write_picture
from texeditor.markov.dpj import DPJ
from texeditor.recipe.history import History
from texeditor.recipe.texturefile import read_texture, render_texture

BUILTINS = sorted(bk.BUILTIN_DIR.glob("*.texture"))


def tiny_dpj(seed: int = 0) -> DPJ:
    rng = np.random.default_rng(seed)
    return DPJ.from_codes(np.arange(16), rng.dirichlet(np.ones(16)), 2, (2, 2))


@pytest.fixture
def no_synthesis(monkeypatch):
    """Any synthesis fails the test: what is shown must come from a stored picture."""
    def refuse(*args, **kwargs):
        raise AssertionError("a synthesis ran")
    monkeypatch.setattr(synthesis, "synthesize", refuse)
    monkeypatch.setattr(synthesis, "synthesize_given", refuse)    # a multi-scale one's finer
    yield


@pytest.fixture
def builtin_bank(tmp_path):
    with Bank(tmp_path / "bank.sqlite") as bank:
        yield bank


def gravel(bank, name: str = "Gravel") -> int:
    return next(e.id for e in bank.search("gravel") if e.name == name)


def forge(path: Path, levels, palette) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(picture_bytes(levels, palette))


# -- the bundled pictures ---------------------------------------------------------------------

@pytest.mark.parametrize("path", BUILTINS, ids=[p.stem for p in BUILTINS])
def test_every_builtin_has_a_stored_picture_equal_to_its_replay(path):
    m = read_texture(path).manifest
    picture = read_picture(bk.PICTURES_DIR / f"{m.result_sha256}.npz", m.result_sha256,
                           (m.height, m.width), m.levels)
    assert picture is not None, f"{path.name}: no sound picture (python resources/make_bank.py --pictures)"
    doc = render_texture(path)                       # replayed, hash checked
    assert np.array_equal(picture[0], doc.levels) and np.array_equal(picture[1], doc.palette)


def test_a_first_start_needs_no_synthesis(builtin_bank, no_synthesis):
    """Opening the start entry and preparing every built-in's thumbnail and attributes."""
    bank = builtin_bank
    assert len(bank.pending()) == len(BUILTINS)
    history = bank.open_stored(gravel(bank))
    entry = bank.get(gravel(bank))
    assert history is not None and history.document.result_hash() == entry.sha256
    assert np.array_equal(history.document.levels, bank.stored_picture(entry)[0])
    assert [a.TYPE for a in history.actions] == ["synthesize"]
    assert bank.prepare_pending() == [] and bank.pending() == []
    assert all(bank.thumbnails([e.id]) for e in bank.entries())


def test_the_toned_start_entry_opens_from_its_picture_and_is_confirmed(builtin_bank,
                                                                      monkeypatch):
    """The window opens on "Gravel with tone", a multi-scale synthesis: its stored picture
    stands for the synthesis (no kernel), and the check drawn later compares them."""
    from texeditor.recipe.actions import SynthesizeScales
    bank, entry_id = builtin_bank, gravel(builtin_bank, "Gravel with tone")
    with monkeypatch.context() as m:
        m.setattr(synthesis, "synthesize", lambda *a, **k: pytest.fail("a synthesis ran"))
        m.setattr(synthesis, "synthesize_given", lambda *a, **k: pytest.fail("a synthesis ran"))
        history = bank.open_stored(entry_id)
    entry = bank.get(entry_id)
    assert history is not None and history.document.result_hash() == entry.sha256
    assert [a.TYPE for a in history.actions] == ["synthesize_scales"]
    assert np.array_equal(history.document.levels, bank.stored_picture(entry)[0])
    assert bank.confirm_stored(entry_id)
    drawn = SynthesizeScales.render_result
    monkeypatch.setattr(SynthesizeScales, "render_result", lambda self, dpjs, **kw: drawn(
        dataclasses.replace(self, seed=self.seed + 1), dpjs, **kw))
    assert not bank.confirm_stored(entry_id)        # another seed's texture is not the picture


def test_the_history_from_a_picture_is_real(builtin_bank, no_synthesis):
    """Its steps are the log's; edits undo back to the picture; its DPJ is there."""
    history = builtin_bank.open_stored(gravel(builtin_bank))
    shown = history.document.levels.copy()
    history.apply(SetLevels(0, 0, 8, 8, 3))
    assert history.document.levels[:8, :8].min() == 3
    history.undo()
    assert np.array_equal(history.document.levels, shown) and history.index == 1
    assert history.document.dpj is not None


def test_a_forged_picture_is_refused_and_the_entry_replayed(builtin_bank, tmp_path):
    bank = Bank(builtin_bank.path, pictures=tmp_path / "pictures")
    entry = bank.get(gravel(bank))
    good = read_picture(bk.PICTURES_DIR / f"{entry.sha256}.npz", entry.sha256,
                        (entry.height, entry.width), entry.levels)
    levels, palette = good[0].copy(), good[1]
    levels[5, 7] = (levels[5, 7] + 1) % entry.levels           # one point changed
    forge(bank.pictures / f"{entry.sha256}.npz", levels, palette)
    assert bank.stored_picture(entry) is None
    assert bank.open_stored(entry.id) is None
    assert bank.open(entry.id).document.result_hash() == entry.sha256     # replayed instead
    bank.close()


@pytest.mark.parametrize("damage", ["truncated", "extra member", "object array", "wrong shape",
                                    "level too high", "not a zip", "bad name"])
def test_a_damaged_picture_is_refused(tmp_path, damage):
    levels = np.random.default_rng(1).integers(0, 3, (12, 10)).astype(np.uint8)
    palette = np.array([[0, 0, 0], [128, 128, 128], [255, 255, 255]], np.uint8)
    path = write_picture(tmp_path, levels, palette)
    sha = path.stem
    assert read_picture(path, sha, (12, 10), 3) is not None
    data = path.read_bytes()
    if damage == "truncated":
        path.write_bytes(data[:len(data) // 2])
    elif damage == "extra member":
        with zipfile.ZipFile(path, "a") as zf:
            zf.writestr("more.npy", b"x")
    elif damage == "object array":
        out = io.BytesIO()
        with zipfile.ZipFile(out, "w") as zf:
            for name, array in (("levels.npy", levels.astype(object)), ("palette.npy", palette)):
                buf = io.BytesIO()
                np.save(buf, array, allow_pickle=True)
                zf.writestr(name, buf.getvalue())
        path.write_bytes(out.getvalue())
    elif damage == "wrong shape":
        forge(path, levels[:, :9], palette)
    elif damage == "level too high":
        forge(path, np.where(levels == 2, 7, levels).astype(np.uint8), palette)
    elif damage == "not a zip":
        path.write_bytes(b"\x93NUMPY not a zip at all")
    if damage == "bad name":                   # a recorded hash is never a path
        with Bank(tmp_path / "b.sqlite", builtins=False, pictures=tmp_path / "sub") as bank:
            entry = bank.get(bank.add(_synth(1), "x"))
            assert bank.stored_picture(_with_sha(entry, "../" + sha)) is None
        return
    assert read_picture(path, sha, (12, 10), 3) is None


def _synth(seed, dpj=None, size=(20, 16)) -> History:
    history = History()
    ref = history.add_dpj(dpj or tiny_dpj())
    history.apply(Synthesize(ref, size[1], size[0], seed))
    return history


def _with_sha(entry, sha):
    import dataclasses
    return dataclasses.replace(entry, sha256=sha)


def test_open_stored_only_stands_for_a_synthesis(tmp_path):
    """A log whose later steps change the levels is replayed, picture or not; palette steps
    may follow the synthesis."""
    pictures = tmp_path / "pictures"
    with Bank(tmp_path / "b.sqlite", builtins=False, pictures=pictures) as bank:
        edited = _synth(3)
        edited.apply(SetLevels(0, 0, 4, 4, 1))
        coloured = _synth(4)
        coloured.apply(SetPalette(((10, 20, 30), (200, 100, 0))))
        ids = [bank.add(h, name) for h, name in ((edited, "edited"), (coloured, "coloured"))]
        for h in (edited, coloured):
            write_picture(pictures, h.document.levels, h.document.palette)
        assert bank.open_stored(ids[0]) is None
        history = bank.open_stored(ids[1])
        assert history is not None and history.document.result_hash() == coloured.document.result_hash()
        assert bank.confirm_stored(ids[1])


def test_a_log_that_does_not_give_the_picture_leaves_no_result_behind(tmp_path):
    """The picture is the recorded texture, but the stored log (damaged) gives another palette:
    refused, and the synthesis result the picture stood for is forgotten."""
    pictures = tmp_path / "pictures"
    with Bank(tmp_path / "b.sqlite", builtins=False, pictures=pictures) as bank:
        h = _synth(5)
        h.apply(SetPalette(((10, 20, 30), (200, 100, 0))))
        entry_id = bank.add(h, "coloured")
        write_picture(pictures, h.document.levels, h.document.palette)
        damaged = log_text([h.actions[0], SetPalette(((0, 0, 0), (1, 1, 1)))])
        with bank._write() as conn:
            conn.execute("UPDATE logs SET actions = ? WHERE entry = ?", (damaged, entry_id))
        assert bank.open_stored(entry_id) is None


def test_confirm_stored_finds_a_picture_its_recipe_does_not_give(tmp_path, monkeypatch):
    pictures = tmp_path / "pictures"
    with Bank(tmp_path / "b.sqlite", builtins=False, pictures=pictures) as bank:
        h = _synth(6)
        entry_id = bank.add(h, "s")
        write_picture(pictures, h.document.levels, h.document.palette)
        assert bank.confirm_stored(entry_id)
        other = synthesis.synthesize(tiny_dpj(), (20, 16), seed=99)
        monkeypatch.setattr(Synthesize, "render_result", lambda self, dpj, **kw: other)
        assert not bank.confirm_stored(entry_id)


# -- the warm-up ------------------------------------------------------------------------------

@pytest.fixture
def fresh_warmup(monkeypatch):
    warmup.wait(timeout=120)
    warmup._reset()
    yield
    warmup.wait(timeout=120)
    warmup._reset()
    warmup.start()          # leave the process as an application leaves it: warmed up
    warmup.wait(timeout=120)


def test_the_warm_up_runs_once_in_the_background(fresh_warmup, monkeypatch):
    import threading
    gate, calls = threading.Event(), []
    monkeypatch.setattr(warmup, "_compile", lambda: (calls.append(1), gate.wait(30)))
    assert not warmup.pending() and not warmup.started()
    assert warmup.start() and not warmup.start()
    assert warmup.pending() and not warmup.wait(timeout=0.1)
    gate.set()
    assert warmup.wait(timeout=10) and warmup.ready() and not warmup.pending()
    assert calls == [1] and warmup.error() is None and warmup.seconds() >= 0


def test_the_warm_up_prepares_a_photo_models_kernels_last(fresh_warmup, monkeypatch):
    """The synthesis kernels first (steps wait for them), then a photo model's, which the
    window's tone waits for (pending("photo")) so it is never drawn on the GUI thread."""
    import threading
    engine, photo, order = threading.Event(), threading.Event(), []
    monkeypatch.setattr(warmup, "_compile", lambda: (order.append("engine"), engine.wait(30)))
    real = warmup._photo_model
    monkeypatch.setattr(warmup, "_photo_model", lambda: (order.append("photo"), photo.wait(30),
                                                         real()))
    assert warmup.start()
    assert warmup.pending() and warmup.pending("tone") and warmup.pending("photo")
    engine.set()
    assert warmup.wait(timeout=10) and not warmup.pending() and not warmup.pending("tone")
    assert warmup.pending("photo")
    photo.set()
    for _ in range(600):
        if not warmup.pending("photo"):
            break
        threading.Event().wait(0.05)
    assert not warmup.pending("photo") and order == ["engine", "photo"]
    assert warmup.error() is None


def test_the_warm_up_compiles_the_tone_before_the_synthesis(monkeypatch):
    """The start entry's tone waits for the tone's kernels (~10 s on a first start), not for
    the synthesis's (~a minute)."""
    warmup._tone()                                   # draws every way a tone tiles
    order = []
    monkeypatch.setattr(warmup, "_tone", lambda: order.append("tone"))
    monkeypatch.setattr(synthesis, "synthesize", lambda *a, **k: (order.append("synthesis"),
                                                                  synthesis.SynthesisResult(
        np.zeros((8, 8), np.uint8), 0, 0, 0))[1])
    warmup._compile()
    assert order == ["tone", "synthesis"]


def test_a_failed_warm_up_is_kept_never_raised(fresh_warmup, monkeypatch):
    def broken():
        raise RuntimeError("no compiler")
    monkeypatch.setattr(warmup, "_compile", broken)
    warmup.warm_up()
    assert warmup.ready() and "no compiler" in str(warmup.error())


def test_which_steps_need_the_kernels():
    from texeditor.recipe.document import Document
    from texeditor.texture.actions import RenderGrains
    doc = _synth(7).document
    ref = doc.dpj_ref
    assert warmup.needs_kernels(Synthesize(ref, 20, 16, 7), doc)
    assert not warmup.needs_kernels(SetLevels(0, 0, 2, 2, 1), doc)
    assert not warmup.needs_kernels(SetPalette(((0, 0, 0), (9, 9, 9))), Document())
    assert warmup.needs_kernels(RenderGrains(), doc)


TONED = [p for p in BUILTINS if p.stem.endswith("-with-tone")]


def test_three_builtins_show_a_photo_model_in_its_photos_tone(builtin_bank):
    """A newcomer finds the multi-scale synthesis with the photo's tone among the built-ins
    (what `texeditor resynth` makes), not only the 1984 flat greys: the entry's thumbnail is
    the tone picture of its levels, which has many more greys than its four levels."""
    from texeditor.bank.store import document_thumbnail, thumbnail_png
    from texeditor.photo import document_tone
    assert [p.stem[3:] for p in TONED] == ["gravel-with-tone", "grass-with-tone",
                                           "brick-with-tone"]
    assert len(BUILTINS) == 12 and [p.name[:2] for p in TONED] == ["04", "05", "06"]
    for path in TONED:
        doc = render_texture(path)                       # replayed, hash checked
        assert [a.TYPE for a in doc.actions] == ["synthesize_scales"]
        tone = document_tone(doc)
        assert tone is not None and tone.shape == doc.levels.shape
        assert len(np.unique(tone)) > 8 * doc.num_levels
        flat = thumbnail_png(doc.levels, doc.palette)
        assert document_thumbnail(doc) != flat
        entry = next(e for e in builtin_bank.entries() if e.sha256 == doc.result_hash())
        assert entry.builtin and entry.name == path.stem[3:].replace("-", " ").capitalize()


def test_every_toned_builtin_has_a_stored_tone_equal_to_its_drawn_tone(builtin_bank):
    from texeditor.photo import document_tone
    toned = 0
    for entry in builtin_bank.find():
        entry = builtin_bank.get(entry) if isinstance(entry, int) else entry
        doc = builtin_bank.render(entry.id)
        tone, stored = document_tone(doc), builtin_bank.stored_tone(entry)
        assert (tone is None) == (stored is None), entry.name
        if tone is not None:
            toned += 1
            assert np.array_equal(stored, tone), entry.name
    assert toned == 3


@pytest.mark.parametrize("damage", ["garbage", "two members", "wrong shape", "float", "huge"])
def test_a_damaged_stored_tone_is_ignored(tmp_path, damage):
    path = tmp_path / "t.npz"
    good = np.zeros((8, 6), np.uint8)
    if damage == "garbage":
        path.write_bytes(b"PK\x03\x04 not a zip")
    else:
        out = io.BytesIO()
        arrays = {"two members": dict(tone=good, extra=good), "wrong shape": dict(tone=good.T),
                  "float": dict(tone=good.astype(float)),
                  "huge": dict(tone=np.zeros((8, 6, 300), np.uint8))}[damage]
        np.savez_compressed(out, **arrays)
        path.write_bytes(out.getvalue())
    assert bk.read_tone(path, (8, 6)) is None
    np.savez_compressed(path, tone=good)
    assert np.array_equal(bk.read_tone(path, (8, 6)), good)


def test_a_builtins_thumbnail_from_its_stored_pictures_is_the_replayed_one(builtin_bank,
                                                                           no_synthesis):
    """Toned built-ins are thumbnailed in their tone, as a replayed entry is, without a replay."""
    bank = builtin_bank
    assert bank.prepare_pending() == []
    for entry_id in bank.find():
        entry = bank.get(entry_id)
        picture = bank.stored_picture(entry)
        tone = bank.stored_tone(entry)
        expected = bk.stored_thumbnail(*picture, tone)
        assert bank.thumbnails([entry_id])[entry_id] == expected, entry.name
        if tone is not None:
            assert expected != bk.thumbnail_png(*picture), entry.name      # not the palette's


@pytest.mark.parametrize("kind", ["fifo", "folder", "dangling", "device"])
def test_a_stored_tone_that_is_no_regular_file_is_ignored_without_blocking(tmp_path, kind):
    import os
    path = tmp_path / "t.npz"
    if kind == "fifo":
        if not hasattr(os, "mkfifo"):
            return
        os.mkfifo(path)
    elif kind == "folder":
        path.mkdir()
    elif kind == "dangling":
        path.symlink_to(tmp_path / "nowhere")
    else:
        path = Path("/dev/zero")
    assert bk.read_tone(path, (8, 6)) is None
