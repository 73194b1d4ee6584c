"""Crash journals: every completed change of a document's log is appended, and flushed to disk,
to a journal file of its own, so a crash loses at most the action that was being applied.

It sits beside History: the GUI calls ``sync`` after every change, ``reset`` after a save and
``discard`` when the window closes; on the next start ``orphans`` finds the journals of processes
that died, and ``recover`` rebuilds their logs. One window, one file: a live journal is locked.

A journal is JSON Lines. ``start`` (format, the document's file if any, time), then ``dpj`` records
(a DPJ the log refers to, base64 of its `.dpj` bytes), ``exemplar`` records (a model step's photo,
base64 of its PNG), ``current`` records (the reference of the DPJ the next synthesis draws
from, when it changes without a step: a DPJ edited and used), ``log`` records: keep the first ``keep``
actions of the log as it was and append ``append`` (undo keeps n-1 and appends nothing; an edit of
step k keeps k-1 and appends the rest), and ``thumbnail`` records (base64 of a PNG of the middle
of the picture as the window showed it, at most THUMB_SIDE a side; the last one is shown when the
work is offered back, and a damaged one is passed over: it holds no work). A line cut short by
the crash is ignored.

A journal grows with every change and is read whole at recovery, within MAX_JOURNAL_BYTES: one
past COMPACT_BYTES (and twice its size when last written afresh) is written afresh — the log as
it is now, its DPJs and photos, the last thumbnail — into a locked ``.journal-new`` file that
then replaces it, so its path always names a complete, locked journal; the start record then
carries the number of ``changes`` the records it replaced had made.
"""

from __future__ import annotations

import base64
import dataclasses
import io
import json
import os
import time
import uuid
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image

from .codec import action_from_json
from .exemplars import MIN_SIDE, exemplar_png, is_picture, read_exemplar_png
from ..markov.dpj import DPJ
from ..errors import FormatError, TexeditorError
from ..fileio import load_json, read_limited
from .texturefile import MAX_ACTIONS
from ..userdata import data_dir

try:
    import fcntl
except ImportError:          # not POSIX: journals still work, orphans are told by age
    fcntl = None

FORMAT = 1
SUFFIX = ".journal"
MAX_JOURNAL_BYTES = 256 * 2**20       # measured: recovery at the limit stays near 1 GiB
MAX_START_TIME = 253402300799       # 9999-12-31 23:59:59 UTC: any later "time" is damage
THUMB_SIDE = 64                     # a thumbnail: the picture's middle, at most this a side,
THUMB_CROP = 128                    # ... from a crop this wide, every other point (the texture
                                    # at half its size: its grain still shows)
MAX_THUMB_BYTES = 64 * 2**10
COMPACT_BYTES = 32 * 2**20            # a journal past this is written afresh (a day's painting
                                      # without a save, or edits of early steps of a long log,
                                      # each appending the rest of it, passed the read limit)
NEW_SUFFIX = ".journal-new"           # a journal being written afresh (never an orphan)


def journal_dir() -> Path:
    return data_dir() / "journals"


