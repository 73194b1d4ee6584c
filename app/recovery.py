"""Restoring work after a crash: the journals of dead processes, offered back on start-up.

`texeditor.recipe.journal` keeps them; this module asks the user, replays the log into a History and
shows it as an unsaved document (its title starred), one window per document.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from PySide6 import QtWidgets

from texeditor.errors import TexeditorError
from texeditor.wording import counted
from texeditor.recipe.history import History
from texeditor.recipe.journal import orphans, recover
from texeditor.userdata import set_aside_line

Yes, No = QtWidgets.QMessageBox.StandardButton.Yes, QtWidgets.QMessageBox.StandardButton.No


def offer_recovery(window, make_window=None, problems: list | None = None) -> int:
    """Ask about each journal left by a crash; the first document restored goes into ``window``,
    the next ones into windows from ``make_window()``. Returns how many were restored.

    A journal that cannot be read or replayed (a folder or a FIFO named like one, damage) is set
    aside, never deleted, and never stops the start: a line naming it is appended to
    ``problems``, or, without that list, shown at once by `report_problems`."""
    restored, own = 0, problems is None
    problems = [] if own else problems
    try:
        found_paths = orphans()
    except OSError as exc:
        found_paths = []
        problems.append(f"the crash journals cannot be listed ({exc.strerror or exc})")
    for path in found_paths:
        try:
            found = recover(path)
        except RecursionError:
            problems.append(set_aside_line(path, "nested too deep"))
            continue
        except Exception as exc:             # any defect: this file must not stop the start
            problems.append(set_aside_line(path, str(exc) or type(exc).__name__))
            continue
        if found.changes == 0:               # saved (or untouched) when it died: nothing lost
            path.unlink(missing_ok=True)
            continue
        if _ask(window, found) != Yes:
            path.unlink(missing_ok=True)
            continue
        try:
            history = History.from_log(found.actions, found.dpjs, exemplars=found.exemplars)
        except (TexeditorError, ValueError, TypeError, KeyError, ArithmeticError,
                MemoryError) as exc:
            problems.append(set_aside_line(path, f"the unsaved work cannot be restored "
                                                  f"({str(exc) or type(exc).__name__})"))
            continue
        target = window if restored == 0 or make_window is None else make_window()
        target.set_history(history, Path(found.source) if found.source else None)
        target.mark_unsaved()                # restored work is unsaved work
        target.journal_sync(reset=True)      # a journal of its own from now on
        path.unlink(missing_ok=True)
        restored += 1
        target.statusBar().showMessage(
            f"Restored {counted(len(found.actions), 'step')} of unsaved work: save it to keep "
            "it.", 10000)
    if own:
        report_problems(window, problems)
    return restored


def report_problems(window, problems: list[str]) -> None:
    """Say, in one message, which files of the user data folder were set aside at start-up: in
    the status bar, and on stderr when the window is headless (--screenshot) — never a dialog,
    which would block the start."""
    if not problems:
        return
    text = (f"{len(problems)} file{'s' if len(problems) > 1 else ''} of your data folder "
            f"could not be read and {'were' if len(problems) > 1 else 'was'} set aside: "
            + "; ".join(problems))
    window.statusBar().showMessage(text, 30000)
    if getattr(window, "headless", False):
        print(f"texeditor: {text}", file=sys.stderr)


def _ask(window, found) -> QtWidgets.QMessageBox.StandardButton:
    try:
        when = time.strftime("%Y-%m-%d %H:%M", time.localtime(found.started))
    except (OverflowError, OSError, ValueError):
        when = "at an unknown time"
    what = Path(found.source).name if found.source else "an unsaved texture"
    return QtWidgets.QMessageBox.question(
        window, "Restore unsaved work?",
        f"texeditor closed unexpectedly while editing {what} (opened {when}).\n\n"
        f"Restore it as it was after its last completed step "
        f"({counted(len(found.actions), 'step')})?",
        Yes | No, Yes)
