"""Colour fidelity of photo → texture: how far the output's colours are from the photo's.

Run: python benchmarks/bench_colour.py [--photos immunohistochemistry coffee ...] [--size 256]
                                        [--seeds 3] [--quantizer lloyd lab]

Sliced Wasserstein distance in CIELAB (64 fixed directions, 1-D W1 per direction on sorted
projections, 20 000 pixels drawn with a fixed seed) between the output and the photo, beside the
same distance between the photo's top and bottom halves (the issue's yardstick: ≤ 1.5× it).
Photos: scikit-image data names (crops of the larger ones: their top-left 512²) or picture files.
"""

from __future__ import annotations

import argparse

import numpy as np
from skimage import color, data

import texeditor

DIRECTIONS = 64
SAMPLES = 20_000


def load(name):
    if callable(getattr(data, name, None)):
        image = getattr(data, name)()
        return image[:512, :512]
    return texeditor.load_image(name)


def lab_pixels(image, rng):
    image = np.asarray(image)
    rgb = np.repeat(image[..., None], 3, axis=2) if image.ndim == 2 else image[..., :3]
    lab = color.rgb2lab(rgb).reshape(-1, 3)
    return lab[rng.choice(len(lab), min(SAMPLES, len(lab)), replace=False)]


def sliced_wasserstein(a, b):
    rng = np.random.default_rng(64)
    dirs = rng.normal(size=(DIRECTIONS, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    n = min(len(a), len(b))
    total = 0.0
    for d in dirs:
        pa, pb = np.sort(a[:n] @ d), np.sort(b[:n] @ d)
        total += np.abs(pa - pb).mean()
    return total / DIRECTIONS


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--photos", nargs="+",
                    default=["immunohistochemistry", "coffee", "chelsea", "astronaut", "rocket"])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--quantizer", nargs="+", default=["lloyd", "lab"])
    args = ap.parse_args()
    print(f"{'photo':<22} {'halves':>7} " + " ".join(f"{q + ' out':>10} {'ratio':>6}"
                                                     for q in args.quantizer))
    for name in args.photos:
        photo = load(name)
        rng = np.random.default_rng(0)
        half = len(photo) // 2
        halves = sliced_wasserstein(lab_pixels(photo[:half], rng), lab_pixels(photo[half:], rng))
        cells = []
        for q in args.quantizer:
            d = np.mean([sliced_wasserstein(
                lab_pixels(texeditor.resynthesize(photo, (args.size, args.size), seed=s,
                                                  quantizer=q).image, rng),
                lab_pixels(photo, rng)) for s in range(args.seeds)])
            cells.append(f"{d:>10.2f} {d / halves:>6.2f}")
        print(f"{name:<22} {halves:>7.2f} " + " ".join(cells), flush=True)


if __name__ == "__main__":
    main()
