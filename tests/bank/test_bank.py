"""The texture bank (issue 10): exact replay with a hash check, search by text, tag, attribute range
and likeness, schema migrations, damaged and locked files, concurrent writers, hostile imports."""

import json
import sqlite3
import subprocess
import sys
import tempfile
import threading
import zipfile
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from tests.support import PROPERTY, REFS, ROOT, TINY_DPJS, engine_types, random_history
from tests.support.bank import drawn, one_of_each, synthesised
from texeditor.bank import attributes as attrs
from texeditor.bank import store as bk
from texeditor.recipe import texturefile as tf
from texeditor.recipe.actions import (CropCanvas, NewCanvas, ResizeCanvas, SetLevels,
                               SetPalette, Synthesize)
from texeditor.bank.store import Bank, BankError
from texeditor.recipe.codec import log_text
from texeditor.recipe.document import dpj_ref
from texeditor.errors import FormatError, InputError, ReplayError
from texeditor.recipe.history import History


@pytest.fixture
def bank(tmp_path):
    with Bank(tmp_path / "bank.sqlite", builtins=False) as b:
        yield b


def stripes(width: int, vertical: bool, size: int = 32) -> History:
    step = range(width, size, 2 * width)
    return drawn([(0, c, size, width, 1) if vertical else (c, 0, width, size, 1) for c in step],
                 (size, size))


def pattern(levels: np.ndarray) -> History:
    """Any small matrix, drawn point by point (runs of one row as one rectangle)."""
    rects = []
    for r, row in enumerate(levels):
        c = 0
        while c < len(row):
            end = c
            while end < len(row) and row[end] == row[c]:
                end += 1
            if row[c]:
                rects.append((r, c, 1, end - c, int(row[c])))
            c = end
    return drawn(rects, (levels.shape[1], levels.shape[0]), int(levels.max()) + 1)


def raw(bank) -> sqlite3.Connection:
    """A second, plain connection to the bank file (to damage it as a user or a bug could)."""
    return sqlite3.connect(bank.path, isolation_level=None)


# -- save, reopen, identical -----------------------------------------------------------------------

BASE_ACTIONS = {NewCanvas, Synthesize, SetPalette, SetLevels, CropCanvas, ResizeCanvas}


def test_the_examples_cover_every_action_type_of_the_engine():
    """The histories round-tripped below hold every type of the registry (but test modules'
    own, as test_history's): a new Action of the engine without an example fails here."""
    types = {a.TYPE for _, h in one_of_each() for a in h.applied}
    assert types == engine_types()


@pytest.mark.parametrize("name, history", one_of_each(), ids=lambda x: x if isinstance(x, str)
                         else "")
def test_save_then_open_gives_the_identical_matrix(bank, name, history):
    doc = history.document
    entry_id = bank.add(history, name, tags=["test"])
    again = bank.open(entry_id)
    assert np.array_equal(again.document.levels, doc.levels)
    assert np.array_equal(again.document.palette, doc.palette)
    assert again.document.result_hash() == doc.result_hash() == bank.get(entry_id).sha256
    assert again.document.dpj_ref == doc.dpj_ref
    assert bank.render(entry_id).result_hash() == doc.result_hash()


@settings(PROPERTY, max_examples=25)
@given(st.data())
def test_random_logs_reopen_identical(data):
    history = random_history(data)
    assume(history.document.levels.size)
    with tempfile.TemporaryDirectory() as folder, \
            Bank(Path(folder) / "b.sqlite", builtins=False) as bank:
        entry = bank.get(bank.add(history, "random"))
        again = bank.open(entry.id).document
        assert np.array_equal(again.levels, history.document.levels)
        assert again.result_hash() == history.document.result_hash() == entry.sha256
        assert entry.actions <= len(history.applied)


def test_the_stored_log_is_the_optimised_one(bank):
    history = synthesised(2)
    for k in range(6):                            # each covered by the next, then by the last
        history.apply(SetLevels(0, 0, 16, 24, k % 2))
    history.apply(SetPalette([(0, 0, 0), (90, 90, 90)]))
    history.apply(SetPalette([(0, 0, 0), (250, 250, 250)]))
    entry = bank.get(bank.add(history, "optimised"))
    assert entry.actions < len(history.applied)
    assert bank.open(entry.id).document.result_hash() == history.document.result_hash()


