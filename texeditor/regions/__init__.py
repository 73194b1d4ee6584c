"""EXTRACTEXT (thesis §3.4): regions picked by level and connectivity, local and global operators."""

from . import actions  # noqa: F401  (registers the region Actions)
