"""Acquisition speed: quantising a 1024² photo (band, Lloyd–Max) and counting its windows.

Run: python benchmarks/bench_acquire.py
"""

import time

import numpy as np
from skimage import data

from texeditor import estimate_dpj, quantize


def best(fn, repeat=5):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times) * 1e3


def main() -> None:
    photo = np.tile(data.gravel(), (2, 2))
    print(f"photo: gravel tiled to {photo.shape[1]}x{photo.shape[0]}")
    for levels in (4, 16):
        for method in ("band", "lloyd"):
            print(f"quantize G={levels:<2} {method:5s} {best(lambda: quantize(photo, levels, method)):7.1f} ms")
    q = quantize(photo, 4).levels
    for window in ((2, 2), (3, 3), (4, 4)):
        for wrap in (False, True):
            ms = best(lambda: estimate_dpj(q, window, 4, wrap=wrap))
            n = len(estimate_dpj(q, window, 4, wrap=wrap))
            print(f"estimate {window[0]}x{window[1]} G=4 wrap={wrap!s:5} {ms:7.1f} ms  {n} entries")


if __name__ == "__main__":
    main()
