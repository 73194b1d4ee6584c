"""Spots (thesis §3.3.3b): an envelope (equator, meridians, parallels) perturbed into an outline,
rasterised as a stamp and placed or scattered, with their Actions and the spot library.
"""

from . import envelope
from .actions import SPOT_ACTIONS
from .envelope import Envelope, Perturbation
from .library import SpotLibrary

__all__ = ["envelope", "SPOT_ACTIONS", "Envelope", "Perturbation", "SpotLibrary"]
