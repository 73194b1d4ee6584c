"""Safe file writing and reading shared by every format (`.dpj`, `.texture`, PNG exports).

A user file is never left half-written: it is written to a temporary file in the same folder,
flushed to disk and renamed over the target, so a crash leaves either the old file or the new one.
"""

from __future__ import annotations

import errno
import json
import os
import re
import stat
import tempfile
from pathlib import Path
from typing import Callable, BinaryIO

import numpy as np

from .errors import FormatError, InputError


def atomic_write(path: str | os.PathLike, write: Callable[[BinaryIO], None]) -> None:
    """Call ``write(f)`` on a temporary file, fsync it, then rename it to ``path``.

    Any failure (a full disk, a folder that cannot be written) leaves ``path`` as it was and no
    temporary file; it raises an OSError whose ``filename`` is ``path`` — never the hidden
    temporary file, which the user has never heard of."""
    path = Path(path)
    try:
        _atomic_write(path, write)
    except OSError as exc:
        raise _naming(exc, path) from None


def _naming(exc: OSError, path: Path) -> OSError:
    """``exc`` again, naming ``path`` (OSError(errno, …) picks the subclass: ENOSPC stays an
    OSError, EACCES a PermissionError)."""
    if exc.errno is None:
        return OSError(errno.EIO, str(exc) or type(exc).__name__, os.fspath(path))
    return OSError(exc.errno, exc.strerror or os.strerror(exc.errno), os.fspath(path))


def write_file(path: str | os.PathLike, data: bytes, error=FormatError) -> None:
    """Write ``data`` to ``path`` atomically; a failure is ``error`` naming ``path`` and why
    ("…: cannot write (No space left on device)"), with ``path`` left as it was."""
    try:
        atomic_write(path, lambda f: f.write(data))
    except OSError as exc:
        raise error(f"{path}: cannot write ({exc.strerror or exc})") from None


def _atomic_write(path: Path, write: Callable[[BinaryIO], None]) -> None:
    try:
        mode = os.stat(path).st_mode
    except (FileNotFoundError, NotADirectoryError):
        mode = None
    if mode is not None and not stat.S_ISREG(mode):   # renaming over it would replace a
        raise OSError(errno.EINVAL, f"it is {describe_kind(mode)}, not a regular file",
                      os.fspath(path))             # device, a FIFO or a folder
    folder = path.parent if str(path.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=folder)
    try:
        os.chmod(tmp, _mode_for(path))
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    _fsync_folder(folder)


def _mode_for(path: Path) -> int:
    """Keep an existing file's permissions; a new file gets the usual 0666 minus the umask
    (mkstemp's own 0600 would hide the user's files from their other programs)."""
    try:
        return path.stat().st_mode & 0o7777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> None:
    atomic_write(path, lambda f: f.write(data))


def _fsync_folder(folder: Path) -> None:
    """Make the rename itself durable (POSIX); harmless where folders cannot be opened."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def describe_kind(mode: int) -> str:
    """What a file that is not a regular file is, in words ("a FIFO", "a character device"…)."""
    for test, words in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                        (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                        (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return words
    return "not a regular file"


def _a(what: str) -> str:
    return f"{'an' if what[:1].lower() in 'aeio' else 'a'} {what}"


def as_path(path) -> Path:
    """A file's path from text, a path object or bytes (what ``open`` takes); anything else
    is an InputError naming what was given, not a TypeError from deep inside pathlib."""
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"a file path must be text or a path, got {type(path).__name__} "
                         f"{path!r:.40}")
    return Path(path)


def check_regular(path: str | os.PathLike, what: str, error=FormatError) -> os.stat_result:
    """Refuse anything but an existing regular file (symbolic links followed) *before* it is
    opened: a FIFO would block the reader forever, a device (``/dev/zero``) never ends, and
    their ``st_size`` is 0, so no size check can bound them. Returns the file's stat."""
    path = as_path(path)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except PermissionError:
        raise error(f"{path}: permission denied") from None
    except (OSError, ValueError) as exc:
        raise error(f"{path}: cannot read ({getattr(exc, 'strerror', None) or exc})") from None
    if stat.S_ISDIR(st.st_mode):
        raise error(f"{path}: is a folder, not {_a(what)}")
    if not stat.S_ISREG(st.st_mode):
        raise error(f"{path}: is {describe_kind(st.st_mode)}, not a regular file: "
                    f"not {_a(what)}")
    return st


