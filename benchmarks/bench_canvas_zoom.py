"""The canvas zoomed out (issue 16): mip level build time and the time of one zoom step.

Prints figures, passes or fails nothing. A 2048² texture of 8 levels in a 1100×750 canvas:
1. box_average for levels 1..4 (the build, once per image or palette change and level);
2. one zoom step (ZOOM_STEP, as the − key) from fit down to 1/16 and back, each ending with a
   paint of the viewport: the first crossing of a level builds it, later ones reuse it;
3. set_image of a changed matrix while zoomed out (what follows a stroke), then a paint.

    QT_QPA_PLATFORM=offscreen python3 benchmarks/bench_canvas_zoom.py [--size 2048]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

import numpy as np  # noqa: E402
from PySide6 import QtWidgets  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=int, default=2048)
    args = parser.parse_args()
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    from app.canvas import CanvasView, palette_lut
    from app.mip import box_average

    rng = np.random.default_rng(1)
    n = args.size
    levels = rng.integers(0, 8, (n, n), dtype=np.uint8)
    palette = rng.integers(0, 256, (8, 3), dtype=np.uint8)
    lut = palette_lut(palette)
    box_average(levels[:8, :8], lut, 1)          # load the compiled kernel
    print(f"mip build, {n}×{n}:")
    for k in range(1, 5):
        best = min(_timed(lambda: box_average(levels, lut, k)) for _ in range(3))
        print(f"  level {k} (1/{1 << k}): {best * 1e3:6.1f} ms")

    canvas = CanvasView()
    canvas.resize(1100, 750)
    canvas.show()
    app.processEvents()
    canvas.set_image(levels, palette)
    canvas.fit()
    app.processEvents()

    def step(fn):
        t = time.perf_counter()
        fn()
        canvas.viewport().repaint()
        return time.perf_counter() - t

    print(f"zoom steps from fit ({canvas.zoom():.3f}):")
    for label in ("first pass (builds levels)", "second pass (cached)"):
        canvas.fit()
        app.processEvents()
        times = []
        while canvas.zoom() > 1 / 16 + 1e-3:
            times.append((canvas.zoom(), step(canvas.zoom_out)))
        while canvas.zoom() < 1.0:
            times.append((canvas.zoom(), step(canvas.zoom_in)))
        worst = max(t for _, t in times)
        print(f"  {label}: {len(times)} steps, mean {np.mean([t for _, t in times]) * 1e3:.1f} ms, "
              f"worst {worst * 1e3:.1f} ms")
    for zoom in (1.0, 0.5, 0.25, 0.125):
        canvas.set_zoom(zoom)
        app.processEvents()
        edited = levels.copy()
        edited[100:300, 100:300] = 3
        t = min(step(lambda: canvas.set_image(edited, palette)) for _ in range(3))
        print(f"set_image of an edited {n}² matrix at zoom {zoom:g} (level "
              f"{canvas.shown_level}): {t * 1e3:.1f} ms")


def _timed(fn) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


if __name__ == "__main__":
    main()
