"""The user guide's level-share pictures:

- steering.png: photo | drawn unsteered | steered (coffee at 2048², seed 1, and logo at 512²,
  seed 0, shown whole at 320²: the level shares are the picture's overall make-up);
- rebalance.png: photo | its finest shares as drawn | rebalanced (unsteered, as steps before
  version 9 draw; 512² textures, seed 0, their top-left 320² shown);
- forced.png: a small crop | its texture with the moves free of the parents only (as steps
  before version 15) | with forced moves after them (bench_shares.py's crops: moon 128² drawn
  at 64², cell 128² at 64², coffee 128² at 64²; shown whole at 320², small ones enlarged
  without smoothing).

Run: PYTHONPATH=. python3 docs/make_share_pictures.py  (about half a minute)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from skimage import data, io, transform, util

import texeditor

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))
from bench_shares import photo as crop  # noqa: E402  (bench_shares.py's crops)

IMG = Path(__file__).resolve().parent / "img"
PHOTOS = ("chelsea", "rocket", "text")
STEERED = (("coffee", 2048, 1), ("logo", 512, 0))
FORCED = (("moon", 128, 64, 2), ("cell", 128, 64, 2), ("coffee", 128, 64, 0))
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


def whole(image: np.ndarray) -> np.ndarray:
    return util.img_as_ubyte(transform.resize(rgb(image), (SIDE, SIDE), anti_aliasing=True))


def share_error(model, drawn) -> float:
    shares = np.bincount(drawn.levels.ravel(), minlength=model.levels) / drawn.levels.size
    return float(np.abs(shares - model.frequencies()).max())


def panels(photo: np.ndarray, *pictures) -> np.ndarray:
    gap = np.full((SIDE, GAP, 3), 255, np.uint8)
    parts = [photo_panel(photo)]
    for picture in pictures:
        parts += [gap, picture]
    return np.concatenate(parts, axis=1)


def rebalance_row(name: str) -> np.ndarray:
    photo = getattr(data, name)()
    model = texeditor.acquire_model(photo)
    kept = model.synthesize((512, 512), seed=0, rebalance=False, steer=False)
    moved = model.synthesize((512, 512), seed=0, steer=False)
    print(f"{name}: {moved.moved} border moves")
    return panels(photo, rgb(kept.image)[:SIDE, :SIDE], rgb(moved.image)[:SIDE, :SIDE])


def two_draws(photo: np.ndarray, size: int, seed: int, what: str, **before):
    """The photo's model and two size² draws: with ``before``'s switches, and as today."""
    model = texeditor.acquire_model(photo)
    old = model.synthesize((size, size), seed=seed, **before)
    new = model.synthesize((size, size), seed=seed)
    print(f"{what}: worst level share off by {share_error(model, old):.3f} "
          f"with {before}, {share_error(model, new):.3f} as today")
    return old, new


def steering_row(name: str, side: int, seed: int) -> np.ndarray:
    photo = getattr(data, name)()
    plain, steered = two_draws(photo, side, seed, f"{name} {side}²", steer=False)
    return panels(photo, whole(plain.image), whole(steered.image))


def enlarged(image: np.ndarray) -> np.ndarray:
    image = rgb(image)
    k = SIDE // image.shape[0]
    return np.kron(image, np.ones((k, k, 1), np.uint8)) if k > 1 else whole(image)


def forced_row(name: str, side: int, size: int, seed: int) -> np.ndarray:
    photo = rgb(crop(name, side))
    free, forced = two_draws(photo, size, seed, f"{name} {side}² at {size}²",
                             forced_moves=False)
    return panels(photo, enlarged(free.image), enlarged(forced.image))


def save(rows, name: str) -> None:
    gap = np.full((GAP, rows[0].shape[1], 3), 255, np.uint8)
    picture = np.concatenate([part for r in rows for part in (r, gap)][:-1])
    io.imsave(IMG / name, picture, check_contrast=False)
    print(IMG / name)


def main() -> None:
    save([steering_row(*case) for case in STEERED], "steering.png")
    save([rebalance_row(name) for name in PHOTOS], "rebalance.png")
    save([forced_row(*case) for case in FORCED], "forced.png")


if __name__ == "__main__":
    main()