def test_an_entry_keeps_the_dpj_that_was_current_even_if_unused(bank):
    history = drawn([(1, 1, 3, 3, 1)])
    history.add_dpj(TINY_DPJS[0])                 # acquired, not yet synthesised
    entry_id = bank.add(history, "hand-made with a DPJ")
    assert bank.open(entry_id).document.dpj == TINY_DPJS[0]
    assert set(bank.recipe(entry_id).dpjs) == {REFS[0]}


def test_dpjs_are_stored_once_for_many_entries(bank):
    for seed in range(4):
        bank.add(synthesised(seed), f"seed {seed}")
    with raw(bank) as conn:
        assert conn.execute("SELECT count(*) FROM dpjs").fetchone()[0] == 1


def test_an_entry_has_thumbnail_attributes_and_times(bank):
    history = stripes(2, vertical=True)
    entry = bank.get(bank.add(history, "  Thin   stripes ", tags="Stripes, #Regular,stripes",
                              description=" vertical "))
    assert (entry.name, entry.tags, entry.description) == ("Thin stripes", ("regular", "stripes"),
                                                           "vertical")
    assert (entry.width, entry.height, entry.levels) == (32, 32, 2) and not entry.pending
    assert entry.attributes == attrs.compute(history.document.levels, history.document.palette)
    assert entry.created == entry.modified and entry.trashed is None and not entry.builtin
    png = iio.imread(bank.thumbnails([entry.id])[entry.id])
    assert png.shape[:2] == (128, 128)            # 32 points enlarged 4 times
    grey = png if png.ndim == 2 else png[..., 0]
    assert np.array_equal(grey[::4, ::4] > 127, history.document.levels == 1)


def test_grain_and_density_parameters_are_kept_with_the_entry(bank):
    from texeditor.texture.actions import RenderGrains
    history = stripes(4, True, size=16)
    history.apply(RenderGrains("hexagon", 4, explosion_x=2.0, compression=0.0))
    history.apply(SetPalette([(0, 0, 0), (200, 180, 150)]))
    entry = bank.get(bank.add(history, "grains"))
    assert entry.grain["render_grains"]["shape"] == "hexagon"
    assert entry.grain["render_grains"]["explosion_x"] == 2.0
    assert bank.open(entry.id).document.result_hash() == history.document.result_hash()
    assert bank.get(bank.add(stripes(2, True), "plain")).grain == {}


def test_an_empty_document_and_bad_names_are_refused(bank):
    with pytest.raises(InputError, match="empty"):
        bank.add(History(), "nothing")
    for name, tags in (("", ()), ("x" * 300, ()), ("ok", ["a" * 100]), ("ok", ["bell\x07"])):
        with pytest.raises(InputError):
            bank.add(synthesised(), name, tags=tags)
    assert bank.count() == 0


# -- tampering is reported, the rest of the bank stays usable ------------------------------------

@pytest.fixture
def three(bank):
    return [bank.add(drawn([(0, 0, 4, 4 + k, 1)]), f"entry {k}") for k in range(3)]


def test_a_tampered_log_is_reported_on_open_and_by_verify(bank, three):
    log = json.loads(raw(bank).execute("SELECT actions FROM logs WHERE entry = ?",
                                       (three[1],)).fetchone()[0])
    log["actions"][-1]["value"] = 0               # a valid log that draws another texture
    raw(bank).execute("UPDATE logs SET actions = ? WHERE entry = ?",
                      (json.dumps(log), three[1]))
    with pytest.raises(ReplayError, match="entry 1"):
        bank.open(three[1])
    checks = bank.verify()
    assert [c.ok for c in checks] == [True, True, False, True]
    assert "damaged" in checks[2].message and checks[0].message == "ok"
    assert bank.open(three[0]).document.levels[0, 0] == 1     # the others still open


def test_a_tampered_hash_is_reported(bank, three):
    raw(bank).execute("UPDATE entries SET sha256 = ? WHERE id = ?", ("0" * 64, three[2]))
    with pytest.raises(ReplayError, match="not shown"):
        bank.open(three[2])
    assert [c.ok for c in bank.verify()] == [True, True, True, False]


