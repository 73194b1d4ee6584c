"""Pictures of docs/models.md's flow texture section: photo | its field | flow texture | the
step's canvas, and a drawn field: strokes | texture | the same on the torus, tiled 2 × 2.

Run: PYTHONPATH=. python3 docs/make_flow_pictures.py  (a few seconds; seed 1)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw
from skimage import data

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "docs"))

from make_models import figure  # noqa: E402

import texeditor  # noqa: E402
from texeditor.flow import orientation_field, strokes_field  # noqa: E402
from texeditor.flow.actions import FlowTexture, strokes_param  # noqa: E402
from texeditor.recipe.document import Document  # noqa: E402

OUT = ROOT / "docs" / "img"
SIDE = 256
SPACING = 12              # points between the field's lines
PHOTOS = {"grass": lambda: data.grass()[:SIDE, :SIDE],
          "brick": lambda: data.brick()[:SIDE, :SIDE],
          "gravel": lambda: data.gravel()[:SIDE, :SIDE]}
STROKES = [[(40, 10), (20, 80), (50, 150), (25, 245)],
           [(200, 20), (140, 90), (150, 170), (230, 240)],
           [(128, 128), (100, 128)]]


def field_picture(background: np.ndarray, theta, coherence=None) -> np.ndarray:
    """The field as short lines every SPACING points over the picture dimmed; a line's
    length is the coherence (a full line: one clear direction, a dot: none)."""
    grey = background if background.ndim == 2 else background.mean(axis=2)
    out = Image.fromarray((0.45 * grey).astype(np.uint8)).convert("RGB")
    draw = ImageDraw.Draw(out)
    half = 0.45 * SPACING
    for r in range(SPACING // 2, theta.shape[0], SPACING):
        for c in range(SPACING // 2, theta.shape[1], SPACING):
            k = half * (1.0 if coherence is None else max(coherence[r, c], 0.08))
            dr, dc = k * np.sin(theta[r, c]), k * np.cos(theta[r, c])
            draw.line([(c - dc, r - dr), (c + dc, r + dr)], fill=(255, 220, 60), width=2)
    return np.asarray(out)


def strokes_picture(shape, strokes) -> np.ndarray:
    out = Image.new("RGB", shape[::-1], (235, 235, 235))
    draw = ImageDraw.Draw(out)
    for s in strokes:
        draw.line([(c, r) for r, c in s], fill=(220, 40, 60), width=3)
    return np.asarray(out)


def grey(picture) -> np.ndarray:
    return np.round(picture * 255).astype(np.uint8)


def photo_rows() -> list:
    rows = []
    for name, load in PHOTOS.items():
        photo = load()
        theta, coherence = orientation_field(photo)
        texture = texeditor.flow_texture((SIDE, SIDE), photo=photo, seed=1)
        rows.append([(f"photo: {name}", photo),
                     ("its field (line length: coherence)",
                      field_picture(photo, theta, coherence)),
                     ("flow texture, L = 20, seed 1", grey(texture)),
                     ("as a canvas, G = 8", photo_canvas(photo))])
    return rows


def photo_canvas(photo) -> np.ndarray:
    doc = Document()
    ref = doc.add_exemplar(photo)
    doc.apply(FlowTexture("photo", ref, (), SIDE, SIDE, seed=1, levels=8))
    return doc.palette[doc.levels]


def drawn_rows() -> list:
    theta, _ = strokes_field(STROKES, (SIDE, SIDE))
    segments = strokes_param(STROKES)
    plain = texeditor.flow_texture((SIDE, SIDE), strokes=STROKES, seed=1, length=30)
    doc = Document()
    ref = doc.add_exemplar(data.grass())
    doc.apply(FlowTexture("strokes", ref, segments, SIDE, SIDE, seed=1, length=30,
                          tileable=True, levels=6))
    tile = doc.palette[doc.levels]
    tiled = np.tile(tile, (2, 2, 1))[SIDE // 2:SIDE // 2 + SIDE, SIDE // 2:SIDE // 2 + SIDE]
    return [[("strokes drawn", strokes_picture((SIDE, SIDE), STROKES)),
             ("their field", field_picture(np.full((SIDE, SIDE), 200.0), theta)),
             ("flow texture, L = 30, no photo", grey(plain))],
            [("tileable, grass's greys, G = 6", tile),
             ("the same tiled: seams at the middle", tiled)]]


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    figure(photo_rows(), OUT / "models-flow-photo.png")
    figure(drawn_rows(), OUT / "models-flow-drawn.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
