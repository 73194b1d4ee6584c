"""Fuzzing the loaders: valid files mutated at random must load or fail with a TexeditorError.

Every loader (.dpj, .texture and its replay, images) gets byte flips, truncations, insertions,
zip member tampering and JSON field mutations. The budget is modest in the normal suite; set
TEXEDITOR_FUZZ_EXAMPLES (per loader and mutation family) for a long run. Inputs that once crashed
a loader are kept in tests/fuzz/corpus/<loader>/ and replayed by test_corpus.
"""

import hashlib
import io
import json
import os
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st
from skimage import data

from tests.support.fuzz import DPJ_BYTES, TEXTURE_BYTES, seed_dpj
from texeditor import DPJ, estimate_dpj, quantize
from texeditor.errors import TexeditorError
from texeditor.recipe.history import History
from texeditor.markov.levels import load_image
from texeditor.recipe.texturefile import parse_texture, texture_bytes

EXAMPLES = int(os.environ.get("TEXEDITOR_FUZZ_EXAMPLES", "300"))
CORPUS = Path(__file__).parent / "corpus"
FUZZ = settings(max_examples=EXAMPLES, deadline=None, derandomize=not os.environ.get("CI_FUZZ_RANDOM"),
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
# Mutated archives repeat member names on purpose (a loader must refuse them): zipfile warns.
pytestmark = pytest.mark.filterwarnings("ignore:Duplicate name:UserWarning")


# -- valid seeds ------------------------------------------------------------------------------------


def _recipe_texture() -> bytes:
    """A texture whose steps carry recipes of two DPJs, one of them nested two deep."""
    from texeditor.recipe.actions import Synthesize
    from texeditor.texture.actions import Incrust, Mix
    from texeditor.recipe.sources import recipe_of, synthesis_recipe

    history = History()
    ref = history.add_dpj(seed_dpj())
    q = quantize(data.camera()[:48, :48], 2)
    other = history.document.store_dpj(estimate_dpj(q.levels, (1, 2), 2, palette=q.palette))
    flat = recipe_of([Synthesize(ref, 8, 6, 1),
                      Mix(synthesis_recipe(other, 5, 4, 2), (other,), op2="max")])
    for action in (Synthesize(ref, 16, 12, 3), Mix(flat, (ref, other), op2="xor"),
                   Incrust(synthesis_recipe(other, 6, 6, 4), (other,), mask="texture",
                           levels="1", mask_source=flat, mask_dpjs=(other, ref))):
        history.apply(action)
    return texture_bytes(history.document, history.applied)[0]


RECIPE_TEXTURE_BYTES = _recipe_texture()


def _png() -> bytes:
    import imageio.v3 as iio
    return iio.imwrite("<bytes>", data.camera()[:32, :48], extension=".png")


PNG_BYTES = _png()


# -- mutations --------------------------------------------------------------------------------------

@st.composite
def byte_mutations(draw, seed: bytes) -> bytes:
    """Flip, overwrite, insert or delete a few bytes, or truncate."""
    buf = bytearray(seed)
    for _ in range(draw(st.integers(1, 6))):
        if not buf:
            break
        op = draw(st.sampled_from(["flip", "set", "insert", "delete", "truncate"]))
        i = draw(st.integers(0, len(buf) - 1))
        if op == "flip":
            buf[i] ^= 1 << draw(st.integers(0, 7))
        elif op == "set":
            buf[i] = draw(st.sampled_from([0, 0xFF, 0x7F, 0x80, draw(st.integers(0, 255))]))
        elif op == "insert":
            buf[i:i] = draw(st.binary(min_size=1, max_size=16))
        elif op == "delete":
            del buf[i:i + draw(st.integers(1, 16))]
        else:
            del buf[i:]
    return bytes(buf)


JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-2**70, 2**70) | st.floats(allow_nan=True)
    | st.text(max_size=20),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner,
                                                                   max_size=4),
    max_leaves=8)


