"""EXTRACTEXT (thesis §3.4): regions picked by level and connectivity, the local operators on
them (fill, move, copy, scale, rotate…) and the global ones (identity, isometry, similarity,
affinity), with their Actions.
"""

from . import extractext, transforms
from .actions import REGION_ACTIONS

__all__ = ["extractext", "transforms", "REGION_ACTIONS"]
