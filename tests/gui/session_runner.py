"""Realistic GUI sessions and seeded monkey walks, each run in a child process.

A segfault in Qt kills the process it happens in; run in pytest's own process it would take the
whole test run with it and say nothing. So ``run_child`` starts ``python -m
tests.gui.session_runner …`` with offscreen Qt and temporary user data, bank and settings, and
turns a crash (a negative return code, 139) into a test failure that quotes the child's stderr.

In the child, every gesture is a real input event (keys, mouse drags and clicks on the canvas,
the wheel, clicks on dock buttons), exceptions that reach Qt are recorded by ``sys.excepthook``
and modal message boxes are recorded instead of blocking. The child prints one JSON report line
(prefixed ``REPORT ``) and exits 0, or exits 1 with what went wrong on stderr.

    python -m tests.gui.session_runner session paint
    python -m tests.gui.session_runner monkey 7 [--events 320] [--models] [--photo] [--menus]
    python -m tests.gui.session_runner start 3 [--events 60]
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CHILD_TIMEOUT = 240          # seconds: a hung child is a failure too, never a hung test run


# -- the parent's side -----------------------------------------------------------------------------

def run_child(args: list[str], tmp: Path, timeout: float = CHILD_TIMEOUT) -> dict:
    """Run the runner in a child process with isolated user data; return its report, or fail
    the calling test with the reason (a crash by its signal, an error by its stderr tail)."""
    import pytest
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen", "TEXEDITOR_DATA": str(tmp / "data"),
           "TEXEDITOR_BANK": str(tmp / "bank"), "TEXEDITOR_SETTINGS": str(tmp / "settings"),
           "PYTHONFAULTHANDLER": "1"}
    try:
        proc = subprocess.run([sys.executable, "-m", "tests.gui.session_runner", *args],
                              cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired as exc:
        pytest.fail(f"{' '.join(args)}: no end after {timeout} s\n{_tail(exc.stderr)}")
    if proc.returncode < 0 or proc.returncode >= 128:
        signal = -proc.returncode if proc.returncode < 0 else proc.returncode - 128
        pytest.fail(f"{' '.join(args)}: the application CRASHED (signal {signal}, return code "
                    f"{proc.returncode})\n{_tail(proc.stderr)}")
    if proc.returncode != 0:
        pytest.fail(f"{' '.join(args)}: failed (return code {proc.returncode})\n"
                    f"{_tail(proc.stderr)}")
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("REPORT ")]
    assert lines, f"{' '.join(args)}: no report\n{_tail(proc.stderr)}"
    return json.loads(lines[-1][len("REPORT "):])


def _tail(text, lines: int = 40) -> str:
    if isinstance(text, bytes):
        text = text.decode(errors="replace")
    return "\n".join((text or "").splitlines()[-lines:])


# -- the child's side: a window with its recorders -------------------------------------------------

def isolate() -> None:
    """Settings in a temporary INI file (never the user's); Qt offscreen."""
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from PySide6 import QtCore
    folder = os.environ.get("TEXEDITOR_SETTINGS") or tempfile.mkdtemp(prefix="texeditor-settings")
    QtCore.QSettings.setDefaultFormat(QtCore.QSettings.Format.IniFormat)
    QtCore.QSettings.setPath(QtCore.QSettings.Format.IniFormat, QtCore.QSettings.Scope.UserScope,
                             folder)


class Recorder:
    """What reached the user instead of the document: exceptions that got to Qt's event loop
    (sys.excepthook) and modal dialogs, recorded and answered at once so none blocks."""

    def __init__(self):
        self.exceptions: list[str] = []
        self.dialogs: list[tuple[str, str]] = []

    def install(self) -> None:
        import traceback

        from PySide6 import QtGui, QtWidgets
        import pyqtgraph.debug
        sys.excepthook = lambda t, v, tb: self.exceptions.append(
            "".join(traceback.format_exception(t, v, tb)))
        printed = pyqtgraph.debug.printExc      # pyqtgraph's scene catches a tool's exception
        pyqtgraph.debug.printExc = lambda msg="", *a, **k: (   # in a mouse event and prints it
            self.exceptions.append(f"{msg} (caught by pyqtgraph)\n{traceback.format_exc()}"),
            printed(msg, *a, **k))
        box = QtWidgets.QMessageBox
        for name, answer in (("critical", box.StandardButton.Ok),
                             ("warning", box.StandardButton.Ok),
                             ("information", box.StandardButton.Ok),
                             ("question", box.StandardButton.Discard)):
            setattr(box, name, self._answer(name, answer))
        QtWidgets.QInputDialog.getText = lambda *a, **k: ("", False)
        QtWidgets.QInputDialog.getInt = lambda *a, **k: (0, False)
        QtWidgets.QFileDialog.getOpenFileName = lambda *a, **k: ("", "")
        QtWidgets.QFileDialog.getSaveFileName = lambda *a, **k: ("", "")
        QtWidgets.QColorDialog.getColor = lambda *a, **k: QtGui.QColor()

    def _answer(self, kind: str, answer):
        def record(parent, title, text, *args, **kwargs):
            self.dialogs.append((kind, f"{title}: {text}"))
            return answer
        return staticmethod(record)


def open_window(recorder: Recorder):
    """The main window at 1100×750 on a 64×48 synthesis from the bundled gravel DPJ, as the
    GUI tests' fixture makes it."""
    from PySide6 import QtTest, QtWidgets

    from app import resources
    from app.main_window import MainWindow
    from texeditor.recipe.history import History

    QtWidgets.QApplication.instance() or QtWidgets.QApplication(["texeditor-session"])
    recorder.install()
    win = MainWindow()
    win.resize(1100, 750)
    win.show()
    QtTest.QTest.qWaitForWindowExposed(win)
    history = History()
    history.add_dpj(resources.default_dpj())
    win.set_history(history)
    dock = win.synthesis_dock
    dock.width_box.setValue(64)
    dock.height_box.setValue(48)
    dock.seed.set_value(7)
    win.synthesise_from_dock()
    assert win.runner.wait(120_000), "the first synthesis did not end"
    QtTest.QTest.qWait(50)
    assert win.history.index == 1 and win.document.shape == (48, 64), "no synthesised texture"
    win.mark_clean()
    return win


def close_window(win) -> None:
    """Close as a user quits (nothing to save is asked: the document is marked clean)."""
    from PySide6 import QtWidgets

    from app.dpj_editor import DPJEditor
    win.runner.cancel()
    win.runner.wait(10_000)
    win.mark_clean()
    for editor in win.findChildren(DPJEditor):
        editor.undo_stack.setClean()
    win.close()
    QtWidgets.QApplication.processEvents()


def state(win) -> dict:
    """The document as a user sees it: levels, palette and the log's length."""
    doc = win.document
    return {"levels": doc.levels.copy(), "palette": doc.palette.copy(), "index": win.history.index}


def same_document(a: dict, b: dict) -> bool:
    import numpy as np
    return (np.array_equal(a["levels"], b["levels"]) and np.array_equal(a["palette"], b["palette"])
            and a["index"] == b["index"])


class Hand:
    """A user's hand on the window: keys, canvas gestures and dock clicks as real events.
    Positions are read just before each event, as the view may move between gestures."""

    def __init__(self, win):
        self.win = win
        self.canvas = win.canvas

    # -- keyboard ----------------------------------------------------------------------------------
    def key(self, key, modifiers=None, widget=None) -> None:
        """A key press in the main window (made active first, as a click on it would)."""
        from PySide6 import QtCore, QtTest, QtWidgets
        if widget is None:
            widget = self.win
            if QtWidgets.QApplication.activeWindow() is not self.win:
                self.win.activateWindow()          # Qt activates it in the next events
                QtTest.QTest.qWait(10)
        QtTest.QTest.keyClick(widget, key, modifiers or QtCore.Qt.KeyboardModifier.NoModifier)
        QtTest.QTest.qWait(5)

    def shortcut(self, text: str) -> None:
        """Type a shortcut written as Qt writes it ("B", "Shift+D", "Ctrl+G")."""
        from PySide6 import QtGui
        combo = QtGui.QKeySequence(text)[0]
        self.key(combo.key(), combo.keyboardModifiers())

    def undo(self) -> None:
        self.shortcut("Ctrl+Z")

    def redo(self) -> None:
        self.shortcut("Ctrl+Shift+Z")

    def choose(self, tool_type, by_button: bool = False) -> None:
        """Select a tool by its shortcut, or by its button above the tool options."""
        tool = next(t for t in self.win.tools if type(t) is tool_type)
        if by_button:
            self.button(self.win.tool_dock.buttons[id(tool)])
        else:
            self.shortcut(tool.SHORTCUT)
        assert self.win.tool is tool, f"{tool.NAME} was not selected"

    # -- the canvas --------------------------------------------------------------------------------
    def pos(self, cell):
        from .support import cell_pos
        return cell_pos(self.canvas, *cell)

    def _send(self, kind, cell, button, buttons, modifiers) -> None:
        from PySide6 import QtCore, QtGui, QtWidgets
        widget, pos = self.canvas.viewport(), self.pos(cell)
        ev = QtGui.QMouseEvent(kind, QtCore.QPointF(pos), QtCore.QPointF(widget.mapToGlobal(pos)),
                               button, buttons,
                               modifiers or QtCore.Qt.KeyboardModifier.NoModifier)
        QtWidgets.QApplication.sendEvent(widget, ev)

    def stroke(self, cells, modifiers=None, button=None, move_ms: int = 15) -> None:
        """A drag through cells (x, y): press, a move per cell (spaced as a hand spaces them:
        pyqtgraph drops faster moves), release."""
        from PySide6 import QtCore, QtTest
        Type, none = QtCore.QEvent.Type, QtCore.Qt.MouseButton.NoButton
        button = button or QtCore.Qt.MouseButton.LeftButton
        QtTest.QTest.qWait(30)              # a tool change may have moved the view
        self._send(Type.MouseButtonPress, cells[0], button, button, modifiers)
        for cell in cells[1:]:
            QtTest.QTest.qWait(move_ms)
            self._send(Type.MouseMove, cell, none, button, modifiers)
        self._send(Type.MouseButtonRelease, cells[-1], button, none, modifiers)
        QtTest.QTest.qWait(5)

    def click(self, cell, modifiers=None) -> None:
        from PySide6 import QtCore, QtTest
        QtTest.QTest.qWait(30)
        QtTest.QTest.mouseClick(self.canvas.viewport(), QtCore.Qt.MouseButton.LeftButton,
                                modifiers or QtCore.Qt.KeyboardModifier.NoModifier, self.pos(cell))
        QtTest.QTest.qWait(5)

    def wheel(self, cell, notches: int) -> None:
        from .support import wheel
        wheel(self.canvas.viewport(), self.pos(cell), notches)

    def level_at(self, cell) -> int:
        x, y = cell
        return int(self.win.document.levels[y, x])

    # -- docks and dialogs -------------------------------------------------------------------------
    def button(self, widget) -> None:
        from PySide6 import QtCore, QtTest
        assert widget.isVisible() and widget.isEnabled(), f"{widget.text()!r} cannot be clicked"
        QtTest.QTest.mouseClick(widget, QtCore.Qt.MouseButton.LeftButton)
        QtTest.QTest.qWait(5)

    def swatch(self, level: int) -> None:
        """Click a palette swatch: the current level."""
        from PySide6 import QtCore, QtTest
        bar = self.win.palette_dock.swatches
        QtTest.QTest.mouseClick(bar, QtCore.Qt.MouseButton.LeftButton,
                                QtCore.Qt.KeyboardModifier.NoModifier,
                                bar.swatch_rect(level).center())
        assert self.win.current_level == level, f"swatch {level} was not selected"

    def history_row(self, step: int) -> None:
        """Click a step (0-based) in the History list."""
        from PySide6 import QtCore, QtTest
        dock = self.win.history_dock
        dock.view.scrollTo(dock.model.index(step))
        QtTest.QTest.mouseClick(dock.view.viewport(), QtCore.Qt.MouseButton.LeftButton,
                                QtCore.Qt.KeyboardModifier.NoModifier, dock.row_rect(step).center())

    def wait_idle(self, seconds: float = 60) -> None:
        """Wait for the worker (synthesis, replay, a large scatter) as a user would."""
        from PySide6 import QtTest
        for _ in range(int(seconds * 50)):
            if not self.win.runner.busy:
                QtTest.QTest.qWait(5)
                return
            QtTest.QTest.qWait(20)
        raise AssertionError(f"the worker was still busy after {seconds} s")


def report(**fields) -> None:
    print("REPORT " + json.dumps(fields), flush=True)


def main(argv: list[str]) -> int:
    isolate()
    kind = argv[0] if argv else ""
    if kind == "session" and len(argv) == 2:
        from .sessions import run_session
        return run_session(argv[1])
    if kind == "monkey" and len(argv) >= 2:
        from .monkey import run_monkey
        rest = argv[2:]
        models, photo = "--models" in rest, "--photo" in rest
        events = int(rest[rest.index("--events") + 1]) if "--events" in rest else 320
        return run_monkey(int(argv[1]), events, models, photo, "--menus" in rest)
    if kind == "start" and len(argv) >= 2:
        from .monkey import run_start_walk
        rest = argv[2:]
        return run_start_walk(int(argv[1]),
                              int(rest[rest.index("--events") + 1]) if "--events" in rest else 60)
    if kind == "crash":                  # for the runner's own test: a segfault, as Qt's was
        import faulthandler
        faulthandler._sigsegv()
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
