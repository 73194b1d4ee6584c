"""The spot library (thesis §3.3.3b: spots "standardisées, issues d'une banque ou entrées
manuellement"): standard envelopes, and the user's own saved as JSON in the user data folder.

The spot editor lists, saves and removes entries; an entry is an envelope and the perturbation it
was saved with. The file is ``spots.json`` in the user data directory (`userdata`: platformdirs,
``TEXEDITOR_DATA`` overrides the folder). Writes are atomic; every entry read is validated, and a
damaged entry is skipped with a message instead of hiding the others.
"""

from __future__ import annotations

import os
import re
from dataclasses import asdict, dataclass, field
from pathlib import Path

from ..errors import FormatError, InputError
from .envelope import Envelope, Meridian, Parallel, Perturbation
from ..userdata import ITEM_ERRORS, MAX_ITEMS, data_dir, read_library, write_library

FILE_NAME = "spots.json"
KIND = "spots"
VERSION = 1
MAX_NAME = 64
_NAME = re.compile(r"^[^\x00-\x1f]{1,64}$")


@dataclass(frozen=True)
class LibrarySpot:
    """A named envelope with the perturbation it was saved with; ``standard`` ones are built in."""

    name: str
    envelope: Envelope
    perturbation: Perturbation = field(default_factory=Perturbation)
    standard: bool = False

    def to_json(self) -> dict:
        return {"name": self.name, "envelope": self.envelope.to_json(),
                "perturbation": asdict(self.perturbation)}

    @classmethod
    def from_json(cls, obj) -> "LibrarySpot":
        if not isinstance(obj, dict):
            raise InputError("an entry must be a JSON object")
        unknown = sorted(set(obj) - {"name", "envelope", "perturbation"})
        if unknown:
            raise InputError(f"unexpected fields {unknown}")
        name = check_name(obj.get("name"))
        pert = obj.get("perturbation", {})
        if not isinstance(pert, dict):
            raise InputError("its perturbation must be a JSON object")
        fields = set(Perturbation.__dataclass_fields__)
        if set(pert) - fields:
            raise InputError(f"unexpected perturbation fields {sorted(set(pert) - fields)}")
        try:
            perturbation = Perturbation(**pert)
        except TypeError as exc:
            raise InputError(f"bad perturbation ({exc})") from None
        return cls(name, Envelope.from_json(obj.get("envelope")), perturbation)


def check_name(name) -> str:
    if not isinstance(name, str) or not _NAME.match(name.strip() or "\x00"):
        raise InputError(f"a spot's name must be 1..{MAX_NAME} printable characters")
    return name.strip()


def standard_spots() -> list[LibrarySpot]:
    """The built-in spots: shapes that make good stones, pebbles, leaves and bark knots."""
    def env(a, b, meridians, kind="interpolating_spline", parallels=()):
        return Envelope(a, b, tuple(Meridian(*m) for m in meridians),
                        tuple(Parallel(*p) for p in parallels), kind)

    return [LibrarySpot(name, e, p, standard=True) for name, e, p in [
        ("Ellipse", Envelope.ellipse(40, 24), Perturbation()),
        ("Pebble", env((0, -18), (0, 18), [(0.22, 9, 10), (0.5, 13, 12, True), (0.8, 10, 8)]),
         Perturbation(contour=0.12, frequency=5, fractal=0.08, h=0.6, interior="levels",
                      density=0.3, scale=4)),
        ("Stone", env((2, -20), (-1, 19), [(0.15, 8, 9), (0.45, 15, 13, True), (0.8, 11, 9)],
                      "catmull_rom"),
         Perturbation(contour=0.18, frequency=7, fractal=0.12, h=0.45, interior="levels",
                      density=0.35, scale=3)),
        ("Leaf", env((0, -24), (0, 24), [(0.2, 6, 6), (0.45, 10, 10, True), (0.75, 7, 7)],
                     "linear"),
         Perturbation(contour=0.05, frequency=12)),
        ("Bark knot", env((-22, 0), (22, 0), [(0.3, 6, 7), (0.5, 8, 8, True), (0.7, 6, 6)],
                          "catmull_rom"),
         Perturbation(contour=0.08, frequency=9, fractal=0.1, h=0.5, interior="levels",
                      density=0.45, scale=5)),
        ("Brick", env((0, -22), (0, 22), [(0.5, 9, 9, True)], "linear",
                      [(9, 0.04, 0.96), (-9, 0.04, 0.96)]),
         Perturbation(contour=0.04, frequency=10, fractal=0.06, h=0.5)),
    ]]


