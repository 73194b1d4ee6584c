"""The live preview of a DPJ being edited: a small synthesis redrawn in the background after every
change, debounced, the latest change winning.

It sits beside the editor, off the GUI thread: each change restarts a short timer; when it fires
one synthesis starts (a running one is told to stop, and only the newest waiting DPJ is kept, so
work never piles up); a result older than the latest change is dropped.
"""

from __future__ import annotations

import time

import shiboken6
from PySide6 import QtCore, QtWidgets

from texeditor.errors import TexeditorError
from texeditor.markov.synthesis import synthesize

from ..canvas import colourize
from ..params_form import SeedEdit
from ..images import pixmap
from ..synthesis_worker import Job

PREVIEW_SIZE = 128
DEBOUNCE_MS = 250
SHOWN = 256             # screen pixels of the preview (each point 2×2)


class LatestWins(QtCore.QObject):
    """Background work where only the latest request matters: ``request(work)`` restarts a short
    timer, a running job is told to stop, only the newest waiting request is kept (no queue),
    and a result older than the latest request is dropped. ``done(result)`` / ``failed(exc)``
    carry the newest outcome, ``progress(fraction)`` the newest job's progress;
    ``work(progress, cancel)`` runs in a one-thread pool."""

    done = QtCore.Signal(object)
    failed = QtCore.Signal(object)
    progress = QtCore.Signal(float)

    def __init__(self, parent=None, delay_ms: int = DEBOUNCE_MS):
        super().__init__(parent)
        self.pool = QtCore.QThreadPool(self)
        self.pool.setMaxThreadCount(1)
        self.timer = QtCore.QTimer(self, singleShot=True, interval=delay_ms)
        self.timer.timeout.connect(self._start)
        self.job: Job | None = None
        self.pending = None           # (generation, work): only the newest is kept
        self.generation = 0           # of the latest request
        self.shown = 0                # generation of the last outcome delivered
        self.started = 0              # jobs actually started (the debounce at work)

    def request(self, work) -> None:
        self.generation += 1
        self.pending = (self.generation, work)
        if self.job is not None:
            self.job.cancel()         # the latest change wins
        self.timer.start()

    def drop(self) -> None:
        """Forget every request: a result still coming is not delivered."""
        self.generation += 1
        self.pending = None
        self.timer.stop()
        if self.job is not None:
            self.job.cancel()

    def _start(self) -> None:
        if self.job is not None or self.pending is None:
            return                    # started again when the running job ends
        generation, work = self.pending
        self.pending = None
        job = self.job = Job(work)
        job.signals.done.connect(lambda out: self._finished(job, generation, out, False))
        job.signals.failed.connect(lambda exc: self._finished(job, generation, exc, True))
        job.signals.cancelled.connect(lambda: self._finished(job, generation, None, False))
        job.signals.progress.connect(lambda f: self._progressed(generation, f))
        self.started += 1
        self.pool.start(job)

    def _progressed(self, generation, fraction: float) -> None:
        if shiboken6.isValid(self) and generation == self.generation:
            self.progress.emit(fraction)

    def _finished(self, job, generation, outcome, failed: bool) -> None:
        if not shiboken6.isValid(self):
            return               # the editor closed meanwhile: nobody is left to tell
        if self.job is job:
            self.job = None
        if generation == self.generation and (outcome is not None or failed):
            self.shown = generation
            (self.failed if failed else self.done).emit(outcome)
        if self.pending is not None and not self.timer.isActive():
            self._start()

    @property
    def current(self) -> bool:
        return self.shown == self.generation

    def wait(self, timeout_ms: int = 30_000) -> bool:
        """Block until the latest request is delivered (tests and scripts only)."""
        deadline = time.perf_counter() + timeout_ms / 1000
        while not self.current and time.perf_counter() < deadline:
            self.pool.waitForDone(10)
            QtCore.QCoreApplication.processEvents(QtCore.QEventLoop.ProcessEventsFlag.AllEvents, 10)
        return self.current

    def stop(self) -> None:
        self.timer.stop()
        self.pending = None
        if self.job is not None:
            self.job.cancel()
        self.pool.waitForDone(10_000)


class LivePreview(LatestWins):
    """A small synthesis of the latest DPJ: ``ready(levels, palette, seconds, repairs)`` or
    ``unusable(message)``."""

    ready = QtCore.Signal(object, object, float, int)
    unusable = QtCore.Signal(str)

    def __init__(self, parent=None, size: int = PREVIEW_SIZE, delay_ms: int = DEBOUNCE_MS):
        super().__init__(parent, delay_ms)
        self.preview_size = size
        self.done.connect(lambda out: self.ready.emit(*out))
        self.failed.connect(lambda exc: self.unusable.emit(
            str(exc) if isinstance(exc, TexeditorError) else repr(exc)))

    def request_dpj(self, dpj, seed: int) -> None:
        size = self.preview_size

        def work(progress, cancel):
            t0 = time.perf_counter()
            result = synthesize(dpj, (size, size), seed=seed, progress=progress, cancel=cancel)
            return result.levels, dpj.palette, time.perf_counter() - t0, result.repairs
        self.request(work)


class PreviewPanel(QtWidgets.QWidget):
    """The preview image, its seed, what it cost, and the buttons that leave the editor."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.preview = LivePreview(self)
        self.levels = None
        self.image = QtWidgets.QLabel()
        self.image.setFixedSize(SHOWN, SHOWN)
        self.image.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.image.setStyleSheet("background: #2b2b2b; color: #bbbbbb;")
        self.image.setWordWrap(True)
        self.seed = SeedEdit(7)
        self.seed.setToolTip("Seed of the preview: same seed, same picture")
        self.status = QtWidgets.QLabel()
        self.status.setWordWrap(True)
        self.use_button = QtWidgets.QPushButton("Use this DPJ")
        self.use_button.setToolTip("Make it the main window's current DPJ (Synthesis dock)")
        self.full_button = QtWidgets.QPushButton("Synthesise full size")
        self.full_button.setToolTip("Use this DPJ and synthesise at the Synthesis dock's size")
        self.preview.ready.connect(self._show)
        self.preview.unusable.connect(self._show_failure)
        layout = QtWidgets.QVBoxLayout(self)
        centre = QtWidgets.QHBoxLayout()
        centre.addStretch(1)
        centre.addWidget(self.image)
        centre.addStretch(1)
        layout.addLayout(centre)
        form = QtWidgets.QFormLayout()
        form.addRow("Preview seed", self.seed)
        layout.addLayout(form)
        layout.addWidget(self.status)
        buttons = QtWidgets.QHBoxLayout()
        buttons.addWidget(self.use_button)
        buttons.addWidget(self.full_button)
        layout.addLayout(buttons)
        layout.addStretch(1)

    def request(self, dpj) -> None:
        self.status.setText("Synthesising a preview…")
        self.preview.request_dpj(dpj, self.seed.value())

    def _show(self, levels, palette, seconds: float, repairs: int) -> None:
        self.levels = levels
        self.image.setPixmap(pixmap(colourize(levels, palette), SHOWN))
        n = self.preview.preview_size
        self.status.setText(f"{n}×{n} in {seconds * 1000:.0f} ms"
                            + (f", {repairs:,} repairs (dead ends)" if repairs else ""))

    def _show_failure(self, message: str) -> None:
        self.levels = None
        self.image.clear()
        self.image.setText("no preview")
        self.status.setText(message)
