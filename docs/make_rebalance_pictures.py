"""The user guide's rebalancing picture: photo | its finest shares as drawn | rebalanced.

Run: PYTHONPATH=. python3 docs/make_rebalance_pictures.py  (a few seconds; 512² textures, seed 0,
their top-left 320² shown)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from skimage import data, io, transform, util

import texeditor

OUT = Path(__file__).resolve().parent / "img" / "rebalance.png"
PHOTOS = ("chelsea", "rocket", "text")
SIDE, GAP = 320, 8


def rgb(image: np.ndarray) -> np.ndarray:
    return np.stack([image] * 3, axis=-1) if image.ndim == 2 else image[..., :3]


def photo_panel(photo: np.ndarray) -> np.ndarray:
    """The photo scaled to SIDE rows, cut or padded (white) to SIDE columns."""
    width = round(SIDE * photo.shape[1] / photo.shape[0])
    small = util.img_as_ubyte(transform.resize(rgb(photo), (SIDE, width), anti_aliasing=True))
    panel = np.full((SIDE, SIDE, 3), 255, np.uint8)
    panel[:, :min(SIDE, width)] = small[:, :SIDE]
    return panel


def row(name: str) -> np.ndarray:
    photo = getattr(data, name)()
    model = texeditor.acquire_model(photo)
    kept = model.synthesize((512, 512), seed=0, rebalance=False)
    moved = model.synthesize((512, 512), seed=0)
    print(f"{name}: {moved.moved} border moves")
    gap = np.full((SIDE, GAP, 3), 255, np.uint8)
    return np.concatenate([photo_panel(photo), gap, rgb(kept.image)[:SIDE, :SIDE], gap,
                           rgb(moved.image)[:SIDE, :SIDE]], axis=1)


def main() -> None:
    rows = [row(name) for name in PHOTOS]
    gap = np.full((GAP, rows[0].shape[1], 3), 255, np.uint8)
    picture = np.concatenate([part for r in rows for part in (r, gap)][:-1])
    io.imsave(OUT, picture, check_contrast=False)
    print(OUT)


if __name__ == "__main__":
    main()
