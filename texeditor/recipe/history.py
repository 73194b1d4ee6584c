"""History: the action log of one Document, with undo, redo and non-destructive editing of past steps.

It sits between the tools (GUI, CLI) that submit Actions and the Document they change. Undo of a
step swaps back what the step overwrote (its footprint); snapshots bound the replay after an edit.
"""

from __future__ import annotations

import time
from bisect import bisect_right
from collections import ChainMap
from dataclasses import dataclass
from typing import Callable, Iterable

from .actions import Action
from .cache import Cache
from .document import Document, State, footprint, union_box
from ..errors import InputError
from .replay import Cancel, Progress, apply_step, replay_failure, replay_log


# Snapshots are thinned to this many: more would make thinning slow (it is linear in their
# number) and gain little (a step is then at most 1/256 of the log away from one).
MAX_SNAPSHOTS = 256


@dataclass(frozen=True)
class Change:
    """What one change of a History did, so that a view redraws only that: ``kind`` (apply,
    undo, redo, goto, edit, dpj), the index after it, ``what`` changed (a subset of levels,
    palette, dpj, log, plates) and ``box``, the (top, left, height, width) of the levels changed
    (None: the whole canvas, or its shape changed)."""

    kind: str
    index: int
    what: frozenset
    box: tuple[int, int, int, int] | None = None


EVERYTHING = frozenset({"levels", "palette", "dpj", "log", "plates"})


