"""The `texeditor` console script: ``main(argv)`` opens the window for `texeditor` and
`texeditor gui [--screenshot OUT.png] [--open FILE]` (``run``), and hands every other command to
the headless CLI (`texeditor.cli`) without importing Qt, so `texeditor synth …` runs anywhere.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from pathlib import Path


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="texeditor gui", description="Open the texture studio.")
    parser.add_argument("--open", metavar="FILE", type=Path, help="a .texture file to open")
    parser.add_argument("--screenshot", metavar="OUT.png", type=Path,
                        help="render the window offscreen to a PNG and exit")
    parser.add_argument("--size", metavar="WxH", default="1280x800", type=window_size,
                        help="window size for --screenshot (default 1280x800; at most "
                             f"{MAX_SIZE[0]}x{MAX_SIZE[1]})")
    return parser.parse_args(argv)


MIN_SIZE, MAX_SIZE = (320, 240), (7680, 4320)     # an 8K screen: ~130 MB of window picture


def window_size(text: str) -> tuple[int, int]:
    """'WxH' within MIN_SIZE..MAX_SIZE (Qt cannot paint a 99999×99999 window: it crashes)."""
    match = re.fullmatch(r"(\d{1,6})x(\d{1,6})", text.strip())
    if match is None:
        raise argparse.ArgumentTypeError(f"{text!r} is not WIDTHxHEIGHT, e.g. 1280x800")
    size = int(match[1]), int(match[2])
    if not all(lo <= v <= hi for v, lo, hi in zip(size, MIN_SIZE, MAX_SIZE)):
        raise argparse.ArgumentTypeError(
            f"{text} is outside {MIN_SIZE[0]}x{MIN_SIZE[1]}..{MAX_SIZE[0]}x{MAX_SIZE[1]}")
    return size


def main(argv=None) -> int:
    """The console script: the window, or the engine's command line for any other command."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] == "gui":
        return run(argv[1:])
    if argv[0].startswith("-") and argv[0] not in ("-h", "--help", "--version"):
        return run(argv)                     # `texeditor --open F`: the window's own options
    from texeditor.cli import main as headless
    return headless(argv)


def run(argv=None) -> int:
    """Start the GUI. ``argv`` excludes the program name (None: ``sys.argv[1:]``); returns the exit
    code (0; 2 when no window can open here, or --open or --screenshot fails in screenshot
    mode)."""
    args = parse_args(sys.argv[1:] if argv is None else list(argv))
    if args.screenshot is not None:
        os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    else:
        from .display_check import problem
        reason = problem()
        if reason is not None:
            print(f"texeditor: {reason}", file=sys.stderr)
            return 2

    from PySide6 import QtWidgets

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([sys.argv[0]])
    app.setApplicationName("texeditor")
    app.setOrganizationName("texeditor")

    from .main_window import MainWindow
    from .recovery import offer_recovery, report_problems
    from texeditor.libraries import check_libraries

    problems = check_libraries()           # a bad library is set aside before any dock reads it
    window = MainWindow()
    window.headless = args.screenshot is not None
    if args.screenshot is not None:
        window.resize(*args.size)
    window.show()
    extra_windows = []                     # more documents restored after a crash

    def another_window():
        extra = MainWindow()
        extra.show()
        extra.bank_dock.load(prepare=False)       # the bank beside the restored work
        extra_windows.append(extra)
        return extra

    offered = False                        # crash journals: read in the worker, then offered
    if args.open is not None:
        window.open_file(args.open)
        window.bank_dock.load(prepare=False)      # the bank is listed beside the file
    elif args.screenshot is None:
        offered = offer_recovery(window, another_window, problems,
                                 otherwise=window.start_default)
    if args.open is None and not offered:
        window.start_default()
    if not offered:                        # (offer_recovery names them once it has read)
        report_problems(window, problems)  # one message naming every file set aside
    if args.screenshot is None:
        return app.exec()

    window.runner.wait(120_000)
    app.processEvents()
    if args.open is not None and window.path is None:
        return 2                 # the reason was printed by the window
    png = _png_bytes(window.grab())
    window.mark_clean()
    window.close()
    return write_screenshot(args.screenshot, png)


def _png_bytes(pixmap) -> bytes | None:
    """The picture encoded as PNG in memory (None when Qt cannot encode it)."""
    from PySide6 import QtCore
    buffer = QtCore.QBuffer()
    buffer.open(QtCore.QIODevice.OpenModeFlag.WriteOnly)
    ok = pixmap.save(buffer, "PNG")
    data = bytes(buffer.data())
    buffer.close()
    return data if ok and data else None


def write_screenshot(path: Path, png: bytes | None) -> int:
    """Write the screenshot atomically (texeditor.fileio): a full disk or a folder that cannot
    be written leaves any existing file as it was and exits 2 naming the file."""
    from texeditor.errors import TexeditorError
    from texeditor.fileio import write_file
    if png is None:
        print(f"texeditor: error: {path}: cannot write (the window could not be encoded as PNG)",
              file=sys.stderr)
        return 2
    try:
        write_file(path, png)
    except TexeditorError as exc:
        print(f"texeditor: error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
