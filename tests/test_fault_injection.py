"""Killing a process while it saves must never leave a damaged file (issue 11, fault injection).

A forked child saves version B of a file over version A again and again; the parent kills it with
SIGKILL at a random moment. Afterwards the file must be exactly A or exactly B — never a mix, never
truncated — because every write goes to a temporary file that is renamed over the target.
TEXEDITOR_KILLS sets the number of kills per format (default 50).
"""

import os
import random
import signal
import time

import numpy as np

from texeditor import DPJ, estimate_dpj
from texeditor.recipe.actions import SetLevels, Synthesize
from texeditor.recipe.history import History
from texeditor.recipe.texturefile import parse_texture, save_texture

KILLS = int(os.environ.get("TEXEDITOR_KILLS", "50"))


def _history(seed: int, steps: int) -> History:
    dpj = estimate_dpj(np.random.default_rng(seed).integers(0, 3, (40, 40)), (2, 2), 3)
    history = History()
    ref = history.add_dpj(dpj)
    history.apply(Synthesize(ref, 96, 64, seed))
    for k in range(steps):
        history.apply(SetLevels(k % 60, (3 * k) % 90, 3, 4, k % 3))
    return history


def _kill_while_writing(write, rounds: int) -> int:
    """Fork a child that calls write() in a loop, SIGKILL it after a random delay. Returns how
    many kills landed while the child was still alive (writing)."""
    landed = 0
    rng = random.Random(1984)
    for _ in range(rounds):
        pid = os.fork()
        if pid == 0:                              # the child: write until killed
            try:
                while True:
                    write()
            finally:
                os._exit(0)
        time.sleep(rng.uniform(0.0, 0.03))
        os.kill(pid, signal.SIGKILL)
        _, status = os.waitpid(pid, 0)
        landed += os.WIFSIGNALED(status)
    return landed


def test_killing_a_texture_save_leaves_the_old_or_the_new_file(tmp_path):
    path = tmp_path / "t.texture"
    old, new = _history(1, 3), _history(2, 400)
    save_texture(path, old)
    versions = {path.read_bytes()}
    save_texture(tmp_path / "new.texture", new)
    versions.add((tmp_path / "new.texture").read_bytes())
    landed = _kill_while_writing(lambda: save_texture(path, new), KILLS)
    assert landed == KILLS
    data = path.read_bytes()
    assert data in versions                        # intact: exactly one of the two versions
    parse_texture(data, "after the kills")         # and it reads
    leftovers = [p for p in tmp_path.iterdir() if p.name not in ("t.texture", "new.texture")]
    assert all(p.name.startswith(".t.texture.") and p.suffix == ".part" for p in leftovers)


def test_killing_a_dpj_save_leaves_the_old_or_the_new_file(tmp_path):
    path = tmp_path / "d.dpj"
    rng = np.random.default_rng(0)
    old = estimate_dpj(rng.integers(0, 2, (30, 30)), (2, 2), 2)
    new = estimate_dpj(rng.integers(0, 4, (300, 300)), (3, 3), 4)
    old.save(path)
    versions = {path.read_bytes(), new.to_bytes()}
    landed = _kill_while_writing(lambda: new.save(path), KILLS)
    assert landed == KILLS
    assert path.read_bytes() in versions
    DPJ.load(path)


def test_killing_bank_writers_leaves_a_sound_bank(tmp_path, monkeypatch, capsys):
    from texeditor.bank.store import Bank, make_record

    path = tmp_path / "bank.sqlite"
    records = [make_record(_history(3, 5), "first"), make_record(_history(4, 50), "second")]
    bank = Bank(path, builtins=False)
    bank.insert(records[0])
    bank.close()

    def write():
        with_bank = Bank(path, builtins=False)
        entry = with_bank.insert(records[1])
        with_bank.update(entry, tags=("killed", "maybe"))
        with_bank.trash(entry)
        with_bank.close()

    landed = _kill_while_writing(write, KILLS)
    assert landed == KILLS
    bank = Bank(path, builtins=False)
    checks = bank.verify()
    assert bank.integrity() == "ok"
    assert all(check.ok for check in checks), [c for c in checks if not c.ok][:3]
    assert bank.count() >= 1
    bank.close()
    from texeditor.cli import main
    monkeypatch.setenv("TEXEDITOR_BANK", str(path))
    assert main(["bank", "verify"]) == 0
