"""Issue 17, class 3: the bank never trusts the type of a SQLite cell. A row changed by another
program (text in a REAL column, a TEXT where a blob belongs, a BLOB name, deep JSON in the grain
cell) is skipped by `list` and `search`, reported by `verify` and `show`, never a traceback.
Every command runs as `texeditor` in a child process with a timeout."""

import os
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support import ROOT
from tests.support.bank import drawn, synthesised
from texeditor.bank.store import Bank

DAMAGE = {   # name → SQL run on entry 2 (?) of three
    "text in a REAL column": "UPDATE entries SET contrast = 'abc' WHERE id = ?",
    "a BLOB name": "UPDATE entries SET name = x'00ff80' WHERE id = ?",
    "text as a width": "UPDATE entries SET width = 'wide' WHERE id = ?",
    "a REAL time that is text": "UPDATE entries SET created = 'yesterday' WHERE id = ?",
    "deep JSON in the grain cell": "UPDATE entries SET grain = '" + "[" * 100000 + "' WHERE id = ?",
    "a grain cell that is a BLOB": "UPDATE entries SET grain = x'7b7d' WHERE id = ?",
    "a grain cell that is a list": "UPDATE entries SET grain = '[1, 2]' WHERE id = ?",
    "a BLOB tag": "INSERT INTO tags (entry, tag) VALUES (?, x'ff')",
    "a BLOB log": "UPDATE logs SET actions = x'00' WHERE entry = ?",
    "a TEXT thumbnail": "UPDATE thumbnails SET png = 'not a png' WHERE entry = ?",
    "a TEXT where the DPJ blob belongs": "UPDATE dpjs SET data = 'text' WHERE ref IN "
                                         "(SELECT ref FROM entry_dpjs WHERE entry = ?)",
    "a BLOB current DPJ": "UPDATE entries SET main_dpj = x'01' WHERE id = ?",
    "an infinite attribute": "UPDATE entries SET density = 9e999 WHERE id = ?",
}


def texeditor(bank: Path, *argv, timeout: float = 120) -> subprocess.CompletedProcess:
    env = {**os.environ, "TEXEDITOR_BANK": str(bank)}
    return subprocess.run([sys.executable, "-m", "texeditor.cli", "bank", *map(str, argv)],
                          env=env, capture_output=True, text=True, timeout=timeout, cwd=ROOT)


@pytest.fixture
def three(tmp_path):
    path = tmp_path / "bank.sqlite"
    with Bank(path, builtins=False) as bank:
        ids = [bank.add(synthesised(2) if k == 1 else drawn([(0, 0, 4, 4 + k, 1)]), f"entry {k}",
                        tags=["t"]) for k in range(3)]      # the middle one has a DPJ
        bank.prepare_pending()
    return path, ids


def damage(path: Path, sql: str, entry_id: int) -> None:
    conn = sqlite3.connect(path)
    with conn:
        conn.execute(sql, (entry_id,))
    conn.close()


def test_the_cli_runs(three):
    path, ids = three
    proc = texeditor(path, "list")
    assert proc.returncode == 0 and "entry 1" in proc.stdout, proc.stderr


@pytest.mark.parametrize("what", list(DAMAGE))
def test_a_damaged_row_never_makes_a_traceback(three, what):
    path, (first, bad, last) = three
    damage(path, DAMAGE[what], bad)
    for argv in (["list"], ["search", "entry"], ["search", "--like", first],
                 ["search", "--filter", "contrast=0:1e9"], ["show", first], ["show", bad],
                 ["verify"], ["render", bad, "-o", path.parent / "out.png"]):
        proc = texeditor(path, *argv)
        assert "Traceback" not in proc.stderr, (argv, proc.stderr[-3000:])
        assert proc.returncode in (0, 1, 2), (argv, proc.returncode, proc.stderr)
        if argv[0] == "list":                 # the others are listed, the bad one skipped
            assert proc.returncode == 0
            assert "entry 0" in proc.stdout and "entry 2" in proc.stdout
        if argv[0] == "show" and argv[1] == first:
            assert proc.returncode == 0 and "entry 0" in proc.stdout
        if argv[0] == "verify" and what == "a TEXT thumbnail":
            assert proc.returncode == 0       # derived data: computed again
        elif argv[0] == "verify":             # reported, by its id
            assert proc.returncode == 1
            assert f"entry {bad}" in proc.stdout and "1 do not" in proc.stdout, proc.stdout


@pytest.mark.parametrize("what", ["text in a REAL column", "a BLOB name", "text as a width",
                                  "deep JSON in the grain cell"])
def test_list_names_the_row_it_skips(three, what):
    path, (_, bad, _) = three
    damage(path, DAMAGE[what], bad)
    proc = texeditor(path, "list")
    assert proc.returncode == 0
    assert "entry 1" not in proc.stdout
    assert f"skipped: bank entry {bad}:" in proc.stderr and "damaged" in proc.stderr


@pytest.mark.parametrize("stamp", ["1e300", "-1e300", "1e18"])
def test_a_time_past_the_clock_shows_as_unknown_not_as_a_traceback(three, stamp):
    """A REAL creation or modification time the platform's clock cannot show (a hand-edited or
    damaged bank) made `bank show` die with OverflowError, or say "Value too large for defined
    data type" naming nothing; the entry itself is whole."""
    path, (first, bad, _) = three
    damage(path, f"UPDATE entries SET created = {stamp}, modified = {stamp} WHERE id = ?", bad)
    proc = texeditor(path, "show", bad)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr[-2000:]
    assert "entry 1" in proc.stdout and "created at an unknown time" in proc.stdout
    assert texeditor(path, "render", bad, "-o", path.parent / "out.png").returncode == 0
