"""Region operator timings on a 2048² synthesised texture (issue 5): prints figures only.

Target: fill, each extraction and translate in ≤ 30 ms per operation. The texture is synthesised
from resources/dpj/gravel-3x3-g4.dpj; each operation runs at the same random points, and both the
pure function (`regions`) and the Action applied to a Document (writes and undo record included)
are timed. Run: python3 benchmarks/bench_regions.py [--side 2048] [--points 16] [--seed 1]
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from pathlib import Path

import numpy as np

from texeditor import DPJ, synthesize
from texeditor.regions import extractext as regions
from texeditor.regions import transforms
from texeditor.recipe.document import Document
from texeditor.regions.actions import (ChangeLevel, Copy, Fill, Identity, Isometry,
                                      RotateSelection, Translate)

DPJ_PATH = Path(__file__).resolve().parent.parent / "resources" / "dpj" / "gravel-3x3-g4.dpj"
TARGET_MS = 30.0


def timed(fn, points, repeat: int = 3) -> list[float]:
    """Best-of-``repeat`` milliseconds of ``fn(point)`` for each point."""
    out = []
    for p in points:
        best = float("inf")
        for _ in range(repeat):
            start = time.perf_counter()
            fn(p)
            best = min(best, time.perf_counter() - start)
        out.append(best * 1e3)
    return out


def document_of(levels: np.ndarray, g: int) -> Document:
    doc = Document.new(levels.shape[1], levels.shape[0], g)
    with doc.step():
        doc.set_levels(levels)
    return doc


def action_timer(doc: Document, make):
    """Time apply() of an Action with undo recording on, then swap the record back (undo)."""
    def run(p):
        with doc.step(record=[]) as atoms:
            make(p).apply(doc)
        for atom in reversed(atoms):
            atom.swap(doc)
    return run


def row(name: str, ms: list[float], extra: str = "") -> None:
    mark = "ok" if np.median(ms) <= TARGET_MS else "SLOW"
    print(f"{name:<34} {np.median(ms):8.2f} {max(ms):8.2f}  {mark:<4} {extra}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--side", type=int, default=2048)
    ap.add_argument("--points", type=int, default=16)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()

    dpj = DPJ.load(DPJ_PATH)
    start = time.perf_counter()
    levels = synthesize(dpj, (args.side, args.side), seed=args.seed).levels
    synth_s = time.perf_counter() - start
    g = dpj.levels
    rng = np.random.default_rng(args.seed)
    margin = args.side // 16
    points = [tuple(int(x) for x in rng.integers(margin, args.side - margin, 2))
              for _ in range(args.points)]
    sizes = [int(regions.extractext(levels, p).sum()) for p in points]
    ring_sizes = [int(regions.neighbour_labels(levels, p).max()) for p in points]

    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python "
          f"{platform.python_version()}; texture {args.side}² from {DPJ_PATH.name} "
          f"(G = {g}, synthesised in {synth_s:.2f} s); {len(points)} random points, best of 3")
    print(f"regions at the points: median {int(np.median(sizes))} points (max {max(sizes)}), "
          f"median {int(np.median(ring_sizes))} neighbours (max {max(ring_sizes)})")
    print(f"{'operation':<34} {'med ms':>8} {'max ms':>8}  target {TARGET_MS:g} ms")

    print("-- pure functions (regions, transforms)")
    shift = (37, -23)
    for name, fn in [
        ("extractext (region)", lambda p: regions.extractext(levels, p)),
        ("extractext (global)", lambda p: regions.extractext(levels, p, scope="global")),
        ("fill (region)", lambda p: regions.fill(levels, p, 1)),
        ("fill (global)", lambda p: regions.fill(levels, p, 1, scope="global")),
        ("translate (region)", lambda p: regions.translate(levels, p, (p[0] + shift[0],
                                                                       p[1] + shift[1]))),
        ("copy (region)", lambda p: regions.copy(levels, p, (p[0] + shift[0], p[1] + shift[1]))),
        ("extract region in region", lambda p: regions.extract_region_in_region(levels, p)),
        ("extract regions in region", lambda p: regions.extract_regions_in_region(levels, p)),
        ("extract neighbours (labels)", lambda p: regions.neighbour_labels(levels, p)),
        ("extract neighbours (mask list)", lambda p: regions.extract_neighbours(levels, p)),
        ("extract partial", lambda p: regions.extract_partial(levels, p)),
        ("extract neighbours (8-conn.)",
         lambda p: regions.neighbour_labels(levels, p, connectivity=8)),
        ("rotate selection 30°", lambda p: regions.rotate(levels, regions.extractext(levels, p),
                                                          30)),
    ]:
        row(name, timed(fn, points))

    print("-- Actions on a Document (selection + write + undo record)")
    doc = document_of(levels, g)
    for name, make in [
        ("Fill", lambda p: Fill(p[0], p[1], 1)),
        ("Translate", lambda p: Translate(p[0], p[1], p[0] + shift[0], p[1] + shift[1])),
        ("Copy", lambda p: Copy(p[0], p[1], p[0] + shift[0], p[1] + shift[1])),
        ("ChangeLevel (neighbours)", lambda p: ChangeLevel(p[0], p[1], 1, kind="neighbours")),
        ("ChangeLevel (regions in region)",
         lambda p: ChangeLevel(p[0], p[1], 1, kind="regions_in_region")),
        ("ChangeLevel (partial)", lambda p: ChangeLevel(p[0], p[1], 1, kind="partial")),
        ("RotateSelection 30°", lambda p: RotateSelection(p[0], p[1], 30)),
    ]:
        row(name, timed(action_timer(doc, make), points))
    print(f"(each Action undone after timing; texture restored: {np.array_equal(doc.levels, levels)})")

    print("-- whole-texture and global-scope operators (no target; for reference)")
    few = points[:3]
    for name, fn in [
        ("translate (global scope)", lambda p: regions.translate(levels, p, (p[0] + 3, p[1] + 5),
                                                                 scope="global")),
        ("regions in region (global scope)",
         lambda p: regions.extract_regions_in_region(levels, p, scope="global")),
        ("neighbours (global scope)",
         lambda p: regions.neighbour_labels(levels, p, scope="global")),
        ("identity, whole texture, wrap", lambda p: transforms.identity(levels, p, wrap=True)),
        ("isometry 30°, whole texture", lambda p: transforms.isometry(levels, 30, p)),
        ("isometry 30°, whole, wrap", lambda p: transforms.isometry(levels, 30, p, wrap=True)),
        ("similarity ×0.5, whole, wrap",
         lambda p: transforms.similarity(levels, 0.5, p, wrap=True)),
        ("affinity shear, whole, wrap",
         lambda p: transforms.affinity(levels, ((1, 0), (0.5, 1)), p, wrap=True)),
    ]:
        ms = timed(fn, few, repeat=2)
        print(f"{name:<34} {np.median(ms):8.2f} {max(ms):8.2f}")
    for name, make in [("Isometry action, whole texture", lambda p: Isometry(30, *p)),
                       ("Identity action, 3×3 grid of a region",
                        lambda p: Identity(40, 40, 3, 3, row=p[0], col=p[1]))]:
        ms = timed(action_timer(doc, make), few, repeat=2)
        print(f"{name:<34} {np.median(ms):8.2f} {max(ms):8.2f}")


if __name__ == "__main__":
    main()