def _mutate_json(draw, obj):
    """Replace, delete or add one field somewhere in a JSON tree."""
    if isinstance(obj, dict) and obj:
        key = draw(st.sampled_from(sorted(obj)))
        op = draw(st.sampled_from(["replace", "delete", "recurse", "add"]))
        obj = dict(obj)
        if op == "replace":
            obj[key] = draw(JSON_VALUES)
        elif op == "delete":
            del obj[key]
        elif op == "add":
            obj[draw(st.text(max_size=8))] = draw(JSON_VALUES)
        else:
            obj[key] = _mutate_json(draw, obj[key])
        return obj
    if isinstance(obj, list) and obj:
        i = draw(st.integers(0, len(obj) - 1))
        obj = list(obj)
        op = draw(st.sampled_from(["replace", "delete", "recurse", "duplicate"]))
        if op == "replace":
            obj[i] = draw(JSON_VALUES)
        elif op == "delete":
            del obj[i]
        elif op == "duplicate":
            obj.insert(i, obj[i])
        else:
            obj[i] = _mutate_json(draw, obj[i])
        return obj
    if isinstance(obj, bool) or obj is None:
        return draw(JSON_VALUES)
    if isinstance(obj, int):
        return draw(st.sampled_from([-1, 0, obj + 1, obj * 1000, 2**31, 2**63, -2**63, 10**30]))
    if isinstance(obj, float):
        return draw(st.sampled_from([float("nan"), float("inf"), -obj, obj * 1e12]))
    return draw(JSON_VALUES)


@st.composite
def zip_mutations(draw, seed: bytes) -> bytes:
    """Tamper with the members of a zip: drop, rename, duplicate, replace, mutate JSON inside."""
    with zipfile.ZipFile(io.BytesIO(seed)) as zf:
        members = [(i.filename, zf.read(i)) for i in zf.infolist()]
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(["drop", "rename", "duplicate", "replace", "json", "bytes",
                                   "extra"]))
        if not members:
            break
        k = draw(st.integers(0, len(members) - 1))
        name, content = members[k]
        if op == "drop":
            del members[k]
        elif op == "rename":
            members[k] = (draw(st.sampled_from(["../evil", "/abs", "a/../../b", "dpj.npz",
                                                "manifest.json", "x" * 300, "dpjs/zz.npz"])),
                          content)
        elif op == "duplicate":
            members.append((name, content))
        elif op == "replace":
            members[k] = (name, draw(st.binary(max_size=64)))
        elif op == "json":
            try:
                obj = json.loads(content)
            except ValueError:
                continue
            members[k] = (name, json.dumps(_mutate_json(draw, obj)).encode())
        elif op == "bytes":
            members[k] = (name, draw(byte_mutations(content)))
        else:
            members.append((draw(st.text(min_size=1, max_size=12).filter(
                lambda n: n.replace("\\", "/").strip("/").strip(".") and "\x00" not in n)), b"{}"))
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, content in members:
            zf.writestr(name, content)
    return buf.getvalue()


@st.composite
def recipe_mutations(draw, seed: bytes) -> bytes:
    """Mutate the JSON inside a step's recipe (a source or a mask), at the top or one level
    down, and put the file back together."""
    with zipfile.ZipFile(io.BytesIO(seed)) as zf:
        members = {i.filename: zf.read(i) for i in zf.infolist()}
    log = json.loads(members["actions.json"])
    carriers = [a for a in log["actions"] if "source" in a]
    step = draw(st.sampled_from(carriers))
    key = draw(st.sampled_from([k for k in ("source", "mask_source") if step.get(k)]))
    step[key] = _mutate_recipe(draw, step[key], draw(st.booleans()))
    members["actions.json"] = json.dumps(log).encode()
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, content in members.items():
            zf.writestr(name, content)
    return buf.getvalue()


def _mutate_recipe(draw, text: str, deeper: bool) -> str:
    obj = json.loads(text)
    inner = [a for a in obj["actions"] if isinstance(a.get("source"), str)]
    if deeper and inner:
        inner[0]["source"] = _mutate_recipe(draw, inner[0]["source"], False)
    else:
        obj = _mutate_json(draw, obj)
    return json.dumps(obj, separators=(",", ":"))


# -- oracles ----------------------------------------------------------------------------------------

def load_dpj(blob: bytes) -> None:
    DPJ.from_bytes(blob, "fuzz.dpj")


def load_texture(blob: bytes) -> None:
    """Parse, then replay the log: a file may be well formed and still not replay."""
    tex = parse_texture(blob, "fuzz.texture")
    History.from_log(tex.actions, tex.dpjs)


