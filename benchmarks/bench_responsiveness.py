"""Responsiveness under load (issue 11): the GUI's event loop while heavy work runs in the worker.

A 10 ms timer ticks on the GUI thread while the window's TaskRunner runs, one after another:
a 2048² synthesis, a verify of the bank (every entry replayed), and a 1,000-action replay. The
longest gap between ticks is how long the window froze (target ≤ 100 ms). Then Cancel: a 4096²
synthesis is cancelled after 0.3 s, and the time until the runner reports it stopped is measured
(target ≤ 200 ms). Prints figures; passes or fails nothing.

    QT_QPA_PLATFORM=offscreen python3 benchmarks/bench_responsiveness.py
"""

from __future__ import annotations

import os
import platform
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")


def replay_log(n: int):
    """1,000 mixed actions: a synthesis, then fills and copies of regions, level edits, palettes."""
    import numpy as np

    from texeditor.actions import SetLevels, SetPalette, Synthesize
    from texeditor.dpj import DPJ
    from texeditor.region_actions import Copy, Fill
    from texeditor.resources import bundled_dpj

    dpj = DPJ.load(bundled_dpj())
    from texeditor.document import dpj_ref
    ref = dpj_ref(dpj)
    rng = np.random.default_rng(7)
    actions = [Synthesize(ref, 512, 512, 3)]
    for k in range(n - 1):
        r, c = (int(x) for x in rng.integers(0, 500, 2))
        kind = k % 4
        if kind == 0:
            actions.append(SetLevels(r, c, 8, 8, int(rng.integers(0, 4))))
        elif kind == 1:
            actions.append(Fill(r, c, int(rng.integers(0, 4))))
        elif kind == 2:
            actions.append(Copy(r, c, int(rng.integers(0, 500)), int(rng.integers(0, 500))))
        else:
            actions.append(SetPalette(tuple((g, g, g) for g in sorted(rng.integers(0, 256, 4)))))
    return actions, {ref: dpj}


def measure(app, window, label: str, work) -> tuple[float, float]:
    """Run work in the window's runner with a 10 ms GUI timer ticking: (seconds, longest gap)."""
    from PySide6 import QtCore

    ticks: list[float] = []
    timer = QtCore.QTimer()
    timer.setTimerType(QtCore.Qt.TimerType.PreciseTimer)
    timer.setInterval(10)
    timer.timeout.connect(lambda: ticks.append(time.perf_counter()))
    done: list[float] = []
    timer.start()
    start = time.perf_counter()
    window.runner.run(label, work, lambda _result: done.append(time.perf_counter()),
                      on_error=lambda exc: done.append(time.perf_counter()))
    while not done:
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.WaitForMoreEvents, 20)
    timer.stop()
    gaps = [b - a for a, b in zip([start] + ticks, ticks)]
    return done[0] - start, 1000 * max(gaps)


def cancel_latency(app, window) -> float:
    from PySide6 import QtCore

    from texeditor.dpj import DPJ
    from texeditor.resources import bundled_dpj
    from texeditor.synthesis import synthesize

    dpj = DPJ.load(bundled_dpj())
    stopped: list[float] = []
    window.runner.run("long synthesis",
                      lambda progress, cancel: synthesize(dpj, (4096, 4096), seed=1,
                                                          progress=progress, cancel=cancel),
                      lambda _r: stopped.append(time.perf_counter()),
                      on_cancel=lambda: stopped.append(time.perf_counter()))
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < 0.3:
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 10)
    asked = time.perf_counter()
    window.runner.cancel()
    while not stopped:
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.WaitForMoreEvents, 5)
    return 1000 * (stopped[0] - asked)


def main() -> int:
    from PySide6 import QtWidgets

    from app.main_window import MainWindow
    from texeditor.bank import Bank
    from texeditor.dpj import DPJ
    from texeditor.history import History
    from texeditor.resources import bundled_dpj
    from texeditor.synthesis import synthesize

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    window = MainWindow()
    window.show()
    window.set_history(History())
    dpj = DPJ.load(bundled_dpj())
    synthesize(dpj, (64, 64))                       # load the numba cache outside the timing
    actions, dpjs = replay_log(1000)
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python "
          f"{platform.python_version()}; GUI offscreen, 10 ms timer on the GUI thread")
    with tempfile.TemporaryDirectory() as folder:
        bank = Bank(Path(folder) / "bank.sqlite")    # with the built-in entries
        jobs = [
            ("2048² synthesis", lambda p, c: synthesize(dpj, (2048, 2048), seed=2, progress=p,
                                                        cancel=c)),
            (f"bank verify ({bank.count()} entries)", lambda p, c: bank.verify(progress=p,
                                                                               cancel=c)),
            ("1,000-action replay (512²)", lambda p, c: History.from_log(actions, dpjs,
                                                                         progress=p, cancel=c)),
        ]
        for label, work in jobs:
            seconds, gap = measure(app, window, label, work)
            print(f"{label:32s} {seconds:6.2f} s in the worker; longest GUI stall "
                  f"{gap:5.0f} ms (target ≤ 100)")
        bank.close()
    print(f"Cancel of a 4096² synthesis: stopped {cancel_latency(app, window):.0f} ms after the "
          f"request (target ≤ 200)")
    window.mark_clean()
    window.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
