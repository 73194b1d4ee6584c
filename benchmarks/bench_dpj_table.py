"""The DPJ editor with a 200k-entry DPJ: how long the GUI thread is blocked by scrolling, sorting,
filtering and editing the table of configurations (target: never more than 100 ms).

    QT_QPA_PLATFORM=offscreen python3 benchmarks/bench_dpj_table.py [--entries 200000]

Each step is timed from the event that causes it to a finished synchronous repaint of the view.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

import numpy as np  # noqa: E402
from PySide6 import QtCore, QtGui, QtWidgets  # noqa: E402

TARGET_MS = 100.0
CTRL = QtCore.Qt.KeyboardModifier.ControlModifier


def timed(app, fn) -> float:
    """Milliseconds for fn() plus the events it posts and a synchronous repaint."""
    t0 = time.perf_counter()
    fn()
    app.processEvents()
    return (time.perf_counter() - t0) * 1000


def line(name: str, samples: list[float]) -> float:
    worst = max(samples)
    print(f"  {name:<38} median {statistics.median(samples):7.1f} ms   worst {worst:7.1f} ms"
          f"   ({len(samples)} steps){'   OVER' if worst > TARGET_MS else ''}")
    return worst


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--entries", type=int, default=200_000)
    args = parser.parse_args(argv)

    from app.dpj_editor import DPJEditor
    from app.dpj_editor.table import CHAIN, CONFIG, PROB, SHARE
    from texeditor.markov import dpj_edit

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    total = 4 ** 9
    t0 = time.perf_counter()
    dpj = dpj_edit.random_dpj((3, 3), 4, seed=1, sparsity=1 - args.entries / total)
    print(f"DPJ 3×3, G = 4: {len(dpj):,} entries (drawn in {time.perf_counter() - t0:.2f} s)")

    editor = DPJEditor()
    editor.resize(1400, 900)
    editor.show()
    app.processEvents()
    view = editor.table.view
    repaint = view.viewport().repaint
    worst = []

    print("GUI-thread time per step (event → repainted view):")
    load = timed(app, lambda: (editor.start(dpj, "load"), repaint()))
    print(f"  {'show the DPJ (table, checks, charts)':<38} {load:7.1f} ms (once, on opening)")
    editor.preview.preview.wait(60_000)

    bar = view.verticalScrollBar()
    rng = np.random.default_rng(0)
    steps = []
    for _ in range(30):                                     # wheel notches, page by page
        steps.append(timed(app, lambda: (QtWidgets.QApplication.sendEvent(
            view.viewport(), _wheel(view.viewport(), -3)), repaint())))
    worst.append(line("scroll: wheel, 3 notches", steps))
    steps = [timed(app, lambda: (bar.setValue(int(rng.integers(0, bar.maximum()))), repaint()))
             for _ in range(30)]
    worst.append(line("scroll: jump anywhere (scroll bar)", steps))
    view.setFocus()
    steps = [timed(app, lambda: (_key(view, QtCore.Qt.Key.Key_PageDown), repaint()))
             for _ in range(30)]
    worst.append(line("scroll: Page Down", steps))

    header = view.horizontalHeader()
    steps = []
    for column in (PROB, CONFIG, SHARE, CHAIN, PROB):
        for _ in range(2):                                 # a click per order
            x = header.sectionViewportPosition(column) + 10
            steps.append(timed(app, lambda: (_click(header.viewport(), QtCore.QPoint(x, 5)),
                                             repaint())))
    worst.append(line("sort: header click (4 columns × 2)", steps))

    table = editor.table
    steps = []
    for level in range(4):
        table._level_buttons[level].setChecked(True)
        steps.append(timed(app, lambda: (table.apply_filter(), repaint())))
    table.mode.setCurrentIndex(1)
    steps.append(timed(app, lambda: (table.apply_filter(), repaint())))
    table.pmin.setText("5e-6")
    steps.append(timed(app, lambda: (table.apply_filter(), repaint())))
    steps.append(timed(app, lambda: (table.clear_filter(), repaint())))
    worst.append(line("filter: levels, mode, probability", steps))

    steps = []
    for k in range(5):
        rect = view.visualRect(table.proxy.index(k, CONFIG))
        steps.append(timed(app, lambda: (_click(view.viewport(), rect.center()), repaint())))
    worst.append(line("select a row (painter loads it)", steps))
    view.setFocus()
    steps = [timed(app, lambda: (_key(view, QtCore.Qt.Key.Key_A, CTRL), repaint(),
                                 table.selected_codes()))]
    worst.append(line("select all (Ctrl+A) and read it", steps))
    view.clearSelection()

    code = int(dpj.codes[7])
    steps = [timed(app, lambda: (editor._set_code(code, 1e-6 * (k + 1)), repaint()))
             for k in range(5)]
    worst.append(line("edit one probability (whole refresh)", steps))
    steps = [timed(app, lambda: (editor.undo_stack.undo(), repaint())) for _ in range(3)]
    worst.append(line("undo an edit", steps))

    t0 = time.perf_counter()
    dpj_edit.make_stationary(dpj)
    print(f"  {'make stationary (worker thread)':<38} {(time.perf_counter() - t0) * 1000:7.0f} ms")
    editor.preview.preview.stop()

    over = max(worst) > TARGET_MS
    print(f"scrolling, sorting, filtering, selecting and editing: worst {max(worst):.1f} ms — "
          f"{'above' if over else 'within'} the {TARGET_MS:.0f} ms target")
    return 0


def _wheel(widget, notches: int) -> QtGui.QWheelEvent:
    pos = QtCore.QPointF(widget.rect().center())
    return QtGui.QWheelEvent(pos, QtCore.QPointF(widget.mapToGlobal(pos.toPoint())),
                             QtCore.QPoint(0, 0), QtCore.QPoint(0, 120 * notches),
                             QtCore.Qt.MouseButton.NoButton, QtCore.Qt.KeyboardModifier.NoModifier,
                             QtCore.Qt.ScrollPhase.NoScrollPhase, False)


def _click(widget, pos: QtCore.QPoint) -> None:
    from PySide6.QtTest import QTest
    QTest.mouseClick(widget, QtCore.Qt.MouseButton.LeftButton,
                     QtCore.Qt.KeyboardModifier.NoModifier, pos)


def _key(widget, key, modifier=QtCore.Qt.KeyboardModifier.NoModifier) -> None:
    from PySide6.QtTest import QTest
    QTest.keyClick(widget, key, modifier)


if __name__ == "__main__":
    sys.exit(main())
