"""Pictures of docs/models.md's Heeger–Bergen section: photo | texture, side by side.

Run: PYTHONPATH=. python3 docs/make_heeger_bergen_pictures.py  (a few seconds; seed 0)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from skimage import data, io

import texeditor

OUT = Path(__file__).resolve().parent / "img"
GAP = 8
PHOTOS = {
    "brick": lambda: data.brick(),
    "grass": lambda: data.grass(),
    "gravel": lambda: data.gravel(),
    "immunohistochemistry": lambda: data.immunohistochemistry()[:256, :256],
}


def side_by_side(photo: np.ndarray, texture: np.ndarray) -> np.ndarray:
    """photo | texture on white, top-aligned."""
    height = max(photo.shape[0], texture.shape[0])
    width = photo.shape[1] + GAP + texture.shape[1]
    out = np.full((height, width) + photo.shape[2:], 255, np.uint8)
    out[:photo.shape[0], :photo.shape[1]] = photo
    out[:texture.shape[0], photo.shape[1] + GAP:] = texture
    return out


def main() -> None:
    for name, load in PHOTOS.items():
        photo = load()
        texture = texeditor.heeger_bergen(photo, photo.shape[:2], seed=0)
        path = OUT / f"model-heeger-bergen-{name}.png"
        io.imsave(path, side_by_side(photo, texture), check_contrast=False)
        print(path)


if __name__ == "__main__":
    main()
