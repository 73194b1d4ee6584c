"""Where the application finds its bundled material: sample photos and DPJs in ``resources/``.

Until the bundled DPJs exist the start-up texture comes from a sample photo, and failing that from
scikit-image's own gravel sample, so the window never opens on nothing.
"""

from __future__ import annotations

from pathlib import Path

import texeditor.resources
from texeditor.errors import TexeditorError

START_WINDOW, START_LEVELS = (3, 3), 4
START_NAME = "gravel"      # the bundled DPJ the window opens on, when present


def sample_images() -> list[Path]:
    return texeditor.resources.sample_images()


def bundled_dpjs() -> list[Path]:
    return texeditor.resources.bundled_dpjs()


def default_dpj():
    """The DPJ the window starts on: the first bundled one that loads, else one estimated."""
    from texeditor.markov.dpj import DPJ
    for path in sorted(bundled_dpjs(), key=lambda p: (not p.stem.startswith(START_NAME), p.name)):
        try:
            dpj = DPJ.load(path)
        except TexeditorError:
            continue
        if "name" not in dpj.meta:
            dpj = DPJ(dpj.configs, dpj.probs, dpj.levels, palette=dpj.palette,
                      meta={**dpj.meta, "name": path.stem})
        return dpj
    return estimate_from_photo(sample_images()[0] if sample_images() else None)


def estimate_from_photo(path: Path | None, window=START_WINDOW, levels=START_LEVELS):
    """A DPJ acquired from a photo (or scikit-image's gravel when there is none)."""
    from texeditor.markov.estimation import estimate_dpj
    from texeditor.markov.levels import load_image, quantize
    if path is None:
        from skimage import data
        image, name = data.gravel(), "gravel"
    else:
        image, name = load_image(path), path.stem
    q = quantize(image, levels, "band")
    return estimate_dpj(q.levels, window, levels, palette=q.palette,
                        meta={"name": name, "quantiser": "band"})
