"""Flow textures (issue 22 item 4): time of each part for 512² and 2048² outputs, warm (numba
compiled by a first small call), best of a few runs.

Run: PYTHONPATH=. python3 benchmarks/bench_flow.py [--sizes 512 2048] [--length 20] [--runs 2]

Parts: the photo's field (structure tensor of grass 512², resampled), a drawn field (3 strokes,
8 segments), the line integral convolution, and the whole step (`FlowTexture`: field, LIC,
the photo's greys, cut into 8 levels) as the editor applies it.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from skimage import data

from texeditor.flow import line_integral_convolution, orientation_field, strokes_field
from texeditor.flow.actions import FlowTexture, strokes_param
from texeditor.recipe.document import Document

STROKES = [[(0.15, 0.05), (0.08, 0.3), (0.2, 0.6), (0.1, 0.95)],
           [(0.8, 0.05), (0.55, 0.35), (0.6, 0.65), (0.9, 0.95)], [(0.5, 0.5), (0.4, 0.5)]]


def best(run, runs: int) -> float:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[512, 2048])
    parser.add_argument("--length", type=float, default=20.0)
    parser.add_argument("--runs", type=int, default=2)
    args = parser.parse_args(argv)
    photo = data.grass()
    line_integral_convolution(np.zeros((16, 16)), 4, seed=0)            # compile
    line_integral_convolution(np.zeros((16, 16)), 4, seed=0, wrap=True)
    strokes_field([[(0, 0), (5, 5)]], (16, 16))
    for n in args.sizes:
        strokes = [[(r * (n - 1), c * (n - 1)) for r, c in s] for s in STROKES]
        theta, _ = orientation_field(photo, (n, n))
        doc = Document()
        ref = doc.add_exemplar(photo)
        photo_step = FlowTexture("photo", ref, (), n, n, seed=1, length=args.length)
        drawn_step = FlowTexture("strokes", ref, strokes_param(strokes), n, n, seed=1,
                                 length=args.length)
        rows = {
            "photo field (grass 512²)": lambda: orientation_field(photo, (n, n)),
            "drawn field": lambda: strokes_field(strokes, (n, n)),
            "LIC": lambda: line_integral_convolution(theta, args.length, seed=1),
            "LIC on the torus": lambda: line_integral_convolution(theta, args.length, seed=1,
                                                                  wrap=True),
            "step, photo's field": lambda: doc.apply(photo_step),
            "step, drawn field": lambda: doc.apply(drawn_step),
        }
        for name, run in rows.items():
            seconds = best(run, args.runs)
            print(f"{n}² L={args.length:g}  {name:26s} {seconds:7.2f} s  "
                  f"{n * n / seconds / 1e6:6.1f} Mpoints/s")


if __name__ == "__main__":
    main()
