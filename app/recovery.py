"""Restoring work after a crash: the journals of dead processes, offered back on start-up.

`texeditor.recipe.journal` keeps them; this module lists them all in one dialog (as LibreOffice's
document recovery does: a crash of several windows leaves several), replays each one chosen into a
History in a window's task runner — progress and Cancel in the status bar, the window live while a
long log replays or a first start compiles the kernels — and shows it as an unsaved document (its
title starred), one window per document. A journal is deleted only once its work is on screen or
the user discarded it: a cancelled or postponed restore is offered again at the next start.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from PySide6 import QtCore, QtGui, QtWidgets

from texeditor.errors import Cancelled
from texeditor.wording import counted
from texeditor.recipe.history import History
from texeditor.recipe.journal import THUMB_SIDE, orphans, recover
from texeditor.userdata import set_aside_line

from .images import photo_rgb, pixmap

def offer_recovery(window, make_window=None, problems: list | None = None, *,
                   otherwise=None) -> bool:
    """Offer the work of crashed sessions back. False when no journal was left (nothing
    happens). Else True: the journals are read in ``window``'s runner (a journal may hold
    hundreds of MB: seconds), then offered in one dialog; the first document chosen is restored
    into ``window``, the next ones into windows from ``make_window()`` (without it they wait for
    the next start). ``otherwise()`` runs when nothing is restored: none chosen, Not now, the
    reading cancelled; and, in ``window`` only, when its restore fails or is cancelled.

    A journal that cannot be read or replayed (a folder or a FIFO named like one, damage) is set
    aside, never deleted, and never stops the start: the lines naming them, after ``problems``
    (say, libraries set aside), are shown in one message by `report_problems` once read."""
    problems = list(problems or [])
    try:
        paths = orphans()
    except OSError as exc:
        report_problems(window, problems + [f"the crash journals cannot be listed "
                                            f"({exc.strerror or exc})"])
        return False
    if not paths:
        return False
    otherwise = otherwise or (lambda: None)

    def read(progress, cancel):
        lines = []
        return _readable(paths, lines, progress, cancel), lines

    def offer(result):
        found, lines = result
        if window.closing:
            return
        if found:
            _ask(window, found, make_window, otherwise)
        else:
            otherwise()
        report_problems(window, problems + lines)

    def later():
        if window.closing:
            return
        otherwise()
        report_problems(window, problems)

    window.runner.run("Reading the work a crash left unsaved…", read, offer,
                      on_cancel=later, on_error=lambda exc: later())
    return True


def _ask(window, found, make_window, otherwise) -> None:
    """The dialog (window-modal, no nested event loop); then the restores, or ``otherwise``."""
    dialog = RecoveryDialog(window, found)

    def answered(code):
        if window.closing:                   # the window closed under the dialog: keep all
            return
        chosen = dialog.chosen() if code == QtWidgets.QDialog.DialogCode.Accepted else []
        if code == QtWidgets.QDialog.DialogCode.Accepted:
            for item in found:
                if not any(item is c for c in chosen):
                    item.path.unlink(missing_ok=True)
        if make_window is None and len(chosen) > 1:
            window.statusBar().showMessage(f"{counted(len(chosen) - 1, 'more texture')} will "
                                           "be offered again at the next start.", 10000)
            chosen = chosen[:1]
        if not chosen:
            otherwise()
            return
        window.bank_dock.load(prepare=False)     # the bank is listed beside restored work
        for k, item in enumerate(chosen):
            restore(window if k == 0 else make_window(), item,
                    fallback=otherwise if k == 0 else None, elsewhere=make_window)
    dialog.finished.connect(answered)
    dialog.finished.connect(dialog.deleteLater)
    dialog.open()


def _readable(paths, problems: list, progress=None, cancel=None) -> list:
    """The journals at ``paths`` that hold unsaved work, read (in the worker); the unreadable
    ones set aside (a line in ``problems`` each), those with nothing unsaved deleted."""
    found = []
    for n, path in enumerate(paths):
        if cancel is not None and cancel():
            raise Cancelled()
        if progress is not None:
            progress(n / len(paths))
        try:
            item = recover(path)
        except RecursionError:
            problems.append(set_aside_line(path, "nested too deep"))
            continue
        except Exception as exc:             # any defect: this file must not stop the start
            problems.append(set_aside_line(path, str(exc) or type(exc).__name__))
            continue
        if item.changes == 0:                # saved (or untouched) when it died: nothing lost
            path.unlink(missing_ok=True)
            continue
        found.append(item)
    return found


def restore(target, item, *, fallback=None, elsewhere=None):
    """Replay the journal ``item`` in ``target``'s runner and show it there as unsaved work;
    in a window from ``elsewhere()`` if the user began another texture in ``target`` meanwhile
    (without it, the journal waits for the next start). When the replay fails (the journal is
    set aside and named) or is cancelled (it is kept), an empty ``target`` runs ``fallback()``
    (the start-up texture), or without it closes (an extra window). Returns the runner's job."""
    name = describe(item)

    def work(progress, cancel):
        return History.from_log(item.actions, item.dpjs, exemplars=item.exemplars,
                                current=item.current, progress=progress, cancel=cancel)

    def done(history):
        window = target
        if target.history is not None and target.is_modified():
            if elsewhere is None:
                target.statusBar().showMessage(f"{name} was not restored over your new work: "
                                               "it will be offered again at the next start.",
                                               15000)
                return
            window = elsewhere()
        window.set_history(history, Path(item.source) if item.source else None)
        window.mark_unsaved()                # restored work is unsaved work
        window.journal_sync(reset=True)      # a journal of its own from now on
        item.path.unlink(missing_ok=True)
        window.statusBar().showMessage(
            f"Restored {counted(len(item.actions), 'step')} of unsaved work: save it to keep "
            "it.", 10000)

    def given_up():
        if target.history is None and not target.closing:   # nothing begun in it meanwhile
            fallback() if fallback is not None else target.close()

    def cancelled():
        given_up()
        target.statusBar().showMessage(f"Restoring {name} was cancelled: it will be offered "
                                       "again at the next start.", 15000)

    def failed(exc):
        line = set_aside_line(item.path, f"the unsaved work cannot be restored "
                                         f"({str(exc) or type(exc).__name__})")
        given_up()
        report_problems(target, [line])

    return target.runner.run(f"Restoring {name}…", work, done, on_cancel=cancelled,
                             on_error=failed)


