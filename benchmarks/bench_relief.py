"""Relief previews and exports: the time of one plane and one sphere preview (256×256, as the
Relief dock draws them on every change) for textures of several sizes, and of a normal map.
Prints figures; target ≤ 30 ms a preview, whatever the texture's size.

    python3 benchmarks/bench_relief.py [--repeat 20]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from texeditor.relief import heights, normal_map, plane_preview, sphere_preview  # noqa: E402

PALETTE = np.array([[40, 40, 40], [100, 100, 100], [160, 160, 160], [220, 220, 220]], np.uint8)


def timed(fn, repeat: int) -> float:
    """The median of ``repeat`` runs, in milliseconds (after one run to warm the caches)."""
    fn()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1000


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(0)
    print(f"{'texture':>9} {'plane ms':>9} {'sphere ms':>10} {'normal map ms':>14}")
    for side in (256, 1024, 4096):
        levels = rng.integers(0, 4, (side, side)).astype(np.uint8)
        plane = timed(lambda: plane_preview(levels, PALETTE, size=256), args.repeat)
        sphere = timed(lambda: sphere_preview(levels, PALETTE, size=256), args.repeat)
        full = timed(lambda: normal_map(heights(levels, PALETTE, 4.0)), max(1, args.repeat // 10))
        print(f"{side:>8}² {plane:9.1f} {sphere:10.1f} {full:14.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
