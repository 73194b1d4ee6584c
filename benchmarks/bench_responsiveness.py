"""Responsiveness under load (issue 11): the GUI's event loop while heavy work runs in the worker.

A 10 ms timer ticks on the GUI thread while the window's TaskRunner runs, one after another:
a 2048² synthesis, a verify of the bank (every entry replayed), and a 1,000-action replay. The
longest gap between ticks is how long the window froze (target ≤ 100 ms). The same is measured
through the window's own paths: an edit of step 1 of that log at 512² (click the step, new seed,
Apply & replay, until the new document is in), File ▸ Acquire on a 3000×2000 photo (read,
quantise, count, until the result is shown), the same photo pasted (Edit ▸ Paste as photo),
learnt by Image ▸ Double the levels… and taken as colour plates. Then Cancel: a 4096² synthesis is cancelled after
0.3 s, and the time until the runner reports it stopped is measured (target ≤ 200 ms). Last,
fills on a 2048² texture shown with a photo's tone (gravel, plain and tileable): the stall with
the tone drawn on a thread (the default for a million points or more) and drawn on the GUI
thread. Prints figures; passes or fails nothing.

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

    from texeditor.recipe.actions import SetLevels, SetPalette, Synthesize
    from texeditor.markov.dpj import DPJ
    from texeditor.regions.actions import Copy, Fill
    from texeditor.resources import bundled_dpj

    dpj = DPJ.load(bundled_dpj())
    from texeditor.recipe.document import dpj_ref
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


def stall(app, begin, finished) -> tuple[float, float]:
    """Call ``begin()``, then run the event loop until ``finished()``, a 10 ms GUI timer
    ticking: (seconds, longest gap in ms, the work done on the GUI thread at either end too)."""
    from PySide6 import QtCore

    ticks: list[float] = []
    timer = QtCore.QTimer()
    timer.setTimerType(QtCore.Qt.TimerType.PreciseTimer)
    timer.setInterval(10)
    timer.timeout.connect(lambda: ticks.append(time.perf_counter()))
    timer.start()
    start = time.perf_counter()
    begin()
    while not finished():
        app.processEvents(QtCore.QEventLoop.ProcessEventsFlag.WaitForMoreEvents, 20)
    end = time.perf_counter()
    timer.stop()
    gaps = [b - a for a, b in zip([start] + ticks, ticks + [end])]
    return end - start, 1000 * max(gaps)


def measure(app, window, label: str, work) -> tuple[float, float]:
    """Run work in the window's runner: (seconds, longest GUI stall in ms)."""
    done: list[bool] = []
    return stall(app, lambda: window.runner.run(label, work, lambda _result: done.append(True),
                                                on_error=lambda exc: done.append(True)),
                 lambda: bool(done))


def edit_step_one(app, window, actions, dpjs) -> tuple[float, float]:
    """Click step 1 of the log, give it a new seed, Apply & replay: until the new document is in."""
    from texeditor.recipe.actions import replace_params
    from texeditor.recipe.history import History

    window.set_history(History.from_log(actions, dpjs))

    def begin():
        window.goto_step(1)
        window.edit_step(0, replace_params(actions[0], seed=4))
    seconds, gap = stall(app, begin, lambda: not window.runner.busy)
    assert window.history.actions[0].seed == 4 and window.history.index == len(actions)
    return seconds, gap


def photo(folder: Path) -> Path:
    """A 3000×2000 JPEG with a photo's detail (the astronaut enlarged, with grain)."""
    import numpy as np
    from skimage import data, transform
    from PIL import Image

    rng = np.random.default_rng(0)
    image = transform.resize(data.astronaut(), (2000, 3000), order=1) * 255
    image = np.clip(image + rng.normal(0, 12, image.shape), 0, 255).astype(np.uint8)
    path = folder / "photo-3000x2000.jpg"
    Image.fromarray(image).save(path, quality=90)
    return path


def acquisition(app, window, path: Path) -> tuple[float, float]:
    """File ▸ Acquire on a large photo: choose it, until its DPJ is shown."""
    from app.acquire_dialog import AcquireDialog

    dialog = AcquireDialog([], window)
    dialog.show()
    seconds, gap = stall(app, lambda: dialog.set_image_path(path),
                         lambda: dialog.dpj is not None)
    dialog.reject()
    return seconds, gap


