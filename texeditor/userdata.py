"""The user's own data folder and the small JSON libraries kept in it (grains, brush presets).

Libraries sit beside the bank in the user data directory (platformdirs; ``TEXEDITOR_DATA``
overrides it, as tests do). Files are written atomically and every read is validated.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

from .errors import FormatError, InputError
from .fileio import load_json, read_limited, write_file

ENV_VAR = "TEXEDITOR_DATA"
MAX_LIBRARY_BYTES = 4 * 2**20
MAX_ITEMS = 1000
ITEM_ERRORS = (InputError, TypeError, ValueError, KeyError, AttributeError, ArithmeticError)
"""What reading one library item (``from_json``) may raise on a hostile item: each is reported
as the item's defect, never a traceback."""


def data_dir() -> Path:
    """The folder of the user's texeditor data (created on first write, not here)."""
    override = os.environ.get(ENV_VAR)
    if override:
        return Path(override)
    from platformdirs import user_data_dir
    return Path(user_data_dir("texeditor", appauthor=False))


def read_library(path: Path, kind: str, version: int = 1) -> list[dict]:
    """The items of a library file: ``{"format": kind, "version": n, "items": [...]}``.

    A missing file is an empty library; a damaged, foreign or newer one is a FormatError that
    names the file, so the caller can say so and carry on with the standard items.
    """
    path = Path(path)
    if not os.path.lexists(path):
        return []
    data = read_limited(path, MAX_LIBRARY_BYTES, f"{kind} library")   # a regular file only
    try:
        obj = load_json(data, "the file", limit=MAX_LIBRARY_BYTES)     # size and depth bounded
    except FormatError as exc:
        raise FormatError(f"{path}: not a {kind} library ({exc})") from None
    if not isinstance(obj, dict) or obj.get("format") != kind:
        raise FormatError(f"{path}: not a {kind} library (its format is not {kind!r})")
    found = obj.get("version")
    if isinstance(found, bool) or not isinstance(found, int) or not 1 <= found <= version:
        raise FormatError(f"{path}: {kind} library version {found!r} is not supported "
                          f"(this program reads version {version})")
    items = obj.get("items")
    if not isinstance(items, list) or len(items) > MAX_ITEMS:
        raise FormatError(f"{path}: the library must list at most {MAX_ITEMS} items")
    if not all(isinstance(item, dict) for item in items):
        raise FormatError(f"{path}: every library item must be a JSON object")
    return items


def set_aside(path: str | os.PathLike) -> Path:
    """Rename a bad file of the user data folder out of the way, never deleting it:
    ``<name>.bad-<UTC time>`` beside it (``-2``, ``-3``… when that name is taken). Returns the
    new path. Works for anything with a name: a folder, a FIFO, a dangling link."""
    path = Path(path)
    stamp = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime())
    target = path.with_name(f"{path.name}.bad-{stamp}")
    n = 1
    while os.path.lexists(target):
        n += 1
        target = path.with_name(f"{path.name}.bad-{stamp}-{n}")
    os.rename(path, target)
    return target


def set_aside_line(path: Path, reason: str) -> str:
    """Set ``path`` aside and say so in one line naming it, its new name and ``reason``."""
    reason = reason.removeprefix(f"{path}: ")
    try:
        moved = set_aside(path)
    except OSError as exc:
        return f"{path} cannot be read and cannot be set aside ({exc.strerror or exc}): {reason}"
    return f"{path} cannot be read, set aside as {moved.name}: {reason}"


def write_library(path: Path, kind: str, items: list[dict], version: int = 1) -> None:
    """Write a library file atomically (its folder is created when needed)."""
    path = Path(path)
    if len(items) > MAX_ITEMS:
        raise FormatError(f"a library holds at most {MAX_ITEMS} items")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise FormatError(f"{path}: cannot write ({exc.strerror or exc})") from None
    import json
    text = json.dumps({"format": kind, "version": version, "items": items}, indent=1)
    write_file(path, text.encode("utf-8"))
