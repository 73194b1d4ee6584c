"""EXTRACTEXT (thesis §3.4): regions picked by level and connectivity, the local operators on
them (fill, move, copy, scale, rotate…) and the global ones (identity, isometry, similarity,
affinity, and the random manipulation of every region at once), with their Actions.
"""

from . import extractext, scatter, transforms
from .actions import REGION_ACTIONS

__all__ = ["extractext", "scatter", "transforms", "REGION_ACTIONS"]
