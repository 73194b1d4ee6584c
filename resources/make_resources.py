"""Regenerate the bundled sample photos and DPJs (run from the repository root).

The photos are 256² crops of scikit-image's CC0 textures (brick, grass, gravel: CC0Textures and
DeviantArt, Creative Commons CC0). The DPJs are acquired from the full photos.
"""

from pathlib import Path

from skimage import data, io

from texeditor import estimate_dpj, quantize

HERE = Path(__file__).resolve().parent
PHOTOS = {"brick": (128, 128), "grass": (0, 0), "gravel": (0, 0)}
# name: (photo, window (u, v), G, quantiser, wrap)
DPJS = {
    "gravel-3x3-g4": ("gravel", (3, 3), 4, "lloyd", True),
    "grass-2x2-g8": ("grass", (2, 2), 8, "band", False),
    "brick-2x3-g4": ("brick", (2, 3), 4, "lloyd", True),
}


def main() -> None:
    for name, (top, left) in PHOTOS.items():
        crop = getattr(data, name)()[top:top + 256, left:left + 256]
        io.imsave(HERE / "images" / f"{name}.png", crop, check_contrast=False)
    for name, (photo, window, levels, method, wrap) in DPJS.items():
        q = quantize(getattr(data, photo)(), levels, method=method)
        meta = {"source": f"scikit-image {photo} (CC0)", "quantizer": method, "name": name}
        estimate_dpj(q.levels, window, levels, wrap=wrap, palette=q.palette, meta=meta).save(
            HERE / "dpj" / f"{name}.dpj")


if __name__ == "__main__":
    main()