class SpotLibrary:
    """The standard spots followed by the user's, read from ``folder/spots.json``.

    ``problems`` lists what could not be read (a damaged file or entry), for the GUI to show.
    """

    def __init__(self, folder: str | os.PathLike | None = None):
        self.folder = Path(folder) if folder is not None else data_dir()
        self.problems: list[str] = []
        self._user: list[LibrarySpot] = []
        self._damaged = False       # the file holds something we could not read: keep it
        self.reload()

    @property
    def path(self) -> Path:
        return self.folder / FILE_NAME

    def reload(self) -> None:
        self.problems = []
        try:
            self._user = self._read()
        except FormatError as exc:
            self._user = []
            self.problems.append(str(exc))
        self._damaged = bool(self.problems)

    def entries(self) -> list[LibrarySpot]:
        return standard_spots() + list(self._user)

    def names(self) -> list[str]:
        return [e.name for e in self.entries()]

    def get(self, name: str) -> LibrarySpot:
        for entry in reversed(self.entries()):
            if entry.name == name:
                return entry
        raise InputError(f"there is no spot named {name!r} in the library")

    def save(self, name: str, envelope: Envelope, perturbation: Perturbation | None = None) -> \
            LibrarySpot:
        """Add an entry (or replace the user's entry of that name); standard names are kept."""
        name = check_name(name)
        if any(s.name == name for s in standard_spots()):
            raise InputError(f"{name!r} is a standard spot: save yours under another name")
        entry = LibrarySpot(name, envelope, perturbation or Perturbation())
        user = [e for e in self._user if e.name != name] + [entry]
        if len(user) > MAX_ITEMS:
            raise InputError(f"the library holds at most {MAX_ITEMS} spots")
        self._write(user)
        self._user = user
        return entry

    def remove(self, name: str) -> None:
        if any(s.name == name for s in standard_spots()):
            raise InputError(f"{name!r} is a standard spot: it cannot be removed")
        user = [e for e in self._user if e.name != name]
        if len(user) == len(self._user):
            raise InputError(f"there is no spot of yours named {name!r}")
        self._write(user)
        self._user = user

    # -- the file ---------------------------------------------------------------------------------
    def _read(self) -> list[LibrarySpot]:
        out: list[LibrarySpot] = []
        for k, item in enumerate(read_library(self.path, KIND, VERSION)):
            try:
                entry = LibrarySpot.from_json(item)
            except ITEM_ERRORS as exc:
                self.problems.append(f"{self.path}: entry {k + 1} skipped: {exc}")
                continue
            out = [e for e in out if e.name != entry.name] + [entry]
        return out

    def _write(self, entries: list[LibrarySpot]) -> None:
        if self._damaged and self.path.exists():
            self._set_aside()
            self._damaged = False
        write_library(self.path, KIND, [e.to_json() for e in entries], VERSION)

    def _set_aside(self) -> None:
        """Keep a damaged file under another name before writing a new one: never lose data."""
        k = 1
        while (aside := self.path.with_name(f"{FILE_NAME}.damaged-{k}")).exists():
            k += 1
        os.replace(self.path, aside)
        self.problems.append(f"the damaged library was kept as {aside.name}")
