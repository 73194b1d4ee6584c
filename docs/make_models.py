"""Render the pictures of docs/models.md: each model next to the photo it came from.

    python3 docs/make_models.py [--out docs/img]

The canvases are made by the same Actions the Models menu applies (on a Document holding the
photo as an exemplar), the continuous outputs by the engine functions they call.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from skimage import data  # noqa: E402

import texeditor  # noqa: E402
from texeditor.recipe.document import Document  # noqa: E402
from texeditor.spectral.actions import MatchHistogram, RandomPhaseNoise, Texton  # noqa: E402

SIDE = 256
CAPTION = 18
GAP = 8


def photos() -> dict[str, np.ndarray]:
    """Micro-textures in grey and colour, and a macro-texture the model cannot keep."""
    gravel = texeditor.load_image(ROOT / "resources" / "images" / "gravel.png")
    return {"gravel": gravel[:SIDE, :SIDE],
            "tissue (colour)": data.immunohistochemistry()[128:128 + SIDE, 128:128 + SIDE],
            "brick": texeditor.load_image(ROOT / "resources" / "images" / "brick.png")[:SIDE,
                                                                                   :SIDE]}


def rgb(image: np.ndarray) -> np.ndarray:
    return np.repeat(image[..., None], 3, axis=2) if image.ndim == 2 else image


def canvas(doc: Document) -> np.ndarray:
    return doc.palette[doc.levels]


def applied(photo: np.ndarray, *actions) -> Document:
    doc = Document()
    ref = doc.add_exemplar(photo)
    for make in actions:
        doc.apply(make(ref))
    return doc


def figure(rows: list[list[tuple[str, np.ndarray]]], path: Path) -> None:
    """Captioned panels, one row per photo, left to right."""
    width = max(sum(p.shape[1] for _, p in row) + GAP * (len(row) + 1) for row in rows)
    height = sum(max(p.shape[0] for _, p in row) + CAPTION + GAP for row in rows) + GAP
    out = Image.new("RGB", (width, height), (250, 250, 250))
    draw = ImageDraw.Draw(out)
    y = GAP
    for row in rows:
        x = GAP
        for caption, panel in row:
            draw.text((x, y), caption, fill=(30, 30, 30))
            out.paste(Image.fromarray(rgb(panel)), (x, y + CAPTION))
            x += panel.shape[1] + GAP
        y += max(p.shape[0] for _, p in row) + CAPTION + GAP
    out.save(path, optimize=True)
    print(path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(ROOT / "docs" / "img"))
    out = Path(parser.parse_args(argv).out)
    rpn, tex = [], []
    for name, photo in photos().items():
        noise = texeditor.random_phase_noise(photo, (SIDE, 2 * SIDE), seed=1)
        doc = applied(photo, lambda r: RandomPhaseNoise(r, 2 * SIDE, SIDE, seed=1, levels=8))
        rpn.append([(f"photo: {name}", photo), ("random-phase noise 512x256, seed 1", noise),
                    ("as a canvas, G = 8", canvas(doc))])
        tex.append([(f"photo: {name}", photo), ("periodic component",
                     np.clip(np.round(texeditor.spectral.periodic_component(photo)), 0, 255)
                     .astype(np.uint8)),
                    ("texton (centred)", texeditor.texton(photo)),
                    ("as a canvas, G = 8", canvas(applied(photo, lambda r: Texton(r, 8))))])
    figure(rpn, out / "models-rpn.png")
    figure(tex, out / "models-texton.png")
    figure(histogram_rows(), out / "models-histogram.png")
    return 0


def histogram_rows() -> list:
    """A grey Markov texture from gravel, recoloured with the tissue's and the brick's
    distributions (the levels stay)."""
    gravel, tissue, brick = photos().values()
    q = texeditor.quantize(gravel, 6, "lloyd")
    dpj = texeditor.estimate_dpj(q.levels, (3, 3), 6, wrap=True, palette=q.palette)
    rows = []
    for name, photo in (("tissue (colour)", tissue), ("brick", brick)):
        doc = Document()
        ref = doc.add_exemplar(photo)
        doc.add_dpj(dpj)
        doc.apply(texeditor.recipe.actions.Synthesize(dpj.ref, SIDE, SIDE, seed=2, tileable=True))
        before = canvas(doc)
        doc.apply(MatchHistogram(ref))
        rows.append([("Markov texture from gravel, G = 6", before), (f"photo: {name}", photo),
                     ("its histogram matched", canvas(doc))])
    return rows


if __name__ == "__main__":
    sys.exit(main())
