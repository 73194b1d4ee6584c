"""Texture bank timings with 10,000 generated entries (issue 10): prints figures only.

Targets: a search ≤ 50 ms; the browser's first paint ≤ 1 s; scrolling never blocks the event loop
more than 100 ms. The entries are made from a few hundred distinct small textures (real recipes,
thumbnails and attributes), copied with random names, tags, descriptions and jittered attributes.
Run: python3 benchmarks/bench_bank.py [--entries 10000] [--distinct 300] [--seed 1]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from texeditor.bank import attributes as attrs  # noqa: E402
from texeditor.recipe.actions import NewCanvas, SetLevels  # noqa: E402
from texeditor.bank.store import Bank, make_record  # noqa: E402
from texeditor.recipe.history import History  # noqa: E402

WORDS = ("gravel sand stone brick grass moss bark wood marble granite slate linen canvas wool "
         "rust cork leather pebble concrete plaster ripple dune cloud foam lichen coral straw "
         "tile weave mesh").split()
TAGS = ("granular fine coarse oriented regular irregular airy dense warm cold grey colour photo "
        "edited seed hand-made spots stripes").split()


def texture(rng) -> History:
    """A small hand-made texture: random rectangles of random levels on a 64×64 canvas."""
    g = int(rng.integers(2, 6))
    history = History()
    history.apply(NewCanvas(64, 64, g))
    size = int(rng.integers(1, 12))
    for _ in range(int(rng.integers(20, 120))):
        h, w = (int(x) for x in rng.integers(1, size + 1, 2) * (1 + rng.integers(0, 4, 2)))
        history.apply(SetLevels(int(rng.integers(0, 64)), int(rng.integers(0, 64)), h, w,
                                int(rng.integers(0, g))))
    return history


def jitter(a: attrs.Attributes, rng) -> attrs.Attributes:
    f = rng.uniform(0.8, 1.2)
    return dataclasses.replace(a, contrast=min(1.0, a.contrast * f), density=min(1.0, a.density * f),
                               granularity=a.granularity * rng.uniform(0.5, 2),
                               orientation=float(rng.uniform(0, 180)),
                               coarseness=a.coarseness * f)


def build(path: Path, n: int, distinct: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    start = time.perf_counter()
    base = [make_record(texture(rng), "base") for _ in range(distinct)]
    made = time.perf_counter() - start
    records = []
    for k in range(n):
        r = base[k % distinct]
        words = rng.choice(WORDS, 3, replace=False)
        records.append(dataclasses.replace(
            r, name=f"{words[0].capitalize()} {words[1]} {k}",
            tags=tuple(sorted(set(rng.choice(TAGS, int(rng.integers(1, 5)))))),
            description=f"A {words[2]} texture, variant {k % 97}, made for the benchmark.",
            attributes=jitter(r.attributes, rng)))
    start = time.perf_counter()
    with Bank(path, builtins=False) as bank:
        for i in range(0, n, 1000):
            bank.insert_many(records[i:i + 1000])
    return {"make": made, "insert": time.perf_counter() - start}


def timed(fn, repeat: int = 7, before=None) -> tuple[float, float, object]:
    """(median ms, max ms, last result) of ``fn()``; ``before()`` runs untimed ahead of each call
    (a change whose cost is not the search's: a write waits for the disk)."""
    times, result = [], None
    for _ in range(repeat):
        if before is not None:
            before()
        start = time.perf_counter()
        result = fn()
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times), max(times), result


