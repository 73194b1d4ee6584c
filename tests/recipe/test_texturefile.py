"""The `.texture` file: round trips, and truncated, corrupted or hostile files (issue 3)."""

import io
import json
import os
import struct
import warnings
import zipfile

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY, REFS, TINY, TINY_DPJS, random_history
from texeditor import fileio
from texeditor.recipe import texturefile as tf
from texeditor.recipe.actions import NewCanvas, SetLevels, SetPalette, Synthesize
from texeditor.recipe.document import Document
from texeditor.errors import FormatError, InputError, ReplayError
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay


def sample_history() -> History:
    history = tf.synthesize_texture(TINY_DPJS[0], 24, 16, seed=3)
    second = history.add_dpj(TINY_DPJS[1])
    history.apply(SetLevels(2, 2, 4, 4, 1))
    history.apply(Synthesize(second, 8, 8, 1))
    history.apply(Synthesize(REFS[0], 12, 10, 2))
    history.apply(SetLevels(0, 0, 3, 3, 0))
    return history


@pytest.fixture
def saved(tmp_path):
    path = tmp_path / "a.texture"
    tf.save_texture(path, sample_history(), tags=["stone", "grey"], description="a test")
    return path


def members(path) -> dict[str, bytes]:
    with zipfile.ZipFile(path) as zf:
        return {i.filename: zf.read(i) for i in zf.infolist()}


def write_zip(path, items):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                # duplicate names are the point
        with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
            for name, data in items:
                zf.writestr(name, data)
    return path


# -- round trips -----------------------------------------------------------------------------------

def test_save_reopen_gives_the_same_document_and_the_same_bytes(saved, tmp_path):
    history, manifest = tf.load_texture(saved)
    original = sample_history().document
    assert history.document.result_hash() == original.result_hash() == manifest.result_sha256
    assert np.array_equal(history.document.levels, original.levels)
    assert history.actions == original.actions
    assert manifest.tags == ("stone", "grey") and manifest.description == "a test"
    assert (manifest.width, manifest.height, manifest.levels) == (12, 10, 2)
    again = tmp_path / "b.texture"
    tf.save_texture(again, history, tags=manifest.tags, description=manifest.description)
    assert again.read_bytes() == saved.read_bytes()
    rendered = tf.render_texture(again)
    assert rendered.levels.tobytes() == original.levels.tobytes()


def test_members_and_manifest_layout(saved):
    m = members(saved)
    assert list(m) == ["manifest.json", "actions.json", "dpj.npz", f"dpjs/{REFS[1]}.npz"]
    manifest = json.loads(m["manifest.json"])
    assert manifest["format"] == "texeditor-texture" and manifest["format_version"] == 1
    assert manifest["dpj"] == REFS[0] and manifest["dpjs"] == [REFS[1]]
    assert manifest["actions"] == 5
    assert [a["type"] for a in json.loads(m["actions.json"])["actions"]][:2] == \
        ["synthesize", "set_levels"]


def test_loaded_history_can_undo_and_the_dpj_is_current(saved):
    history, _ = tf.load_texture(saved)
    assert history.document.dpj_ref == REFS[0]
    history.undo()
    assert history.document.result_hash() == replay(history.actions[:4], TINY).result_hash()
    history.goto(1)
    assert history.document.shape == (16, 24)


def test_a_hand_made_texture_has_no_dpj(tmp_path):
    doc = Document.new(5, 4, 3).apply(SetLevels(1, 1, 2, 2, 2))
    path = tmp_path / "hand.texture"
    manifest = tf.save_texture(path, doc)
    assert manifest.dpj is None and set(members(path)) == {"manifest.json", "actions.json"}
    assert tf.render_texture(path).result_hash() == doc.result_hash()


def test_empty_history_round_trips(tmp_path):
    path = tmp_path / "empty.texture"
    tf.save_texture(path, History())
    history, manifest = tf.load_texture(path)
    assert history.document.shape == (0, 0) and manifest.actions == 0


@PROPERTY
@given(st.data())
def test_random_logs_round_trip_through_the_file_format(data):
    history = random_history(data)
    blob, manifest = tf.texture_bytes(history.document, history.applied)
    tex = tf.parse_texture(blob)
    assert tex.actions == history.applied and tex.manifest == manifest
    again = History.from_log(tex.actions, tex.dpjs)
    assert again.document.result_hash() == history.document.result_hash()