@pytest.mark.parametrize("log, message", [
    ('{"actions": [', "damaged"),
    ('{"actions": [{"type": "melt", "version": 1}]}', "unknown action type"),
    ('{"actions": [{"type": "set_levels", "version": 1, "top": 0}]}', "lacks parameters"),
    ('{"actions": [], "extra": 1}', "damaged"),
    ('{"actions": [{"type": "new_canvas", "version": 1, "width": NaN, "height": 2, '
     '"levels": 2}]}', "damaged"),
])
def test_a_row_with_a_corrupted_log_is_a_clear_error(bank, three, log, message):
    raw(bank).execute("UPDATE logs SET actions = ? WHERE entry = ?", (log, three[0]))
    with pytest.raises(FormatError, match=message):
        bank.open(three[0])
    assert len(bank.search("entry")) == 3 and bank.open(three[1])
    assert not bank.verify()[1].ok


def test_a_missing_log_row_is_a_clear_error(bank, three):
    raw(bank).execute("DELETE FROM logs WHERE entry = ?", (three[2],))
    with pytest.raises(FormatError, match="damaged"):
        bank.open(three[2])
    assert [c.ok for c in bank.verify()] == [True, True, True, False]


def test_a_damaged_dpj_row_is_a_clear_error(bank):
    entry_id = bank.add(synthesised(), "synth")
    raw(bank).execute("UPDATE dpjs SET data = ?", (b"PK\x03\x04 nonsense",))
    with pytest.raises(FormatError, match="DPJ"):
        bank.open(entry_id)


def test_a_file_that_is_not_a_bank_is_refused_untouched(tmp_path):
    garbage = tmp_path / "garbage.sqlite"
    garbage.write_bytes(b"this is not a database at all" * 200)
    with pytest.raises(BankError, match="not a texture bank"):
        Bank(garbage)
    foreign = tmp_path / "foreign.sqlite"
    with sqlite3.connect(foreign) as conn:
        conn.execute("CREATE TABLE photos (id INTEGER)")
    before = foreign.read_bytes()
    with pytest.raises(BankError, match="not a texture bank"):
        Bank(foreign)
    assert foreign.read_bytes() == before


def test_a_bank_from_a_newer_program_is_refused(tmp_path):
    path = tmp_path / "new.sqlite"
    Bank(path, builtins=False).close()
    with sqlite3.connect(path) as conn:
        conn.execute(f"PRAGMA user_version = {bk.SCHEMA_VERSION + 1}")
    with pytest.raises(BankError, match="newer texeditor"):
        Bank(path)


def test_a_locked_bank_is_a_clear_error_and_reads_go_on(tmp_path):
    path = tmp_path / "bank.sqlite"
    with Bank(path, builtins=False, timeout=0.1) as bank:
        entry_id = bank.add(synthesised(), "synth")
        other = sqlite3.connect(path, isolation_level=None)
        other.execute("BEGIN EXCLUSIVE")          # another program holds the write lock
        with pytest.raises(BankError, match="busy"):
            bank.update(entry_id, tags=["new"])
        assert bank.get(entry_id).tags == () and bank.count() == 1
        assert bank.open(entry_id).document.levels.shape == (16, 24)
        other.execute("ROLLBACK")
        other.close()
        bank.update(entry_id, tags=["new"])
        assert bank.get(entry_id).tags == ("new",)


