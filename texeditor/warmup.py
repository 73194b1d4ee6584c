"""The numba kernels compiled ahead of need, in a background thread.

A first start (an empty numba cache: a fresh install, a new numba or Python) compiles the
synthesis kernels for ~15-40 s (the tone's first, ~10 s), then the rest of a photo model's
(multi-scale: ~10 s more); with a warm cache, warming up only loads them (under a second). The
GUI calls ``start()`` as soon as its window shows, and shows a stored picture meanwhile
(`bank.Bank.open_stored`). Work in a worker thread that needs a kernel simply waits for numba's
compiler lock; work on the GUI thread must not, so the GUI asks ``pending()`` and
``needs_kernels(action, doc)`` and lets such a step wait in its worker for ``wait()``. The small
kernels the GUI thread itself calls (grain rendering for a preview, the canvas's mip levels)
compile first, in a second or two: ``pending("gui")`` says when they are not ready yet.

Nothing here imports Qt. Process-wide state: compiled kernels are the process's.
"""

from __future__ import annotations

import threading
import time
from typing import Callable

import numpy as np

_lock = threading.Lock()
_done = threading.Event()
_gui_done = threading.Event()      # the first stage: kernels the GUI thread calls
_tone_done = threading.Event()     # the second: the photographic tone's (the canvas draws a
                                   # tone off the GUI thread until then)
_photo_done = threading.Event()    # the last: the rest of a photo model's (multi-scale)
_first: list = []                  # more such kernels, from the application (no Qt here)
_thread: threading.Thread | None = None
_result: dict = {"seconds": None, "error": None}


def _compile() -> None:
    """Call every kernel once on tiny inputs of the types real work passes (so nothing compiles
    again later). First the small ones the GUI thread may call, then the tone's, then the
    synthesis."""
    from .texture import grain_render
    from .markov.balance import rebalance
    from .markov.dpj import DPJ
    from .markov.synthesis import synthesize

    grain_render.render(np.ones((2, 2), np.uint8), "square", 2)
    for kernel in _first:
        kernel()
    _gui_done.set()
    _tone()                 # (~10 s on a first start: the start entry soon shows its tone)
    _tone_done.set()
    dpj = DPJ.from_codes(np.arange(16), np.full(16, 1 / 16), 2, (2, 2))
    levels = synthesize(dpj, (8, 8), seed=0).levels
    rebalance(levels, dpj, [0.0, 1.0])        # shares far off: every kernel of it runs


def _tone() -> None:
    """The tone's kernels: a tiny colour picture drawn from itself, each way it may tile."""
    from .photo.tone import BALANCED, FINISHED, PLAIN, TILED, TILED_LANES, render

    ramp = np.add.outer(np.arange(24), np.arange(24))
    levels = (ramp % 4).astype(np.uint8)
    pixels = (np.stack([ramp * 5, ramp * 7, ramp * 11], axis=-1) % 256).astype(np.uint8)
    grey = pixels[..., 1].copy()
    for way in (PLAIN, TILED, TILED_LANES):
        render(levels, 4, levels, grey, pixels, seed=0, wrap=way | BALANCED | FINISHED)


def _photo_model() -> None:
    """The rest of a photo model's kernels (the scales drawn given their parents, steered,
    rebalanced): a tiny colour model acquired and drawn, plain and tiling."""
    from .photo import acquire_model

    ramp = np.add.outer(np.arange(48), np.arange(48)) * 5
    photo = np.stack([ramp % 256, ramp * 3 % 256, 255 - ramp % 256], axis=-1).astype(np.uint8)
    model = acquire_model(photo, scales=2)
    for tileable in (False, True):
        model.synthesize((32, 32), seed=0, tileable=tileable)


