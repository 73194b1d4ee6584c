"""The one cache of replayed results: the last few, within a memory budget, shared by threads.

A recipe named by a composition step and a rasterised spot are slow to rebuild and often asked
for twice in a row (a preview, then the step; a replay after an undo). Values are treated as
read-only; the least recently used go first.
"""

from __future__ import annotations

import threading
from collections import OrderedDict


def _nbytes(value) -> int:
    """Bytes a value holds: its own ``nbytes``, or its items' (a (levels, G) pair)."""
    if hasattr(value, "nbytes"):
        return int(value.nbytes)
    if isinstance(value, tuple):
        return sum(_nbytes(v) for v in value)
    return 0


class Cache:
    """At most ``max_items`` values and ``max_bytes`` bytes; ``get`` returns None when absent.
    A value larger than the whole budget is not kept."""

    def __init__(self, max_items: int = 1_000_000, max_bytes: int = 128 * 2**20):
        self.max_items, self.max_bytes = max_items, max_bytes
        self._items: OrderedDict = OrderedDict()
        self._bytes = 0
        self._lock = threading.Lock()

    def get(self, key):
        with self._lock:
            value = self._items.get(key)
            if value is not None:
                self._items.move_to_end(key)
            return value

    def put(self, key, value) -> None:
        size = _nbytes(value)
        if size > self.max_bytes:
            return
        with self._lock:
            if key in self._items:
                self._bytes -= _nbytes(self._items.pop(key))
            self._items[key] = value
            self._bytes += size
            while len(self._items) > self.max_items or self._bytes > self.max_bytes:
                _, old = self._items.popitem(last=False)
                self._bytes -= _nbytes(old)

    def clear(self) -> None:
        with self._lock:
            self._items.clear()
            self._bytes = 0

    def __len__(self) -> int:
        return len(self._items)
