"""The user's libraries (grain stamps, brush presets, spots), checked together at start-up.

It sits above the libraries (paint, spots) and the data folder (`userdata`), so that neither
needs the other: the application calls it once before any dock reads a library.
"""

from __future__ import annotations

import os
from pathlib import Path

from .paint.brushes import BrushLibrary
from .paint.grains import GrainLibrary
from .spots.library import KIND, VERSION, SpotLibrary
from .userdata import data_dir, read_library, set_aside_line


def check_libraries(folder: str | os.PathLike | None = None) -> list[str]:
    """Read every library of the user data folder as the application will at start-up (grains,
    brush presets, spots); each one that cannot be read — not a regular file, too big, not JSON,
    nested too deep, foreign, an item that is not valid — is set aside (`set_aside`) so that the
    application starts with its standard items. Returns one line per file set aside, naming it
    and its new name (empty: all is well)."""
    folder = Path(folder) if folder is not None else data_dir()
    problems = []
    for make, read in ((GrainLibrary, lambda lib: lib.user()),
                       (BrushLibrary, lambda lib: lib.user()),
                       (SpotLibrary, _spot_problems)):
        lib = make(folder)
        if not os.path.lexists(lib.path):
            continue
        try:
            read(lib)
            continue
        except RecursionError:
            reason = f"{lib.path}: nested too deep"
        except Exception as exc:        # any defect of the file: it must not stop the start
            reason = str(exc) or type(exc).__name__
        problems.append(set_aside_line(lib.path, reason))
    return problems


def _spot_problems(lib) -> None:
    """The spot library skips a bad entry and keeps the others (it says so in its editor): only
    a file that cannot be read as a whole is set aside."""
    read_library(lib.path, KIND, VERSION)
    lib.reload()