# -- CLI helpers -----------------------------------------------------------------------------------

def test_describe_log_numbers_the_actions():
    lines = tf.describe_log(sample_history().actions)
    assert lines[0] == "1. Synthesise 24×16, seed 3" and lines[1].startswith("2. Set 4×4")


def test_optimize_texture_writes_a_shorter_log_with_the_same_result(saved, tmp_path):
    out = tmp_path / "short.texture"
    before, after, notes = tf.optimize_texture(saved, out)
    assert (before, after) == (5, 2) and len(notes) == 3
    assert notes[0].startswith("dropped step 1 (Synthesise 24×16, seed 3): step 3")
    assert tf.render_texture(out).result_hash() == tf.render_texture(saved).result_hash()
    assert set(members(out)) == {"manifest.json", "actions.json", "dpj.npz"}
    assert tf.read_texture(out).manifest.tags == ("stone", "grey")


def test_synthesize_texture_is_one_logged_synthesis():
    history = tf.synthesize_texture(TINY_DPJS[1], 9, 7, seed=4)
    assert history.actions == (Synthesize(REFS[1], 9, 7, 4),)


# -- hostile and broken files ----------------------------------------------------------------------

def replace_member(saved, tmp_path, name, data, extra=(), more=None):
    """A copy of ``saved`` with member ``name`` (and those in ``more``) replaced, ``extra`` added."""
    changes = {name: data, **(more or {})}
    items = [(n, changes.get(n, d)) for n, d in members(saved).items()]
    return write_zip(tmp_path / "bad.texture", items + list(extra))


def test_not_a_zip(tmp_path):
    path = tmp_path / "x.texture"
    path.write_bytes(b"this is not a texture")
    with pytest.raises(FormatError, match="not a zip archive"):
        tf.load_texture(path)


def test_missing_file_and_folder(tmp_path):
    with pytest.raises(FormatError, match="no such file"):
        tf.load_texture(tmp_path / "none.texture")
    with pytest.raises(FormatError, match="folder"):
        tf.load_texture(tmp_path)


@pytest.mark.parametrize("keep", [0.3, 0.6, 0.9, 0.99])
def test_truncated(saved, tmp_path, keep):
    data = saved.read_bytes()
    path = tmp_path / "cut.texture"
    path.write_bytes(data[:int(len(data) * keep)])
    with pytest.raises(FormatError):
        tf.load_texture(path)


def test_corrupted_member_data(saved, tmp_path):
    data = bytearray(saved.read_bytes())
    with zipfile.ZipFile(saved) as zf:
        info = zf.getinfo("actions.json")
    start = info.header_offset + 30 + len(info.filename)
    for k in range(start + 5, start + 25):
        data[k] ^= 0xFF
    path = tmp_path / "corrupt.texture"
    path.write_bytes(bytes(data))
    with pytest.raises(FormatError, match="actions.json"):
        tf.load_texture(path)


@pytest.mark.parametrize("name", ["../evil.json", "/etc/evil", "dpjs/../../evil.npz",
                                  "C:\\evil.npz", "dpjs\\..\\evil.npz"])
def test_path_traversal_names(saved, tmp_path, name):
    path = replace_member(saved, tmp_path, None, None, [(name, b"{}")])
    with pytest.raises(FormatError, match="unsafe member name"):
        tf.load_texture(path)
    assert not (tmp_path.parent / "evil.json").exists()


@pytest.mark.parametrize("name", ["notes.txt", "dpjs/", "dpjs/abc.npz", "DPJ.NPZ"])
def test_unexpected_members(saved, tmp_path, name):
    path = replace_member(saved, tmp_path, None, None, [(name, b"x")])
    with pytest.raises(FormatError, match="unexpected member"):
        tf.load_texture(path)


def test_duplicate_member(saved, tmp_path):
    path = replace_member(saved, tmp_path, None, None, [("manifest.json", b"{}")])
    with pytest.raises(FormatError, match="appears twice"):
        tf.load_texture(path)