class Journal:
    """The journal of one open document (one window)."""

    def __init__(self, folder: Path | None = None):
        self.folder = Path(folder) if folder is not None else journal_dir()
        self.folder.mkdir(parents=True, exist_ok=True)
        _sweep_rewrites(self.folder)
        self.path = self.folder / f"{os.getpid()}-{uuid.uuid4().hex[:12]}{SUFFIX}"
        self._file = _locked(self.path, "ab")
        self._logged: tuple = ()
        self._refs: dict = {}     # ref → where its record lies in the file (offset, length)
        self._start: dict = {}
        self._logs = 0            # log records since the start record
        self._thumb = None        # the last thumbnail record
        self._afresh = 0          # the size when last written afresh
        self._current = None      # the current DPJ's reference, as last recorded

    def reset(self, actions, dpjs: dict, *, source=None, exemplars=None, current=None) -> None:
        """Start afresh from this log (a new or just-saved document): the old records go, but
        for the DPJs and photos still used, copied as they were written."""
        wanted = set(dpjs) | set(exemplars or {})
        with open(self.path, "rb") as written:
            kept = {ref: line for ref in wanted
                    if (line := _copied((written, self._refs), ref)) is not None}
        self._file.seek(0)
        self._file.truncate()
        self._logged, self._refs, self._logs, self._thumb = (), {}, 0, None
        self._current = None
        self._start = {"kind": "start", "format": FORMAT, "time": time.time(),
                       "source": None if source is None else str(source)}
        self._write(self._start, flush=False)
        for ref, line in kept.items():
            self._refs[ref] = self._write_line(line)
        self._afresh = MAX_JOURNAL_BYTES          # (not written afresh again at once)
        self.sync(actions, dpjs, exemplars, current)
        self._afresh = self._file.tell()

    def sync(self, actions, dpjs: dict, exemplars=None, current=None) -> None:
        """Record how the log changed since the last call (nothing if it did not), with the
        DPJs and exemplar photos (ref → picture) not recorded yet, and the ``current`` DPJ's
        reference when it changed."""
        actions = tuple(actions)
        if actions == self._logged:
            if current != self._current:
                self._write_sources(dpjs, exemplars)
                self._write_current(current)
            return
        keep = 0
        for old, new in zip(self._logged, actions):
            if old != new:
                break
            keep += 1
        self._write_sources(dpjs, exemplars)
        self._write({"kind": "log", "keep": keep,
                     "append": [a.to_json() for a in actions[keep:]]})
        self._logged = actions
        self._logs += 1
        if current != self._current:
            self._write_current(current)
        if self._start and self._file.tell() > max(COMPACT_BYTES, 2 * self._afresh):
            self._rewrite(dpjs, exemplars)

    def _write_current(self, current) -> None:
        self._write({"kind": "current", "ref": current})
        self._current = current

    def _write_sources(self, dpjs: dict, exemplars, before=None) -> None:
        """The DPJs and exemplar photos not recorded yet (not flushed: the log record is);
        ``before``: (the file, {ref: its record's place}) they are copied from, as written
        (encoding five 1024² photos again took 0.7 s)."""
        sources = [(ref, "dpj", dpj) for ref, dpj in dpjs.items()]
        sources += [(ref, "exemplar", image) for ref, image in (exemplars or {}).items()]
        for ref, kind, source in sources:
            if ref in self._refs:
                continue
            line = _copied(before, ref)
            if line is not None:
                self._refs[ref] = self._write_line(line)
            elif kind == "dpj":
                self._refs[ref] = self._write(
                    {"kind": "dpj", "ref": ref,
                     "data": base64.b64encode(source.to_bytes()).decode("ascii")}, flush=False)
            else:
                self._refs[ref] = self._write(
                    {"kind": "exemplar", "ref": ref,
                     "png": base64.b64encode(exemplar_png(source)).decode("ascii")},
                    flush=False)

    def _rewrite(self, dpjs: dict, exemplars) -> None:
        """Write this journal afresh (see the module's note): the new file is complete, flushed
        and locked before it takes the journal's name. If that fails, the journal goes on as
        it was."""
        new = self.path.with_name(self.path.stem + NEW_SUFFIX)
        old, logged, refs = self._file, self._logged, self._refs
        try:
            with open(self.path, "rb") as written:
                self._file = _locked(new, "wb")
                self._refs = {}
                changes = _changes(self._start) + self._logs - 1
                self._write({**self._start, "changes": changes}, flush=False)
                self._write_sources(dpjs, exemplars, (written, refs))
                self._write({"kind": "log", "keep": 0,
                             "append": [a.to_json() for a in logged]},
                            flush=self._thumb is None and self._current is None)
                if self._current is not None:
                    self._write({"kind": "current", "ref": self._current},
                                flush=self._thumb is None)
                if self._thumb is not None:
                    self._write(self._thumb)
            os.replace(new, self.path)
        except OSError:
            if self._file is not old:
                self._file.close()
            self._file, self._refs = old, refs
            new.unlink(missing_ok=True)
            return
        old.close()
        self._start, self._logs, self._afresh = {**self._start, "changes": changes}, 1, \
            self._file.tell()

    def thumbnail(self, picture) -> None:
        """Record what the document looks like now (``picture``: uint8 (H, W) or (H, W, 3), as
        the window shows it): the one offered back with the work is the last recorded."""
        image = thumbnail_of(picture)
        self._thumb = {"kind": "thumbnail",
                       "png": base64.b64encode(exemplar_png(image)).decode("ascii")}
        self._write(self._thumb)

    def discard(self) -> None:
        """The document was saved and closed, or dropped on purpose: nothing to recover."""
        if not self._file.closed:
            self._file.close()
        self.path.unlink(missing_ok=True)

    def _write(self, record: dict, *, flush: bool = True) -> tuple[int, int]:
        """Append one record; where its line lies (offset, length)."""
        return self._write_line(json.dumps(record, separators=(",", ":")).encode() + b"\n",
                                flush=flush)

    def _write_line(self, line: bytes, *, flush: bool = False) -> tuple[int, int]:
        start = self._file.tell()
        self._file.write(line)
        if flush:
            self._file.flush()
            os.fsync(self._file.fileno())
        return start, len(line)


