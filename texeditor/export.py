"""Showing a level matrix: through its palette to RGB, and out to PNG or `.npy` files.

The last step of the data flow (levels + palette → picture). Every write is atomic.
"""

from __future__ import annotations

import io

import numpy as np

from .errors import InputError
from .fileio import write_file

MAX_EXPORT_PIXELS = 2**28


def to_rgb(levels: np.ndarray, palette: np.ndarray) -> np.ndarray:
    """(H, W, 3) uint8: each level drawn in its palette colour."""
    return np.asarray(palette, dtype=np.uint8)[levels]


def write_png(path, levels: np.ndarray, palette: np.ndarray, scale: int = 1) -> None:
    """Write the texture as a PNG, each point drawn as a scale×scale block; grey if the palette is."""
    _check_scale(levels.shape, scale)    # before the (maybe huge) RGB array is made
    rgb = to_rgb(levels, palette)
    pal = np.asarray(palette)
    if np.all(pal[:, 0] == pal[:, 1]) and np.all(pal[:, 1] == pal[:, 2]):
        rgb = rgb[:, :, 0]
    write_picture(path, rgb, scale)


def write_picture(path, picture: np.ndarray, scale: int = 1) -> None:
    """Write a uint8 picture, grey (H, W) or RGB (H, W, 3), or a 16-bit grey one (uint16
    (H, W): a height map, relief.write_height_map) as a PNG, each pixel drawn as a scale×scale
    block (a texture shown with its photo's tone, photo.PhotoModel.render)."""
    picture = np.asarray(picture)
    if not (picture.dtype == np.uint8 and (picture.ndim == 2 or picture.ndim == 3
                                           and picture.shape[2] == 3)
            or picture.dtype == np.uint16 and picture.ndim == 2):
        raise InputError(f"a picture is uint8 (H, W) or (H, W, 3), or uint16 (H, W), got "
                         f"{picture.shape} {picture.dtype}")
    _check_scale(picture.shape, scale)
    if scale > 1:
        picture = np.repeat(np.repeat(picture, scale, axis=0), scale, axis=1)
    import imageio.v3 as iio  # scikit-image's own reader/writer; loaded only when exporting

    write_file(path, iio.imwrite("<bytes>", picture, extension=".png"), error=InputError)


def _check_scale(shape, scale) -> None:
    if not isinstance(scale, int) or scale < 1:
        raise InputError(f"the upscale factor must be a positive integer, got {scale!r}")
    if shape[0] * shape[1] * scale * scale > MAX_EXPORT_PIXELS:
        raise InputError("the exported picture would be too large: choose a smaller upscale")


def write_npy(path, levels: np.ndarray) -> None:
    """Write the uint8 level matrix as a `.npy` (no pickle: a plain numeric array)."""
    buf = io.BytesIO()
    np.save(buf, np.ascontiguousarray(levels, dtype=np.uint8), allow_pickle=False)
    write_file(path, buf.getvalue(), error=InputError)
