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

from texeditor import DPJ, journal
from texeditor.errors import TexeditorError
from texeditor.fileio import MAX_JSON_DEPTH, json_depth, load_json
from texeditor.levels import load_image
from texeditor.texturefile import parse_texture, read_texture
from texeditor.userdata import read_library

from test_hostile_inputs import within

from .test_fuzz_loaders import DPJ_BYTES, TEXTURE_BYTES

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
        from texeditor.texture_actions import parse_recipe
        box = ends(parse_recipe, '{"actions": ' + text + "}")
    elif where == "envelope":
        from texeditor.spots import Envelope
        box = ends(Envelope.loads, text)
    else:
        from texeditor.bank import parse_log
        box = ends(parse_log, '{"actions": ' + text + "}", "entry 1")
    if deep:
        assert "error" in box and ("nests" in str(box["error"])
                                   or "more than the limit" in str(box["error"])), (where, box)


@BOMBS
@given(st.binary(max_size=4096))
def test_load_json_on_arbitrary_bytes_is_clean(blob):
    box = ends(lambda b: load_json(b, "x", limit=2048), blob)
    if "result" in box:
        assert json_depth(blob) <= MAX_JSON_DEPTH
