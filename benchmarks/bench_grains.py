"""Grain rendering, composition and doubling timings (issue 9): prints figures only.

Target: a 512² texture drawn with 8-pixel grains (a 4096² picture) in well under a second. The
texture is synthesised from resources/dpj/gravel-3x3-g4.dpj; each case is timed best-of-N after
one warm-up call (the numba kernel is compiled or loaded from its cache on the first call).
Run: python3 benchmarks/bench_grains.py [--side 512] [--size 8] [--repeat 5]
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from pathlib import Path


from texeditor import DPJ, synthesize
from texeditor.texture import composition
from texeditor.markov import doubling
from texeditor.texture import grain_render as gr
from texeditor.markov.levels import load_image
from texeditor.texture.actions import RenderGrains

ROOT = Path(__file__).resolve().parent.parent / "resources"
TARGET_S = 1.0


def best(fn, repeat: int) -> float:
    fn()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, default=512)
    parser.add_argument("--size", type=int, default=8)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
          f"Python {platform.python_version()}")
    dpj = DPJ.load(ROOT / "dpj" / "gravel-3x3-g4.dpj")
    levels = synthesize(dpj, (args.side, args.side), seed=1).levels
    print(f"texture {args.side}², G = {dpj.levels}, "
          f"{(levels > 0).mean() * 100:.0f} % of points not background")

    print("\ngrain rendering (best of %d)" % args.repeat)
    print(f"{'case':<44} {'picture':>11} {'seconds':>8} {'MPix/s':>8}")
    cases = [
        ("square", {}), ("circle", {}), ("hexagon", {}), ("polygon", {"sides": 5}),
        ("circle", {"explosion_x": 2.0}), ("circle", {"compression": 0.5, "overlap": "max"}),
        ("hexagon", {"compression": 0.3, "overlap": "min"}), ("square", {"angle": 30.0}),
    ]
    headline = None
    for shape, kw in cases:
        seconds = best(lambda: gr.render(levels, shape, args.size, **kw), args.repeat)
        out = gr.render(levels, shape, args.size, **kw)
        name = f"{shape} {args.size} px " + " ".join(f"{k}={v}" for k, v in kw.items())
        print(f"{name:<44} {out.shape[1]:>5}×{out.shape[0]:<5} {seconds:8.3f} "
              f"{out.size / seconds / 1e6:8.0f}")
        if headline is None:
            headline = seconds
    action = RenderGrains("circle", args.size)
    doc_seconds = best(lambda: action.render(levels), args.repeat)
    print(f"{'RenderGrains action (circle), render only':<44} {'':>11} {doc_seconds:8.3f}")
    verdict = "meets" if headline < TARGET_S else "MISSES"
    print(f"\n{args.side}² at {args.size}-px squares: {headline:.3f} s — {verdict} the "
          f"{TARGET_S:g} s target ({TARGET_S / headline:.0f}× margin)")

    print("\ncomposition and doubling on the texture (best of %d)" % args.repeat)
    other = synthesize(dpj, (args.side, args.side), seed=2).levels
    t = best(lambda: composition.mix(levels, other, levels=4, a=0.5, op2="add", b=0.5),
             args.repeat)
    print(f"{'mix (½ T1) add (½ T2)':<44} {t:8.3f} s")
    t = best(lambda: composition.incrust(other > 1, [levels, other]), args.repeat)
    print(f"{'incrustation, two textures':<44} {t:8.3f} s")
    photo = load_image(ROOT / "images" / "gravel.png")
    t = best(lambda: doubling.learn(photo, 4, "lloyd"), args.repeat)
    table = doubling.learn(photo, 4, "lloyd")
    print(f"{'learn a doubling table (256² photo, G 4→8)':<44} {t:8.3f} s  "
          f"({len(table):,} configurations)")
    t = best(lambda: doubling.double_levels(levels, table, 1), args.repeat)
    ctx = doubling.double_levels(levels, table, 1).contexts
    print(f"{'double the levels':<44} {t:8.3f} s  (contexts 8/4/own/none: {ctx})")


if __name__ == "__main__":
    main()