def test_two_connections_writing_at_once_do_not_corrupt_the_bank(tmp_path):
    path = tmp_path / "bank.sqlite"
    records = [bk.make_record(drawn([(k % 8, 0, 2, 5, 1)]), f"entry {k}", tags=[f"t{k % 3}"])
               for k in range(12)]
    banks = [Bank(path, builtins=False, timeout=30) for _ in range(2)]
    errors = []

    def writer(bank, offset):
        try:
            for k in range(offset, len(records), 2):
                entry_id = bank.insert(records[k])
                bank.update(entry_id, tags=[f"t{k % 3}", "written"])
                bank.find("entry")
        except Exception as exc:          # reported below: the assertion shows it
            errors.append(exc)

    threads = [threading.Thread(target=writer, args=(b, k)) for k, b in enumerate(banks)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    assert banks[0].integrity() == "ok" and banks[1].count() == 12
    assert len(banks[1].find("tag:written")) == 12 and len(banks[0].find(tags=["t1"])) == 4
    assert all(c.ok for c in banks[0].verify())
    for b in banks:
        b.close()


WRITER = """
import sys
from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.bank.store import Bank
from texeditor.recipe.history import History
bank = Bank(sys.argv[1], builtins=False, timeout=60)
for k in range(15):
    h = History()
    h.apply(NewCanvas(16, 16, 2))
    h.apply(SetLevels(k % 16, 0, 1, 16, 1))
    entry = bank.add(h, f"{sys.argv[2]} {k}", tags=[sys.argv[2]])
    bank.update(entry, description=f"written by process {sys.argv[2]}")
    bank.find(sys.argv[2])
"""


def test_two_processes_writing_at_once_do_not_corrupt_the_bank(tmp_path):
    path = tmp_path / "bank.sqlite"
    Bank(path, builtins=False).close()
    procs = [subprocess.Popen([sys.executable, "-c", WRITER, str(path), name],
                              cwd=ROOT,
                              stderr=subprocess.PIPE, text=True) for name in ("alpha", "beta")]
    errors = [p.communicate(timeout=120)[1] for p in procs]
    assert [p.returncode for p in procs] == [0, 0], errors
    with Bank(path, builtins=False) as bank:
        assert bank.integrity() == "ok" and bank.count() == 30
        assert len(bank.find("tag:alpha")) == len(bank.find("process beta")) == 15
        assert all(c.ok for c in bank.verify())


# -- search -----------------------------------------------------------------------------------------

@pytest.fixture
def known(bank):
    """A hand-made bank whose answers are known."""
    rng = np.random.default_rng(4)
    made = {
        "thin vertical": (stripes(2, True), ["stripes", "regular"], "fine lines up and down"),
        "wide vertical": (stripes(4, True), ["stripes", "regular"], "broad lines up and down"),
        "thin horizontal": (stripes(2, False), ["stripes", "regular"], "fine lines across"),
        "noise a": (pattern(rng.integers(0, 2, (32, 32))), ["granular"], "salt and pepper"),
        "noise b": (pattern(rng.integers(0, 2, (32, 32))), ["granular"], "more salt, pepper"),
        "blocks": (pattern(np.kron(rng.integers(0, 2, (8, 8)), np.ones((8, 8), int))),
                   ["spots"], "large squares"),
    }
    return {name: bank.add(h, name.capitalize(), tags=tags, description=d)
            for name, (h, tags, d) in made.items()}


def names(bank, ids) -> list:
    return [bank.get(i).name.lower() for i in ids]


def test_search_by_text_in_names_descriptions_and_tags(bank, known):
    assert set(names(bank, bank.find("vertical"))) == {"thin vertical", "wide vertical"}
    assert set(names(bank, bank.find("vert"))) == {"thin vertical", "wide vertical"}  # prefixes
    assert names(bank, bank.find("pepper salt")) == ["noise b", "noise a"] or \
        set(names(bank, bank.find("pepper salt"))) == {"noise a", "noise b"}
    assert names(bank, bank.find("squares")) == ["blocks"]
    assert set(names(bank, bank.find("granular"))) == {"noise a", "noise b"}   # a tag is text
    assert bank.find("nothing-like-this") == []
    for hostile in ('"', 'a AND OR', '*', 'NEAR(', "x' OR 1=1 --", "(", "tag:"):
        bank.find(hostile)                        # never FTS5 or SQL syntax errors


def test_search_by_tag(bank, known):
    assert set(names(bank, bank.find("tag:stripes"))) == {"thin vertical", "wide vertical",
                                                         "thin horizontal"}
    assert set(names(bank, bank.find(tags=["REGULAR"]))) == set(names(bank,
                                                                     bank.find("#stripes")))
    assert set(names(bank, bank.find("fine #stripes"))) == {"thin vertical", "thin horizontal"}
    assert bank.find(tags=["stripes", "granular"]) == []
    assert dict(bank.all_tags())["stripes"] == 3


def test_search_by_attribute_ranges(bank, known):
    oriented = bank.find(ranges={"directivity": (0.9, None)})
    assert set(names(bank, oriented)) == {"thin vertical", "wide vertical", "thin horizontal"}
    vertical = bank.find(ranges={"directivity": (0.9, None), "orientation": (80, 100)})
    assert set(names(bank, vertical)) == {"thin vertical", "wide vertical"}
    assert names(bank, bank.find(ranges={"granularity": (40, None), "regularity": (None, 0.5)})) \
        == ["blocks"]
    assert set(names(bank, bank.find("stripes", ranges={"coarseness": (None, 1.0)}))) == \
        {"thin vertical", "thin horizontal"}
    with pytest.raises(InputError, match="unknown attribute"):
        bank.find(ranges={"beauty; DROP TABLE entries": (0, 1)})
    with pytest.raises(InputError, match="empty"):
        bank.find(ranges={"contrast": (0.8, 0.2)})


def test_more_like_this(bank, known):
    assert names(bank, bank.find(like=known["noise a"]))[0] == "noise b"
    assert names(bank, bank.find(like=known["thin vertical"]))[0] == "wide vertical"
    nearest = bank.similar(known["thin horizontal"], k=2)
    assert len(nearest) == 2 and known["thin horizontal"] not in [e.id for e in nearest]
    # likeness among a filtered set
    assert names(bank, bank.find("tag:stripes", like=known["wide vertical"])) == \
        ["thin vertical", "thin horizontal"]


def test_likeness_sees_entries_added_by_another_program(bank, known):
    other = Bank(bank.path, builtins=False)
    assert known["noise a"] in bank.find(like=known["noise b"])     # cached from here on
    twin = other.add(pattern(np.kron(np.random.default_rng(4).integers(0, 2, (32, 32)),
                                     np.ones((1, 1), int))), "Noise a twin")
    assert bank.find(like=known["noise a"])[0] == twin
    other.purge([twin])
    assert twin not in bank.find(like=known["noise a"])
    other.close()


def test_likeness_after_inserts_equals_a_fresh_read(bank, known):
    """Inserts extend the cached feature rows (only the new ids are read): the ranking and the
    spread must be those of a bank opened afresh, and a later purge reads everything again."""
    target = known["noise a"]
    bank.find(like=target)                                        # the cache is filled
    copy = bank.duplicate(known["noise b"], "Noise b again")
    added = bank.add(stripes(3, False), "Wider horizontal", tags=["stripes"])
    fresh = Bank(bank.path, builtins=False)
    assert copy in bank.find(like=target) and added in bank.find(like=target)
    for like in (target, known["thin horizontal"], added):
        assert bank.find(like=like) == fresh.find(like=like)
    bank.purge([copy])
    assert copy not in bank.find(like=target)
    assert bank.find(like=target) == fresh.find(like=target)
    fresh.close()


def test_a_change_made_by_another_program_is_noticed(bank):
    bank.changed_elsewhere()
    other = Bank(bank.path, builtins=False)
    bank.add(stripes(2, True), "mine")
    assert not bank.changed_elsewhere()           # its own writes are not news
    other.add(stripes(4, True), "theirs")
    assert bank.changed_elsewhere() and not bank.changed_elsewhere()
    assert names(bank, bank.find("theirs")) == ["theirs"]
    other.close()


def test_search_without_fts5_falls_back_to_substrings(tmp_path, monkeypatch):
    path = tmp_path / "bank.sqlite"
    monkeypatch.setattr(bk, "_has_fts5", lambda conn: False)
    with Bank(path, builtins=False) as plain:
        assert "no FTS5" in plain.search_mode
        plain.add(stripes(2, True), "Fine lines", tags=["stripes"], description="50% grey")
        plain.add(stripes(4, True), "Broad_lines", tags=["wide"])
        assert len(plain.find("lines")) == 2 and len(plain.find("LINE")) == 2
        assert names(plain, plain.find("wid")) == ["broad_lines"]
        assert names(plain, plain.find("50%")) == ["fine lines"]      # % is a character here
        assert names(plain, plain.find("d_l")) == ["broad_lines"]
    monkeypatch.undo()
    with Bank(path) as full:                      # the index is rebuilt with what was added
        assert "FTS5" in full.search_mode and len(full.find("lines")) == 2


# -- schema -----------------------------------------------------------------------------------------

def test_a_new_bank_is_migrated_from_version_0_and_gets_the_builtins(tmp_path):
    path = tmp_path / "fresh.sqlite"
    sqlite3.connect(path).close()                 # an empty SQLite file: user_version 0
    with Bank(path) as bank:
        builtins = sorted(bk.BUILTIN_DIR.glob("*.texture"))
        assert len(builtins) >= 6 and bank.count() == len(builtins)
        assert all(e.builtin and e.pending for e in bank.entries())
        with raw(bank) as conn:
            assert conn.execute("PRAGMA user_version").fetchone()[0] == bk.SCHEMA_VERSION
            assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
        assert bank.prepare_pending() == [] and bank.pending() == []
        assert all(not e.pending for e in bank.entries())
        assert all(c.ok for c in bank.verify())
        assert bank.find("tag:edited") and bank.find(ranges={"regularity": (0.9, None)})
    with Bank(path) as again:                     # installed once only
        assert again.count() == len(builtins)


def test_migration_from_version_1_keeps_the_entries(tmp_path):
    path = tmp_path / "v1.sqlite"
    history = stripes(3, vertical=True)
    record = bk.make_record(history, "Old stripes", tags=["old"])
    conn = sqlite3.connect(path, isolation_level=None)
    for statement in bk.MIGRATIONS[0]:            # the bank as version 1 of the program made it
        conn.execute(statement)
    conn.execute("PRAGMA user_version = 1")
    a = record.attributes
    conn.execute("INSERT INTO entries (name, width, height, levels, action_count, sha256, "
                 "contrast, granularity, density, directivity, orientation, regularity, created, "
                 "modified) VALUES (?, 32, 32, 2, ?, ?, ?, ?, ?, ?, ?, ?, 1.0, 1.0)",
                 ("Old stripes", len(record.actions), record.sha256, a.contrast, a.granularity,
                  a.density, a.directivity, a.orientation, a.regularity))
    conn.execute("INSERT INTO logs VALUES (1, ?)", (log_text(record.actions),))
    conn.execute("INSERT INTO thumbnails VALUES (1, ?)", (record.thumbnail,))
    conn.execute("INSERT INTO tags VALUES (1, 'old')")
    conn.close()
    with Bank(path) as bank:
        entry = bank.get(1)
        assert entry.name == "Old stripes" and entry.tags == ("old",)
        assert entry.pending and bank.pending() == [1]     # coarseness and period are new
        assert bank.find("stripes") == [1] and bank.find("tag:old") == [1]
        assert bank.open(1).document.result_hash() == history.document.result_hash()
        bank.prepare_pending()
        assert bank.get(1).attributes == record.attributes
        bank.trash(1)
        assert bank.find() == [] and bank.find(trash=True) == [1]
        assert bank.integrity() == "ok"


# -- import and export ----------------------------------------------------------------------------

def test_export_then_import_gives_the_same_texture(bank, tmp_path):
    history = synthesised(5)
    history.apply(SetLevels(1, 1, 3, 3, 1))
    entry_id = bank.add(history, "Exported", tags=["a", "b"], description="round trip")
    out = tmp_path / "out.texture"
    bank.export_texture(entry_id, out)
    loaded, manifest = tf.load_texture(out)
    assert loaded.document.result_hash() == history.document.result_hash()
    assert manifest.tags == ("a", "b") and manifest.description == "round trip"
    with Bank(tmp_path / "other.sqlite", builtins=False) as other:
        new = other.get(other.import_texture(out))
        assert (new.name, new.tags, new.sha256) == ("Out", ("a", "b"), manifest.result_sha256)
        named = other.import_texture(out, name="Mine", tags="x")
        assert other.get(named).tags == ("x",)
        assert other.open(new.id).document.dpj_ref == history.document.dpj_ref


def hostile_files(tmp_path, good):
    """Files an import must refuse: not a zip, path traversal, a manifest lying about the result,
    a DPJ stored under the reference of another one."""
    yield "not a zip", tmp_path / "a.texture", b"hello"
    members = {}
    with zipfile.ZipFile(good) as zf:
        members = {i.filename: zf.read(i) for i in zf.infolist()}
    yield "traversal", tmp_path / "b.texture", {**members, "../evil.json": b"{}"}
    manifest = json.loads(members["manifest.json"])
    yield "lying hash", tmp_path / "c.texture", {
        **members, "manifest.json": json.dumps({**manifest, "result_sha256": "1" * 64}).encode()}
    swapped = dict(members)
    swapped["dpj.npz"] = TINY_DPJS[1].to_bytes()      # another DPJ under the same reference
    yield "forged dpj", tmp_path / "d.texture", swapped


def test_hostile_textures_are_refused_without_side_effects(bank, tmp_path):
    good = tmp_path / "good.texture"
    tf.save_texture(good, synthesised(1))
    bank.add(synthesised(1), "the real one")
    before = list(raw(bank).iterdump())
    for what, path, content in hostile_files(tmp_path, good):
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            with zipfile.ZipFile(path, "w") as zf:
                for name, data in content.items():
                    zf.writestr(name, data)
        with pytest.raises((FormatError, ReplayError)):
            bank.import_texture(path)
    assert list(raw(bank).iterdump()) == before
    assert bank.count() == 1 and bank.integrity() == "ok"


def test_a_forged_dpj_reference_cannot_replace_a_stored_dpj(bank):
    bank.add(synthesised(1), "genuine")
    history = History()
    with pytest.raises(InputError, match="does not name this DPJ"):
        history.document.add_dpj(TINY_DPJS[1], REFS[0])   # TINY_DPJS[1] posing as REFS[0]
    history.document.dpjs[REFS[0]] = TINY_DPJS[1]          # forged behind the document's back
    with history.document.step():
        history.document.set_current_dpj(REFS[0])
    history.apply(NewCanvas(4, 4, 3))
    with pytest.raises(FormatError, match="another DPJ"):
        bank.add(history, "forged")
    assert bank.count() == 1 and bank.open(1).document.dpj == TINY_DPJS[0]
    assert dpj_ref(TINY_DPJS[0]) == REFS[0]


# -- editing ----------------------------------------------------------------------------------------

def test_rename_retag_duplicate_trash_restore_purge(bank):
    first = bank.add(synthesised(1), "First", tags=["a"])
    second = bank.add(stripes(2, True), "Second", tags=["b"])
    bank.update(first, name="Renamed", tags=["c", "d"], description="now described")
    entry = bank.get(first)
    assert (entry.name, entry.tags, entry.description) == ("Renamed", ("c", "d"), "now described")
    assert entry.modified > entry.created
    assert bank.find("renamed") == [first] and bank.find("first") == [] and \
        bank.find("tag:a") == [] and bank.find("described") == [first]

    copy = bank.duplicate(first)
    assert bank.get(copy).name == "Renamed (copy)" and bank.get(copy).tags == ("c", "d")
    assert bank.open(copy).document.result_hash() == bank.get(first).sha256
    assert bank.find()[0] == copy                 # newest first

    bank.trash(first)
    assert first not in bank.find() and bank.find(trash=True) == [first]
    assert bank.open(first)                       # a trashed entry still opens (to look at it)
    bank.restore(first)
    assert first in bank.find()
    bank.trash(second)
    bank.trash(first)
    assert bank.purge() == 2 and bank.count() == 1 and bank.count(trash=True) == 0
    assert bank.find("renamed") == [copy]
    with pytest.raises(BankError, match="no entry"):
        bank.get(first)
    with raw(bank) as conn:                       # the DPJ is still used by the copy
        assert conn.execute("SELECT count(*) FROM dpjs").fetchone()[0] == 1
    bank.purge([copy])
    with raw(bank) as conn:                       # now no entry uses it: gone
        assert conn.execute("SELECT count(*) FROM dpjs").fetchone()[0] == 0


def test_versions_point_to_their_parent(bank):
    first = bank.add(synthesised(1), "Stone")
    history = bank.open(first)
    history.apply(SetLevels(0, 0, 2, 2, 1))
    second = bank.add(history, "Stone", parent=first)
    assert bank.get(second).parent == first and bank.get(second).actions == 2
    with pytest.raises(BankError):
        bank.add(history, "orphan", parent=999)


def test_unknown_entries_are_bank_errors(bank):
    for call in (lambda: bank.open(7), lambda: bank.update(7, name="x"), lambda: bank.trash(7),
                 lambda: bank.duplicate(7), lambda: bank.recipe(7)):
        with pytest.raises(BankError, match="no entry 7"):
            call()


# -- small helpers ----------------------------------------------------------------------------------

def test_queries_ranges_and_names():
    assert bk.parse_query("fine tag:Stone #grey  sand") == (["fine", "sand"], ["Stone", "grey"])
    assert bk.fts_query(['say "hi"', "x"]) == '"say ""hi"""* AND "x"*'
    assert bk.parse_range("contrast=0.2..0.8") == ("contrast", (0.2, 0.8))
    assert bk.parse_range("granularity=..10") == ("granularity", (None, 10.0))
    for bad in ("contrast", "contrast=1", "beauty=0..1", "contrast=a..b", "contrast=1..0"):
        with pytest.raises(InputError):
            bk.parse_range(bad)
    assert bk.name_from_file("dir/fine-gravel_2.texture") == "Fine gravel 2"
    assert bk.normalize_tags(" Stone , stone,#Grey  Scale,,") == ("stone", "grey scale")


def test_default_path_follows_the_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("TEXEDITOR_BANK", str(tmp_path / "my.sqlite"))
    assert bk.default_path() == tmp_path / "my.sqlite"
    monkeypatch.setenv("TEXEDITOR_BANK", str(tmp_path))
    assert bk.default_path() == tmp_path / "bank.sqlite"
    monkeypatch.delenv("TEXEDITOR_BANK")
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path / "data"))
    assert bk.default_path() == tmp_path / "data" / "bank.sqlite"
    monkeypatch.delenv("TEXEDITOR_DATA")
    assert bk.default_path().name == "bank.sqlite" and "texeditor" in str(bk.default_path())


