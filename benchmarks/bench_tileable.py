"""Tileable synthesis against the issue's targets, on the torus (windows across both seams and the
corner included).

Run: python benchmarks/bench_tileable.py [--photos brick grass gravel] [--size 256] [--seeds 6]
     [--previous]  (the seams, not the times, of the closures before the current ones)

For each photo (scikit-image data name or picture file), 4 Lloyd levels, DPJs estimated on the
torus:
- share of torus windows outside the DPJ, plain and tileable, for a 2×2 and a 3×3 window;
- the seam band (windows starting within BAND points of a seam) against the interior: total
  variation distance of their 3×3 window histograms, beside two yardsticks: the same cross-shaped
  band moved to the middle of the same texture, where no seam is, against the same interior (the
  fair one: its windows are as correlated as the seam band's), and the seed-to-seed spread, two
  ways: the interior of one seed, subsampled to the band's count, against the interior of the
  next seed (random windows, so less spread than any contiguous band shows even without a
  seam), and the next seed's band moved to the middle against this seed's interior (a band of
  the same shape: the spread the seam band is to be read against); then each of the band's four
  sides apart, beside a strip of the same shape in the middle, and the level changes between
  the two rows (columns) meeting at each seam over those between neighbours inside;
- time of a tileable draw over a plain one (warm; the draws take turns, seed after seed, so a
  busy spell of a shared machine falls on both: the median's ratio, and best over best), at the
  size and by size (128² to 1024²), for the 3×3 DPJ and for a photo model (256² to 1024²), each
  with its current seam closure beside the one before (which older recipes keep), the photo
  model also drafted as before SynthesizeScales 16 (lean_drafts off, plain and tileable);
- a photo model (multi-scale + tone): mean grey jump across each seam over the mean jump between
  neighbours inside (1: no seam to see), and the same for its finest levels' changes, plain and
  tileable.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import quality  # noqa: E402  (the module next to this script)

import texeditor  # noqa: E402
from texeditor.markov.estimation import window_codes  # noqa: E402
from texeditor.markov.multiscale import SCALES_CLOSURE  # noqa: E402
from texeditor.markov.synthesis import CLOSURE  # noqa: E402

BAND = 4


def torus_codes(levels, window, g):
    """The code of the window at each point, read on the torus (across both seams)."""
    return window_codes(levels, window, g, wrap=True).reshape(levels.shape)


def off_share(levels, dpj):
    return float(np.mean(~np.isin(torus_codes(levels, dpj.window, dpj.levels), dpj.codes)))


def tv(a, b):
    keys = np.unique(np.concatenate([a, b]))
    pa = np.bincount(np.searchsorted(keys, a), minlength=len(keys)) / len(a)
    pb = np.bincount(np.searchsorted(keys, b), minlength=len(keys)) / len(b)
    return 0.5 * float(np.abs(pa - pb).sum())


def band_mask(shape):
    h, w = shape
    mask = np.zeros(shape, bool)
    mask[np.r_[h - BAND:h, 0:BAND], :] = True
    mask[:, np.r_[w - BAND:w, 0:BAND]] = True
    return mask


def interleaved_times(fs, seeds, repeats=1):
    """Each function's times, f(seed) for every seed and repeat, the functions taking turns draw
    after draw (so a busy spell of a shared machine falls on all of them alike)."""
    times = [[] for _ in fs]
    for _ in range(repeats):
        for s in range(seeds):
            for f, spent in zip(fs, times):
                t = time.perf_counter()
                f(s)
                spent.append(time.perf_counter() - t)
    return [np.array(t) for t in times]


def ratios(times):
    """(median, best) of each later function's times over the first's."""
    base = times[0]
    return [(np.median(t) / np.median(base), t.min() / base.min()) for t in times[1:]]


def seam_jump(picture, axis):
    g = picture.astype(float) if picture.ndim == 2 else picture.mean(axis=2)
    inside = np.abs(np.diff(g, axis=axis)).mean()
    return float(np.abs(np.take(g, 0, axis=axis) - np.take(g, -1, axis=axis)).mean() / inside)


def bench(name, size, seeds, previous=False):
    photo = quality.photo(name)
    closure = CLOSURE - previous             # the single-DPJ seam closure read, and the scales'
    scales_closure = SCALES_CLOSURE - previous
    q = texeditor.quantize(photo, 4, "lloyd")
    shape = (size, size)
    print(f"\n{name}: {size}x{size}, {seeds} seeds")
    for window in ((2, 2), (3, 3)):
        dpj = texeditor.estimate_dpj(q.levels, window, 4, wrap=True)
        texeditor.synthesize(dpj, (32, 32), seed=0, tileable=True)
        plain = [texeditor.synthesize(dpj, shape, seed=s).levels for s in range(seeds)]
        tiled = [texeditor.synthesize(dpj, shape, seed=s, tileable=True, closure=closure).levels
                 for s in range(seeds)]
        plain_t, tiled_t = interleaved_times(
            [lambda s: texeditor.synthesize(dpj, shape, seed=s),
             lambda s: texeditor.synthesize(dpj, shape, seed=s, tileable=True)], seeds, 3)
        (median, best), = ratios([plain_t, tiled_t])
        print(f"  {window[0]}x{window[1]}: torus windows outside the DPJ: plain "
              f"{100 * np.mean([off_share(x, dpj) for x in plain]):.3f} %, tileable "
              f"{100 * np.mean([off_share(x, dpj) for x in tiled]):.4f} % (worst "
              f"{100 * max(off_share(x, dpj) for x in tiled):.4f} %); time tileable/plain "
              f"{median:.2f} (median {np.median(tiled_t) * 1000:.0f} / "
              f"{np.median(plain_t) * 1000:.0f} ms; best {best:.2f})")
        if window == (3, 3):
            codes = [torus_codes(x, window, 4) for x in tiled]
            sides(codes, tiled, size)
            print("  3x3 " + band_text(band_figures(codes, shape)))
    model = texeditor.acquire_model(photo)
    if previous:
        print(f"  (closures {closure} and {scales_closure} of the scales; times: without "
              f"--previous)")
    else:
        sweep(dpj, model, seeds)
    for tileable in (False, True):
        drawn = [model.synthesize((size, size), seed=s, tileable=tileable,
                                  closure=scales_closure) for s in range(seeds)]
        across_rows, across_cols = np.mean([[seam_jump(r.image, a) for a in (0, 1)]
                                            for r in drawn], axis=0)
        rows, cols = seam_changes([r.levels for r in drawn])
        print(f"  photo model {'tileable' if tileable else 'plain   '}: grey jump across the seam "
              f"/ inside: bottom-top {across_rows:.2f}, right-left {across_cols:.2f}; its finest "
              f"levels' changes: bottom-top {rows:.2f}, right-left {cols:.2f}")
        if tileable:
            codes = [torus_codes(r.levels, (3, 3), model.levels) for r in drawn]
            print("  photo model tileable, its finest levels' 3x3 windows: "
                  + band_text(band_figures(codes, (size, size))))


def band_figures(codes, shape) -> dict:
    """TVs of window histograms, one a seed: the seam band (the windows across either seam)
    against the interior of the same texture ("seam"), the same band moved to the middle
    ("moved"), the interior of one seed against the next's, a sample of the band's size
    ("spread"), and the next seed's band against this interior ("banded")."""
    seeds, size = len(codes), shape[0]
    mask = band_mask(shape)
    middle = np.roll(mask, (size // 2, size // 2), axis=(0, 1))
    rest = ~mask & ~middle
    rng = np.random.default_rng(0)
    return {"seam": [tv(c[mask], c[rest]) for c in codes],
            "moved": [tv(c[middle], c[rest]) for c in codes],
            "spread": [tv(rng.choice(codes[s][~mask], mask.sum(), replace=False),
                          codes[(s + 1) % seeds][~mask]) for s in range(seeds)],
            "banded": [tv(codes[(s + 1) % seeds][middle], codes[s][rest])
                       for s in range(seeds)]}


def band_text(f: dict) -> str:
    def both(k):
        return f"{np.mean(f[k]):.3f} (worst {max(f[k]):.3f})"
    return (f"seam band vs interior TV {both('seam')}; the band moved to the middle "
            f"{both('moved')}; interior seed-to-seed spread {both('spread')}; the next seed's "
            f"band vs this interior {both('banded')}")


def seam_changes(fields):
    """How often the two rows (columns) meeting at the seam differ, over how often two
    neighbours inside do: (bottom-top, right-left), the mean over ``fields``."""
    return (np.mean([np.mean(x[-1] != x[0]) / np.mean(x[1:] != x[:-1]) for x in fields]),
            np.mean([np.mean(x[:, -1] != x[:, 0]) / np.mean(x[:, 1:] != x[:, :-1])
                     for x in fields]))


def sides(codes, fields, size):
    """Each side of the seam band apart: the BAND rows (or columns) of windows starting before
    the bottom seam, after the top one, before the right and after the left, each against the
    interior (TV of their 3×3 window histograms) beside the same strip in the middle of the
    texture; and how often the two rows (columns) meeting at the seam differ over how often two
    neighbours inside do. The bottom strip's windows cross the seam the columns' closure drew
    (the texture turned a quarter, so the law of its columns). The interior leaves out the
    middle strips, so that none is measured against itself."""
    mid = size // 2
    interior = np.zeros((size, size), bool)
    interior[4 * BAND:size - 4 * BAND, 4 * BAND:size - 4 * BAND] = True
    interior[mid:mid + BAND] = interior[:, mid:mid + BAND] = False
    strips = {"bottom": (slice(size - BAND, size), slice(None)),
              "top": (slice(0, BAND), slice(None)),
              "right": (slice(None), slice(size - BAND, size)),
              "left": (slice(None), slice(0, BAND))}
    middle = {"rows": (slice(mid, mid + BAND), slice(None)),
              "columns": (slice(None), slice(mid, mid + BAND))}
    figures = {k: np.mean([tv(c[at].ravel(), c[interior]) for c in codes])
               for k, at in {**strips, **middle}.items()}
    change = seam_changes(fields)
    print("  3x3 seam band side by side, TV vs interior: "
          + ", ".join(f"{k} {figures[k]:.3f}" for k in strips)
          + f" (a strip in the middle: rows {figures['rows']:.3f}, columns "
          f"{figures['columns']:.3f}); level changes across the seam / inside: bottom-top "
          f"{change[0]:.2f}, right-left {change[1]:.2f}")


def sweep(dpj, model, seeds, sizes=(128, 256, 512, 1024)):
    """Time tileable/plain by size, the draws taking turns (median of the ratios' seeds, and
    best over best), warm: the seams cost a stretch per row and column, so the ratio falls as
    the side grows. Beside it, the closure before the current one (older recipes)."""
    line = []
    for n in sizes:
        times = interleaved_times(
            [lambda s: texeditor.synthesize(dpj, (n, n), seed=s),
             lambda s: texeditor.synthesize(dpj, (n, n), seed=s, tileable=True),
             lambda s: texeditor.synthesize(dpj, (n, n), seed=s, tileable=True,
                                            closure=CLOSURE - 1)], seeds, 3 if n <= 256 else 1)
        (now, now_best), (old, old_best) = ratios(times)
        line.append(f"{n}² {now:.2f}/{now_best:.2f} (closure {CLOSURE - 1}: "
                    f"{old:.2f}/{old_best:.2f})")
    print(f"  3x3 time tileable/plain by size, closure {CLOSURE} (median/best): "
          + ", ".join(line))
    line = []
    for n in sizes[1:]:
        times = interleaved_times(
            [lambda s: model.synthesize((n, n), seed=s),
             lambda s: model.synthesize((n, n), seed=s, tileable=True),
             lambda s: model.synthesize((n, n), seed=s, tileable=True,
                                        closure=SCALES_CLOSURE - 1),
             lambda s: model.synthesize((n, n), seed=s, lean_drafts=False),
             lambda s: model.synthesize((n, n), seed=s, tileable=True, lean_drafts=False)],
            seeds)
        (now, now_best), (old, old_best) = ratios(times[:3])
        (drafted, drafted_best), = ratios(times[3:])
        line.append(f"{n}² {now:.2f}/{now_best:.2f} ({np.median(times[1]):.2f} / "
                    f"{np.median(times[0]):.2f} s; closure {SCALES_CLOSURE - 1}: "
                    f"{old:.2f}/{old_best:.2f}; drafted as before version 16: "
                    f"{drafted:.2f}/{drafted_best:.2f}, {np.median(times[4]):.2f} / "
                    f"{np.median(times[3]):.2f} s)")
    print(f"  photo model (scales + tone) time tileable/plain, closure {SCALES_CLOSURE} "
          "(median/best): " + ", ".join(line))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--photos", nargs="+", default=["brick", "grass", "gravel"])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--previous", action="store_true",
                    help="draw with the seam closures before the current ones (older recipes)")
    args = ap.parse_args()
    for name in args.photos:
        bench(name, args.size, args.seeds, args.previous)


if __name__ == "__main__":
    main()