def warm_up(then: Callable[[], None] | None = None) -> float:
    """Compile (or load from numba's cache) every kernel; returns the seconds it took. A failure
    is kept in ``error()`` and never raised: a kernel then compiles when first used. ``then()``
    runs after the kernels are ready, in the same thread (its exceptions are kept too)."""
    start = time.perf_counter()
    try:
        _compile()
    except Exception as exc:          # noqa: BLE001 - reported, never fatal
        _result["error"] = exc
    finally:
        _result["seconds"] = time.perf_counter() - start
        _gui_done.set()
        _tone_done.set()
        _done.set()
    try:
        _photo_model()
    except Exception as exc:          # noqa: BLE001
        _result["error"] = _result["error"] or exc
    finally:
        _photo_done.set()
    if then is not None:
        try:
            then()
        except Exception as exc:      # noqa: BLE001
            _result["error"] = exc
    return _result["seconds"]


def start(then: Callable[[], None] | None = None, first=()) -> bool:
    """Warm up in a daemon thread (once per process; later calls do nothing and return False).
    ``first``: more calls that compile kernels the GUI thread uses, made in the first stage."""
    global _thread
    with _lock:
        if _thread is not None:
            return False
        _first[:] = list(first)
        _thread = threading.Thread(target=warm_up, args=(then,), name="texeditor-warm-up",
                                   daemon=True)
        _thread.start()
        return True


def started() -> bool:
    return _thread is not None


def ready() -> bool:
    """The warm-up has finished (kernels compiled, or its failure recorded)."""
    return _done.is_set()


def pending(stage: str | None = None) -> bool:
    """A warm-up is under way: kernel work on the GUI thread would wait for it (``"gui"``: the
    first stage, the GUI thread's own small kernels, is not done yet; ``"tone"``: the second,
    the photographic tone's; ``"photo"``: the last, the rest of a photo model's)."""
    done = {"gui": _gui_done, "tone": _tone_done, "photo": _photo_done}.get(stage, _done)
    return _thread is not None and not done.is_set()


def wait(timeout: float | None = None, cancel: Callable[[], bool] | None = None) -> bool:
    """Block until the warm-up ends (or ``timeout`` seconds, or ``cancel()``); True when it has
    (at once when none was started)."""
    if _thread is None:
        return True
    deadline = None if timeout is None else time.perf_counter() + timeout
    while not _done.wait(0.05):
        if cancel is not None and cancel():
            return False
        if deadline is not None and time.perf_counter() > deadline:
            return False
    return True


def seconds() -> float | None:
    return _result["seconds"]


def error() -> Exception | None:
    return _result["error"]


def needs_kernels(action, doc) -> bool:
    """Whether applying ``action`` to ``doc`` (without a result prepared in a worker) may call a
    numba kernel: a synthesis, a grain rendering, or any step naming one of the document's DPJs
    (a spot or source texture drawn from it). Conservative: such a step only waits, never
    fails."""
    from .recipe.actions import Synthesize, dpj_refs

    if isinstance(action, Synthesize):
        return True
    if action.TYPE == "render_grains":
        return True
    return any(ref in doc.dpjs for ref in dpj_refs([action]))


def on_first_compile(note: Callable[[], None]) -> Callable[[], None]:
    """Call ``note()`` once, when this process first compiles a kernel (numba's cache missed: a
    fresh install, a new numba or Python), so that a command can say why it is silent for a
    minute. Loading a cached kernel is no compilation and says nothing. Returns a function that
    removes the listener."""
    from numba.core import event

    class _First(event.Listener):
        told = False

        def on_start(self, ev):
            if not self.told:
                self.told = True
                note()

        def on_end(self, ev):
            pass

    listener = _First()
    event.register("numba:compile", listener)
    return lambda: event.unregister("numba:compile", listener)


def _reset() -> None:
    """Forget a finished warm-up (tests only: the kernels stay compiled)."""
    global _thread
    with _lock:
        if _thread is not None:
            _thread.join(120)             # its last stage may outlast wait()
            if _thread.is_alive():
                raise RuntimeError("a warm-up is still running")
        _thread = None
        _done.clear()
        _gui_done.clear()
        _tone_done.clear()
        _photo_done.clear()
        _first.clear()
        _result.update(seconds=None, error=None)
