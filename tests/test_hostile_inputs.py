"""Hostile inputs of issue 17 (classes 1, 2, 5 and 6): forged DPJ references, special files and
JSON bombs, atomic writes on a full disk, and the smaller cases (planar TIFFs, read-only and
damaged banks). Anything that could hang runs in a child process or a thread with a timeout,
so a hang fails the test instead of stopping the suite."""

from __future__ import annotations

import base64
import errno
import io
import json
import os
import sqlite3
import subprocess
import sys
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest

from texeditor import fileio
from texeditor.recipe.actions import Synthesize
from texeditor.bank.store import Bank, BankError
from texeditor.recipe.document import Document, dpj_ref
from texeditor.markov.dpj import DPJ, bytes_ref
from texeditor.errors import FormatError, ImageError, InputError
from texeditor.recipe.history import History
from texeditor.recipe import journal
from texeditor.recipe import texturefile as tf
from texeditor.markov.synthesis import synthesize
from texeditor.recipe.sources import render_recipe, synthesis_recipe
from texeditor.userdata import read_library

from tests.support import REFS, TINY_DPJS, within

ROOT = Path(__file__).resolve().parents[1]
TIMEOUT = 60


def run_cli(*argv, timeout=TIMEOUT, env=None):
    """The real command line in a child process: a hang is a TimeoutExpired, a failure."""
    return subprocess.run([sys.executable, "-m", "texeditor.cli", *map(str, argv)],
                          capture_output=True, text=True, timeout=timeout, cwd=ROOT,
                          env={**os.environ, **(env or {})})


def members(path) -> dict:
    with zipfile.ZipFile(path) as zf:
        return {i.filename: zf.read(i) for i in zf.infolist()}


def write_zip(path, content: dict) -> Path:
    with zipfile.ZipFile(path, "w") as zf:
        for name, data in content.items():
            zf.writestr(name, data)
    return path


def synth_history(k: int, seed: int = 3, size=(12, 10)) -> History:
    history = History()
    ref = history.add_dpj(TINY_DPJS[k])
    history.apply(Synthesize(ref, size[0], size[1], seed))
    return history


# == class 1: a reference always names its content ================================================

def forged_texture(tmp_path) -> Path:
    """A file whose dpj.npz is TINY_DPJS[1] stored under TINY_DPJS[0]'s reference, its manifest
    recording what that forgery replays to, so only the reference check can catch it."""
    good = tmp_path / "good.texture"
    tf.save_texture(good, synth_history(0))
    content = members(good)
    content["dpj.npz"] = TINY_DPJS[1].to_bytes()
    doc = Document()
    doc.dpjs[REFS[0]] = TINY_DPJS[1]
    levels = synthesize(TINY_DPJS[1], (10, 12), seed=3).levels
    with doc.step():
        doc.set_levels(levels, TINY_DPJS[1].palette)
    manifest = json.loads(content["manifest.json"])
    manifest.update(result_sha256=doc.result_hash(), levels=TINY_DPJS[1].levels,
                    palette=TINY_DPJS[1].palette.tolist())
    content["manifest.json"] = json.dumps(manifest).encode()
    return write_zip(tmp_path / "forged.texture", content)


def test_a_forged_dpj_member_is_refused_and_the_memo_stays_clean(tmp_path):
    path = forged_texture(tmp_path)
    for reader in (tf.read_texture, tf.load_texture, tf.render_texture):
        with pytest.raises(FormatError, match=f"not DPJ {REFS[0]}.*forged"):
            reader(path)
    expected = synthesize(TINY_DPJS[0], (10, 12), seed=3).levels
    # the user's own synthesis of the real DPJ at that size and seed, saved and opened again
    history = synth_history(0)
    assert np.array_equal(history.document.levels, expected)
    tf.save_texture(tmp_path / "mine.texture", history)
    again, _ = tf.load_texture(tmp_path / "mine.texture")
    assert np.array_equal(again.document.levels, expected)