def bench_search(path: Path) -> list:
    rows = []
    start = time.perf_counter()
    bank = Bank(path)
    rows.append(("open the bank", (time.perf_counter() - start) * 1e3, None, bank.count()))
    queries = [
        ("list everything (newest first)", lambda: bank.find()),
        ("text: one word", lambda: bank.find("gravel")),
        ("text: two prefixes", lambda: bank.find("mar gran")),
        ("text: a word of the descriptions", lambda: bank.find("variant")),
        ("tag", lambda: bank.find("tag:stripes")),
        ("two tags", lambda: bank.find(tags=["warm", "granular"])),
        ("attribute range", lambda: bank.find(ranges={"contrast": (0.3, 0.6)})),
        ("three ranges", lambda: bank.find(ranges={"contrast": (0.2, 0.8), "density": (0.5, None),
                                                   "granularity": (None, 40)})),
        ("text + tag + range", lambda: bank.find("stone", tags=["grey"],
                                                 ranges={"regularity": (None, 0.5)})),
        ("more like this (whole bank)", lambda: bank.find(like=1)),
        ("more like this, after a re-tag", lambda: bank.find(like=1),
         lambda: bank.update(2, tags=["x"])),
        ("more like this, after an insert", lambda: bank.find(like=1), lambda: bank.duplicate(2)),
        ("an insert (a synchronous commit)", lambda: [bank.duplicate(2)]),
        ("more like this among a tag", lambda: bank.find("tag:fine", like=1)),
        ("entries of a visible page (60)", lambda: bank.entries(range(1, 61))),
        ("thumbnails of a visible page (60)", lambda: bank.thumbnails(range(1000, 1060))),
    ]
    for label, fn, *before in queries:
        median, worst, result = timed(fn, before=before[0] if before else None)
        rows.append((label, median, worst, len(result)))
    bank.close()
    return rows


def bench_browser(path: Path) -> dict:
    from PySide6 import QtWidgets

    from app.main_window import MainWindow
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    window = MainWindow()
    window.resize(1280, 800)
    window.show()
    app.processEvents()
    dock, model = window.bank_dock, window.bank_dock.model

    start = time.perf_counter()
    dock.load(path, prepare=False)
    listed = time.perf_counter() - start
    app.processEvents()              # the view asks for its visible rows, the model reads them
    while model.wanted or model._timer.isActive():
        app.processEvents()
    dock.view.viewport().grab()      # a complete paint with thumbnails
    first_paint = time.perf_counter() - start
    rows = len(model.ids)

    bar = dock.view.verticalScrollBar()
    steps, longest = [], 0.0
    for value in np.linspace(0, bar.maximum(), 120).astype(int):
        t = time.perf_counter()
        bar.setValue(int(value))
        app.processEvents()
        while model._timer.isActive():
            app.processEvents()
        dock.view.viewport().repaint()
        steps.append((time.perf_counter() - t) * 1e3)
    longest = max(steps)

    t = time.perf_counter()
    dock.search.setText("gravel")
    dock.refresh()
    app.processEvents()
    search = (time.perf_counter() - t) * 1e3
    result = {"listed": listed * 1e3, "first_paint": first_paint * 1e3,
              "scroll_median": statistics.median(steps), "scroll_max": longest,
              "scroll_steps": len(steps), "typed_search": search, "cached": len(model.pixmaps),
              "rows": rows}
    window.close()
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--entries", type=int, default=10_000)
    parser.add_argument("--distinct", type=int, default=300)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    print(f"# {platform.processor() or platform.machine()}, Python {platform.python_version()}, "
          f"{os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bench.sqlite"
        built = build(path, args.entries, args.distinct, args.seed)
        size = path.stat().st_size + sum(p.stat().st_size for p in Path(folder).glob("*-wal"))
        print(f"built {args.entries:,} entries from {args.distinct} textures: records "
              f"{built['make']:.1f} s, insert {built['insert']:.2f} s, file {size / 2**20:.1f} MB")
        print(f"\n{'search (10,000 entries)':<36} {'median ms':>10} {'max ms':>8} {'found':>7}")
        for label, median, worst, found in bench_search(path):
            worst_text = f"{worst:>8.1f}" if worst is not None else f"{'':>8}"
            print(f"{label:<36} {median:>10.1f} {worst_text} {found:>7}")
        print("target: ≤ 50 ms per search")
        b = bench_browser(path)
        print(f"\nbrowser: list {b['rows']:,} ids {b['listed']:.0f} ms; first paint with thumbnails "
              f"{b['first_paint']:.0f} ms (target ≤ 1000)")
        print(f"scrolling top to bottom in {b['scroll_steps']} steps: median {b['scroll_median']:.1f}"
              f" ms, longest {b['scroll_max']:.1f} ms per step (target ≤ 100); "
              f"{b['cached']} thumbnails cached")
        print(f"a search typed in the browser, listed and laid out: {b['typed_search']:.0f} ms")


if __name__ == "__main__":
    main()
