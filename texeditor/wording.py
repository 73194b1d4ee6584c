"""How messages, labels and the command line count things: "1 scale", "3 steps"."""

from __future__ import annotations


def counted(n: int, noun: str) -> str:
    """``n`` and ``noun``, plural unless n is 1 (regular plurals only)."""
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"