def test_a_forged_member_of_dpjs_is_refused(tmp_path):
    good = tmp_path / "two.texture"
    history = synth_history(0)
    history.add_dpj(TINY_DPJS[1])
    history.apply(Synthesize(REFS[1], 5, 4, 1))
    history.document.add_dpj(TINY_DPJS[0], REFS[0])       # the main DPJ is the first again
    tf.save_texture(good, history)
    content = members(good)
    name = f"dpjs/{REFS[1]}.npz"
    assert name in content
    content[name] = TINY_DPJS[0].to_bytes()
    with pytest.raises(FormatError, match=f"dpjs/{REFS[1]}.npz.*not DPJ {REFS[1]}"):
        tf.read_texture(write_zip(tmp_path / "bad.texture", content))


def test_a_document_and_the_synthesis_memo_refuse_a_dpj_under_another_reference():
    doc = Document()
    with pytest.raises(InputError, match="does not name this DPJ"):
        doc.add_dpj(TINY_DPJS[1], REFS[0])
    doc.dpjs[REFS[0]] = TINY_DPJS[1]                       # forged behind its back
    with pytest.raises(InputError, match=f"not {REFS[0]}"):
        doc.apply(Synthesize(REFS[0], 8, 8, 5))
    with pytest.raises(InputError, match=f"not {REFS[0]}"):
        Synthesize(REFS[0], 8, 8, 5).render_result(TINY_DPJS[1])
    with pytest.raises(InputError, match="another DPJ's content"):
        render_recipe(synthesis_recipe(REFS[0], 8, 8, 5), {REFS[0]: TINY_DPJS[1]})


def test_a_forged_bank_row_is_refused_and_reported(tmp_path):
    bank = Bank(tmp_path / "bank.sqlite", builtins=False)
    entry = bank.add(synth_history(0), "genuine")
    with sqlite3.connect(bank.path) as conn:
        conn.execute("UPDATE dpjs SET data = ? WHERE ref = ?", (TINY_DPJS[1].to_bytes(), REFS[0]))
    with pytest.raises(FormatError, match="forged"):
        bank.open(entry)
    problems = [c for c in bank.verify() if not c.ok]
    assert len(problems) == 1 and "forged" in problems[0].message
    bank.close()


def test_a_forged_journal_dpj_ends_the_recovery_before_it(tmp_path):
    folder = tmp_path / "journals"
    j = journal.Journal(folder)
    history = synth_history(0)
    j.reset(history.applied, history.document.dpjs)
    path = j.path
    j._file.close()
    lines = path.read_bytes().split(b"\n")
    forged = [json.loads(x) for x in lines if x]
    for record in forged:
        if record["kind"] == "dpj":
            record["data"] = base64.b64encode(TINY_DPJS[1].to_bytes()).decode()
    path.write_bytes(b"\n".join(json.dumps(r).encode() for r in forged) + b"\n")
    recovered = journal.recover(path)
    assert recovered.dpjs == {} and recovered.actions == ()


def test_bundled_bank_files_still_verify_and_replay_bit_identically():
    for path in sorted((ROOT / "resources" / "bank").glob("*.texture")):
        tex = tf.read_texture(path)
        for ref, dpj in tex.dpjs.items():
            assert dpj.has_ref(ref) and dpj_ref(dpj) == ref
        data = members(path)
        if tex.manifest.dpj:
            assert tex.dpjs[tex.manifest.dpj].to_bytes() == data["dpj.npz"]
        doc = tf.render_texture(path)                        # the recorded SHA-256 is checked
        assert doc.result_hash() == tex.manifest.result_sha256


