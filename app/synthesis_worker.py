"""Long work off the GUI thread: a cancellable job in a thread pool that reports back through signals.

Synthesis, replay and file loading run here so the window never freezes. A job only *computes*
(it never touches the Document); its result is applied as an Action on the GUI thread.
"""

from __future__ import annotations

import threading
import time
from typing import Any, Callable

import shiboken6
from PySide6 import QtCore

from texeditor.errors import Cancelled

Work = Callable[[Callable[[float], None], Callable[[], bool]], Any]


class JobSignals(QtCore.QObject):
    """Created on the GUI thread, so emits from the pool thread arrive queued on the GUI thread."""

    progress = QtCore.Signal(float)
    done = QtCore.Signal(object)
    failed = QtCore.Signal(object)
    cancelled = QtCore.Signal()


class Job(QtCore.QRunnable):
    """Runs ``work(progress, cancel)`` once; the outcome is exactly one of done/failed/cancelled."""

    def __init__(self, work: Work):
        super().__init__()
        self.setAutoDelete(False)
        self.work = work
        self.signals = JobSignals()
        self._cancel = threading.Event()
        self._last_progress = 0.0

    def cancel(self) -> None:
        self._cancel.set()

    def is_cancelled(self) -> bool:
        return self._cancel.is_set()

    def _progress(self, fraction: float) -> None:
        now = time.perf_counter()    # at most ~30 updates a second reach the event loop
        if fraction >= 1.0 or now - self._last_progress > 0.03:
            self._last_progress = now
            self._emit(self.signals.progress, float(fraction))

    def run(self) -> None:
        try:
            result = self.work(self._progress, self.is_cancelled)
        except Cancelled:
            self._emit(self.signals.cancelled)
            return
        except Exception as exc:  # reported to the user as a dialog, never a crash
            self._emit(self.signals.failed, exc)
            return
        if self.is_cancelled():
            self._emit(self.signals.cancelled)
        else:
            self._emit(self.signals.done, result)

    @staticmethod
    def _emit(signal, *args) -> None:
        """Report the outcome; when the window that asked has closed meanwhile (its signals
        deleted), nobody is left to tell, and the pool thread must not raise."""
        try:
            signal.emit(*args)
        except RuntimeError:
            pass


class TaskRunner(QtCore.QObject):
    """One long task at a time, with a label, progress and cancel, for the status bar to show."""

    started = QtCore.Signal(str)
    progress = QtCore.Signal(float)
    finished = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        self.pool = QtCore.QThreadPool(self)
        self.pool.setMaxThreadCount(1)
        self.job: Job | None = None
        self.label = ""

    @property
    def busy(self) -> bool:
        return self.job is not None

    def run(self, label: str, work: Work, on_done: Callable[[Any], None], *,
            on_cancel: Callable[[], None] | None = None,
            on_error: Callable[[Exception], None] | None = None) -> Job:
        """Start ``work`` in the pool; exactly one callback then runs on the GUI thread."""
        if self.job is not None:
            raise RuntimeError("a task is already running")
        job = Job(work)
        self.job, self.label = job, label

        def finish(callback, *args):
            if not shiboken6.isValid(self):
                return           # the window closed meanwhile: nobody is left to tell
            if self.job is job:
                self.job = None
                self.finished.emit()
            if callback is not None:
                callback(*args)

        job.signals.progress.connect(self.progress)
        job.signals.done.connect(lambda result: finish(on_done, result))
        job.signals.cancelled.connect(lambda: finish(on_cancel))
        job.signals.failed.connect(lambda exc: finish(on_error, exc))
        self.started.emit(label)
        self.pool.start(job)
        return job

    def cancel(self) -> None:
        if self.job is not None:
            self.job.cancel()

    def wait(self, timeout_ms: int = 60_000) -> bool:
        """Block until the task ends and its callback has run (scripts and tests only)."""
        deadline = time.perf_counter() + timeout_ms / 1000
        while self.job is not None and time.perf_counter() < deadline:
            self.pool.waitForDone(20)
            QtCore.QCoreApplication.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 20)
        return self.job is None


def render_synthesis(action, dpj, progress=None, cancel=None) -> tuple:
    """Synthesise for a Synthesize action in the worker: (levels, repairs). The GUI thread
    then applies these very levels (``History.apply(action, prepared=levels)``)."""
    result = action.render_result(dpj, progress=progress, cancel=cancel)
    return result.levels, result.repairs
