"""The documented limits hold on both sides (issue 17): what a writer makes, a reader opens, and
what the reader refuses, the writer refuses first with a message; memory held across a replay
stays bounded (synthesis tables, journal recovery). The limits' time and memory are measured by
benchmarks/bench_limits.py, not here."""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest

from texeditor import DPJ
from texeditor.recipe import journal
from texeditor.markov import synthesis
from texeditor.recipe import texturefile
from texeditor.recipe.actions import NewCanvas, SetLevels, Synthesize
from texeditor.recipe.document import Document
from texeditor.errors import FormatError, InputError
from texeditor.recipe.texturefile import load_texture, read_texture, save_texture


def random_dpj(entries: int, seed: int, levels: int = 4, window=(2, 2)) -> DPJ:
    rng = np.random.default_rng(seed)
    codes = rng.choice(levels ** (window[0] * window[1]), entries, replace=False)
    probs = rng.random(entries)
    return DPJ.from_codes(codes, probs / probs.sum(), levels, window)


def test_a_texture_whose_dpjs_exceed_the_limit_is_refused_when_saved_and_when_read(
        tmp_path, monkeypatch):
    doc = Document()
    for k in range(3):
        doc.apply(Synthesize(doc.add_dpj(random_dpj(200, k)), 8, 8, seed=k))
    sizes = [len(d.to_bytes()) for d in doc.dpjs.values()]
    path = tmp_path / "three.texture"
    save_texture(path, doc)                     # within the limit: saved, and it opens
    assert load_texture(path)[0].document.result_hash() == doc.result_hash()
    monkeypatch.setattr(texturefile, "MAX_DPJ_CONTENT", sum(sizes) - 1)
    with pytest.raises(FormatError, match="DPJs take .* together"):
        read_texture(path)
    target = tmp_path / "never.texture"
    with pytest.raises(InputError, match="cannot save the texture: its DPJs take"):
        save_texture(target, doc)
    assert not target.exists()


def test_a_log_that_compresses_past_the_ratio_limit_is_stored_and_opens_again(tmp_path):
    doc = Document.new(8, 8, 2)
    for _ in range(40_000):          # one step repeated: deflate would shrink it ~600×
        doc.apply(SetLevels(1, 1, 2, 2, 1))
    path = tmp_path / "same.texture"
    save_texture(path, doc)
    with zipfile.ZipFile(path) as zf:
        info = zf.getinfo("actions.json")
    assert info.compress_type == zipfile.ZIP_STORED and info.file_size > texturefile.RATIO_FLOOR
    assert len(read_texture(path).actions) == 40_001


def test_a_log_longer_than_the_limit_cannot_be_saved(tmp_path, monkeypatch):
    monkeypatch.setattr(texturefile, "MAX_ACTIONS", 5)
    doc = Document.new(8, 8, 2)
    for k in range(5):
        doc.apply(SetLevels(k, 0, 1, 1, 1))
    target = tmp_path / "long.texture"
    with pytest.raises(InputError, match="cannot save"):
        save_texture(target, doc)
    assert not target.exists()


def test_synthesis_keeps_the_tables_of_old_dpjs_only_within_its_budget(monkeypatch):
    """A document with many large DPJs replayed kept every DPJ's tables (21 DPJs: 17 GB)."""
    monkeypatch.setattr(synthesis, "_cache", {})
    dpjs = [random_dpj(150, k, levels=4, window=(2, 2)) for k in range(5)]
    one = sum(a.nbytes for a in synthesis._tables(dpjs[0]) if isinstance(a, np.ndarray))
    monkeypatch.setattr(synthesis, "TABLES_MEMORY", int(2.5 * one))
    for dpj in dpjs[1:]:
        synthesis.synthesize(dpj, (8, 8), seed=1)
    kept = [ref() for ref, _, _ in synthesis._cache.values()]
    assert kept[-1] is dpjs[-1] and 1 <= len(kept) <= 3
    assert sum(size for _, _, size in synthesis._cache.values()) <= 2.5 * one + one
    # evicted tables are rebuilt the same: the result does not depend on the cache
    again = synthesis.synthesize(dpjs[0], (8, 8), seed=1).levels
    monkeypatch.setattr(synthesis, "_cache", {})
    assert np.array_equal(again, synthesis.synthesize(dpjs[0], (8, 8), seed=1).levels)


def _journal(path, records):
    path.write_bytes(b"".join(json.dumps(r).encode() + b"\n" for r in records))


def test_journal_recovery_stops_before_a_log_longer_than_a_texture_may_hold(tmp_path, monkeypatch):
    monkeypatch.setattr(journal, "MAX_ACTIONS", 4)
    step = SetLevels(0, 0, 1, 1, 1).to_json()
    path = tmp_path / "a.journal"
    _journal(path, [{"kind": "start", "format": journal.FORMAT, "time": 0, "source": None},
                    {"kind": "log", "keep": 0, "append": [NewCanvas(4, 4, 2).to_json(), step]},
                    {"kind": "log", "keep": 2, "append": [step, step]},
                    {"kind": "log", "keep": 4, "append": [step]}])
    got = journal.recover(path)
    assert len(got.actions) == 4 and got.changes == 1


def test_journal_recovery_of_thousands_of_records_ends_at_the_line_cut_short(tmp_path):
    step = SetLevels(0, 0, 1, 1, 1).to_json()
    records = [{"kind": "start", "format": journal.FORMAT, "time": 0, "source": None},
               {"kind": "log", "keep": 0, "append": [NewCanvas(4, 4, 2).to_json()]}]
    records += [{"kind": "log", "keep": k, "append": [step]} for k in range(1, 3000)]
    path = tmp_path / "b.journal"
    _journal(path, records)
    path.write_bytes(path.read_bytes() + b'{"kind": "log", "keep": 3000, "app')   # cut short
    got = journal.recover(path)
    assert len(got.actions) == 3000 and got.changes == 2999


def test_a_large_16_bit_colour_picture_is_refused_with_its_decoded_size(tmp_path, monkeypatch):
    import tifffile
    from texeditor.markov import levels
    from texeditor.markov.levels import ImageError, load_image
    path = tmp_path / "deep.tif"
    tifffile.imwrite(path, np.full((64, 64, 4), 40000, np.uint16))
    monkeypatch.setattr(levels, "MAX_IMAGE_BYTES", 64 * 64 * 4 * 2 - 1)
    with pytest.raises(ImageError, match="4 channel.*16-bit integers.*8 bits per channel"):
        load_image(path)
    monkeypatch.setattr(levels, "MAX_IMAGE_BYTES", 64 * 64 * 4 * 2)
    assert load_image(path).dtype == np.uint16