def test_a_dpj_keeps_the_bytes_it_was_read_from_so_its_reference_survives_a_save(tmp_path):
    """Another numpy/zlib may encode the same arrays differently: the bytes a DPJ was read from
    are the ones saved again, so the reference a file names them by stays true."""
    other = _reencoded(TINY_DPJS[0])                 # same arrays, other bytes (other zlib level)
    assert other != TINY_DPJS[0].to_bytes()
    ref = bytes_ref(other)
    dpj = DPJ.from_bytes(other, "x", ref=ref)
    assert dpj == TINY_DPJS[0] and dpj.to_bytes() == other and dpj_ref(dpj) == ref
    history = History()
    history.document.add_dpj(dpj, ref)
    history.apply(Synthesize(ref, 6, 5, 2))
    tf.save_texture(tmp_path / "a.texture", history)
    assert members(tmp_path / "a.texture")["dpj.npz"] == other
    again, _ = tf.load_texture(tmp_path / "a.texture")
    assert again.document.dpj_ref == ref
    # a file an earlier release re-saved on another machine: the bytes are another encoding,
    # the name this machine's: accepted, and saved again as this machine's encoding
    legacy = DPJ.from_bytes(other, "y", ref=REFS[0])
    assert legacy.to_bytes() == TINY_DPJS[0].to_bytes() and legacy.has_ref(REFS[0])


def _reencoded(dpj: DPJ) -> bytes:
    src = zipfile.ZipFile(io.BytesIO(dpj.to_bytes()))
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED, compresslevel=1) as zf:
        for info in src.infolist():
            zf.writestr(info.filename, src.read(info))
    return out.getvalue()


# == class 2: special files, bounded reads, JSON bombs ============================================

