"""Texture rendering (thesis §5.3–5.4.1): every point drawn as a grain (shape, explosion,
compression), the composition of two textures (mix, incrustation) and colour plates (§1.2.3–1.2.4),
with their Actions.
"""

from . import composition, grain_render, plates
from .actions import TEXTURE_ACTIONS
from .plate_actions import PLATE_ACTIONS

__all__ = ["composition", "grain_render", "plates", "TEXTURE_ACTIONS", "PLATE_ACTIONS"]