def describe(item) -> str:
    """The texture a journal holds, for the user: its file's name, or 'an unsaved texture'."""
    return Path(item.source).name if item.source else "an unsaved texture"


def opened_when(item) -> str:
    try:
        return time.strftime("%Y-%m-%d %H:%M", time.localtime(item.started))
    except (OverflowError, OSError, ValueError):
        return "at an unknown time"


class RecoveryDialog(QtWidgets.QDialog):
    """Every texture a crash left unsaved, each with a tick box (all ticked) and the middle of
    its picture as it was last shown: Restore brings back the ticked ones and discards the
    others; Not now keeps them all for the next start."""

    def __init__(self, parent, found: list):
        super().__init__(parent)
        self.found = list(found)
        self.setWindowTitle("Restore unsaved work?")
        several = len(found) > 1
        if several:
            text = (f"texeditor closed unexpectedly while editing "
                    f"{counted(len(found), 'unsaved texture')}.\n\nRestore the ticked ones as "
                    "they were after their last completed step, each in a window of its own? "
                    "The others are discarded.")
        else:
            text = (f"texeditor closed unexpectedly while editing {describe(found[0])} (opened "
                    f"{opened_when(found[0])}).\n\nRestore it as it was after its last "
                    f"completed step ({counted(len(found[0].actions), 'step')})?")
        intro = QtWidgets.QLabel(text, self)        # the dialog's first label: its message
        intro.setWordWrap(True)
        intro.setAlignment(QtCore.Qt.AlignmentFlag.AlignTop | QtCore.Qt.AlignmentFlag.AlignLeft)
        self.picture = QtWidgets.QLabel(self)       # one texture: what it looked like
        self.picture.setObjectName("thumbnail")
        thumb = found[0].thumbnail
        if not several and thumb is not None:
            self.picture.setPixmap(pixmap(photo_rgb(thumb), 2 * THUMB_SIDE))
            self.picture.setToolTip("The middle of the texture as it was last shown")
        self.picture.setVisible(not several and thumb is not None)
        self.list = QtWidgets.QListWidget()
        self.list.setIconSize(QtCore.QSize(THUMB_SIDE, THUMB_SIDE))
        for item in found:
            row = QtWidgets.QListWidgetItem(
                f"{describe(item)} — opened {opened_when(item)}, "
                f"{counted(len(item.actions), 'step')}")
            if item.thumbnail is not None:
                row.setIcon(QtGui.QIcon(pixmap(photo_rgb(item.thumbnail), THUMB_SIDE)))
            row.setFlags(row.flags() | QtCore.Qt.ItemFlag.ItemIsUserCheckable)
            row.setCheckState(QtCore.Qt.CheckState.Checked)
            self.list.addItem(row)
        self.list.setVisible(several)
        self.list.itemChanged.connect(self._update_buttons)
        buttons = QtWidgets.QDialogButtonBox()
        self.restore_button = buttons.addButton(
            "Restore", QtWidgets.QDialogButtonBox.ButtonRole.AcceptRole)
        self.discard_button = buttons.addButton(
            "Discard" + (" all" if several else ""),
            QtWidgets.QDialogButtonBox.ButtonRole.DestructiveRole)
        self.later_button = buttons.addButton(
            "Not now", QtWidgets.QDialogButtonBox.ButtonRole.RejectRole)
        self.restore_button.setDefault(True)
        self.restore_button.clicked.connect(self.accept)
        self.discard_button.clicked.connect(self.discard_all)
        self.later_button.clicked.connect(self.reject)
        layout = QtWidgets.QVBoxLayout(self)
        top = QtWidgets.QHBoxLayout()
        top.addWidget(self.picture, 0, QtCore.Qt.AlignmentFlag.AlignTop)
        top.addWidget(intro, 1)
        layout.addLayout(top)
        layout.addWidget(self.list)
        layout.addWidget(buttons)
        rows = max(22, THUMB_SIDE + 6) if any(i.thumbnail is not None for i in found) else 22
        self.resize(560, min(520, 160 + rows * len(found)) if several
                    else 200 if self.picture.isVisibleTo(self) else 140)

    def chosen(self) -> list:
        """The journals ticked for restoring."""
        return [item for k, item in enumerate(self.found)
                if self.list.item(k).checkState() == QtCore.Qt.CheckState.Checked]

    def discard_all(self) -> None:
        for k in range(self.list.count()):
            self.list.item(k).setCheckState(QtCore.Qt.CheckState.Unchecked)
        self.accept()

    def _update_buttons(self, _item=None) -> None:
        ticked = len(self.chosen())
        self.restore_button.setEnabled(ticked > 0)
        self.restore_button.setText("Restore" if ticked in (0, len(self.found))
                                    else f"Restore {ticked}")


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
