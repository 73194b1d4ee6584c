"""Replay: a log run step by step on a document — the one loop every replay goes through.

A texture is its log (thesis §5.4): rebuilding it (`replay`), moving a History back and forth,
re-running the steps after an edited one, replaying a log without some of its spots — each walks
the steps with ``replay_log``, and each step is ``apply_step``: its slow part first (cancellable,
in any thread), then its change inside the document's step, where undo atoms are recorded.
"""

from __future__ import annotations

from typing import Callable

from ..errors import Cancelled, InputError, ReplayError
from .document import Document

Progress = Callable[[float], None] | None
Cancel = Callable[[], bool] | None


def apply_step(doc: Document, action, *, record: list | None = None, prepared=None,
               progress: Progress = None, cancel: Cancel = None):
    """Apply one action (not logged: the caller logs it). ``prepared``: the result of its slow
    part, computed elsewhere (a worker's synthesis, a stored picture); else ``prepare`` runs
    here. With ``record``, the undo atoms are collected there and a step that fails puts back
    what it overwrote. Returns the prepared result (None: the step has no slow part)."""
    if prepared is None:
        prepared = action.prepare(doc, progress, cancel)
    try:
        with doc.step(record):
            action.apply(doc, prepared)
    except BaseException:
        for atom in reversed(record or ()):
            atom.swap(doc)
        raise
    return prepared


def replay_log(actions, run: Callable, *, start: int = 0, stop: int | None = None,
               progress: Progress = None, cancel: Cancel = None,
               failure: Callable | None = None) -> None:
    """Call ``run(k, action, progress)`` for steps start..stop-1 of ``actions``, checking
    ``cancel`` between steps and reporting ``progress`` 0..1 (a step's own progress included);
    an InputError of step k becomes ``failure(k, action, exc)`` when given."""
    stop = len(actions) if stop is None else stop
    n = max(stop - start, 1)
    for k in range(start, stop):
        if cancel is not None and cancel():
            raise Cancelled("replay cancelled")
        sub = None if progress is None else (lambda f, j=k - start: progress((j + f) / n))
        try:
            run(k, actions[k], sub)
        except InputError as exc:
            if failure is None:
                raise
            raise failure(k, actions[k], exc) from None
        if progress is not None:
            progress((k + 1 - start) / n)


def replay(actions, dpjs: dict, *, current: str | None = None, prepared: dict | None = None,
           progress: Progress = None, cancel: Cancel = None,
           exemplars: dict | None = None) -> Document:
    """Rebuild a document from its log, DPJs (ref → DPJ) and exemplars (ref → photo, for the
    model steps). ``current``: the DPJ that was
    current when it was stored (recorded state: a DPJ loaded after the last synthesis);
    ``prepared``: step → its result given (a stored picture standing for a synthesis). A step
    that fails is a ReplayError naming it."""
    actions = list(actions)
    doc = Document()
    doc.dpjs.update(dpjs)
    doc.exemplars.update(exemplars or {})
    given = prepared or {}

    def run(k, action, sub):
        apply_step(doc, action, prepared=given.get(k), progress=sub, cancel=cancel)
        doc.append_log(action)

    replay_log(actions, run, progress=progress, cancel=cancel, failure=replay_failure)
    make_current(doc, current)
    return doc


def replay_failure(k: int, action, exc: Exception) -> ReplayError:
    return ReplayError(f"step {k + 1} ({action.label()}) cannot be replayed: {exc}")


def make_current(doc: Document, ref: str | None) -> None:
    """Make the recorded current DPJ current again (None: leave the log's own)."""
    if ref is not None:
        if ref not in doc.dpjs:
            raise ReplayError(f"the current DPJ {ref} is not among the recipe's DPJs")
        doc.add_dpj(doc.dpjs[ref], ref)