def bomb(depth: int = 2**20 // 2) -> bytes:
    """About 1 MB of nested empty arrays."""
    return b"[" * depth + b"]" * depth


def dpj_with_meta(meta_text: str) -> bytes:
    d = TINY_DPJS[0]
    buf = io.BytesIO()
    np.savez_compressed(buf, configs=d.configs, probs=d.probs, meta=np.array(meta_text))
    return buf.getvalue()


@pytest.mark.parametrize("suffix", [".dpj", ".texture"])
def test_cli_refuses_a_device_and_a_fifo_in_bounded_time(tmp_path, suffix):
    command = ["dpj-info"] if suffix == ".dpj" else ["log"]
    fifo = tmp_path / f"x{suffix}"
    os.mkfifo(fifo)
    for target, kind in (("/dev/zero", "character device"), (fifo, "FIFO")):
        done = run_cli(*command, target)
        assert done.returncode == 2, done.stderr
        assert kind in done.stderr and "not a regular file" in done.stderr
        assert len(done.stderr.strip().splitlines()) == 1


def test_every_reader_refuses_special_files_without_blocking(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    readers = [(DPJ.load, FormatError), (tf.read_texture, FormatError),
               (journal.recover, FormatError),
               (lambda p: read_library(p, "texeditor-grains"), FormatError),
               (lambda p: __import__("texeditor.markov.levels").markov.levels.load_image(p), ImageError)]
    for read, error in readers:
        for target in (fifo, Path("/dev/zero"), tmp_path):
            with pytest.raises(error, match="not a regular file|is a folder"):
                within(20, read, target)


def test_an_image_that_is_a_device_is_not_called_empty(tmp_path):
    from texeditor.markov.levels import load_image
    fifo = tmp_path / "photo.png"
    os.mkfifo(fifo)
    for target, kind in ((Path("/dev/zero"), "character device"), (fifo, "FIFO")):
        with pytest.raises(ImageError) as info:
            within(20, load_image, target)
        assert kind in str(info.value) and "empty" not in str(info.value)
    (tmp_path / "empty.png").write_bytes(b"")
    with pytest.raises(ImageError, match="empty"):
        load_image(tmp_path / "empty.png")


def test_read_limited_never_reads_more_than_the_limit(tmp_path):
    path = tmp_path / "big"
    path.write_bytes(b"x" * 1000)
    with pytest.raises(FormatError, match="limit"):
        fileio.read_limited(path, 999, "thing")
    assert fileio.read_limited(path, 1000, "thing") == b"x" * 1000


def test_json_depth_ignores_brackets_inside_strings():
    assert fileio.json_depth(b'[1, "[[[[\\"[[", {"a": [[]]}]') == 4
    assert fileio.json_depth("{}") == 1 and fileio.json_depth("3") == 0
    assert fileio.json_depth(bomb(1000)) == 1000
    assert fileio.load_json(b'{"a": "]]]]"}', "x", limit=100) == {"a": "]]]]"}
    with pytest.raises(FormatError, match="x nests 65 levels deep"):
        fileio.load_json(bomb(65), "x", limit=10**6)
    with pytest.raises(FormatError, match="x is 11 bytes long, more than the limit of 10"):
        fileio.load_json(b"[" * 11, "x", limit=10)
    with pytest.raises(FormatError, match="x holds 5000 arrays and objects, more than the "
                                          "limit of 4096"):
        fileio.load_json(b"[" + b",".join([b"[]"] * 4999) + b"]", "x", limit=15_000)
    with pytest.raises(FormatError, match="NaN is not allowed"):
        fileio.load_json(b"[NaN]", "x", limit=10)


def test_json_bombs_are_refused_everywhere_before_parsing(tmp_path):
    """1 MB of nested arrays, in every JSON a file can carry: each one refused by its depth."""
    # .dpj meta
    (tmp_path / "m.dpj").write_bytes(dpj_with_meta(bomb().decode()))
    with pytest.raises(FormatError, match="meta nests"):
        within(30, DPJ.load, tmp_path / "m.dpj")
    # .texture manifest and actions
    good = tmp_path / "good.texture"
    tf.save_texture(good, synth_history(0))
    for member in ("manifest.json", "actions.json"):
        bad = write_zip(tmp_path / f"{member}.texture", {**members(good), member: bomb()})
        with pytest.raises(FormatError, match=f"{member} nests"):
            within(30, tf.read_texture, bad)
    # a library, a journal line, a bank log, a recipe, an envelope
    lib = tmp_path / "grains.json"
    lib.write_bytes(b'{"format": "texeditor-grains", "version": 1, "items": ' + bomb() + b"}")
    with pytest.raises(FormatError, match="nests"):
        within(30, read_library, lib, "texeditor-grains")
    from texeditor.bank.store import parse_log
    with pytest.raises(FormatError, match="nests"):
        within(30, parse_log, '{"actions": ' + bomb().decode() + "}", "entry 1")
    from texeditor.recipe.sources import parse_recipe
    with pytest.raises(InputError, match="nests"):
        within(30, parse_recipe, '{"actions": ' + bomb(2**16).decode() + "}")
    from texeditor.spots.envelope import Envelope
    with pytest.raises(InputError, match="nests"):
        within(30, Envelope.loads, bomb(2**16).decode())


def test_a_json_bomb_in_a_dpj_stays_small_in_a_child_process(tmp_path):
    """Peak memory of reading the bomb, measured in a fresh process (VmHWM: getrusage's maxrss
    survives exec and would count the forked pytest's own size)."""
    (tmp_path / "m.dpj").write_bytes(dpj_with_meta(bomb().decode()))
    code = ("import re, sys\nfrom texeditor.cli import main\n"
            f"code = main(['dpj-info', {str(tmp_path / 'm.dpj')!r}])\n"
            "print(re.search(r'VmHWM:\\s+(\\d+)', open('/proc/self/status').read())[1])\n"
            "sys.exit(code)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=TIMEOUT, cwd=ROOT)
    assert done.returncode == 2 and "nests" in done.stderr
    assert int(done.stdout.split()[-1]) < 600 * 1024           # KiB: well below 2 GiB


# == class 5: atomic writes, failures named by the user's path ====================================

@pytest.fixture
def full_disk(monkeypatch):
    """Every write of the atomic writer fails as on a full disk (at its fsync)."""
    def no_space(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(fileio.os, "fsync", no_space)


def test_a_full_disk_leaves_the_old_file_and_names_the_users_path(tmp_path, full_disk):
    target = tmp_path / "out.png"
    target.write_bytes(b"old")
    with pytest.raises(FormatError) as info:
        fileio.write_file(target, b"new" * 1000)
    message = str(info.value)
    assert message == f"{target}: cannot write (No space left on device)"
    assert ".part" not in message and target.read_bytes() == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.png"]
    with pytest.raises(OSError) as raw:
        fileio.atomic_write_bytes(target, b"x")
    assert raw.value.filename == str(target) and raw.value.errno == errno.ENOSPC


def test_every_engine_writer_reports_a_full_disk_naming_the_file(tmp_path, full_disk):
    from texeditor import export
    from texeditor.userdata import write_library
    levels = np.zeros((4, 4), np.uint8)
    writers = [
        ("a.dpj", lambda p: TINY_DPJS[0].save(p)),
        ("a.texture", lambda p: tf.save_texture(p, synth_history(0))),
        ("a.png", lambda p: export.write_png(p, levels, TINY_DPJS[0].palette)),
        ("a.npy", lambda p: export.write_npy(p, levels)),
        ("lib.json", lambda p: write_library(p, "texeditor-grains", [])),
    ]
    for name, write in writers:
        with pytest.raises((FormatError, InputError), match=f"{name}: cannot write \\(No space"):
            write(tmp_path / name)
    assert not list(tmp_path.iterdir())          # no file, no hidden temporary file left


def test_cli_exits_2_naming_the_output_on_a_full_disk(tmp_path, monkeypatch, capsys):
    from texeditor.cli import main
    TINY_DPJS[0].save(tmp_path / "in.dpj")
    monkeypatch.setattr(fileio.os, "fsync",
                        lambda fd: (_ for _ in ()).throw(OSError(errno.ENOSPC, "No space left "
                                                                 "on device")))
    for out in ("o.png", "o.npy", "o.texture"):
        code = main(["synth", str(tmp_path / "in.dpj"), "--size", "8x8", "-o", str(tmp_path / out)])
        err = capsys.readouterr().err
        assert code == 2 and f"{tmp_path / out}: cannot write (No space left on device)" in err
        assert ".part" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.dpj"]


def test_a_write_never_replaces_a_device_or_a_fifo(tmp_path):
    fifo = tmp_path / "out.png"
    os.mkfifo(fifo)
    with pytest.raises(FormatError, match="FIFO"):
        within(20, fileio.write_file, fifo, b"x")
    assert not fifo.is_file() and fifo.exists()


# == class 6: the smaller ones ====================================================================

def test_a_planar_rgb_tiff_is_read_like_an_interleaved_one(tmp_path):
    import tifffile
    from texeditor.markov.levels import load_image
    rng = np.random.default_rng(4)
    rgb = (rng.random((30, 40, 3)) * 255).astype(np.uint8)
    tifffile.imwrite(tmp_path / "planar.tif", np.moveaxis(rgb, -1, 0), photometric="rgb",
                     planarconfig="separate")
    tifffile.imwrite(tmp_path / "contig.tif", rgb, photometric="rgb")
    for name in ("planar.tif", "contig.tif"):
        assert np.array_equal(load_image(tmp_path / name), rgb)
    rgba = (rng.random((20, 10, 4)) * 65535).astype(np.uint16)
    tifffile.imwrite(tmp_path / "planar4.tif", np.moveaxis(rgba, -1, 0), photometric="rgb",
                     planarconfig="separate", extrasamples=["unassalpha"])
    assert np.array_equal(load_image(tmp_path / "planar4.tif"), rgba)


def test_a_negative_schema_version_is_called_invalid(tmp_path):
    path = tmp_path / "neg.sqlite"
    with sqlite3.connect(path) as conn:
        conn.execute("PRAGMA user_version = -3")
    with pytest.raises(BankError, match="schema version -3 is invalid"):
        Bank(path)
    done = run_cli("bank", "list", env={"TEXEDITOR_BANK": str(path)})
    assert done.returncode == 2 and "schema version -3 is invalid" in done.stderr
    assert "duplicate column" not in done.stderr


def test_a_read_only_bank_is_listed_searched_and_opened(tmp_path, monkeypatch, capsys):
    """A bank file and folder this user may only read (the tests run as root, who may write
    anything: the permission check is told the truth for another user)."""
    from texeditor.bank import store as bank_module
    from texeditor.cli import main
    folder = tmp_path / "ro"
    folder.mkdir()
    path = folder / "bank.sqlite"
    bank = Bank(path, builtins=False)
    entry = bank.add(synth_history(0), "granite", tags=["stone"])
    bank.close()
    os.chmod(path, 0o444)
    os.chmod(folder, 0o555)
    monkeypatch.setattr(bank_module.os, "access", lambda p, mode, **kw: not mode & os.W_OK)
    try:
        ro = Bank(path)
        assert ro.read_only
        assert [e.name for e in ro.entries()] == ["granite"] and ro.find("granite") == [entry]
        assert np.array_equal(ro.open(entry).document.levels, synth_history(0).document.levels)
        assert all(c.ok for c in ro.verify())
        with pytest.raises(BankError):
            ro.update(entry, name="changed")
        ro.close()
        monkeypatch.setenv("TEXEDITOR_BANK", str(path))
        assert main(["bank", "list"]) == 0
        assert "granite" in capsys.readouterr().out
    finally:
        os.chmod(folder, 0o755)
        os.chmod(path, 0o644)


def test_a_screenshot_on_a_full_disk_exits_2_and_keeps_the_old_file(tmp_path, full_disk, capsys):
    from app.main import write_screenshot
    target = tmp_path / "window.png"
    target.write_bytes(b"old picture")
    assert write_screenshot(target, b"\x89PNG new") == 2
    err = capsys.readouterr().err
    assert f"{target}: cannot write (No space left on device)" in err and ".part" not in err
    assert target.read_bytes() == b"old picture" and len(list(tmp_path.iterdir())) == 1
    assert write_screenshot(target, None) == 2 and target.read_bytes() == b"old picture"


# -- arguments and flags that once gave a raw exception or a wrong message -------------------
@pytest.mark.parametrize("shape, seed, says", [
    ((5,), 0, "two integers"), ("x", 0, "two integers"), ((64.5, 64), 0, "two integers"),
    ((0, 0), 0, "no points"), ((10 ** 20, 1), 0, "more than"), ((9, 1), 0, "at least 17x17"),
    ((64, 64), 1.5, "seed"), ((64, 64), None, "seed"), ((64, 64), True, "seed"),
    ((64, 64), "3", "seed")])
def test_resynthesize_and_a_model_refuse_bad_sizes_and_seeds_clearly(shape, seed, says):
    """As texeditor.synthesize does: an InputError naming the size the caller gave (not a
    coarse scale's) or the seed, for the one-call path and for a model alike."""
    import texeditor
    rng = np.random.default_rng(0)
    photo = (rng.random((128, 128)) * 255).astype(np.uint8)
    with pytest.raises(InputError, match=says):
        texeditor.resynthesize(photo, shape, seed=seed, scales=3)
    model = texeditor.acquire_model(photo, scales=3)
    with pytest.raises(InputError, match=says):
        model.synthesize(shape, seed=seed)
    assert model.synthesize((17, 17), seed=0).levels.shape == (17, 17)   # the smallest


@pytest.mark.parametrize("matrix", [np.zeros(10, np.uint8), np.uint8(3),
                                    np.zeros((4, 4, 1), np.uint8), np.zeros((0, 5), np.uint8)])
def test_estimate_dpj_refuses_anything_but_a_matrix(matrix):
    from texeditor import estimate_dpj
    for scan in ("rows", "columns"):
        with pytest.raises(InputError, match="non-empty 2-D"):
            estimate_dpj(matrix, (2, 2), 4, scan=scan)


def test_readers_take_bytes_paths_and_refuse_what_is_not_a_path(tmp_path):
    """A bytes path (as open() takes) is read; None or a number is an InputError naming it."""
    import texeditor
    from skimage import io as skio
    picture = np.arange(64, dtype=np.uint8).reshape(8, 8)
    skio.imsave(tmp_path / "p.png", picture, check_contrast=False)
    assert np.array_equal(texeditor.load_image(os.fsencode(tmp_path / "p.png")), picture)
    for reader in (texeditor.load_image, texeditor.load_model, texeditor.load_texture):
        for bad in (None, 5):
            with pytest.raises(InputError, match="path"):
                reader(bad)


@pytest.mark.parametrize("flags, says", [
    (["--coarse-levels", "0"], "G = 0"), (["--coarse-levels", "17"], "G = 17"),
    (["--levels", "-3"], "G = -3"), (["--levels", "5"], "G = 5 on a scale of 5 levels")])
def test_acquire_flags_for_levels_name_the_value_given(tmp_path, capsys, flags, says):
    """A level count out of range is refused naming it (0 is not taken for "the default")."""
    from skimage import io as skio
    from texeditor.cli import main
    rng = np.random.default_rng(1)
    skio.imsave(tmp_path / "p.png", (rng.random((96, 96)) * 255).astype(np.uint8))
    code = main(["acquire", str(tmp_path / "p.png"), "--scales", "3", *flags,
                 "-o", str(tmp_path / "m.dpj")])
    err = capsys.readouterr().err
    assert code == 2 and says in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "m.dpj").exists()


def test_synth_of_a_model_at_size_0x0_says_one_line_without_warnings(tmp_path, capsys):
    from skimage import io as skio
    from texeditor.cli import main
    rng = np.random.default_rng(2)
    skio.imsave(tmp_path / "p.png", (rng.random((96, 96)) * 255).astype(np.uint8))
    assert main(["acquire", str(tmp_path / "p.png"), "--scales", "2",
                 "-o", str(tmp_path / "m.dpj")]) == 0
    capsys.readouterr()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code = main(["synth", str(tmp_path / "m.dpj"), "--size", "0x0",
                     "-o", str(tmp_path / "x.png")])
    err = capsys.readouterr().err
    assert code == 2 and "no points" in err and len(err.strip().splitlines()) == 1


# -- zips that Python's zipfile cannot read -----------------------------------------------------------

def unreadable_zip(data: bytes, field: str) -> bytes:
    """``data`` with every central directory entry asking for a zip version (``version``) or a
    compression method (``method``) Python's zipfile does not implement: it raises
    NotImplementedError, not BadZipFile (found by a fuzz run with a random seed)."""
    out = bytearray(data)
    at = out.find(b"PK\x01\x02")
    while at >= 0:
        offset, value = (6, 255) if field == "version" else (10, 99)
        out[at + offset:at + offset + 2] = value.to_bytes(2, "little")
        at = out.find(b"PK\x01\x02", at + 4)
    return bytes(out)


@pytest.mark.parametrize("field", ["version", "method"])
def test_zips_of_a_version_or_method_python_cannot_read_are_refused_cleanly(field, tmp_path):
    """A DPJ, a texture, a photo model and a bank picture in such a zip are a FormatError (the
    picture: None, as any damaged one), never a NotImplementedError."""
    from texeditor.bank.store import picture_bytes, read_picture, result_hash
    from texeditor.photo import acquire_model
    from texeditor.photo.model import model_from_bytes
    dpj = TINY_DPJS[0]
    history = History.from_log([Synthesize(REFS[0], 12, 10, seed=1)], {REFS[0]: dpj})
    photo = np.random.default_rng(2).integers(0, 256, (64, 64), dtype=np.uint8)
    for data, read in ((dpj.to_bytes(), lambda b: DPJ.from_bytes(b, "x.dpj")),
                       (tf.texture_bytes(history.document, history.actions)[0],
                        lambda b: tf.parse_texture(b, "x.texture")),
                       (acquire_model(photo, scales=2).to_bytes(),
                        lambda b: model_from_bytes(b, "x.dpj"))):
        bad = unreadable_zip(data, field)
        assert bad != data
        with pytest.raises(FormatError):
            read(bad)
    levels = np.zeros((4, 5), np.uint8)
    palette = np.zeros((2, 3), np.uint8)
    path = tmp_path / "picture.npz"
    path.write_bytes(unreadable_zip(picture_bytes(levels, palette), field))
    assert read_picture(path, result_hash(levels, palette), (4, 5), 2) is None
