"""The texture as relief (companion document 003): a height map P, its bump normals
N' = (−∂P/∂u, −∂P/∂v, 1) and the shading I = k_a + k_d·max(0, N̂'·L̂).

Levels + palette → heights → normals → shading (the previews) or a normal map (the export).
The frame is OpenGL's tangent space: u runs along the columns (right), v up the picture
(towards row 0), z out of it; a DirectX normal map is the same with v (green) flipped.
"""

from __future__ import annotations

import math

import numpy as np
from skimage.color import rgb2gray

from ..errors import InputError

MAX_STRENGTH = 1000.0


def palette_grey(palette) -> np.ndarray:
    """(G,) float in 0..1: each level's displayed grey (a colour's luminance), the height of
    its points before the strength."""
    pal = np.asarray(palette, dtype=np.float64).reshape(1, -1, 3) / 255.0
    return np.clip(rgb2gray(pal)[0], 0.0, 1.0)


def check_strength(strength) -> float:
    if not isinstance(strength, (int, float)) or not 0 <= strength <= MAX_STRENGTH:
        raise InputError(f"the relief strength must be a number from 0 to {MAX_STRENGTH:g}, "
                         f"got {strength!r}")
    return float(strength)


def heights(levels: np.ndarray, palette, strength: float = 1.0) -> np.ndarray:
    """P: the displayed grey of each point (0..1) times the strength S."""
    return palette_grey(palette)[levels] * check_strength(strength)


def slopes(P: np.ndarray, *, wrap: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """(∂P/∂u, ∂P/∂v) by central differences, one point apart on each side.

    ``wrap``: differences taken on the torus, so that a texture that tiles gives slopes that
    tile; otherwise one-sided at the border. v points up, so ∂P/∂v is the row above minus the
    row below.

    >>> du, dv = slopes(np.array([[3., 4., 5.],
    ...                           [1., 2., 3.]]), wrap=False)
    >>> du.tolist(), dv.tolist()
    ([[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]], [[2.0, 2.0, 2.0], [2.0, 2.0, 2.0]])
    """
    P = np.asarray(P, dtype=np.float64)
    if wrap:
        return ((np.roll(P, -1, axis=1) - np.roll(P, 1, axis=1)) / 2,
                (np.roll(P, 1, axis=0) - np.roll(P, -1, axis=0)) / 2)
    return _one_sided(P, axis=1), -_one_sided(P, axis=0)


def _one_sided(P: np.ndarray, axis: int) -> np.ndarray:
    """np.gradient (central inside, one-sided at the border); a single row or column is flat."""
    if P.shape[axis] < 2:
        return np.zeros_like(P)
    return np.gradient(P, axis=axis)


def unit_normals(du: np.ndarray, dv: np.ndarray) -> np.ndarray:
    """(..., 3): N' = (−∂P/∂u, −∂P/∂v, 1), normalised."""
    n = np.stack([-du, -dv, np.ones_like(du)], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def normal_map(P: np.ndarray, *, wrap: bool = True) -> np.ndarray:
    """(H, W, 3) float: the unit bump normal of each point of the height map P."""
    return unit_normals(*slopes(P, wrap=wrap))


def light_direction(azimuth: float, elevation: float) -> np.ndarray:
    """L̂ (3,): azimuth in degrees counter-clockwise from +u (0: from the right, 90: from the
    top of the picture), elevation in degrees above the surface (90: straight above).

    >>> light_direction(0, 90).round(12).tolist()
    [0.0, 0.0, 1.0]
    """
    for name, value in (("azimuth", azimuth), ("elevation", elevation)):
        if not isinstance(value, (int, float)) or not math.isfinite(value):
            raise InputError(f"the light's {name} must be a number of degrees, got {value!r}")
    if not 0 <= elevation <= 90:
        raise InputError(f"the light's elevation is from 0 to 90 degrees, got {elevation!r}")
    a, e = math.radians(azimuth), math.radians(elevation)
    return np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])


def shade(normals: np.ndarray, light: np.ndarray, ambient: float, diffuse: float) -> np.ndarray:
    """I = k_a + k_d·max(0, N̂'·L̂) for unit normals (..., 3) and a unit light (3,)."""
    return lambert(normals @ np.asarray(light, dtype=np.float64), ambient, diffuse)


def lambert(cosine: np.ndarray, ambient: float, diffuse: float) -> np.ndarray:
    """k_a + k_d·max(0, cosine): ambient light everywhere, diffuse light where the surface faces
    the light, none behind it."""
    for name, value in (("ambient", ambient), ("diffuse", diffuse)):
        if not isinstance(value, (int, float)) or not 0 <= value <= 2:
            raise InputError(f"the {name} coefficient is from 0 to 2, got {value!r}")
    return ambient + diffuse * np.maximum(0, cosine)