class History:
    """The log of a document: ``actions[:index]`` are applied, the rest is the redo tail.

    Every applied step keeps an undo record (what it overwrote) while ``undo_memory`` allows;
    a snapshot of the whole state is kept every ``snapshot_every`` steps, or sooner after
    ``snapshot_cost`` seconds of work, within ``snapshot_memory`` bytes (thinned evenly when
    full). Undo never replays from step 0: it swaps a record back or replays from a snapshot.

    An edit of a past step (``commit``) is itself undoable: ``undo`` right after it puts the
    old log and document back, ``redo`` the edit again (a Revision, as Krita's undo stack keeps
    one command for a whole replayed change). Region steps remember a digest of the region they
    acted on, so an edit tells which later steps now act on a different one (``retargeted``).
    """

    def __init__(self, document: Document | None = None, *, snapshot_every: int = 32,
                 snapshot_memory: int = 128 * 2**20, undo_memory: int = 256 * 2**20,
                 snapshot_cost: float = 0.05):
        if snapshot_every < 1 or snapshot_memory < 0 or undo_memory < 0:
            raise InputError("snapshot_every must be ≥ 1 and memory budgets ≥ 0")
        self.snapshot_every, self.snapshot_memory = snapshot_every, snapshot_memory
        self.undo_memory, self.snapshot_cost = undo_memory, snapshot_cost
        self._doc = document if document is not None else Document()
        self._actions: list[Action] = list(self._doc.actions)
        self._index = len(self._actions)
        self._records: dict[int, list] = {}    # step → atoms (undo form below index, redo above)
        self._record_bytes = 0
        self._snaps: dict[int, State] = {0: Document().state()}
        self._snap_keys = [0]
        self._spacing = 1                      # the least gap a new snapshot needs (thinning)
        self._snap_bytes = 0
        self._costs: dict[int, float] = {}
        # the slow parts of recent steps (a synthesis's levels), so that undo past them and
        # their redo, which replay from a snapshot, do not compute them again
        self._results = Cache(max_items=4, max_bytes=256 * 2**20)
        self._subscribers: list[Callable[[], None]] = []
        self._changes = 0                      # notifications so far: a PendingEdit's staleness
        self._targets: dict[int, str] = {}     # region step → digest of the region it acted on
        self.retargeted: frozenset[int] = frozenset()   # later steps the last edit re-targeted
        self._dirty: set[str] = set()          # what changed since the last notification
        self._box: tuple | None = None         # and where (None: everywhere)
        self._done: list[Revision] = []        # edits of past steps, undoable (latest last)
        self._undone: list[Revision] = []      # edits undone, redoable (latest last)
        if self._index:
            self._add_snapshot(self._index, self._doc.state())

    @classmethod
    def from_log(cls, actions: Iterable[Action], dpjs: dict, *, current: str | None = None,
                 prepared: dict | None = None, progress: Progress = None, cancel: Cancel = None,
                 exemplars: dict | None = None, **options) -> "History":
        """Replay a log (ref → DPJ for its syntheses, ref → photo for its model steps) into a
        new History, step by step, as `replay.replay` does (``current``, ``prepared``: see
        there); a failing step is a ReplayError naming it."""
        from .replay import make_current
        history = cls(**options)
        history._doc.dpjs.update(dpjs)
        history._doc.exemplars.update(exemplars or {})
        actions, given = list(actions), prepared or {}
        replay_log(actions, lambda k, a, sub: history._advance(a, k, given.get(k), sub, cancel),
                   progress=progress, cancel=cancel, failure=replay_failure)
        make_current(history._doc, current)
        return history

    # -- reading ------------------------------------------------------------------------------
    @property
    def document(self) -> Document:
        return self._doc

    @property
    def actions(self) -> tuple[Action, ...]:
        return tuple(self._actions)

    @property
    def applied(self) -> tuple[Action, ...]:
        """The recipe of the current document: ``actions[:index]``."""
        return tuple(self._actions[:self._index])

    @property
    def index(self) -> int:
        return self._index

    @property
    def can_undo(self) -> bool:
        return self._index > 0 or self.undoes_edit

    @property
    def can_redo(self) -> bool:
        return self._index < len(self._actions) or self.redoes_edit

    @property
    def undoes_edit(self) -> bool:
        """True when ``undo`` would take back the edit of a past step (the state is the one
        that edit left), not the last step."""
        return bool(self._done) and self._done[-1].after.matches(self)

    @property
    def redoes_edit(self) -> bool:
        return bool(self._undone) and self._undone[-1].before.matches(self)

    @property
    def memory(self) -> dict:
        """Bytes held by undo records and snapshots (for a status line or a benchmark)."""
        return {"undo_records": self._record_bytes, "snapshots": self._snap_bytes,
                "records": len(self._records), "snapshot_count": len(self._snap_keys)}

    def labels(self) -> list[str]:
        return [a.label() for a in self._actions]

    # -- changing -----------------------------------------------------------------------------
    def subscribe(self, callback: Callable[[Change], None]) -> Callable[[], None]:
        """Call ``callback(change)`` after every change (a `Change`: what changed, and where);
        returns a function that unsubscribes."""
        self._subscribers.append(callback)
        return lambda: self._subscribers.remove(callback) if callback in self._subscribers else None

    def add_dpj(self, dpj) -> str:
        ref = self._doc.add_dpj(dpj)
        self._dirty.add("dpj")
        self._notify("dpj")
        return ref

    def add_exemplar(self, image) -> str:
        """Keep a photo in the document for the model steps (not a step: nothing changes)."""
        return self._doc.add_exemplar(image)

    def apply(self, action: Action, *, if_changed: bool = False, prepared=None) -> bool:
        """Apply a new step after the current one; the redo tail is dropped. ``if_changed``: a
        step that changes nothing (a fill with the region's own level) is not added, and the
        log stays as it was. ``prepared``: the step's slow part, done in a worker (what its
        ``prepare`` returned), applied as it is. Returns whether a step was added."""
        if not isinstance(action, Action):
            raise InputError(f"only an Action can be applied, got {type(action).__name__}")
        k, records, costs, targets = self._index, {}, {}, {}
        self._step(self._doc, action, k, records, costs, targets, prepared,
                   results=self._results)
        if if_changed and not any(atom.differs(self._doc) for atom in records[k]):
            for atom in reversed(records[k]):
                atom.swap(self._doc)
            return False
        self._truncate(k)
        self._touch(records[k])
        self._accept(action, k, records, costs, targets)
        self._notify("apply")
        return True

    def undo(self) -> bool:
        if not self.can_undo:
            return False
        try:
            if self.undoes_edit:
                self._undone.append(self._done.pop())
                self._undone[-1].undo(self)
            else:
                self._goto(self._index - 1)
        finally:
            self._notify("undo")
        return True

    def redo(self) -> bool:
        if not self.can_redo:
            return False
        try:
            if self.redoes_edit:
                self._done.append(self._undone.pop())
                self._done[-1].redo(self)
            else:
                self._goto(self._index + 1)
        finally:
            self._notify("redo")
        return True

    def goto(self, index: int) -> None:
        """Move to the state after ``index`` steps (0 = empty), keeping the whole log."""
        if not 0 <= index <= len(self._actions):
            raise InputError(f"step {index} is outside 0..{len(self._actions)}")
        try:
            self._goto(index)
        finally:
            self._notify("goto")

    def replace(self, i: int, action: Action, *, to_end: bool = False) -> None:
        """Edit step i (new parameters) and replay the steps after it: non-destructive history.
        ``to_end`` also replays the redo tail and stands at the end of the log."""
        self.commit(self.pending_replace(i, action, to_end=to_end).run())

    def pending_replace(self, i: int, action: Action, *, to_end: bool = False) -> "PendingEdit":
        """replace() in two halves, so that a long replay can run in a worker thread while the
        history stays as it is (a Cancel then changes nothing): ``run()`` it, then commit()."""
        self._check_step(i)
        end = len(self._actions) if to_end else self._index
        return self._pending(i, [action] + self._actions[i + 1:], end)

    def pending_rewrite(self, actions: Iterable[Action]) -> "PendingEdit":
        """The applied steps replaced by ``actions``, a log that gives the same document (the
        log optimiser's, say), as one undoable edit whose replay starts at the first step that
        differs; the redo tail goes, as after any new step. Run it, then commit() it."""
        actions = list(actions)
        if not actions:
            raise InputError("an empty log cannot replace this one: start a new document")
        same = next((k for k, (a, b) in enumerate(zip(self._actions[:self._index], actions))
                     if a != b), min(self._index, len(actions)))
        i = min(same, len(actions) - 1)
        return self._pending(i, actions[i:], len(actions))

    def commit(self, edit: "PendingEdit") -> None:
        """Make a replayed PendingEdit the current state, in one short step; refused when the
        history changed since the edit was made (its replay would then undo that change)."""
        if edit.history is not self or edit.changes != self._changes:
            raise InputError("the history changed while this edit was replayed: apply it again")
        if not edit.finished:
            raise InputError("this edit has not been replayed yet")
        before = Version(self)
        self._actions = edit.actions
        if edit.i >= edit.new_index:         # only the redo tail changed: nothing was replayed
            self._truncate_records(edit.i)
            self._drop_targets(edit.i)
            self.retargeted = frozenset()
            self._dirty.add("log")
        else:
            self._take_replay(edit)
        self._remember(Revision(edit.i, before, Version(self)))
        self._notify("edit")

    def _remember(self, revision: "Revision") -> None:
        """Keep an edit for undo; the oldest go first beyond a quarter of the undo budget."""
        self._done.append(revision)
        self._undone.clear()
        while (len(self._done) > 1
               and sum(r.nbytes for r in self._done) > self.undo_memory // 4):
            self._done.pop(0)

    def _take_replay(self, edit: "PendingEdit") -> None:
        """Forget what was learnt from the edited steps on; keep the replay's state and records."""
        self._truncate_records(edit.start)
        for key in [s for s in self._snap_keys if s > edit.i]:
            self._drop_snapshot(key)
        self.retargeted = frozenset(k for k, digest in edit.targets.items()
                                    if k > edit.i and self._targets.get(k, digest) != digest)
        self._drop_targets(edit.start)
        self._targets.update(edit.targets)
        self._costs = {k: c for k, c in self._costs.items() if k < edit.i}
        self._costs.update(edit.costs)
        self._doc.restore(edit.state, copy=False)
        self._doc.set_log(edit.actions[:edit.new_index])
        self._touch_all()
        self._index = edit.new_index
        for step, atoms in edit.records.items():
            self._keep_record(step, atoms)
        for key, state in edit.snaps.items():
            self._add_snapshot(key, state)
        self._trim_records()

    def remove(self, i: int) -> None:
        """Delete step i and replay the later ones."""
        self._check_step(i)
        self._edit(i, self._actions[i + 1:], self._index - (i < self._index))

    def insert(self, i: int, action: Action) -> None:
        """Insert a step before step i (i = len(actions) appends to the tail)."""
        if not 0 <= i <= len(self._actions):
            raise InputError(f"step {i} is outside 0..{len(self._actions)}")
        self._edit(i, [action] + self._actions[i:], self._index + (i < self._index))

    # -- internals: stepping ------------------------------------------------------------------
    def _check_step(self, i: int) -> None:
        if not 0 <= i < len(self._actions):
            raise InputError(f"step {i} is outside 0..{len(self._actions) - 1}")

    def _advance(self, action: Action, k: int, prepared=None, progress: Progress = None,
                 cancel: Cancel = None) -> None:
        """Apply action as step k (= index) on the live document, recording its undo atoms."""
        records, costs, targets = {}, {}, {}
        self._step(self._doc, action, k, records, costs, targets, prepared, progress, cancel,
                   self._results)
        self._accept(action, k, records, costs, targets)

    def _accept(self, action: Action, k: int, records: dict, costs: dict, targets: dict) -> None:
        """Make an applied action step k: the log, the undo records, costs and snapshots."""
        self._targets.update(targets)
        if k < len(self._actions):
            self._actions[k] = action
        else:
            self._actions.append(action)
        self._doc.append_log(action)
        self._index = k + 1
        self._costs.update(costs)
        for step, atoms in records.items():
            self._keep_record(step, atoms)
        self._maybe_snapshot(self._index, self._doc)
        self._trim_records()

    @staticmethod
    def _step(doc, action, k, records, costs, targets, prepared=None, progress=None,
              cancel=None, results: Cache | None = None) -> None:
        """Step k on ``doc``: what it picks, its undo atoms, its cost (a failed step leaves the
        document as it was). ``results`` keeps the slow part of a step for its next replay
        (Actions are immutable values: an equal action on a canvas of the same shape gives the
        same result; a slow part that reads the levels before is not kept, see Action.prepare;
        one that reads the canvas's shape, as colour plates do, is kept by shape)."""
        atoms: list = []
        target = action.picked_region(doc.levels)
        if target is not None:
            targets[k] = target
        start = time.perf_counter()
        if type(action).prepare is Action.prepare:
            results = None                   # no slow part to keep
        key = (action, doc.shape)
        if prepared is None and results is not None:
            prepared = results.get(key)
        prepared = apply_step(doc, action, record=atoms, prepared=prepared, progress=progress,
                              cancel=cancel)
        if prepared is not None and results is not None:
            results.put(key, prepared)
        costs[k] = time.perf_counter() - start
        records[k] = atoms

    def _goto(self, target: int) -> None:
        while self._index > target and (self._index - 1) in self._records:
            self._swap(self._index - 1, reverse=True)
            self._index -= 1
            self._doc.truncate_log(self._index)
        while self._index < target and self._index in self._records:
            self._swap(self._index, reverse=False)
            self._doc.append_log(self._actions[self._index])
            self._index += 1
        if self._index != target:
            self._jump(target)

    def _swap(self, step: int, reverse: bool) -> None:
        atoms = self._records[step]
        self._touch(atoms)
        before = _atoms_bytes(atoms)
        for atom in (reversed(atoms) if reverse else atoms):
            atom.swap(self._doc)
        self._record_bytes += _atoms_bytes(atoms) - before

    def _jump(self, target: int) -> None:
        """Reach ``target`` by replay from the nearest snapshot (or the live state, if nearer)."""
        start = self._snap_keys[bisect_right(self._snap_keys, target) - 1]
        if self._index <= target and start < self._index:
            start = self._index
        else:
            self._doc.restore(self._snaps[start])
        self._touch_all()
        lo, hi = min(start, self._index), max(self._index, target)
        for step in [s for s in self._records if lo <= s < hi]:
            self._drop_record(step)
        self._doc.set_log(self._actions[:start])
        self._index = start
        replay_log(self._actions, lambda k, a, _: self._advance(a, k), start=start, stop=target,
                   failure=_redo_failure)

    # -- internals: editing past steps --------------------------------------------------------
    def _edit(self, i: int, tail: list, new_index: int) -> None:
        """Make ``actions[i:] = tail`` and stand at ``new_index``, replaying on a scratch copy
        first so that a step made invalid by the edit leaves the history untouched."""
        self.commit(self._pending(i, tail, new_index).run())

    def _pending(self, i: int, tail: list, new_index: int) -> "PendingEdit":
        for action in tail:
            if not isinstance(action, Action):
                raise InputError(f"only an Action can be in a log, got {type(action).__name__}")
        return PendingEdit(self, i, self._actions[:i] + list(tail), new_index)

    def _truncate(self, index: int) -> None:
        del self._actions[index:]
        self._truncate_records(index)
        self._drop_targets(index)
        self.retargeted = frozenset(k for k in self.retargeted if k < index)
        self._done = [r for r in self._done if r.after.index <= index]
        self._undone.clear()

    def _drop_targets(self, index: int) -> None:
        for step in [s for s in self._targets if s >= index]:
            del self._targets[step]

    def _truncate_records(self, index: int) -> None:
        """Forget what was learnt from steps index and later (records, snapshots, costs)."""
        for step in [s for s in self._records if s >= index]:
            self._drop_record(step)
        for key in [s for s in self._snap_keys if s > index]:
            self._drop_snapshot(key)

    # -- internals: memory --------------------------------------------------------------------
    def _keep_record(self, step: int, atoms: list) -> None:
        if step in self._records:
            self._drop_record(step)
        self._records[step] = atoms
        self._record_bytes += _atoms_bytes(atoms)

    def _drop_record(self, step: int) -> None:
        self._record_bytes -= _atoms_bytes(self._records.pop(step))

    def _trim_records(self) -> None:
        """Over budget, forget the records farthest from the current step first."""
        while self._record_bytes > self.undo_memory and self._records:
            first, last = min(self._records), max(self._records)
            far = first if self._index - first >= last - self._index else last
            self._drop_record(far)

    def _wants_snapshot(self, k: int, keys: list, costs: dict, spacing: int = 1) -> bool:
        """Snapshot state k when the last one is snapshot_every steps or snapshot_cost s back,
        and at least ``spacing`` steps back (once thinning began, a nearer one would only make
        the next thinning drop another)."""
        last = keys[bisect_right(keys, k) - 1]
        if k - last < max(spacing, 1):
            return False
        if k - last >= self.snapshot_every:
            return True
        return sum(costs.get(j, 0.0) for j in range(last, k)) >= self.snapshot_cost

    def _maybe_snapshot(self, k: int, doc: Document) -> None:
        if self._wants_snapshot(k, self._snap_keys, self._costs, self._spacing):
            self._add_snapshot(k, doc.state())

    def _add_snapshot(self, k: int, state: State) -> None:
        if k in self._snaps:
            self._drop_snapshot(k)
        self._snaps[k] = state
        self._snap_keys.insert(bisect_right(self._snap_keys, k), k)
        self._snap_bytes += state.nbytes
        thinned = False
        while ((self._snap_bytes > self.snapshot_memory or len(self._snap_keys) > MAX_SNAPSHOTS)
               and len(self._snap_keys) > 1):
            self._drop_snapshot(self._thinnest())
            thinned = True
        self._spacing = _closest(self._snap_keys) if thinned else 1

    def _thinnest(self) -> int:
        return _thinnest(self._snap_keys)

    def _drop_snapshot(self, k: int) -> None:
        if k == 0:
            return
        self._snap_bytes -= self._snaps.pop(k).nbytes
        self._snap_keys.remove(k)
        self._spacing = 1

    def _touch(self, atoms: list) -> None:
        """Note what a step's atoms changed (and where) for the next notification."""
        what, box = footprint(atoms)
        if "levels" in what and "levels" in self._dirty:
            box = union_box(self._box, box)
        elif "levels" not in what:
            box = self._box
        self._dirty |= what | {"log"}
        self._box = box

    def _touch_all(self) -> None:
        self._dirty |= EVERYTHING
        self._box = None

    def _notify(self, kind: str) -> None:
        self._changes += 1
        if kind in ("undo", "redo", "goto", "edit", "apply"):
            self._dirty.add("log")
        change = Change(kind, self._index, frozenset(self._dirty),
                        self._box if "levels" in self._dirty else None)
        self._dirty, self._box = set(), None
        for callback in list(self._subscribers):
            callback(change)


def _atoms_bytes(atoms: list) -> int:
    return sum(a.nbytes for a in atoms)


def _redo_failure(k: int, action, exc: Exception) -> InputError:
    """A redo tail that an edit made invalid."""
    return InputError(f"step {k + 1} ({action.label()}) cannot be redone after the edit of an "
                      f"earlier step: {exc}")


def _thinnest(keys: list) -> int:
    """The snapshot whose removal leaves the smallest gap (keeps the rest evenly spread); never
    ``keys[0]``, and the newest only when it is the one other (it is the nearest to the steps
    being added: dropping it would leave the next ones as far from a snapshot)."""
    if len(keys) <= 2:
        return keys[-1]
    gaps = [keys[j + 1] - keys[j - 1] for j in range(1, len(keys) - 1)]
    return keys[1 + gaps.index(min(gaps))]


def _closest(keys: list) -> int:
    """The smallest gap between two consecutive snapshots."""
    return min((b - a for a, b in zip(keys, keys[1:])), default=1)


class PendingEdit:
    """An edit of past steps, replayed on a scratch copy away from its History.

    Made on the thread that owns the history, it copies what the replay needs (the nearest
    snapshot, the DPJs, the step costs), so ``run()`` reads nothing the history may change and
    can run in a worker thread; History.commit() then swaps the result in. Until then the history
    is exactly as it was. The replay keeps its undo records and snapshots within the history's
    memory budgets as it goes (a thousand steps at 4096² would not fit otherwise).
    """

    def __init__(self, history: History, i: int, actions: list, new_index: int):
        self.history, self.i, self.actions, self.new_index = history, i, actions, new_index
        self.changes = history._changes
        self.start = history._snap_keys[bisect_right(history._snap_keys, min(i, new_index)) - 1]
        self._base = history._snaps[self.start]
        self._dpjs = dict(history._doc.dpjs)
        self._exemplars = dict(history._doc.exemplars)
        self._keys = [s for s in history._snap_keys if s <= i]
        self._snap_budget = history.snapshot_memory - sum(history._snaps[s].nbytes
                                                          for s in self._keys)
        self._old_costs = dict(history._costs)
        self.records: dict[int, list] = {}
        self.costs: dict[int, float] = {}
        self.targets: dict[int, str] = {}
        self.snaps: dict[int, State] = {}
        self._record_bytes = self._snap_bytes = 0
        self._spacing = 1
        self.state: State | None = None
        self.finished = i >= new_index       # only the redo tail changes: nothing to replay

    def run(self, progress: Progress = None, cancel: Cancel = None) -> "PendingEdit":
        """Replay steps start..new_index-1 (progress 0..1; Cancelled when ``cancel()``); a step
        the edit made invalid is an InputError naming it."""
        if self.finished:
            return self
        scratch = Document()
        scratch.dpjs = self._dpjs
        scratch.exemplars = self._exemplars
        scratch.restore(self._base)
        scratch.set_log(self.actions[:self.start])   # actions may read the log before them
        costs = ChainMap(self.costs, self._old_costs)

        def run(k, action, sub):
            self._replay_step(scratch, k, sub, cancel)
            if k + 1 > self.i and self.history._wants_snapshot(k + 1, self._keys, costs,
                                                               self._spacing):
                self._keep_snapshot(k + 1, scratch.state())

        replay_log(self.actions, run, start=self.start, stop=self.new_index, progress=progress,
                   cancel=cancel)
        self.state = scratch.state(copy=False)
        self.finished = True
        return self

    def _replay_step(self, scratch: Document, k: int, progress: Progress, cancel: Cancel) -> None:
        action = self.actions[k]
        try:
            History._step(scratch, action, k, self.records, self.costs, self.targets, None,
                          progress, cancel, self.history._results)
        except InputError as exc:
            raise InputError(f"after this edit, step {k + 1} ({action.label()}) "
                             f"fails: {exc}") from None
        scratch.append_log(action)
        self._record_bytes += _atoms_bytes(self.records[k])
        while self._record_bytes > self.history.undo_memory:   # drop the farthest from the end
            self._record_bytes -= _atoms_bytes(self.records.pop(min(self.records)))

    def _keep_snapshot(self, k: int, state: State) -> None:
        self.snaps[k] = state
        self._keys.append(k)
        self._snap_bytes += state.nbytes
        while self.snaps and (self._snap_bytes > self._snap_budget
                              or len(self.snaps) > MAX_SNAPSHOTS):
            drop = _thinnest([self.start] + sorted(self.snaps))
            self._snap_bytes -= self.snaps.pop(drop).nbytes
            self._keys.remove(drop)
            self._spacing = _closest([self.start] + sorted(self.snaps))


class Version:
    """What an edit of a past step changes: the log, the position in it, the document's state
    and what the region steps acted on. Restoring one forgets the records and snapshots of the
    steps after the edited one (undo then replays from a snapshot before it)."""

    def __init__(self, history: History):
        self.actions = list(history._actions)
        self.index = history._index
        self.state = history._doc.state()
        self.targets = dict(history._targets)
        self.retargeted = history.retargeted

    @property
    def nbytes(self) -> int:
        return self.state.nbytes

    def matches(self, history: History) -> bool:
        """The history stands where this version stood, with the very same steps applied
        (Actions are immutable, so identity is enough)."""
        return history._index == self.index and all(
            a is b for a, b in zip(history._actions[:self.index], self.actions[:self.index]))

    def restore(self, history: History, i: int) -> None:
        history._actions = list(self.actions)
        history._truncate_records(i)
        history._index = self.index
        history._doc.restore(self.state)
        history._doc.set_log(self.actions[:self.index])
        history._touch_all()
        history._targets = dict(self.targets)
        history.retargeted = self.retargeted


class Revision:
    """An edit of step ``i`` as one undoable change: the versions before and after it."""

    def __init__(self, i: int, before: Version, after: Version):
        self.i, self.before, self.after = i, before, after

    @property
    def nbytes(self) -> int:
        return self.before.nbytes + self.after.nbytes

    def undo(self, history: History) -> None:
        """Back to the version before; the steps undone since the edit stay redoable."""
        self.after = Version(history)
        self.before.restore(history, self.i)

    def redo(self, history: History) -> None:
        self.before = Version(history)
        self.after.restore(history, self.i)
