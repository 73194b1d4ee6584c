"""Before Qt starts: is there a display, and can Qt's X11 plugin load?

Without them Qt aborts the process with a message that names neither the cause nor the cure
("could not load the Qt platform plugin xcb"). A newcomer on a bare Linux system (a container, a
minimal install) meets exactly that, so `texeditor` checks first and says what to install.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

_NOT_FOUND = re.compile(r"^\s*(\S+)\s+=>\s+not found", re.MULTILINE)


def problem() -> str | None:
    """Why a window cannot open here (None: go ahead, or it cannot be told in advance)."""
    if not sys.platform.startswith("linux"):
        return None
    platform = os.environ.get("QT_QPA_PLATFORM", "")
    if platform and not platform.startswith("xcb"):
        return None                      # offscreen, wayland…: the user chose
    if not platform and os.environ.get("WAYLAND_DISPLAY"):
        return None
    if not os.environ.get("DISPLAY"):
        return ("there is no display to open a window on (DISPLAY is not set). Start it from a "
                "desktop session, or render the window to a file: "
                "texeditor gui --screenshot window.png")
    missing = missing_libraries(_xcb_plugin())
    if missing:
        return ("Qt's X11 plugin needs system libraries that are missing: "
                f"{', '.join(missing)}. On Debian or Ubuntu: sudo apt-get install "
                f"{' '.join(debian_package(name) for name in missing)}")
    return None


def _xcb_plugin() -> Path | None:
    try:
        import PySide6
    except ImportError:
        return None
    path = Path(PySide6.__file__).parent / "Qt" / "plugins" / "platforms" / "libqxcb.so"
    return path if path.exists() else None


def missing_libraries(library: Path | None) -> list[str]:
    """The shared libraries ``library`` needs that the system does not have (by ldd)."""
    ldd = shutil.which("ldd")
    if library is None or ldd is None:
        return []
    try:
        out = subprocess.run([ldd, str(library)], capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return []
    return not_found(out.stdout)


def not_found(ldd_output: str) -> list[str]:
    """The sonames ldd reports as "not found", each once, in order."""
    return list(dict.fromkeys(_NOT_FOUND.findall(ldd_output)))


def debian_package(soname: str) -> str:
    """Debian's package for a soname: libxcb-icccm.so.4 → libxcb-icccm4, libxkbcommon-x11.so.0 →
    libxkbcommon-x11-0 (a dash when the name ends in a digit)."""
    match = re.fullmatch(r"(lib.+?)\.so\.(\d+).*", soname)
    if match is None:
        return soname
    name, version = match.groups()
    name = name.lower()
    return f"{name}-{version}" if name[-1].isdigit() else f"{name}{version}"
