"""Generators of hostile inputs that mutating seed files never makes (issue 17): special files
(FIFOs, devices, folders, links to them) given to every reader, and JSON depth and size bombs
placed in every JSON a file can carry. Each must end, within a timeout, in a TexeditorError
(or load, for a bomb small enough to be within the limits). TEXEDITOR_FUZZ_EXAMPLES sets the
budget, as for test_fuzz_loaders."""

from __future__ import annotations

import base64
import io
import json
import os
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from texeditor import DPJ
from texeditor.recipe import journal
from texeditor.errors import TexeditorError
from texeditor.fileio import MAX_JSON_DEPTH, json_depth, load_json
from texeditor.markov.levels import load_image
from texeditor.recipe.texturefile import parse_texture, read_texture
from texeditor.userdata import read_library

from tests.support import within

from tests.support.fuzz import DPJ_BYTES, TEXTURE_BYTES

EXAMPLES = int(os.environ.get("TEXEDITOR_FUZZ_EXAMPLES", "300"))
BOMBS = settings(max_examples=max(EXAMPLES // 5, 30), deadline=None,
                 derandomize=not os.environ.get("CI_FUZZ_RANDOM"),
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
TIMEOUT = 30


def ends(fn, *args):
    """fn(*args) in bounded time: a TexeditorError or a result, never a hang or another
    exception (those fail the test)."""
    try:
        return {"result": within(TIMEOUT, fn, *args)}
    except TexeditorError as exc:
        return {"error": exc}


# -- special files -------------------------------------------------------------------------------

def _special(kind: str, folder: Path) -> Path:
    path = folder / f"special-{kind}"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "folder":
        path.mkdir()
    elif kind in ("zero", "null", "urandom"):
        return Path(f"/dev/{kind}")
    elif kind.startswith("link-"):
        os.symlink(_special(kind[5:], folder), path)
    elif kind == "dangling":
        os.symlink(folder / "nowhere", path)
    return path


KINDS = ["fifo", "folder", "zero", "null", "urandom", "link-fifo", "link-zero", "dangling"]
READERS = {
    "dpj": DPJ.load,
    "texture": read_texture,
    "journal": journal.recover,
    "library": lambda p: read_library(p, "texeditor-grains"),
    "image": load_image,
}


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("reader", sorted(READERS))
def test_special_files_are_refused_by_every_reader(tmp_path, reader, kind):
    box = ends(READERS[reader], _special(kind, tmp_path))
    assert "error" in box, f"{reader} read a {kind}: {box}"
    assert "empty (0 bytes)" not in str(box["error"])


# -- JSON bombs ----------------------------------------------------------------------------------

@st.composite
def json_bombs(draw) -> str:
    """Nested arrays/objects, deep or wide, with brackets hidden in strings and escapes."""
    depth = draw(st.one_of(st.integers(1, MAX_JSON_DEPTH + 2),
                           st.integers(MAX_JSON_DEPTH, 2**17)))
    opener = draw(st.sampled_from(["[", '{"a":', '[{"b":[', '["]]\\"[",']))
    closer = {"[": "]", '{"a":': "}", '[{"b":[': "]}]", '["]]\\"[",': "]"}[opener]
    core = draw(st.sampled_from(["[]", "{}", "0", '"[[["', "[" * 3 + "]" * 3]))
    text = opener * depth + core + closer * depth
    width = draw(st.integers(1, 3))
    return "[" + ",".join([text] * width) + "]"


def _dpj_with_meta(text: str) -> bytes:
    d = DPJ.from_bytes(DPJ_BYTES)
    buf = io.BytesIO()
    np.savez_compressed(buf, configs=d.configs, probs=d.probs, meta=np.array(text))
    return buf.getvalue()


def _texture_with(member: str, text: str) -> bytes:
    src = zipfile.ZipFile(io.BytesIO(TEXTURE_BYTES))
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as zf:
        for info in src.infolist():
            zf.writestr(info.filename, text.encode() if info.filename == member
                        else src.read(info))
    return out.getvalue()


def _journal_with(text: str, folder: Path) -> Path:
    path = folder / "x.journal"
    start = json.dumps({"kind": "start", "format": 1, "time": 0.0, "source": None})
    dpj = json.dumps({"kind": "dpj", "ref": "0" * 16,
                      "data": base64.b64encode(DPJ_BYTES).decode()})
    path.write_text("\n".join([start, dpj, text]) + "\n")
    return path


@BOMBS
@given(json_bombs(), st.sampled_from(["meta", "manifest.json", "actions.json", "library",
                                      "journal", "recipe", "envelope", "bank log"]))
def test_json_bombs_are_refused_or_loaded_in_bounded_time(tmp_path_factory, text, where):
    folder = tmp_path_factory.mktemp("bomb")
    deep = json_depth(text) > MAX_JSON_DEPTH
    if where == "meta":
        box = ends(DPJ.from_bytes, _dpj_with_meta(text))
    elif where in ("manifest.json", "actions.json"):
        box = ends(parse_texture, _texture_with(where, text))
    elif where == "library":
        path = folder / "grains.json"
        path.write_text('{"format": "texeditor-grains", "version": 1, "items": ' + text + "}")
        box = ends(read_library, path, "texeditor-grains")
    elif where == "journal":
        box = ends(journal.recover, _journal_with(text, folder))
        return                    # a damaged line ends the recovery: no error to see
    elif where == "recipe":
        from texeditor.recipe.sources import parse_recipe
        box = ends(parse_recipe, '{"actions": ' + text + "}")
    elif where == "envelope":
        from texeditor.spots.envelope import Envelope
        box = ends(Envelope.loads, text)
    else:
        from texeditor.bank.store import parse_log
        box = ends(parse_log, '{"actions": ' + text + "}", "entry 1")
    if deep:
        assert "error" in box and any(reason in str(box["error"]) for reason in (
            "nests", "more than the limit", "zip bomb")), (where, box)


def _png(width: int, height: int, mode: str) -> bytes:
    from PIL import Image
    out = io.BytesIO()
    Image.new(mode, (width, height), 90).save(out, format="PNG")
    return out.getvalue()


@BOMBS
@given(base=st.sampled_from([(8, 8, "L"), (64, 64, "RGB"), (65, 4, "L"), (1, 30, "L"),
                             (16, 16, "P"), (16, 16, "I;16"), (16, 16, "RGBA"),
                             (5000, 5000, "1")]),
       flips=st.lists(st.tuples(st.integers(0, 2**20), st.integers(0, 255)), max_size=6),
       cut=st.integers(0, 2**20), junk=st.binary(max_size=64))
def test_damaged_thumbnails_never_cost_the_steps_after_them(tmp_path_factory, base, flips,
                                                            cut, junk):
    """A journal's thumbnail record holding any mutated, cut or odd PNG (palette, 16-bit,
    alpha, too large, a bomb's header) is passed over: the log after it recovers whole, and a
    thumbnail, when one is kept, is within bounds."""
    png = bytearray(_png(*base))
    for at, value in flips:
        png[at % len(png)] = value
    png = bytes(png[:max(8, cut % (len(png) + 1))]) + junk
    path = tmp_path_factory.mktemp("thumb") / "x.journal"
    records = [{"kind": "start", "format": 1, "time": 0.0, "source": None},
               {"kind": "thumbnail", "png": base64.b64encode(png).decode()},
               {"kind": "log", "keep": 0, "append": [{"type": "new_canvas", "version": 1,
                                                      "width": 9, "height": 7, "levels": 3}]}]
    path.write_text("".join(json.dumps(record) + "\n" for record in records))
    got = ends(journal.recover, path)["result"]
    assert len(got.actions) == 1
    if got.thumbnail is not None:
        assert got.thumbnail.dtype == np.uint8 and got.thumbnail.ndim in (2, 3)
        assert 2 <= min(got.thumbnail.shape[:2]) and max(got.thumbnail.shape[:2]) <= 64


@BOMBS
@given(st.binary(max_size=4096))
def test_load_json_on_arbitrary_bytes_is_clean(blob):
    box = ends(lambda b: load_json(b, "x", limit=2048), blob)
    if "result" in box:
        assert json_depth(blob) <= MAX_JSON_DEPTH


# -- type-confused SQLite cells ------------------------------------------------------------------

BANK_CELLS = {     # table → (key column, {column: the type texeditor writes there})
    "entries": ("id", {**dict.fromkeys(["name", "description", "main_dpj", "grain", "sha256"],
                                       "text"),
                       **dict.fromkeys(["width", "height", "levels", "action_count", "builtin",
                                        "attributes_version", "parent"], "integer"),
                       **dict.fromkeys(["contrast", "granularity", "density", "directivity",
                                        "orientation", "regularity", "created", "modified",
                                        "period", "coarseness", "trashed"], "real")}),
    "logs": ("entry", {"actions": "text"}),
    "thumbnails": ("entry", {"png": "blob"}),
    "tags": ("entry", {"tag": "text"}),
    "entry_dpjs": ("entry", {"ref": "text"}),
}
NOT_UTF8 = st.binary(min_size=1, max_size=12).filter(lambda b: not _utf8(b))


def _utf8(data: bytes) -> bool:
    try:
        data.decode("utf-8")
        return True
    except UnicodeDecodeError:
        return False


def confused(kind: str):
    """(SQL expression, value) of a type other than ``kind``: what another program may store."""
    numbers = st.one_of(st.integers(-2**63, 2**63 - 1), st.floats(allow_nan=True,
                                                                   allow_infinity=True))
    text = st.one_of(st.text(max_size=40), json_bombs(),
                     st.sampled_from(["", "9e999", "NaN", "{}", '{"actions": 1}', "0" * 30]))
    others = {"text": [numbers, st.binary(max_size=40)],
              "integer": [text, st.binary(max_size=40), st.floats(allow_nan=True,
                                                                  allow_infinity=True)],
              "real": [text, st.binary(max_size=40)],
              "blob": [text, numbers]}[kind]
    plain = st.tuples(st.just("?"), st.one_of(*others, st.none()))
    bad_text = st.tuples(st.just("CAST(? AS TEXT)"), NOT_UTF8)      # TEXT that is not UTF-8
    return st.one_of(plain, bad_text) if kind != "text" else st.one_of(plain, bad_text, bad_text)


@pytest.fixture(scope="module")
def bank_seed(tmp_path_factory):
    from tests.support.bank import drawn, synthesised
    from texeditor.bank.store import Bank
    path = tmp_path_factory.mktemp("bank") / "seed.sqlite"
    with Bank(path, builtins=False) as bank:
        ids = [bank.add(synthesised(2) if k == 1 else drawn([(0, 0, 4, 4 + k, 1)]), f"entry {k}",
                        tags=["t", f"k{k}"]) for k in range(3)]
        bank.prepare_pending()
    return path.read_bytes(), ids


def _every_reader(path):
    """What the bank's commands and browser do with a bank: list, search, show, open, verify."""
    from texeditor.bank.store import Bank
    from argparse import Namespace
    from contextlib import redirect_stdout
    from texeditor.bank.cli import cmd_list, cmd_show
    with Bank(path, builtins=False) as bank, redirect_stdout(io.StringIO()):
        cmd_list(bank, Namespace(trash=False))
        found = bank.search()
        bank.search("entry", tags=["t"])
        bank.search(ranges={"contrast": (0, 1), "density": (None, 0.5)})
        bank.all_tags()
        bank.names([e.id for e in found])
        for entry in found:
            bank.thumbnails([entry.id])
            bank.search(like=entry.id)
            try:
                cmd_show(bank, Namespace(id=entry.id))
                bank.render(entry.id)
                bank.open(entry.id)
            except TexeditorError:
                pass             # this entry is damaged: said so, the others still readable
        bank.verify()
        return len(found)


CELLS = settings(BOMBS, max_examples=max(EXAMPLES // 2, 30))


@CELLS
@given(table=st.sampled_from(sorted(BANK_CELLS)), which=st.integers(0, 2), data=st.data())
def test_type_confused_bank_cells_are_skipped_or_refused(tmp_path_factory, bank_seed, table, which,
                                                         data):
    import sqlite3
    seed, ids = bank_seed
    key, columns = BANK_CELLS[table]
    column = data.draw(st.sampled_from(sorted(columns)), label="column")
    expression, value = data.draw(confused(columns[column]), label="value")
    path = tmp_path_factory.mktemp("cells") / "bank.sqlite"
    path.write_bytes(seed)
    conn = sqlite3.connect(path)
    try:
        with conn:
            conn.execute(f"UPDATE {table} SET {column} = {expression} WHERE {key} = ?",
                         (value, ids[which]))
    except (sqlite3.IntegrityError, OverflowError, UnicodeEncodeError, ValueError):
        return                   # SQLite itself refuses to store it: nothing to read back
    finally:
        conn.close()
    box = ends(_every_reader, path)
    if "result" in box:
        assert box["result"] >= 2       # at most the damaged entry is left out of the list
