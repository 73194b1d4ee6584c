"""Spots: how long a real spot takes to rasterise, a scatter to apply, a deletion to replay.

    python3 benchmarks/bench_spots.py

Prints figures (no pass/fail): milliseconds per spot by size and perturbation, the scanline
rasteriser against skimage.draw.polygon, a 1,000-spot scatter on a 1024² canvas (rasterise in
the worker, then apply), a deletion in a log of 200 placements, and the delete tool's search.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from texeditor.recipe.actions import NewCanvas  # noqa: E402
from texeditor.recipe.history import History  # noqa: E402
from texeditor.spots.actions import (_STAMPS, DeleteSpot, PlaceSpot, ScatterSpots,  # noqa: E402
                                    spot_at, spot_ref)
from texeditor.spots.library import standard_spots  # noqa: E402
from texeditor.spots.envelope import Perturbation, Placement, polygon_mask, real_spot  # noqa: E402

STONE = next(s for s in standard_spots() if s.name == "Stone")
PERTURBATIONS = {
    "envelope only": Perturbation(),
    "bumps + fractal": Perturbation(contour=0.2, frequency=7, fractal=0.15, h=0.45),
    "+ level patches": Perturbation(contour=0.2, frequency=7, fractal=0.15, h=0.45,
                                    interior="levels", density=0.35, scale=3),
    "+ relief": Perturbation(contour=0.2, frequency=7, fractal=0.15, h=0.45, interior="relief",
                             density=0.4),
}


def timed(fn, repeat: int) -> float:
    """Best-of-three mean seconds per call."""
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        for k in range(repeat):
            fn(k)
        best = min(best, (time.perf_counter() - start) / repeat)
    return best


def per_spot() -> None:
    print("real_spot, ms per spot (Stone envelope, 40 points long at scale 1)")
    scales = (0.5, 1, 2, 4, 8)
    print(f"  {'':18}" + "".join(f"{f'×{s:g}':>9}" for s in scales))
    for name, pert in PERTURBATIONS.items():
        row = []
        for scale in scales:
            def place(k, scale=scale, pert=pert):
                real_spot(STONE.envelope, pert, seed=k,
                          placement=Placement((0.0, 0.0), 7 * k, scale * (1 + k % 3 / 100)))
            row.append(timed(place, 20) * 1000)
        print(f"  {name:18}" + "".join(f"{v:9.2f}" for v in row))


def rasteriser() -> None:
    from skimage.draw import polygon
    rng = np.random.default_rng(0)
    print("polygon fill of a 2,048-vertex outline, ms (scanline here vs skimage.draw.polygon)")
    for side in (64, 256):
        t = np.linspace(0, 2 * np.pi, 2048, endpoint=False)
        r = side * (0.45 + 0.03 * rng.standard_normal(2048))
        rows, cols = side / 2 + r * np.sin(t), side / 2 + r * np.cos(t)
        ours = timed(lambda k: polygon_mask(rows, cols, (side, side)), 5) * 1000
        theirs = timed(lambda k: polygon(rows, cols, (side, side)), 1) * 1000
        print(f"  {side:>4}²: {ours:8.2f} vs {theirs:8.1f}  ({theirs / ours:,.0f}× faster)")


def scatter() -> None:
    p = STONE.perturbation
    action = ScatterSpots(STONE.envelope.dumps(), 1000, seed=3, scale=0.4, scale_max=1.2,
                          level=1, level_max=5, blend="under", wrap=True, contour=p.contour,
                          frequency=p.frequency, fractal=p.fractal, roughness=p.h,
                          interior="relief", density=0.4)
    shape = (1024, 1024)
    _STAMPS.clear()
    start = time.perf_counter()
    action.rasterise(shape)
    rasterise = time.perf_counter() - start
    history = History()
    history.apply(NewCanvas(1024, 1024, 7))
    start = time.perf_counter()
    history.apply(action)
    apply = time.perf_counter() - start
    print(f"scatter of 1,000 stones on 1024²: rasterise {rasterise:.2f} s "
          f"({rasterise:.2f} ms per spot, in the worker), then apply {apply * 1000:.0f} ms "
          f"(GUI thread); undo record {history.memory['undo_records'] / 2**20:.1f} MiB")


def deletion() -> None:
    env = STONE.envelope.dumps()
    history = History()
    history.apply(NewCanvas(512, 512, 7))
    rng = np.random.default_rng(1)
    for k in range(200):
        history.apply(PlaceSpot(env, float(rng.uniform(0, 512)), float(rng.uniform(0, 512)),
                                angle=float(rng.uniform(-180, 180)), scale=1.0, seed=k,
                                level=1 + k % 6, contour=0.2, blend="under"))
    doc = history.document
    target = 100
    start = time.perf_counter()
    history.apply(DeleteSpot(target, spot_ref(doc.actions[target])))
    delete = time.perf_counter() - start
    start = time.perf_counter()
    history.undo()
    undo = time.perf_counter() - start
    points = rng.integers(0, 512, (200, 2))
    search = timed(lambda k: spot_at(doc.actions, doc.shape, tuple(points[k % 200])), 50)
    print(f"delete spot 100 of 200 placements on 512² (replays the 200 without it): "
          f"{delete * 1000:.0f} ms; undo {undo * 1000:.1f} ms; "
          f"the spot under the pointer: {search * 1000:.2f} ms")


if __name__ == "__main__":
    per_spot()
    rasteriser()
    scatter()
    deletion()
