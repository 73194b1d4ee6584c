"""Render the fractal pictures of docs/models.md: IFS motifs, a spot with a fractal-curve
outline at roughness 0, 0.5 and 1, and a midpoint-displacement relief shaded by the relief
preview; and time the models at 512² and 2048² (warm).

    python3 docs/make_fractal_pictures.py [--out docs/img] [--times]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "docs"))

from make_models import figure  # noqa: E402
from texeditor.fractal.actions import FractalRelief, IFSMotif  # noqa: E402
from texeditor.fractal.ifs import ifs_attractor  # noqa: E402
from texeditor.fractal.midpoint import midpoint_displacement  # noqa: E402
from texeditor.recipe.document import Document  # noqa: E402
from texeditor.relief.previews import plane_preview, sphere_preview  # noqa: E402
from texeditor.spots.envelope import Envelope, Meridian, real_spot  # noqa: E402

SIDE = 256


def motif_picture(name: str) -> np.ndarray:
    counts = ifs_attractor(name, (SIDE, SIDE), points=1_000_000, seed=1).astype(float)
    shade = np.log1p(counts) / np.log1p(counts.max())      # dense parts darker
    return np.round(250 - 220 * np.sqrt(shade)).astype(np.uint8)


def spot_picture(roughness: float) -> np.ndarray:
    env = Envelope((0.0, -100.0), (0.0, 100.0),
                   (Meridian(0.3, 55, 40), Meridian(0.6, 70, 60, main=True), Meridian(0.85, 35, 30)),
                   kind="fractal_curve").with_fractal(roughness, seed=4)
    stamp = real_spot(env)
    out = np.full((SIDE, SIDE), 245, np.uint8)
    top, left = (SIDE - stamp.shape[0]) // 2, (SIDE - stamp.shape[1]) // 2
    out[top:top + stamp.shape[0], left:left + stamp.shape[1]][stamp.mask] = 60
    return out


def relief_document(h: float) -> Document:
    doc = Document()
    with doc.step():
        FractalRelief(SIDE, SIDE, seed=3, roughness=h, levels=12).apply(doc)
    return doc


def pictures(out: Path) -> None:
    figure([[("IFS: the digest's tree", motif_picture("tree")),
             ("IFS: Barnsley's fern", motif_picture("fern")),
             ("IFS: Sierpinski triangle", motif_picture("sierpinski"))]],
           out / "models-ifs.png")
    figure([[(f"fractal curve, roughness {r:g}", spot_picture(r)) for r in (0.0, 0.5, 1.0)]],
           out / "models-fractal-curve.png")
    rows = []
    for h in (0.8, 0.4):
        doc = relief_document(h)
        rows.append([(f"midpoint displacement H {h:g}, G = 12", doc.palette[doc.levels]),
                     ("relief preview (plane)", plane_preview(doc.levels, doc.palette,
                                                              size=SIDE, strength=6)),
                     ("on a sphere", sphere_preview(doc.levels, doc.palette, size=SIDE,
                                                    strength=6))])
    figure(rows, out / "models-midpoint-relief.png")


def timed(fn, repeat: int = 3) -> float:
    fn()                                              # warm: numba compiled, caches filled
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def times() -> None:
    for side in (512, 2048):
        canvas = Document.new(side, side, 4)
        rows = {
            "midpoint_displacement": lambda: midpoint_displacement((side, side), 0.5, seed=1),
            "FractalRelief (G = 8)": lambda: FractalRelief(side, side, seed=1).prepare(None),
            "ifs_attractor fern, 4·side² points": lambda: ifs_attractor(
                "fern", (side, side), points=4 * side * side, seed=1),
            "IFSMotif tree, side², 1M points": lambda: IFSMotif(
                "tree", side // 2, side // 2, side, 1, points=1_000_000).prepare(canvas),
            "fractal-curve spot, side across": lambda: real_spot(Envelope.ellipse(
                side * 0.9, side * 0.6, kind="fractal_curve").with_fractal(1.0, seed=2)),
        }
        for name, fn in rows.items():
            print(f"{side}²  {name:38s} {timed(fn) * 1000:9.1f} ms")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(ROOT / "docs" / "img"))
    parser.add_argument("--times", action="store_true")
    args = parser.parse_args(argv)
    Path(args.out).mkdir(parents=True, exist_ok=True)
    pictures(Path(args.out))
    if args.times:
        times()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
