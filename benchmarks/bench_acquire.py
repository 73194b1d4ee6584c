"""Acquisition speed: quantising a 1024² photo (band, Lloyd–Max) and counting its windows; a
photo model from a phone-sized colour photo (12 MP) and its first 1024² texture.

Run: python benchmarks/bench_acquire.py [--no-large]
"""

import sys
import time

import numpy as np
from skimage import data, transform

from texeditor import acquire_model, estimate_dpj, quantize


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
    if "--no-large" not in sys.argv:
        large_photo_model()


def large_photo_model() -> None:
    """A 4000×3000 colour photo (astronaut, enlarged): the model, then its first texture (the
    tone's index of 12 M photo points is built then) and the next one."""
    photo = transform.resize(data.astronaut(), (3000, 4000), order=1,
                             preserve_range=True).astype(np.uint8)
    acquire_model(photo[:300, :300]).synthesize((64, 64))       # numba compiled
    t0 = time.perf_counter()
    model = acquire_model(photo)
    t1 = time.perf_counter()
    model.synthesize((1024, 1024), seed=0)
    t2 = time.perf_counter()
    model.synthesize((1024, 1024), seed=1)
    t3 = time.perf_counter()
    print(f"photo model of a 4000x3000 colour photo: acquire {t1 - t0:.2f} s, first 1024² "
          f"texture {t2 - t1:.2f} s, the next {t3 - t2:.2f} s")


if __name__ == "__main__":
    main()
