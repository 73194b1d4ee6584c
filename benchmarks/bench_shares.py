"""How far a photo texture's level shares stray from its model's, over many photos and sizes.

Run: python benchmarks/bench_shares.py [--photos chelsea coffee ...] [--crops 128 192 256 512]
         [--sizes 64x64 140x100 256x256 211x333] [--seeds 4]

Issue 19 asks every output's level frequencies within ±0.03 of the model's, on every photo.
A photo texture from a large photo drawn large meets it (bench_quality.py's drift line); this
walks the hard corners: scikit-image's photos, scenes and drawings as well as textures, cropped
small (fewer points at each scale, parents drawn as a few blobs), drawn small and odd-shaped.
For each crop and size, the worst share error over the seeds and how many seeds miss 0.03, for
the finest scale's moves bound by its parents only (free_moves off, SynthesizeScales before
version 14), with moves free of them after (forced_moves off, versions 14), and with forced
moves last (the default, version 15); the rows print only where one misses. The last lines count the draws that miss, and the time of all draws.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import skimage as ski

from texeditor.photo import acquire_model

PHOTOS = ("chelsea", "coffee", "astronaut", "camera", "moon", "gravel", "brick", "grass",
          "rocket", "retina", "cell", "immunohistochemistry", "page", "text", "horse",
          "hubble_deep_field", "colorwheel", "logo", "clock", "coins")
TARGET = 0.03
WAYS = (("bound by the parents", dict(free_moves=False, forced_moves=False)),   # version 13
        ("then free of them", dict(free_moves=True, forced_moves=False)),      # version 14
        ("then forced", dict(free_moves=True, forced_moves=True)))             # version 15


def photo(name: str, side: int) -> np.ndarray:
    """A side×side crop (at most the photo) a third of the way down, two thirds across."""
    a = getattr(ski.data, name)()
    if a.dtype == bool:
        a = a.astype(np.uint8) * 255
    if a.ndim == 3:
        a = a[..., :3]
    h, w = a.shape[:2]
    n = min(side, h, w)
    top, left = int((h - n) * 0.3), int((w - n) * 0.7)
    return a[top:top + n, left:left + n]


def share_error(levels: np.ndarray, aim: np.ndarray) -> float:
    return float(np.abs(np.bincount(levels.ravel(), minlength=len(aim)) / levels.size
                        - aim).max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--photos", nargs="+", default=PHOTOS)
    parser.add_argument("--crops", nargs="+", type=int, default=(128, 192, 256, 512))
    parser.add_argument("--sizes", nargs="+", default=("64x64", "140x100", "256x256", "211x333"))
    parser.add_argument("--seeds", type=int, default=4)
    args = parser.parse_args()
    sizes = [tuple(int(x) for x in s.split("x"))[::-1] for s in args.sizes]   # WxH -> (H, W)
    missed = {label: 0 for label, _ in WAYS}
    spent = {label: 0.0 for label, _ in WAYS}
    draws = 0
    print(f"worst |level share - model's| over {args.seeds} seeds (and seeds beyond {TARGET}): "
          + " | ".join(name for name, _ in WAYS))
    for name in args.photos:
        for side in args.crops:
            model = acquire_model(photo(name, side))
            aim = model.frequencies()
            for shape in sizes:
                cells = []
                for label, moves in WAYS:
                    errors = []
                    for seed in range(args.seeds):
                        start = time.perf_counter()
                        levels = model.synthesize(shape, seed=seed, tone=False,
                                                  **moves).levels
                        spent[label] += time.perf_counter() - start
                        errors.append(share_error(levels, aim))
                    off = sum(e > TARGET for e in errors)
                    missed[label] += off
                    cells.append((max(errors), off))
                draws += args.seeds
                if any(off for _, off in cells):
                    print(f"{name:20s} crop {side:3d}, {shape[1]}x{shape[0]:<4d}  " + " | ".join(
                        f"{worst:.3f} ({off}/{args.seeds})" for worst, off in cells), flush=True)
    for label, _ in WAYS:
        print(f"{label:22s}: {missed[label]} of {draws} draws beyond {TARGET}; "
              f"all draws {spent[label]:.1f} s")


if __name__ == "__main__":
    main()