# -- the command line -------------------------------------------------------------------------------

def cli(capsys, *argv):
    from texeditor.cli import main
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_the_bank_from_the_command_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("TEXEDITOR_BANK", str(tmp_path / "cli.sqlite"))
    code, out, _ = cli(capsys, "bank", "list")
    assert code == 0 and "Tiled motif" in out and "Gravel" in out        # the built-ins
    n = len(out.splitlines()) - 1

    source = tmp_path / "mine.texture"
    tf.save_texture(source, stripes(2, True), tags=["lines"], description="from a file")
    code, out, _ = cli(capsys, "bank", "add", source, "--name", "My lines", "--tags", "mine, b")
    assert code == 0 and out.startswith(f"entry {n + 1}: My lines")
    code, out, _ = cli(capsys, "bank", "import", source)
    assert code == 0 and "Mine" in out and "lines" in out

    code, out, _ = cli(capsys, "bank", "search", "my", "--tag", "mine")
    assert code == 0 and "My lines" in out and "Gravel" not in out
    code, out, err = cli(capsys, "bank", "search", "--filter", "directivity=0.95..",
                         "--filter", "orientation=80..100")
    assert code == 0 and "My lines" in out and "Mine" in out and "Brick" not in out
    assert f"preparing {n} entries" in err             # the built-ins got their attributes
    code, out, _ = cli(capsys, "bank", "search", "--like", n + 1, "--limit", 1)
    assert code == 0 and out.splitlines()[1].split()[1] == "Mine"

    code, out, _ = cli(capsys, "bank", "show", n + 1)
    assert code == 0 and "tags: b, mine" in out and "directivity" in out and "1. New canvas" in out
    code, out, _ = cli(capsys, "bank", "render", n + 1, "-o", tmp_path / "lines.npy")
    assert code == 0 and "hash verified" in out
    assert np.array_equal(np.load(tmp_path / "lines.npy"), stripes(2, True).document.levels)
    code, out, _ = cli(capsys, "bank", "export", n + 1, "-o", tmp_path / "back.texture")
    assert code == 0 and tf.load_texture(tmp_path / "back.texture")[1].tags == ("b", "mine")

    code, out, _ = cli(capsys, "bank", "verify")
    assert code == 0 and f"{n + 2} entries replayed: {n + 2} match" in out


