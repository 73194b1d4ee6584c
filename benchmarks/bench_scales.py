"""Where a photo model's level field gets structure larger than the photo's: scale by scale.

Run: python benchmarks/bench_scales.py [--photos brick grass gravel] [--seeds 4]

The texture is drawn at the photo's size, so each scale compares with the photo's reduction of
the same size.

For each scale (coarsest first), the log10 power of its level field over the photo's reduction at
that scale, at low frequencies: periods of 64 points of the finest scale and more (the band
`bench_quality.py` calls ">=64"; radius 1 to side/64 of the finest, the same radius at every
scale), split by direction: "rows" = mostly vertical frequency (bands along the rows),
"columns" = mostly horizontal frequency (streaks down the columns), and over all directions.
Two ways:
- as synthesized (each scale given the synthesized scale under it, as texeditor.resynthesize);
- given the photo's own parents (each finer scale drawn once from its DPJ given the photo's
  reduction under it): what the scale's own law adds, whatever its parents.
0 is the photo's; the row-by-row draw persists down the columns, which shows as "columns".
"""

from __future__ import annotations

import argparse
import sys
from functools import partial
from pathlib import Path

import numpy as np
from scipy import fft as sfft

sys.path.insert(0, str(Path(__file__).resolve().parent))
import quality  # noqa: E402  (the module next to this script)

from texeditor.markov import multiscale as ms  # noqa: E402
from texeditor.markov.synthesis import synthesize_given  # noqa: E402


def low_power(levels: np.ndarray, radius_max: int) -> np.ndarray:
    """log10 mean power at frequencies of radius 1 to ``radius_max``: mostly vertical, mostly
    horizontal, all."""
    x = levels.astype(float)
    x -= x.mean()
    h, w = x.shape
    window = np.outer(np.hanning(h), np.hanning(w))
    power = np.abs(sfft.fft2(x * window)) ** 2 / (window ** 2).sum()
    fy = np.abs(sfft.fftfreq(h))[:, None] * h
    fx = np.abs(sfft.fftfreq(w))[None, :] * w
    radius = np.hypot(fy, fx)
    low = (radius >= 1) & (radius <= radius_max)
    parts = (low & (fy > 2 * fx), low & (fx > 2 * fy), low)
    return np.array([np.log10(power[m].mean()) for m in parts])


def drawn_scales(model, shape, seed):
    """Every scale's levels as texeditor's multi-scale synthesis draws them (coarsest first)."""
    drawn = []
    original = ms._draw_scale_closest

    def spy(*args, **kwargs):
        result = original(*args, **kwargs)
        drawn.append(result.levels.copy())
        return result
    ms._draw_scale_closest = spy
    try:
        ms.synthesize_scales(model, shape, seed=seed)
    finally:
        ms._draw_scale_closest = original
    return drawn


def given_own_parents(model, reductions, k, seed):
    """Scale k drawn once from its DPJ given the photo's own reduction under it."""
    parents = ms.upsample(reductions[k - 1], reductions[k].shape, ms.parents_under(model.dpjs[k]))
    return synthesize_given(model.dpjs[k], parents, model.levels_at(k - 1), seed=seed).levels


def bench(name, seeds):
    photo_image = quality.photo(name)
    size = photo_image.shape[:2]
    model, reductions = ms.estimate_scales(photo_image)
    power = partial(low_power, radius_max=max(1, min(size) // 64))
    photo = [power(r) for r in reductions]
    synth = np.mean([[power(x) - photo[k] for k, x in enumerate(drawn_scales(model, size, s))]
                     for s in range(seeds)], 0)
    print(f"\n{name}: {size[1]}x{size[0]}, {seeds} seeds; log10 low-frequency power over the "
          "photo's (rows / columns / all)")
    for k in range(model.scales):
        line = (f"  scale {k} ({reductions[k].shape[0]}² in the photo): as synthesized "
                + " / ".join(f"{v:+.2f}" for v in synth[k]))
        if k > 0:
            given = np.mean([power(given_own_parents(model, reductions, k, s)) - photo[k]
                             for s in range(seeds)], 0)
            line += "; given the photo's own parents " + " / ".join(f"{v:+.2f}" for v in given)
        print(line)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--photos", nargs="+", default=["brick", "grass", "gravel"])
    ap.add_argument("--seeds", type=int, default=4)
    args = ap.parse_args()
    for name in args.photos:
        bench(name, args.seeds)


if __name__ == "__main__":
    main()
