"""The relief's exports: the height map as a 16-bit grey PNG and the tangent-space normal map
as an 8-bit RGB PNG, for a game engine or a 3-D program. Both written atomically.

The last step of the relief's data flow (levels + palette → heights → normals → files).
"""

from __future__ import annotations

import numpy as np

from ..export import write_picture
from .shading import heights, normal_map, palette_grey

NORMAL_CONVENTIONS = ("opengl", "directx")


def height_map16(levels: np.ndarray, palette) -> np.ndarray:
    """(H, W) uint16: each point's displayed grey, 0..1 as 0..65535 (a grey palette's 0..255
    exactly ×257); the strength belongs to the program that reads it."""
    return np.rint(palette_grey(palette)[levels] * 65535).astype(np.uint16)


def encode_normals(normals: np.ndarray, *, directx: bool = False) -> np.ndarray:
    """(H, W, 3) uint8: n → (n + 1)/2·255, rounded half up (flat is (128, 128, 255)).
    DirectX's green (v pointing down the picture) is OpenGL's inverted, 255 − g: the very
    channel flip that converts one into the other.

    >>> encode_normals(np.array([[[0.0, 0.0, 1.0]]]), directx=True).tolist()
    [[[128, 127, 255]]]
    """
    rgb = np.floor((np.asarray(normals) + 1) / 2 * 255 + 0.5).astype(np.uint8)
    if directx:
        rgb[..., 1] = 255 - rgb[..., 1]
    return rgb


def write_height_map(path, levels: np.ndarray, palette) -> None:
    write_picture(path, height_map16(levels, palette))


def write_normal_map(path, levels: np.ndarray, palette, *, strength: float = 4.0,
                     directx: bool = False, wrap: bool = True) -> None:
    """The normal map of P = grey × strength; ``wrap``: seamless when the texture tiles."""
    normals = normal_map(heights(levels, palette, strength), wrap=wrap)
    write_picture(path, encode_normals(normals, directx=directx))
