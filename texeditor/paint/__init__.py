"""Painting (thesis §3.2–3.3a): brushes and sprays, grains placed one by one, zones duplicated or
scrambled, Peano-curve levels, dominance trees and fill orders, with their Actions and the brush
and grain libraries.
"""

from . import brushes, grains, orders, peano, trees, zones
from .actions import PAINT_ACTIONS
from .brushes import Brush, BrushLibrary
from .grains import GrainLibrary, GrainType

__all__ = ["brushes", "grains", "orders", "peano", "trees", "zones", "PAINT_ACTIONS", "Brush",
           "BrushLibrary", "GrainLibrary", "GrainType"]
