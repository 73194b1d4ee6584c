"""Photos made here for the photo-model tests (no bundled picture)."""

import numpy as np
import skimage as ski


def speckle(shape=(128, 128), seed=0, colour=False):
    """A textured photo made here (no bundled picture): smoothed noise, grey or RGB."""
    rng = np.random.default_rng(seed)
    grey = ski.filters.gaussian(rng.random(shape), 2)
    grey = (grey - grey.min()) / np.ptp(grey)
    if not colour:
        return np.round(grey * 255).astype(np.uint8)
    rgb = np.stack([grey, grey ** 2, 1 - grey], axis=2)
    return np.round(rgb * 255).astype(np.uint8)