def read_limited(path: str | os.PathLike, limit: int, what: str, error=FormatError) -> bytes:
    """Read a whole regular file of at most ``limit`` bytes.

    Only regular files are read (see `check_regular`); the file is opened non-blocking and
    checked again once open (it may have been swapped meanwhile), and never more than
    ``limit`` + 1 bytes are read, whatever its size said (a file growing while read, a size
    the file system reports wrongly)."""
    path = as_path(path)
    check_regular(path, what, error)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) \
        | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except IsADirectoryError:
        raise error(f"{path}: is a folder, not {_a(what)}") from None
    except PermissionError:
        raise error(f"{path}: permission denied") from None
    except OSError as exc:
        raise error(f"{path}: cannot read ({exc.strerror or exc})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise error(f"{path}: is {describe_kind(st.st_mode)}, not a regular file: "
                        f"not {_a(what)}")
        if st.st_size > limit:
            raise error(f"{path}: {what} is {st.st_size} bytes, more than the limit of {limit}")
        chunks, size = [], 0
        while size <= limit:
            chunk = os.read(fd, min(2**24, limit + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        if size > limit:
            raise error(f"{path}: {what} is more than the limit of {limit} bytes")
        return b"".join(chunks)
    except OSError as exc:
        raise error(f"{path}: cannot read ({exc.strerror or exc})") from None
    finally:
        os.close(fd)


# -- bounded JSON ---------------------------------------------------------------------------------

MAX_JSON_DEPTH = 64
"""Deepest nesting of arrays and objects any JSON texeditor reads may have (its own files nest
at most 6 deep). A text of nested empty arrays 1 MB long would otherwise expand to gigabytes of
Python lists, or overflow the parser's recursion."""

_JSON_STRING = re.compile(rb'"[^"\\]*(?:\\.[^"\\]*)*"', re.DOTALL)
_NOT_BRACKETS = bytes(b for b in range(256) if b not in b"[]{}")
_BRACKET_STEP = np.zeros(256, dtype=np.int8)
_BRACKET_STEP[list(b"[{")] = 1
_BRACKET_STEP[list(b"]}")] = -1


def json_depth(data: bytes | str) -> int:
    """The deepest nesting of ``[``/``{`` in a JSON text, brackets inside strings not counted."""
    return json_shape(data)[0]


def json_shape(data: bytes | str) -> tuple[int, int]:
    """(deepest nesting, number of arrays and objects) of a JSON text, brackets inside strings
    not counted.

    A cheap scan (regular expressions and numpy, no Python loop per character) made before
    parsing; for a text that is not valid JSON the figure is only an estimate, and the parse
    that follows refuses the text anyway."""
    if isinstance(data, str):
        data = data.encode("utf-8", "surrogatepass")
    brackets = _JSON_STRING.sub(b"", data).translate(None, _NOT_BRACKETS)
    steps = _BRACKET_STEP[np.frombuffer(brackets, dtype=np.uint8)]
    containers = int(np.count_nonzero(steps > 0))
    deepest, level = 0, 0
    for start in range(0, len(steps), 2**20):
        depth = np.cumsum(steps[start:start + 2**20], dtype=np.int64) + level
        deepest = max(deepest, int(depth.max()))
        level = int(depth[-1])
    return deepest, containers


def load_json(data: bytes | str, what: str, *, limit: int, max_depth: int = MAX_JSON_DEPTH,
              max_containers: int | None = None, error=FormatError, constants: bool = False):
    """Parse a JSON text (bytes are UTF-8) after bounding its size and its nesting depth.

    Every JSON texeditor reads from outside (files, members of archives, bank cells, journal
    lines, recipes, envelopes, libraries) goes through here: a text longer than ``limit``
    bytes/characters, nesting deeper than ``max_depth``, or holding more than
    ``max_containers`` arrays and objects (default: one per 8 bytes of ``limit``, so that a
    text at the limit made only of ``[]`` parses in well under 1 GiB) is refused *before* it
    is parsed.
    ``NaN``/``Infinity`` are refused unless ``constants``. Any defect is ``error`` (a
    FormatError unless told) whose message starts with ``what``."""
    if not isinstance(data, (bytes, bytearray, memoryview, str)):
        raise error(f"{what} is not a JSON text")
    if len(data) > limit:
        unit = "characters" if isinstance(data, str) else "bytes"
        raise error(f"{what} is {len(data)} {unit} long, more than the limit of {limit}")
    depth, containers = json_shape(bytes(data) if not isinstance(data, str) else data)
    if depth > max_depth:
        raise error(f"{what} nests {depth} levels deep, more than the limit of {max_depth}")
    if max_containers is None:
        max_containers = max(limit // 8, 4096)
    if containers > max_containers:
        raise error(f"{what} holds {containers} arrays and objects, more than the limit of "
                    f"{max_containers}")
    try:
        text = data if isinstance(data, str) else bytes(data).decode("utf-8")
        if constants:
            return json.loads(text)
        return json.loads(text, parse_constant=_no_json_constant)
    except UnicodeDecodeError:
        raise error(f"{what} is not valid JSON (not UTF-8 text)") from None
    except (ValueError, RecursionError) as exc:   # JSONDecodeError is a ValueError
        raise error(f"{what} is not valid JSON ({str(exc).splitlines()[0][:120]})") from None


def _no_json_constant(token):
    raise ValueError(f"{token} is not allowed")


def output_path(path: str, allowed: tuple[str, ...]) -> Path:
    """A command's output file, checked before any work: a known suffix, an existing folder."""
    out = Path(path)
    if out.suffix.lower() not in allowed:
        raise InputError(f"the output must end with {', '.join(allowed)}: got {path!r}")
    if not out.parent.is_dir():
        what = "is not a folder" if out.parent.exists() else "does not exist"
        raise InputError(f"the output folder {str(out.parent)!r} {what}")
    return out