def test_huge_declared_size_is_refused_before_reading(saved, tmp_path):
    data = bytearray(saved.read_bytes())
    with zipfile.ZipFile(saved) as zf:
        first = zf.start_dir                  # (the stored .npz members hold zips of their own)
    # the second central-directory entry is actions.json: declare 2 GiB uncompressed
    second = data.index(b"PK\x01\x02", first + 4)
    struct.pack_into("<I", data, second + 24, 2**31)
    path = tmp_path / "huge.texture"
    path.write_bytes(bytes(data))
    with pytest.raises(FormatError, match="declares 2147483648 bytes"):
        tf.load_texture(path)


def test_zip_bomb_ratio(saved, tmp_path):
    bomb = b'{"actions": [' + b" " * (4 * 2**20) + b"]}"
    path = replace_member(saved, tmp_path, "actions.json", bomb)
    with pytest.raises(FormatError, match="zip bomb"):
        tf.load_texture(path)


def test_too_many_members(saved, tmp_path):
    extra = [(f"dpjs/{k:016x}.npz", b"x") for k in range(70)]
    path = replace_member(saved, tmp_path, None, None, extra)
    with pytest.raises(FormatError, match="more than a texture file holds"):
        tf.load_texture(path)


@pytest.mark.parametrize("manifest, message", [
    (b"{not json", "manifest.json is not valid JSON"),
    (b"[1, 2]", "must be a JSON object"),
    (b'{"format": "zip"}', "not a texture file"),
    (b"\xff\xfe", "not valid JSON"),
    (b"[" * 100_000 + b"]" * 100_000, "nests 100000 levels deep"),
], ids=["broken", "list", "format", "utf8", "deep"])
def test_wrong_manifest_json(saved, tmp_path, manifest, message):
    path = replace_member(saved, tmp_path, "manifest.json", manifest)
    with pytest.raises(FormatError, match=message):
        tf.load_texture(path)


@pytest.mark.parametrize("change, message", [
    ({"format_version": 2}, "format version 2 is not supported"),
    ({"format_version": True}, "format version True"),
    ({"width": -1}, "width must be an integer"),
    ({"levels": 3}, "2 colours for G = 3"),
    ({"palette": [[0, 0, 0], [0, 0, 999]]}, "out of range"),
    ({"tags": "stone"}, "tags must be a list"),
    ({"result_sha256": "abc"}, "result_sha256"),
    ({"surprise": 1}, "unexpected keys \\['surprise'\\]"),
    ({"dpjs": []}, "DPJ members do not match"),
    ({"dpj": None}, "DPJ members do not match"),
    ({"actions": 7}, "announces 7 actions"),
    ({"width": float("nan")}, "not valid JSON"),
])
def test_bad_manifest_fields(saved, tmp_path, change, message):
    manifest = json.loads(members(saved)["manifest.json"])
    manifest.update(change)
    path = replace_member(saved, tmp_path, "manifest.json", json.dumps(manifest).encode())
    with pytest.raises(FormatError, match=message):
        tf.load_texture(path)


@pytest.mark.parametrize("actions, message", [
    (b'[]', 'must be an object {"actions"'),
    (b'{"actions": [{"type": "explode", "version": 1}]}', "action 1: unknown action type"),
    (b'{"actions": [{"type": "set_levels", "version": 9}]}', "version 9 is not supported"),
    (b'{"actions": [{"type": "new_canvas", "version": 1, "width": "big", "height": 1, '
     b'"levels": 2}]}', "width must be an integer"),
])
def test_bad_actions_json(saved, tmp_path, actions, message):
    path = replace_member(saved, tmp_path, "actions.json", actions)
    with pytest.raises(FormatError, match=message):
        tf.load_texture(path)


def test_log_using_a_dpj_the_file_lacks(tmp_path):
    path = tmp_path / "hand.texture"
    tf.save_texture(path, Document.new(4, 4, 2))
    log = json.dumps({"actions": [Synthesize(REFS[1], 4, 4, 0).to_json()]}).encode()
    path = replace_member(path, tmp_path, "actions.json", log)
    with pytest.raises(FormatError, match="does not hold"):
        tf.load_texture(path)