def load_picture(blob: bytes, tmp_dir: Path) -> None:
    path = tmp_dir / "fuzz.png"
    path.write_bytes(blob)
    image = load_image(path)
    quantize(image, 4)


def only_texeditor_errors(fn, blob, *args) -> None:
    """The oracle: a clean load or a TexeditorError. Anything else is a crasher: it is kept in
    the corpus (so it stays a regression test once fixed) and the test fails."""
    try:
        fn(blob, *args)
    except TexeditorError:
        pass
    except BaseException:
        kind = next((k for k, f in LOADERS.items() if f is fn), "other")
        folder = CORPUS / kind
        folder.mkdir(parents=True, exist_ok=True)
        (folder / f"{hashlib.sha256(blob).hexdigest()[:16]}.bin").write_bytes(blob)
        raise


# -- the fuzz tests ---------------------------------------------------------------------------------

@FUZZ
@given(st.one_of(byte_mutations(DPJ_BYTES), zip_mutations(DPJ_BYTES)))
def test_fuzz_dpj(blob):
    only_texeditor_errors(load_dpj, blob)


@FUZZ
@given(st.one_of(byte_mutations(TEXTURE_BYTES), zip_mutations(TEXTURE_BYTES)))
def test_fuzz_texture(blob):
    only_texeditor_errors(load_texture, blob)


@FUZZ
@given(zip_mutations(TEXTURE_BYTES))
def test_fuzz_texture_members(blob):
    only_texeditor_errors(load_texture, blob)


@FUZZ
@given(st.one_of(zip_mutations(RECIPE_TEXTURE_BYTES), recipe_mutations(RECIPE_TEXTURE_BYTES)))
def test_fuzz_texture_recipes(blob):
    only_texeditor_errors(load_texture, blob)


@FUZZ
@given(byte_mutations(PNG_BYTES))
def test_fuzz_image(tmp_path_factory, blob):
    only_texeditor_errors(load_picture, blob, tmp_path_factory.mktemp("img"))


# -- the corpus of past crashers ----------------------------------------------------------------------

LOADERS = {"dpj": load_dpj, "texture": load_texture, "image": load_picture}


def test_corpus(tmp_path):
    """Every kept crasher now loads or fails cleanly (the folder names the loader)."""
    for kind, loader in LOADERS.items():
        for path in sorted((CORPUS / kind).glob("*")):
            extra = (tmp_path,) if kind in ("image", "bank") else ()
            only_texeditor_errors(loader, path.read_bytes(), *extra)


def test_the_seeds_themselves_load():
    load_dpj(DPJ_BYTES)
    load_texture(TEXTURE_BYTES)
    load_texture(RECIPE_TEXTURE_BYTES)
    assert np.asarray(load_image_bytes(PNG_BYTES)).shape == (32, 48)


def load_image_bytes(blob):
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "seed.png"
        path.write_bytes(blob)
        return load_image(path)


# -- the bank's database ----------------------------------------------------------------------------

def _bank_bytes() -> bytes:
    import tempfile

    from texeditor.bank.store import Bank, make_record

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bank.sqlite"
        bank = Bank(path, builtins=False)
        history = History()
        ref = history.add_dpj(seed_dpj())
        from texeditor.recipe.actions import Synthesize
        history.apply(Synthesize(ref, 16, 16, 1))
        bank.insert(make_record(history, "seed entry", tags=("fuzz",)))
        bank.close()
        return path.read_bytes()


BANK_BYTES = _bank_bytes()


def load_bank(blob: bytes, tmp_dir: Path) -> None:
    """Open a mutated bank file, list and search it, open and verify every entry."""
    from texeditor.bank.store import Bank

    path = tmp_dir / "bank.sqlite"
    for stale in tmp_dir.glob("bank.sqlite*"):
        stale.unlink()
    path.write_bytes(blob)
    bank = Bank(path, builtins=False)
    try:
        for entry in bank.entries():
            bank.render(entry.id)
        bank.search("seed")
        bank.verify()
    finally:
        bank.close()


LOADERS["bank"] = load_bank


@settings(max_examples=max(EXAMPLES // 3, 20), deadline=None,
          derandomize=not os.environ.get("CI_FUZZ_RANDOM"),
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(byte_mutations(BANK_BYTES))
def test_fuzz_bank(tmp_path_factory, blob):
    only_texeditor_errors(load_bank, blob, tmp_path_factory.mktemp("bank"))
