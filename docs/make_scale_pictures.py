"""The user guide's picture of the parents' phase (markov.multiscale.PARENT_PHASE):

- phase.png: brick's bundled 256² sample | its 256² texture from a model without the phase (as
  models acquired before it draw) | from today's model, two seeds a row; the same tone.

Run: PYTHONPATH=. python3 docs/make_scale_pictures.py  (a few seconds)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from skimage import io

from texeditor import load_image, resources
from texeditor.markov.multiscale import estimate_scales
from texeditor.photo.model import PhotoModel, photo_tone

IMG = Path(__file__).resolve().parent / "img"
GAP = 6


def models(photo: np.ndarray) -> list[PhotoModel]:
    """The photo's model without the parents' phase, then with it (the same tone)."""
    out = []
    for phase in (False, True):
        scales, levels = estimate_scales(photo, phase=phase)
        out.append(PhotoModel(scales, photo_tone(photo, levels[-1])))
    return out


def row(photo: np.ndarray, drawn: list[np.ndarray]) -> np.ndarray:
    gap = np.full((photo.shape[0], GAP), 255, np.uint8)
    parts = [photo]
    for picture in drawn:
        parts += [gap, picture]
    return np.hstack(parts)


def main() -> None:
    path = next(p for p in resources.sample_images() if p.name == "brick.png")
    photo = load_image(path)
    before, now = models(photo)
    rows = [row(photo, [m.synthesize(photo.shape, seed=seed).image for m in (before, now)])
            for seed in (0, 1)]
    gap = np.full((GAP, rows[0].shape[1]), 255, np.uint8)
    io.imsave(IMG / "phase.png", np.vstack([rows[0], gap, rows[1]]), check_contrast=False)
    print(IMG / "phase.png")


if __name__ == "__main__":
    main()