def test_damaged_dpj_member(saved, tmp_path):
    path = replace_member(saved, tmp_path, "dpj.npz", b"PK\x03\x04 garbage")
    with pytest.raises(FormatError, match="dpj.npz"):
        tf.load_texture(path)


def npy_header(shape, dtype) -> bytes:
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": np.lib.format.dtype_to_descr(
        np.dtype(dtype)), "fortran_order": False, "shape": shape})
    return buf.getvalue()


def test_dpj_member_declaring_huge_arrays(saved, tmp_path):
    """An .npy header may declare terabytes: refused before numpy allocates anything."""
    inner = io.BytesIO()
    with zipfile.ZipFile(inner, "w") as zf:
        zf.writestr("configs.npy", npy_header((10**12, 2, 2), "u1"))
        zf.writestr("probs.npy", npy_header((10**12,), "<f8"))
        zf.writestr("meta.npy", npy_header((), "<U10") + b"x" * 40)
    path = replace_member(saved, tmp_path, "dpj.npz", inner.getvalue())
    with pytest.raises(FormatError, match="declares"):
        tf.load_texture(path)


def test_hash_mismatch_is_a_replay_error(saved, tmp_path):
    manifest = json.loads(members(saved)["manifest.json"])
    manifest["result_sha256"] = "0" * 64
    path = replace_member(saved, tmp_path, "manifest.json", json.dumps(manifest).encode())
    with pytest.raises(ReplayError, match="another texture"):
        tf.load_texture(path)
    with pytest.raises(ReplayError):
        tf.render_texture(path)


def test_a_log_that_cannot_replay_is_a_replay_error(saved, tmp_path):
    log = {"actions": [NewCanvas(2, 2, 2).to_json(), SetPalette(((0, 0, 0),) * 3).to_json()]}
    manifest = json.loads(members(saved)["manifest.json"])
    manifest["actions"] = 2
    path = replace_member(saved, tmp_path, "actions.json", json.dumps(log).encode(),
                          more={"manifest.json": json.dumps(manifest).encode()})
    with pytest.raises(ReplayError, match="step 2"):
        tf.load_texture(path)


# -- saving never harms an existing file -----------------------------------------------------------

def test_failed_saves_leave_the_existing_file_untouched(saved, monkeypatch):
    before = saved.read_bytes()
    folder = sorted(os.listdir(saved.parent))
    doc = Document()
    doc.apply(NewCanvas(3, 3, 2))
    doc.append_log(Synthesize(REFS[1], 4, 4, 0))        # a log naming a DPJ it does not hold
    with pytest.raises(InputError, match="does not hold"):
        tf.save_texture(saved, doc)
    with pytest.raises(InputError, match="tags"):
        tf.save_texture(saved, Document.new(2, 2, 2), tags=[1, 2])

    def broken_fsync(fd):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(fileio.os, "fsync", broken_fsync)
    with pytest.raises(FormatError, match="cannot write"):
        tf.save_texture(saved, Document.new(2, 2, 2))
    assert saved.read_bytes() == before
    assert sorted(os.listdir(saved.parent)) == folder       # no temporary file left behind


def test_the_current_dpj_is_recorded_as_it_is(tmp_path):
    """Issue 18: a document with no current DPJ (a hand-made canvas whose steps name DPJs)
    saves none, and one whose current DPJ no step uses keeps it; both reopen as they were."""
    from texeditor.recipe.sources import synthesis_recipe
    from texeditor.texture.actions import Mix
    history = History()
    history.apply(NewCanvas(6, 5, 3))
    ref = history.document.store_dpj(TINY_DPJS[0])
    history.apply(Mix(synthesis_recipe(ref, 6, 5, 1), (ref,)))
    assert history.document.dpj_ref is None
    tf.save_texture(tmp_path / "none.texture", history)
    again, manifest = tf.load_texture(tmp_path / "none.texture")
    assert manifest.dpj is None and again.document.dpj_ref is None
    assert tf.render_texture(tmp_path / "none.texture").dpj_ref is None
    other = history.add_dpj(TINY_DPJS[1])                 # loaded, not synthesised from
    tf.save_texture(tmp_path / "loaded.texture", history)
    again, manifest = tf.load_texture(tmp_path / "loaded.texture")
    assert manifest.dpj == other == again.document.dpj_ref