def test_bank_command_line_errors(tmp_path, capsys):
    path = tmp_path / "b.sqlite"
    with Bank(path, builtins=False) as bank:
        entry_id = bank.add(stripes(2, True), "lines")
        raw(bank).execute("UPDATE entries SET sha256 = ?", ("f" * 64,))
    code, out, _ = cli(capsys, "bank", "verify", "--bank", path)
    assert code == 1 and "entry 1 “lines”" in out and "0 match" in out
    (tmp_path / "junk.texture").write_bytes(b"junk")
    for argv in (["show", 42], ["search", "--filter", "contrast=1..0"], ["show", "one"],
                 ["add", tmp_path / "junk.texture"], ["render", entry_id, "-o", tmp_path / "x.gif"],
                 ["export", entry_id, "-o", tmp_path / "x.texture"]):
        code, out, err = cli(capsys, "bank", *argv, "--bank", path)
        assert code == 2 and err.count("\n") == 1 and err.startswith("texeditor: error:"), argv
    assert not (tmp_path / "x.texture").exists()
    (tmp_path / "garbage.sqlite").write_bytes(b"x" * 5000)
    code, _, err = cli(capsys, "bank", "list", "--bank", tmp_path / "garbage.sqlite")
    assert code == 2 and "not a texture bank" in err
