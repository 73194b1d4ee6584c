"""Old files still open (issue 18): the bank and the `.texture` files written by release 0.1.0
(tests/data/release-0.1, one history per Action type, see its README.md) replay with today's
code to the very result 0.1.0 recorded — its SHA-256 and its current DPJ (expected.json). A
kernel, an operator or the log reader that changed its output fails here. Never regenerate the
files: they are what users have on their disks."""

import json
import shutil

import pytest

from tests.support import DATA, engine_types
from texeditor.bank.store import Bank
from texeditor.recipe.texturefile import load_texture, render_texture

RELEASE = DATA / "release-0.1"
EXPECTED = json.loads((RELEASE / "expected.json").read_text())   # stem → entry, sha256, dpj_ref, actions
STEMS = sorted(EXPECTED)

# Action types registered after release 0.1.0 (none yet): the old files cannot hold them.
ADDED_SINCE_0_1 = frozenset({"synthesize_scales",                      # issue 19
                             "dominance_tree", "lay_along_order",       # issue 21
                             "scatter_regions", "mix_textures",
                             "add_plates", "plates_from_photo", "remove_plates",  # issue 20
                             "on_plates",
                             "random_phase_noise", "texton", "match_histogram",
                             "heeger_bergen", "flow_texture",  # issue 22
                             "fractal_relief", "ifs_motif"})  # issue 22 item 5


@pytest.fixture(scope="module")
def bank(tmp_path_factory):
    """A copy of the old bank (opening it may migrate its schema: never in tests/data)."""
    path = tmp_path_factory.mktemp("release-0.1") / "bank.sqlite"
    shutil.copyfile(RELEASE / "bank.sqlite", path)
    with Bank(path, builtins=False) as b:
        yield b


def test_the_files_are_all_there():
    assert sorted(p.stem for p in RELEASE.glob("*.texture")) == STEMS
    assert sorted(e["entry"] for e in EXPECTED.values()) == list(range(1, len(STEMS) + 1))


@pytest.mark.parametrize("stem", STEMS)
def test_every_bank_entry_opens_and_renders_to_the_recorded_result(bank, stem):
    expected = EXPECTED[stem]
    entry = bank.get(expected["entry"])
    assert entry.name == stem and entry.sha256 == expected["sha256"]
    history = bank.open(expected["entry"])
    assert history.document.result_hash() == expected["sha256"]
    assert history.document.dpj_ref == expected["dpj_ref"]
    # the bank keeps the optimised log: the file's steps, some perhaps folded away
    assert {a.TYPE for a in history.applied} <= set(expected["actions"])
    doc = bank.render(expected["entry"])
    assert doc.result_hash() == expected["sha256"]
    assert doc.dpj_ref == expected["dpj_ref"]


def test_the_old_bank_verifies_every_entry(bank):
    checks = bank.verify()
    assert all(c.ok for c in checks), [c for c in checks if not c.ok]
    assert {c.id for c in checks} == {None} | {e["entry"] for e in EXPECTED.values()}


@pytest.mark.parametrize("stem", STEMS)
def test_every_texture_file_opens_and_renders_to_the_recorded_result(stem):
    expected, path = EXPECTED[stem], RELEASE / f"{stem}.texture"
    history, manifest = load_texture(path)
    assert manifest.result_sha256 == expected["sha256"]
    assert history.document.result_hash() == expected["sha256"]
    assert [a.TYPE for a in history.applied] == expected["actions"]
    # 0.1.0 recorded as current the last DPJ the log names when the document had none; the
    # recorded current DPJ is part of the recipe: opening and rendering both restore it
    assert manifest.dpj == (expected["dpj_ref"] or manifest.dpj)
    assert history.document.dpj_ref == manifest.dpj
    doc = render_texture(path)
    assert doc.result_hash() == expected["sha256"]
    assert doc.dpj_ref == manifest.dpj


def test_the_old_files_hold_every_action_type_of_the_engine(bank):
    in_files = {a.TYPE for stem in STEMS for a in load_texture(RELEASE / f"{stem}.texture")[0].applied}
    in_bank = {a.TYPE for e in EXPECTED.values() for a in bank.open(e["entry"]).applied}
    assert in_files | in_bank == engine_types() - ADDED_SINCE_0_1
    assert {t for e in EXPECTED.values() for t in e["actions"]} == in_files
