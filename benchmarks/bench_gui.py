"""GUI responsiveness and start-up: prints figures, passes or fails nothing.

1. Start-up in a fresh interpreter, offscreen: seconds to the window shown, to the start-up
   texture on the canvas, and to the numba kernels ready (compiled or loaded in the background),
   with the longest stall of the GUI event loop meanwhile.
   - first start: an empty NUMBA_CACHE_DIR and an empty bank and data folder (a fresh install);
   - warm start: numba's cache and a prepared bank kept from the previous run.
2. Event-loop gaps: a 10 ms QTimer ticks on the GUI thread while a 2048² synthesis runs in the
   worker and its result is applied; the longest gap between ticks is how long the window froze.

    QT_QPA_PLATFORM=offscreen python3 benchmarks/bench_gui.py [--size 2048] [--runs 3]
        [--first-runs 1] [--start-only]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

CHILD = r"""
import sys, time
t0 = float(sys.argv[1])
from PySide6 import QtCore, QtWidgets
app = QtWidgets.QApplication([])
from app.main_window import MainWindow
from texeditor import warmup
w = MainWindow()
w.show()
w.start_default()
app.processEvents()
shown = time.time() - t0
textured = ready = None
last, stall = time.perf_counter(), 0.0
deadline = time.time() + 300
while (textured is None or ready is None or w.runner.busy) and time.time() < deadline:
    app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 20)
    now = time.perf_counter()
    stall, last = max(stall, now - last), now
    if textured is None and w.canvas.levels is not None and w.canvas.levels.size:
        textured = time.time() - t0
    if ready is None and (warmup.ready() or not warmup.started()):
        ready = time.time() - t0
    time.sleep(0.005)
print(f"{shown:.3f} {textured:.3f} {ready:.3f} {1000 * stall:.0f}")
w.mark_clean()
w.close()
"""


def start_up(runs: int, *, fresh: bool, folder: Path) -> list[tuple[float, ...]]:
    """(window shown, texture on the canvas, kernels ready, longest GUI stall ms) per run.
    ``fresh``: every run with an empty numba cache, bank and data folder; else all runs share
    ``folder``'s bank and numba's own cache (warm after a first run)."""
    # a user's Python keeps the bytecode of what it imported, as numba keeps its kernels: a
    # PYTHONDONTWRITEBYTECODE inherited from a CI shell would recompile every module each start
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(ROOT)
    out = []
    for k in range(runs):
        home = folder / (f"fresh{k}" if fresh else "warm")
        env.update(TEXEDITOR_BANK=str(home / "bank.sqlite"), TEXEDITOR_DATA=str(home / "data"))
        if fresh:
            env["NUMBA_CACHE_DIR"] = str(home / "numba")
        t0 = time.time()
        res = subprocess.run([sys.executable, "-c", CHILD, repr(t0)], cwd=ROOT, env=env,
                             capture_output=True, text=True, check=True)
        out.append(tuple(float(x) for x in res.stdout.split()[-4:]))
    return out


def event_loop_gaps(size: int) -> dict:
    sys.path.insert(0, str(ROOT))
    from PySide6 import QtCore, QtWidgets

    from app.main_window import MainWindow
    from app.resources import default_dpj
    from texeditor.recipe.history import History

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    window = MainWindow()
    window.show()
    history = History()
    history.add_dpj(default_dpj())
    window.set_history(history)
    window.synthesis_dock.width_box.setValue(64)
    window.synthesis_dock.height_box.setValue(64)
    window.synthesise_from_dock()                  # warm the kernels outside the measurement
    window.runner.wait()

    ticks: list[float] = []
    timer = QtCore.QTimer()
    timer.setTimerType(QtCore.Qt.TimerType.PreciseTimer)
    timer.setInterval(10)
    timer.timeout.connect(lambda: ticks.append(time.perf_counter()))
    window.synthesis_dock.width_box.setValue(size)
    window.synthesis_dock.height_box.setValue(size)
    done = []
    window.runner.finished.connect(lambda: done.append(time.perf_counter()))
    timer.start()
    start = time.perf_counter()
    window.synthesise_from_dock()
    while not done:
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.WaitForMoreEvents, 50)
    end = time.perf_counter()
    for _ in range(30):                            # let the apply and the repaint run too
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.WaitForMoreEvents, 10)
    timer.stop()
    gaps = [b - a for a, b in zip([start] + ticks, ticks)]
    assert window.history.document.shape == (size, size)
    window.mark_clean()
    window.close()
    return {"synthesis_s": end - start, "ticks": len(ticks), "max_gap_ms": 1000 * max(gaps),
            "p99_gap_ms": 1000 * sorted(gaps)[int(0.99 * (len(gaps) - 1))]}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=2048)
    parser.add_argument("--runs", type=int, default=3, help="warm starts")
    parser.add_argument("--first-runs", type=int, default=1, help="first starts")
    parser.add_argument("--start-only", action="store_true", help="skip the 2048² synthesis")
    args = parser.parse_args(argv)

    with tempfile.TemporaryDirectory() as tmp:
        first = start_up(args.first_runs, fresh=True, folder=Path(tmp))
        warm = start_up(args.runs + 1, fresh=False, folder=Path(tmp))[1:]
    for what, runs, target in (("first start (empty numba cache, bank and data)", first, 5),
                               ("warm start", warm, 2)):
        for k, (shown, textured, ready, stall) in enumerate(runs, 1):
            print(f"{what}, run {k}: window shown {shown:.2f} s; texture on the canvas "
                  f"{textured:.2f} s (target ≤ {target} s); kernels ready {ready:.2f} s; "
                  f"longest GUI stall {stall:.0f} ms")
    if args.start_only:
        return 0
    gaps = event_loop_gaps(args.size)
    print(f"{args.size}² synthesis in the worker: {gaps['synthesis_s']:.2f} s; GUI timer (10 ms) "
          f"ticked {gaps['ticks']} times; longest gap {gaps['max_gap_ms']:.0f} ms (target ≤ 100), "
          f"99th percentile {gaps['p99_gap_ms']:.0f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