def doubling(app, window, path: Path) -> tuple[float, float]:
    """Image ▸ Double the levels… learning from a large photo: choose it, until Double is
    enabled."""
    from app.doubling_dialog import DoublingDialog

    dialog = DoublingDialog(window)
    dialog.show()
    dialog.wait()                                   # the bundled photo's first
    seconds, gap = stall(app, lambda: dialog.set_photo(path),
                         lambda: dialog.apply_button.isEnabled())
    dialog.reject()
    return seconds, gap


def plates(app, window, path: Path) -> tuple[float, float]:
    """Colour plates from a large photo, until the step is in."""
    steps = len(window.history.applied)
    seconds, gap = stall(app, lambda: window.plates_from_photo(4, 0.02, path),
                         lambda: not window.runner.busy and len(window.history.applied) > steps)
    window.act_undo.trigger()
    return seconds, gap


def paste(app, window, path: Path) -> tuple[float, float]:
    """Edit ▸ Paste as photo of the large photo on the clipboard, until its DPJ is shown."""
    from PySide6 import QtGui, QtWidgets

    QtWidgets.QApplication.clipboard().setImage(QtGui.QImage(str(path)))
    dialogs = []
    seconds, gap = stall(app, lambda: dialogs.append(window.paste_photo()),
                         lambda: dialogs and dialogs[0].dpj is not None)
    dialogs[0].reject()
    return seconds, gap


def cancel_latency(app, window) -> float:
    from PySide6 import QtCore

    from texeditor.markov.dpj import DPJ
    from texeditor.resources import bundled_dpj
    from texeditor.markov.synthesis import synthesize

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


def toned_fills(app, window, tileable: bool, background: bool) -> list[tuple[float, float]]:
    """A 2048² texture from gravel's photo model, shown with its tone; then fills near the
    bottom, the middle and the top: (seconds until the new tone is shown, longest stall)."""
    import numpy as np
    from skimage import data

    from texeditor.photo import acquire_model
    from texeditor.recipe.history import History
    from texeditor.regions.actions import Fill

    window.set_history(History())
    window.TONE_IN_BACKGROUND = 1 << 20 if background else 1 << 62
    window.attach_model(acquire_model(data.gravel()))
    dock = window.synthesis_dock
    dock.width_box.setValue(2048)
    dock.height_box.setValue(2048)
    dock.seed.set_value(3)
    dock.tileable_box.setChecked(tileable)
    stall(app, dock.button.click, lambda: not window.runner.busy and not window._tone_drawing)
    assert window.document.shape == (2048, 2048) and window.canvas.picture is not None
    out = []
    for row in (1900, 1024, 40):
        doc = window.document
        value = (int(doc.levels[row, 100]) + 1) % doc.num_levels

        def shown():
            cached = window._tone_cache
            return not window._tone_drawing and cached is not None and np.array_equal(
                cached[2].levels, window.document.levels)
        out.append(stall(app, lambda: window.submit(Fill(row=row, col=100, value=value)), shown))
    window.mark_clean()
    return out


def main() -> int:
    from PySide6 import QtWidgets

    from app.main_window import MainWindow
    from texeditor.bank.store import Bank
    from texeditor.markov.dpj import DPJ
    from texeditor.recipe.history import History
    from texeditor.resources import bundled_dpj
    from texeditor.markov.synthesis import synthesize

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
        for label, run in (("edit step 1 of 1,000 and replay", lambda: edit_step_one(
                                app, window, actions, dpjs)),
                           ("acquire a 3000×2000 photo", lambda: acquisition(
                                app, window, photo(Path(folder)))),
                           ("paste a 3000×2000 photo", lambda: paste(
                                app, window, photo(Path(folder)))),
                           ("double levels from 3000×2000", lambda: doubling(
                                app, window, photo(Path(folder)))),
                           ("plates from a 3000×2000 photo", lambda: plates(
                                app, window, photo(Path(folder))))):
            seconds, gap = run()
            print(f"{label:32s} {seconds:6.2f} s until done;   longest GUI stall "
                  f"{gap:5.0f} ms (target ≤ 100)")
    print(f"Cancel of a 4096² synthesis: stopped {cancel_latency(app, window):.0f} ms after the "
          f"request (target ≤ 200)")
    for tileable in (False, True):
        for background in (True, False):
            figures = toned_fills(app, window, tileable, background)
            where = "on a thread" if background else "on the GUI thread"
            print(f"fill on a toned 2048² {'tileable ' if tileable else ''}texture, tone {where}: "
                  + ", ".join(f"row {r}: {s:.2f} s, stall {g:.0f} ms"
                              for r, (s, g) in zip((1900, 1024, 40), figures)))
    window.mark_clean()
    window.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