@dataclass(frozen=True)
class Recovered:
    """What a dead process's journal holds: its log, the DPJs and exemplar photos it needs,
    where it came from."""

    path: Path
    actions: tuple
    dpjs: dict
    source: str | None
    started: float
    changes: int          # changes of the log since the document was opened or saved
    exemplars: dict = dataclasses.field(default_factory=dict)
    thumbnail: np.ndarray | None = None     # the last thumbnail recorded (uint8, grey or RGB)
    current: str | None = None              # the current DPJ's reference, when recorded


def thumbnail_of(picture) -> np.ndarray:
    """The middle THUMB_CROP² of a picture, every other point (at most THUMB_SIDE a side)."""
    picture = np.asarray(picture)
    if not is_picture(picture):
        raise ValueError(f"a thumbnail is taken from a uint8 grey or RGB picture, not "
                         f"{picture.dtype} {picture.shape}")
    h, w = picture.shape[:2]
    top, left = max(0, (h - THUMB_CROP) // 2), max(0, (w - THUMB_CROP) // 2)
    crop = picture[top:top + THUMB_CROP, left:left + THUMB_CROP]
    step = max(1, -(-max(crop.shape[:2]) // THUMB_SIDE))
    image = np.ascontiguousarray(crop[::step, ::step])
    for axis in (0, 1):                  # a thumbnail PNG is at least MIN_SIDE (2) a side
        if image.shape[axis] < MIN_SIDE:
            image = np.repeat(image, MIN_SIDE, axis=axis)
    return np.ascontiguousarray(image)


def _copied(before, ref: str) -> bytes | None:
    """The record of ``ref`` in the journal being written afresh, as it lies there (None: not
    there, or not where it was noted)."""
    if before is None or ref not in before[1]:
        return None
    start, size = before[1][ref]
    before[0].seek(start)
    line = before[0].read(size)
    whole = len(line) == size and line.endswith(b"\n")
    return line if whole and f'"ref":"{ref}"'.encode() in line[:200] else None


def _locked(path: Path, mode: str):
    """``path`` opened and locked for as long as this process lives (orphans() tells the
    dead by the lock)."""
    f = open(path, mode)
    if fcntl is not None:
        try:
            fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            f.close()
            raise
    return f


def _sweep_rewrites(folder: Path) -> None:
    """Remove what a process that died while writing its journal afresh left (its journal
    itself was still whole under its own name)."""
    for path in folder.glob(f"*{NEW_SUFFIX}"):
        if not _alive(path):
            path.unlink(missing_ok=True)


def _changes(start: dict) -> int:
    """The changes a journal written afresh carries over (0 when none or damaged)."""
    value = start.get("changes", 0)
    return value if isinstance(value, int) and not isinstance(value, bool) \
        and 0 <= value <= MAX_ACTIONS * 2**10 else 0


def orphans(folder: Path | None = None) -> list[Path]:
    """Journals left by processes that died (their lock is free), newest first."""
    folder = Path(folder) if folder is not None else journal_dir()
    if not folder.is_dir():
        return []
    found = [p for p in folder.glob(f"*{SUFFIX}") if not _alive(p)]
    return sorted(found, key=_mtime, reverse=True)


def _mtime(path: Path) -> float:
    """When a journal last changed; a name that is no file (a dangling link) sorts last."""
    try:
        return path.lstat().st_mtime
    except OSError:
        return 0.0


def _alive(path: Path) -> bool:
    if not path.is_file():
        return False         # a folder, a FIFO, a device or a dangling link: nobody's journal
    if fcntl is None:
        return time.time() - _mtime(path) < 5
    try:
        with open(path, "rb", opener=_nonblocking) as f:
            try:
                fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                return True
            fcntl.flock(f.fileno(), fcntl.LOCK_UN)
            return False
    except FileNotFoundError:
        return True      # gone meanwhile: not ours to recover
    except OSError:
        return False     # cannot be opened: recover() says why, and it is set aside


def _nonblocking(path, flags):
    return os.open(path, flags | getattr(os, "O_NONBLOCK", 0))


def recover(path: Path) -> Recovered:
    """Rebuild the log a journal describes, up to its last complete record.

    Records are parsed and applied one at a time (a long session's journal holds millions of
    small ones); the log may not grow past a .texture's MAX_ACTIONS, or it could never be saved.
    """
    path = Path(path)
    data = read_limited(path, MAX_JOURNAL_BYTES, "journal")      # a regular file, bounded
    lines = iter(io.BytesIO(data))     # one line at a time, no list of them all
    start = _record(next(lines, b""))
    if not isinstance(start, dict) or start.get("kind") != "start" or start.get("format") != FORMAT:
        raise FormatError(f"{path}: not a texeditor journal")
    actions, dpjs, photos, logs, thumb, current = [], {}, {}, 0, None, None
    for line in lines:
        record = _record(line)
        if isinstance(record, dict) and record.get("kind") == "thumbnail":
            thumb = _thumbnail(record.get("png"), thumb)
            continue
        if isinstance(record, dict) and record.get("kind") == "current":
            ref = record.get("ref")       # which DPJ draws next: no work is lost with a bad one
            current = ref if ref is None or (isinstance(ref, str) and ref in dpjs) else current
            continue
        try:
            if record is None:
                break        # the line the crash cut short (and anything after it)
            _apply(record, actions, dpjs, photos)
        except (TexeditorError, KeyError, TypeError, ValueError, AttributeError,
                ArithmeticError):
            break            # keep what was complete before a damaged record
        logs += record.get("kind") == "log"
    source = start.get("source") if isinstance(start.get("source"), str) else None
    return Recovered(path, tuple(actions), dpjs, source, _start_time(start.get("time")),
                     _changes(start) + max(0, logs - 1), photos, thumb, current)


def _thumbnail(data, before):
    """A thumbnail record's picture, or ``before`` when it is damaged (passed over: no work
    is lost with it)."""
    if not isinstance(data, str) or len(data) > 2 * MAX_THUMB_BYTES:
        return before
    try:
        png = base64.b64decode(data, validate=True)
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(io.BytesIO(png), formats=["PNG"]) as im:
                w, h = im.size
                if im.mode not in ("L", "RGB") or not (MIN_SIDE <= min(w, h)
                                                       and max(w, h) <= THUMB_SIDE):
                    return before
                image = np.asarray(im.convert(im.mode))
    except (OSError, ValueError, SyntaxError, Image.DecompressionBombWarning,
            Image.DecompressionBombError):
        return before
    return np.ascontiguousarray(image, dtype=np.uint8)


def _record(line: bytes):
    """One record, or None when the line is not one (cut short by the crash, or damaged)."""
    try:
        return load_json(line, "a journal record", limit=MAX_JOURNAL_BYTES, constants=True)
    except FormatError:
        return None


def _start_time(value) -> float:
    """The start record's time, or 0.0 when it is not a plausible time (10**400 does not even
    convert to a float; NaN, infinities and years past 9999 cannot be shown as a date)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return 0.0
    if isinstance(value, int) and not 0 <= value <= MAX_START_TIME:
        return 0.0
    value = float(value)
    return value if 0.0 <= value <= MAX_START_TIME else 0.0     # False for NaN


def _apply(record, actions: list, dpjs: dict, photos: dict) -> None:
    kind = record["kind"] if isinstance(record, dict) else None
    if kind == "dpj":
        # the reference is the DPJ's name in the log (as in .texture files); its bytes must hash
        # to it (DPJ.from_bytes checks), else the record is damaged and recovery stops here
        ref = record["ref"]
        if not isinstance(ref, str) or len(ref) > 64:
            raise FormatError("a journal DPJ has no valid reference")
        dpjs[ref] = DPJ.from_bytes(base64.b64decode(record["data"], validate=True),
                                   f"journal DPJ {ref}", ref=ref)      # the bytes must be ref
    elif kind == "exemplar":
        ref = record["ref"]                       # the pixels must hash to it
        if not isinstance(ref, str) or len(ref) > 64:
            raise FormatError("a journal exemplar has no valid reference")
        photos[ref] = read_exemplar_png(base64.b64decode(record["png"], validate=True),
                                        f"journal exemplar {ref}", ref)
    elif kind == "log":
        keep = record["keep"]
        if isinstance(keep, bool) or not isinstance(keep, int) or not 0 <= keep <= len(actions):
            raise FormatError("a journal record keeps more actions than there are")
        if keep + len(record["append"]) > MAX_ACTIONS:
            raise FormatError(f"a journal log of more than {MAX_ACTIONS} actions")
        new = [action_from_json(obj) for obj in record["append"]]
        del actions[keep:]
        actions.extend(new)
    else:
        raise FormatError(f"unknown journal record {kind!r}")
