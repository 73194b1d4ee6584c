"""Texture rendering (thesis §5.3–5.4.1): every point drawn as a grain (shape, explosion,
compression) and the composition of two textures (mix, incrustation), with their Actions.
"""

from . import composition, grain_render
from .actions import TEXTURE_ACTIONS

__all__ = ["composition", "grain_render", "TEXTURE_ACTIONS"]
