"""The relief previews of 003, drawn in numpy: the shaded texture repeated on a plane seen in
perspective, and wrapped round a sphere (x = sinθ sinφ, y = cosφ, z = cosθ sinφ).

Each preview pixel is SUPERSAMPLE² samples; a sample's bump normal is the wrapped normal_map's
(central differences on the torus: the texture repeats) computed at its point only, so a
preview costs what it shows, whatever the size of the texture (10–20 ms for 256²,
benchmarks/bench_relief.py).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from .shading import check_strength, lambert, light_direction, palette_grey

SUPERSAMPLE = 2
PITCH = math.radians(50)     # the camera looks down at the plane this far below the horizon
FOV = 0.6                    # tan of half the field of view: the horizon stays above the picture
NEAR_WIDTH = 1.2             # textures across the bottom edge of the plane preview
BACKGROUND = 48              # grey round the sphere


@dataclass(frozen=True, eq=False)
class View:
    """Where a preview's samples fall: ``pixels`` their flat indices in the supersampled
    picture; ``points`` (5, k) the flat indices in the texture (of ``shape``) of each sample's
    point and of its neighbours right, left, above and below; ``frame`` (3, 3, k): the x, y
    and z in view space (right, up, towards the viewer) of the tangent T (along u), bitangent B
    (up v) and normal N of the surface at each sample; None for a plane whose frame is the
    texture's own."""

    size: int
    shape: tuple[int, int]
    pixels: np.ndarray
    points: np.ndarray
    frame: np.ndarray | None = None

    @property
    def rows_cols(self) -> tuple[np.ndarray, np.ndarray]:
        """The texture point (row, col) under each sample."""
        return np.divmod(self.points[0], self.shape[1])


def _view(shape, size, pixels, rows, cols, frame=None) -> View:
    h, w = shape
    points = np.stack([rows * w + cols, rows * w + (cols + 1) % w, rows * w + (cols - 1) % w,
                       (rows - 1) % h * w + cols, (rows + 1) % h * w + cols])
    return View(size, (h, w), pixels, points, frame)


@functools.lru_cache(maxsize=8)
def plane_view(shape: tuple[int, int], size: int) -> View:
    """A size×size view of the plane z = 0, the texture repeated over it one width per unit.

    A projective mapping: the ray through each sample, from a camera pitched down by PITCH, is
    cut by the plane; forward on the plane is up the texture."""
    h, w = shape
    n = size * SUPERSAMPLE
    s = (np.arange(n) + 0.5) / n * 2 - 1                     # −1..1, left to right, top to bottom
    x, y = np.meshgrid(s * FOV, s * FOV)
    sin, cos = math.sin(PITCH), math.cos(PITCH)
    height = NEAR_WIDTH * (sin + FOV * cos) / (2 * FOV)      # the bottom edge spans NEAR_WIDTH
    t = height / (sin + y * cos)                             # sin + y·cos = −ray_z > 0
    cols = np.floor(t * x * w).astype(np.intp) % w
    rows = np.floor(-t * (cos - y * sin) * w).astype(np.intp) % h
    return _view(shape, size, np.arange(n * n), rows.ravel(), cols.ravel())


@functools.lru_cache(maxsize=8)
def sphere_view(shape: tuple[int, int], size: int) -> View:
    """A size×size view of the unit sphere, the texture twice round the equator (square points):
    θ the longitude from the viewer, φ the angle from the north pole."""
    h, w = shape
    n = size * SUPERSAMPLE
    s = (np.arange(n) + 0.5) / n * 2 - 1
    x, y = np.meshgrid(s, -s)
    inside = np.flatnonzero(x * x + y * y < 1)
    x, y = x.ravel()[inside], y.ravel()[inside]
    z = np.sqrt(1 - x * x - y * y)
    theta, phi = np.arctan2(x, z), np.arccos(y)
    cols = np.floor((theta + math.pi) * w / math.pi).astype(np.intp) % w
    rows = np.floor(phi * w / math.pi).astype(np.intp) % h
    sin_t, cos_t, cos_p = np.sin(theta), np.cos(theta), np.cos(phi)
    # columns T = ∂p/∂θ normalised, B = −∂p/∂φ (up the texture), N = p; rows x, y, z
    frame = np.array([[cos_t, -sin_t * cos_p, x],
                      [np.zeros_like(x), np.sin(phi), y],
                      [-sin_t, -cos_t * cos_p, z]], dtype=np.float32)
    return _view(shape, size, inside, rows, cols, frame)


def plane_preview(levels: np.ndarray, palette, *, size: int = 256, strength: float = 4.0,
                  azimuth: float = 135.0, elevation: float = 45.0, ambient: float = 0.3,
                  diffuse: float = 0.7) -> np.ndarray:
    """(size, size, 3) uint8: the texture in its palette colours, shaded as relief, on a plane
    in perspective (the light is given in the plane's own frame)."""
    return render(plane_view(levels.shape, size), levels, palette, strength,
                  light_direction(azimuth, elevation), ambient, diffuse)


def sphere_preview(levels: np.ndarray, palette, *, size: int = 256, strength: float = 4.0,
                   azimuth: float = 135.0, elevation: float = 45.0, ambient: float = 0.3,
                   diffuse: float = 0.7) -> np.ndarray:
    """(size, size, 3) uint8: the shaded texture on a sphere, its normal perturbed by the bump
    normals (N̂ = n_u T + n_v B + n_z N); the light in view space (elevation 90: from the
    viewer)."""
    return render(sphere_view(levels.shape, size), levels, palette, strength,
                  light_direction(azimuth, elevation), ambient, diffuse)


def render(view: View, levels: np.ndarray, palette, strength: float, light: np.ndarray,
           ambient: float, diffuse: float) -> np.ndarray:
    """Each sample's palette colour times k_a + k_d·max(0, N̂·L̂), N̂ = (−∂P/∂u·T − ∂P/∂v·B + N)
    / √(1 + ∂P/∂u² + ∂P/∂v²), averaged into pixels."""
    at = levels.ravel()[view.points]
    P = (palette_grey(palette) * check_strength(strength)).astype(np.float32)[at[1:]]
    du, dv = (P[0] - P[1]) / 2, (P[2] - P[3]) / 2
    light = light.astype(np.float32)
    t_l, b_l, n_l = light if view.frame is None else sum(c * f for c, f in zip(light, view.frame))
    cosine = (n_l - du * t_l - dv * b_l) / np.sqrt(1 + du * du + dv * dv)
    n = view.size * SUPERSAMPLE
    samples = np.full((n * n, 3), BACKGROUND, dtype=np.float32)
    samples[view.pixels] = (np.asarray(palette, dtype=np.float32)[at[0]]
                            * lambert(cosine, ambient, diffuse)[:, None])
    samples = samples.reshape(n, n, 3)
    mean = sum(samples[i::SUPERSAMPLE, j::SUPERSAMPLE] for i in range(SUPERSAMPLE)
               for j in range(SUPERSAMPLE)) / SUPERSAMPLE ** 2
    return np.clip(np.rint(mean), 0, 255).astype(np.uint8)
