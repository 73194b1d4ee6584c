"""Replay and undo timings for the action log (issue 3): prints figures, asserts nothing.

Targets: replaying 1,000 mixed actions on a 512² document in ≤ 1 s; undo of one step ≤ 50 ms at any
depth. Run: python3 benchmarks/bench_replay.py
"""

from __future__ import annotations

import itertools
import time

import numpy as np

from texeditor.recipe.actions import (CropCanvas, ResizeCanvas, SetLevels, SetPalette,
                                      Synthesize)
from texeditor.recipe.document import dpj_ref
from texeditor.markov.dpj import DPJ
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.recipe.logopt import optimize

SIDE = 512
STEPS = 1000
G = 4


def bench_dpj() -> DPJ:
    """A 2×2-window DPJ over G levels with every configuration allowed (no dead ends)."""
    configs = np.array(list(itertools.product(range(G), repeat=4)), np.uint8).reshape(-1, 2, 2)
    probs = np.random.default_rng(1).random(len(configs)) ** 4
    return DPJ(configs, probs / probs.sum(), G)


def mixed_log(ref: str, rng: np.random.Generator) -> list:
    """A synthesis, then fills of every size, palette changes, crops and resizes (back to 512²)."""
    log = [Synthesize(ref, SIDE, SIDE, seed=7)]
    while len(log) < STEPS:
        r = rng.random()
        if r < 0.70:                                   # point and brush-sized edits
            size = int(rng.choice([1, 3, 8, 24]))
            t, l = (int(x) for x in rng.integers(0, SIDE - size, 2))
            log.append(SetLevels(t, l, size, size, int(rng.integers(0, G))))
        elif r < 0.85:                                 # large fills
            h, w = (int(x) for x in rng.integers(64, SIDE, 2))
            log.append(SetLevels(0, 0, h, w, int(rng.integers(0, G))))
        elif r < 0.93:
            pal = tuple(tuple(int(c) for c in rng.integers(0, 256, 3)) for _ in range(G))
            log.append(SetPalette(pal))
        elif r < 0.97:
            log.append(CropCanvas(8, 8, SIDE - 16, SIDE - 16))
            log.append(ResizeCanvas(SIDE, SIDE, fill=int(rng.integers(0, G))))
        else:
            log.append(ResizeCanvas(SIDE + 32, SIDE + 32, fill=1))
            log.append(ResizeCanvas(SIDE, SIDE, fill=0))
    return log[:STEPS]


def timed(fn, repeat: int = 3) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


def main() -> None:
    dpj = bench_dpj()
    ref = dpj_ref(dpj)
    dpjs = {ref: dpj}
    log = mixed_log(ref, np.random.default_rng(0))
    print(f"log: {len(log)} actions on a {SIDE}x{SIDE} document, G = {G}")
    replay(log[:1], dpjs)                                # numba warm-up

    cold, doc = timed(lambda: replay(log, dpjs), repeat=2)
    synth, _ = timed(lambda: replay(log[:1], dpjs), repeat=2)
    print(f"replay (plain Document)        {cold * 1e3:8.1f} ms  (synthesis included: "
          f"{synth * 1e3:.1f} ms)")
    print(f"replay, the synthesis aside    {(cold - synth) * 1e3:8.1f} ms")
    hist, history = timed(lambda: History.from_log(log, dpjs), repeat=2)
    print(f"History.from_log (undo records)  {hist * 1e3:6.1f} ms   memory {history.memory}")
    assert history.document.result_hash() == doc.result_hash()

    opt_time, shorter = timed(lambda: optimize(log, dpjs))
    short_replay, short_doc = timed(lambda: replay(shorter, dpjs))
    assert short_doc.result_hash() == doc.result_hash()
    print(f"optimise                       {opt_time * 1e3:8.1f} ms  -> {len(shorter)} actions, "
          f"replay {short_replay * 1e3:.1f} ms")

    for label, options in [("records kept", {}),
                           ("no undo records (snapshots only)", {"undo_memory": 0})]:
        print(f"undo of one step, {label}:")
        history = History.from_log(log, dpjs, **options)
        for depth in (1, 10, 100, 500, 999, 1000):
            history.goto(STEPS - depth + 1)
            kind = type(history.actions[history.index - 1]).__name__
            start = time.perf_counter()
            history.undo()
            took = time.perf_counter() - start
            start = time.perf_counter()
            history.redo()
            redo = time.perf_counter() - start
            print(f"  at step {history.index:4d} ({kind:12s})  undo {took * 1e3:7.2f} ms   "
                  f"redo {redo * 1e3:7.2f} ms")
        history.goto(STEPS)
        start = time.perf_counter()
        while history.undo():
            pass
        print(f"  all {STEPS} undos one by one: {(time.perf_counter() - start) * 1e3:.1f} ms")
    edit = History.from_log(log, dpjs)
    start = time.perf_counter()
    edit.replace(500, SetLevels(0, 0, 64, 64, 1))
    print(f"edit step 500 of {STEPS} and replay the rest  {(time.perf_counter() - start) * 1e3:.1f} ms")
    start = time.perf_counter()
    edit.replace(0, Synthesize(ref, SIDE, SIDE, seed=8))
    print(f"edit step 1 (new seed) and replay the rest   {(time.perf_counter() - start) * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
