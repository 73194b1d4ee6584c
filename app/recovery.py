"""Restoring work after a crash: the journals of dead processes, offered back on start-up.

`texeditor.journal` keeps them; this module asks the user, replays the log into a History and
shows it as an unsaved document (its title starred), one window per document.
"""

from __future__ import annotations

import time
from pathlib import Path

from PySide6 import QtWidgets

from texeditor.errors import TexeditorError
from texeditor.history import History
from texeditor.journal import orphans, recover

Yes, No = QtWidgets.QMessageBox.StandardButton.Yes, QtWidgets.QMessageBox.StandardButton.No


def offer_recovery(window, make_window=None) -> int:
    """Ask about each journal left by a crash; the first document restored goes into ``window``,
    the next ones into windows from ``make_window()``. Returns how many were restored."""
    restored = 0
    for path in orphans():
        try:
            found = recover(path)
        except (TexeditorError, OSError):
            path.unlink(missing_ok=True)     # unreadable: nothing a user could get back
            continue
        if found.changes == 0:               # saved (or untouched) when it died: nothing lost
            path.unlink(missing_ok=True)
            continue
        if _ask(window, found) != Yes:
            path.unlink(missing_ok=True)
            continue
        try:
            history = History.from_log(found.actions, found.dpjs)
        except TexeditorError as exc:
            window.show_error("The unsaved work cannot be restored", exc)
            continue
        target = window if restored == 0 or make_window is None else make_window()
        target.set_history(history, Path(found.source) if found.source else None)
        target._clean_log = ()               # restored work is unsaved work
        target._update_title()
        target.journal_sync(reset=True)      # a journal of its own from now on
        path.unlink(missing_ok=True)
        restored += 1
        target.statusBar().showMessage(
            f"Restored {len(found.actions)} steps of unsaved work: save it to keep it.", 10000)
    return restored


def _ask(window, found) -> QtWidgets.QMessageBox.StandardButton:
    when = time.strftime("%Y-%m-%d %H:%M", time.localtime(found.started))
    what = Path(found.source).name if found.source else "an unsaved texture"
    return QtWidgets.QMessageBox.question(
        window, "Restore unsaved work?",
        f"texeditor closed unexpectedly while editing {what} (opened {when}).\n\n"
        f"Restore it as it was after its last completed step ({len(found.actions)} steps)?",
        Yes | No, Yes)
