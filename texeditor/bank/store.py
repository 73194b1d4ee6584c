"""The texture bank (thesis §5.4.2, digest §10): every texture kept as its recipe — its DPJs,
the optimised action log, grain and density parameters — with a thumbnail, keys and attributes.

It sits after the Document (a finished texture goes in) and before History (opening an entry
replays its log and checks the result's SHA-256). Storage is SQLite in the user data folder
(``TEXEDITOR_BANK`` names another file); the schema is versioned and every write a transaction.
"""

from __future__ import annotations

import io
import json
import math
import os
import re
import sqlite3
import threading
import time
import zipfile
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import attributes as attrs
from ..recipe.actions import Synthesize, SynthesizeScales, dpj_refs, exemplar_refs
from ..recipe.codec import log_text, read_log
from ..recipe.document import Document, result_hash
from ..recipe.exemplars import exemplar_png, read_exemplar_png
from ..markov.dpj import DPJ
from ..errors import (Cancelled, FormatError, InputError, ReplayError, TexeditorError,
                     check_unicode)
from ..fileio import atomic_write, atomic_write_bytes, load_json
from ..recipe.history import History
from ..recipe.replay import replay
from ..recipe.stored import Recipe, open_recipe
from ..recipe.logopt import optimize
from ..resources import ROOT as RESOURCES
from ..texture.plates import document_picture
from ..recipe.texturefile import (MAX_ACTIONS, MAX_DESCRIPTION_CHARS, TextureFile,
                          read_texture, texture_bytes)

BANK_ENV, DATA_ENV = "TEXEDITOR_BANK", "TEXEDITOR_DATA"
FILENAME = "bank.sqlite"
SCHEMA_VERSION = 3
THUMB = 128                       # thumbnail side in pixels: a central crop shown 1:1 (or enlarged)
MAX_NAME_CHARS, MAX_TAGS, MAX_TAG_CHARS = 200, 64, 64
BUILTIN_DIR = RESOURCES / "bank"
PICTURES_DIR = BUILTIN_DIR / "pictures"   # <SHA-256>.npz: the built-ins' textures, replay-free
TONES = "tones"                            # ... and <SHA-256>.npz in it: their tone pictures
MAX_PICTURE_BYTES = 64 * 2**20
_SHA256 = re.compile(r"^[0-9a-f]{64}$")
GRAIN_TYPES = ("render_grains",)  # §5.3: grain shape, explosion, compression (texture_actions)
_SEP = "\x1f"                     # joins tags in one SQL value (a character no tag may hold)


def _first_dpjs(first, recipe: Recipe):
    """What a log's first step, a synthesis, draws from (render_result's argument: a DPJ, or a
    multi-scale step's DPJs) when the recipe holds it; None for any other step."""
    if isinstance(first, Synthesize) and first.dpj in recipe.dpjs:
        return recipe.dpjs[first.dpj]
    if isinstance(first, SynthesizeScales) and all(r in recipe.dpjs for r in first.dpjs):
        return [recipe.dpjs[r] for r in first.dpjs]
    return None


class BankError(TexeditorError):
    """The bank cannot be used: damaged or foreign file, locked, unknown entry, newer schema."""


# -- what is stored ------------------------------------------------------------------------------

@dataclass(frozen=True)
class Record:
    """A texture ready to enter the bank; ``thumbnail``/``attributes`` None = computed later."""

    name: str
    description: str
    tags: tuple
    width: int
    height: int
    levels: int
    actions: tuple
    dpjs: dict
    main_dpj: str | None
    grain: dict
    sha256: str
    thumbnail: bytes | None = None
    attributes: attrs.Attributes | None = None
    exemplars: dict = field(default_factory=dict)     # ref → uint8 photo (the model steps')


@dataclass(frozen=True)
class Entry:
    """One row of the bank as a browser shows it (the recipe is read only to open it)."""

    id: int
    name: str
    description: str
    tags: tuple
    width: int
    height: int
    levels: int
    actions: int
    sha256: str
    attributes: attrs.Attributes | None
    builtin: bool
    parent: int | None
    created: float
    modified: float
    trashed: float | None = None
    grain: dict = field(default_factory=dict)

    @property
    def pending(self) -> bool:
        """Attributes and thumbnail not computed yet (built-ins on first run, after upgrades)."""
        return self.attributes is None


@dataclass(frozen=True)
class Check:
    """One line of a verification: an entry (or the database itself, id None) and its state."""

    id: int | None
    name: str
    ok: bool
    message: str


# -- schema: migrations[v] turns version v into v + 1 ------------------------------------------

# Entries hold only small columns, so listing and filtering 10,000 of them never reads a log or
# a thumbnail: those live in their own tables, one row per entry.
_V1 = [
    """CREATE TABLE entries (
        id INTEGER PRIMARY KEY,
        name TEXT NOT NULL,
        description TEXT NOT NULL DEFAULT '',
        width INTEGER NOT NULL, height INTEGER NOT NULL, levels INTEGER NOT NULL,
        action_count INTEGER NOT NULL,
        main_dpj TEXT,                        -- the DPJ that was current (maybe unused by the log)
        grain TEXT NOT NULL DEFAULT '{}',     -- grain and density parameters (JSON)
        sha256 TEXT NOT NULL,                 -- result_hash() of the replayed texture
        contrast REAL, granularity REAL, density REAL, directivity REAL, orientation REAL,
        regularity REAL,
        builtin INTEGER NOT NULL DEFAULT 0,
        created REAL NOT NULL, modified REAL NOT NULL)""",
    """CREATE TABLE logs (                   -- the optimised log: {"actions": [...]}
        entry INTEGER PRIMARY KEY REFERENCES entries(id) ON DELETE CASCADE,
        actions TEXT NOT NULL)""",
    """CREATE TABLE thumbnails (             -- PNG; no row until computed
        entry INTEGER PRIMARY KEY REFERENCES entries(id) ON DELETE CASCADE,
        png BLOB NOT NULL)""",
    "CREATE TABLE dpjs (ref TEXT PRIMARY KEY, data BLOB NOT NULL) WITHOUT ROWID",
    """CREATE TABLE entry_dpjs (
        entry INTEGER NOT NULL REFERENCES entries(id) ON DELETE CASCADE,
        ref TEXT NOT NULL REFERENCES dpjs(ref),
        PRIMARY KEY (entry, ref)) WITHOUT ROWID""",
    """CREATE TABLE tags (
        entry INTEGER NOT NULL REFERENCES entries(id) ON DELETE CASCADE,
        tag TEXT NOT NULL,
        PRIMARY KEY (entry, tag)) WITHOUT ROWID""",
    "CREATE INDEX tags_by_tag ON tags (tag)",
    "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL) WITHOUT ROWID",
]
_V2 = [   # the trash, versions, two more attributes and a recomputation mark
    "ALTER TABLE entries ADD COLUMN period REAL",
    "ALTER TABLE entries ADD COLUMN coarseness REAL",
    "ALTER TABLE entries ADD COLUMN attributes_version INTEGER NOT NULL DEFAULT 0",
    "ALTER TABLE entries ADD COLUMN parent INTEGER REFERENCES entries(id) ON DELETE SET NULL",
    "ALTER TABLE entries ADD COLUMN trashed REAL",
    "CREATE INDEX entries_live ON entries (trashed, builtin, modified)",
]
_V3 = [   # the exemplar photos of the model steps (random-phase noise, texton, histogram)
    "CREATE TABLE exemplars (ref TEXT PRIMARY KEY, png BLOB NOT NULL) WITHOUT ROWID",
    """CREATE TABLE entry_exemplars (
        entry INTEGER NOT NULL REFERENCES entries(id) ON DELETE CASCADE,
        ref TEXT NOT NULL REFERENCES exemplars(ref),
        PRIMARY KEY (entry, ref)) WITHOUT ROWID""",
]
MIGRATIONS = [_V1, _V2, _V3]
_ATTR_COLUMNS = attrs.NAMES
# the user's entries newest first, then the built-ins in the order they were installed
_NEWEST_FIRST = "e.builtin, CASE WHEN e.builtin THEN -e.id ELSE e.modified END DESC, e.id DESC"
_ENTRY_COLUMNS = ("e.id, e.name, e.description, e.width, e.height, e.levels, e.action_count, "
                  "e.sha256, e.builtin, e.parent, e.created, e.modified, e.trashed, e.grain, "
                  "e.attributes_version, " + ", ".join(f"e.{c}" for c in _ATTR_COLUMNS) + ", "
                  f"(SELECT group_concat(tag, '{_SEP}') FROM tags t WHERE t.entry = e.id)")


def default_path() -> Path:
    """``$TEXEDITOR_BANK`` (a file, or a folder to hold bank.sqlite), else the user data folder
    (``$TEXEDITOR_DATA`` or platformdirs), where the grain library and presets also live."""
    env = os.environ.get(BANK_ENV)
    if env:
        path = Path(env).expanduser()
        return path / FILENAME if path.is_dir() else path
    data = os.environ.get(DATA_ENV)
    if data:
        return Path(data).expanduser() / FILENAME
    from platformdirs import user_data_dir
    return Path(user_data_dir("texeditor", appauthor=False)) / FILENAME


class Bank:
    """An open bank. Safe to share between threads (one lock around the connection); several
    Bank objects, in one process or many, may use one file at once (SQLite WAL mode).

    ``builtins`` installs the entries of resources/bank when the file is new.
    """

    def __init__(self, path=None, *, timeout: float = 5.0, builtins: bool = True,
                 pictures=None):
        self.path = Path(path) if path is not None else default_path()
        self.pictures = Path(pictures if pictures is not None else PICTURES_DIR)  # see stored_picture
        self.timeout = timeout
        self._lock = threading.RLock()
        self._feature_cache = None
        self.skipped: list[str] = []     # damaged rows `entries` left out (see BadRow)
        self._data_version = None
        self._conn = self._connect()
        self._conn.text_factory = _text      # a TEXT cell that is not UTF-8: a damaged cell
        try:
            self.fts = _has_fts5(self._conn)
            fresh = self._migrate()
            self._sync_fts()
            if fresh and builtins:
                self.install_builtins()
        except BaseException:
            self._conn.close()
            raise

    # -- opening ---------------------------------------------------------------------------------
    read_only = False        # a bank file (or folder) this user may not write: opened read-only

    def _connect(self) -> sqlite3.Connection:
        if _read_only(self.path):
            return self._connect_read_only()
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            conn = sqlite3.connect(self.path, timeout=self.timeout, isolation_level=None,
                                   check_same_thread=False)
        except (OSError, sqlite3.Error) as exc:
            raise BankError(f"{self.path}: cannot open the bank ({exc})") from None
        try:
            conn.execute("PRAGMA foreign_keys = ON")
            conn.execute("SELECT count(*) FROM sqlite_master").fetchone()
        except (sqlite3.Error, UnicodeDecodeError) as exc:
            conn.close()
            raise self._error(exc) from None
        return conn

    def _connect_read_only(self) -> sqlite3.Connection:
        """A bank this user cannot write (a shared or archived copy): listed, searched, opened
        and verified, never changed (a change is refused by SQLite, reported as a BankError).
        A WAL bank in a read-only folder has no shared-memory file SQLite could make: it is
        then opened as immutable."""
        self.read_only = True
        uri = self.path.resolve().as_uri() + "?mode=ro"
        for extra in ("", "&immutable=1"):
            try:
                conn = sqlite3.connect(uri + extra, uri=True, timeout=self.timeout,
                                       isolation_level=None, check_same_thread=False)
            except (OSError, sqlite3.Error) as exc:
                raise BankError(f"{self.path}: cannot open the bank ({exc})") from None
            try:
                conn.execute("PRAGMA query_only = ON")
                conn.execute("SELECT count(*) FROM sqlite_master").fetchone()
                return conn
            except (sqlite3.Error, UnicodeDecodeError) as exc:
                conn.close()
                if extra or "unable to open" not in str(exc):
                    raise self._error(exc) from None
        raise AssertionError("unreachable")

    def _migrate(self) -> bool:
        """Bring the schema to SCHEMA_VERSION; True when the bank was just created. A file that
        is not a bank, or is newer, is refused before anything is written to it."""
        self._check_kind()
        if self.read_only:
            if self._version() != SCHEMA_VERSION:
                raise BankError(f"{self.path}: this bank is read-only and of an older schema "
                                f"({self._version()}); open it once where it can be written "
                                "to bring it up to date")
            return False
        try:
            self._conn.execute("PRAGMA journal_mode = WAL")     # readers never wait for writers
            self._conn.execute("PRAGMA synchronous = FULL")     # a commit survives a power cut
        except sqlite3.Error as exc:
            raise self._error(exc) from None
        if self._version() == SCHEMA_VERSION:
            return False
        with self._write() as conn:      # re-read inside: another program may have migrated
            version = self._check_kind()
            for v in range(version, SCHEMA_VERSION):
                for statement in MIGRATIONS[v]:
                    conn.execute(statement)
                conn.execute(f"PRAGMA user_version = {v + 1}")
            return version == 0

    def _version(self) -> int:
        return self._read("PRAGMA user_version")[0][0]

    def _check_kind(self) -> int:
        version = self._version()
        if version < 0:
            raise BankError(f"{self.path}: the bank's schema version {version} is invalid "
                            "(a damaged or foreign file)")
        if version > SCHEMA_VERSION:
            raise BankError(f"{self.path}: this bank was made by a newer texeditor (schema "
                            f"{version}); this program reads up to {SCHEMA_VERSION}")
        if version == 0 and self._read("SELECT count(*) FROM sqlite_master "
                                       "WHERE name NOT LIKE 'sqlite_%'")[0][0]:
            raise BankError(f"{self.path}: an SQLite database, but not a texture bank")
        return version

    def _sync_fts(self) -> None:
        """Create the full-text index if missing, or rebuild it after writes made by a SQLite
        without FTS5; without FTS5, search falls back to substring matching (``search_mode``)."""
        if not self.fts:
            return
        exists = self._read("SELECT 1 FROM sqlite_master WHERE name = 'search'")
        if self.read_only:        # nothing can be indexed: substring matching unless indexed
            self.fts = bool(exists) and not self._read(
                "SELECT 1 FROM meta WHERE key = 'fts' AND value = 'stale'")
            return
        stale = self._read("SELECT value FROM meta WHERE key = 'fts'")
        if exists and not (stale and stale[0][0] == "stale"):
            return
        with self._write() as conn:
            if not exists:
                conn.execute("CREATE VIRTUAL TABLE search USING fts5(name, description, tags, "
                             "tokenize = 'unicode61 remove_diacritics 2')")
            conn.execute("DELETE FROM search")
            ids = [r[0] for r in conn.execute("SELECT id FROM entries")]
            self._index(conn, ids)
            conn.execute("DELETE FROM meta WHERE key = 'fts'")

    def changed_elsewhere(self) -> bool:
        """True when another connection (another window, the command line) committed a change
        since the last call: a browser then lists the bank again."""
        version = self._read("PRAGMA data_version")[0][0]
        changed, self._data_version = version != self._data_version, version
        return changed

    @property
    def search_mode(self) -> str:
        return ("full text (SQLite FTS5)" if self.fts else
                "substring matching (this SQLite has no FTS5 full-text module)")

    def close(self) -> None:
        with self._lock:
            self._conn.close()

    def __enter__(self) -> "Bank":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # -- low level: every read under the lock, every write in one transaction --------------------
    def _read(self, sql: str, params=()) -> list:
        with self._lock:
            try:
                return self._conn.execute(sql, params).fetchall()
            except (sqlite3.Error, UnicodeDecodeError) as exc:
                raise self._error(exc) from None

    @contextmanager
    def _write(self):
        with self._lock:
            try:
                self._conn.execute("BEGIN IMMEDIATE")
            except sqlite3.Error as exc:
                raise self._error(exc) from None
            try:
                yield self._conn
                self._conn.execute("COMMIT")
            except BaseException as exc:
                if self._conn.in_transaction:
                    self._conn.execute("ROLLBACK")
                if isinstance(exc, sqlite3.Error):
                    raise self._error(exc) from None
                raise

    def _error(self, exc: sqlite3.Error | UnicodeDecodeError) -> BankError:
        """What went wrong, for the user (a damaged schema's text, not UTF-8, fails to decode
        in SQLite's own error message)."""
        if isinstance(exc, UnicodeDecodeError):
            return BankError(f"{self.path}: not a texture bank, or damaged (text that is not "
                             "UTF-8 in its schema)")
        text = str(exc)
        if "locked" in text or "busy" in text:
            return BankError(f"{self.path}: the bank is busy (another program is writing to it "
                             f"for more than {self.timeout:g} s); try again")
        if isinstance(exc, sqlite3.DatabaseError) and not isinstance(exc, sqlite3.OperationalError):
            return BankError(f"{self.path}: not a texture bank, or damaged ({text})")
        return BankError(f"{self.path}: {text}")

    # -- adding ----------------------------------------------------------------------------------
    def add(self, source, name: str, *, tags=(), description: str = "", parent: int | None = None,
            progress=None, cancel=None) -> int:
        """Store a History's applied log (or a Document's log) as a new entry; returns its id."""
        record = make_record(source, name, tags=tags, description=description,
                             progress=progress, cancel=cancel)
        return self.insert(record, parent=parent)

    def insert(self, record: Record, *, builtin: bool = False, parent: int | None = None) -> int:
        return self.insert_many([record], builtin=builtin, parent=parent)[0]

    def insert_many(self, records, *, builtin: bool = False, parent: int | None = None) -> list:
        """Insert records in one transaction (all or none)."""
        ids = []
        with self._write() as conn:
            if parent is not None:
                self._existing(conn, parent)
            for record in records:
                ids.append(self._insert(conn, record, builtin, parent))
            self._index(conn, ids)
            _features_changed(conn, added_only=True)
        return ids

    def _insert(self, conn, r: Record, builtin: bool, parent) -> int:
        now = time.time()
        a = r.attributes
        values = {
            "name": r.name, "description": r.description, "width": r.width, "height": r.height,
            "levels": r.levels, "action_count": len(r.actions), "main_dpj": r.main_dpj,
            "grain": json.dumps(r.grain, allow_nan=False), "sha256": r.sha256,
            "builtin": int(builtin), "parent": parent, "created": now, "modified": now,
            "attributes_version": attrs.VERSION if a is not None else 0,
            **{c: (getattr(a, c) if a is not None else None) for c in _ATTR_COLUMNS}}
        cursor = conn.execute(f"INSERT INTO entries ({', '.join(values)}) "
                              f"VALUES ({', '.join('?' * len(values))})", tuple(values.values()))
        entry = cursor.lastrowid
        conn.execute("INSERT INTO logs (entry, actions) VALUES (?, ?)",
                     (entry, log_text(r.actions)))
        if r.thumbnail is not None:
            conn.execute("INSERT INTO thumbnails (entry, png) VALUES (?, ?)", (entry, r.thumbnail))
        for ref, dpj in r.dpjs.items():
            self._store_dpj(conn, ref, dpj)
            conn.execute("INSERT INTO entry_dpjs (entry, ref) VALUES (?, ?)", (entry, ref))
        for ref, image in r.exemplars.items():
            self._store_exemplar(conn, ref, image)
            conn.execute("INSERT INTO entry_exemplars (entry, ref) VALUES (?, ?)", (entry, ref))
        conn.executemany("INSERT INTO tags (entry, tag) VALUES (?, ?)",
                         [(entry, t) for t in r.tags])
        return entry

    @staticmethod
    def _store_dpj(conn, ref: str, dpj: DPJ) -> None:
        """DPJs are shared between entries by reference; a reference never changes meaning."""
        if not dpj.has_ref(ref):
            raise FormatError(f"DPJ reference {ref} names another DPJ than the one given: "
                              "refused (a forged or damaged recipe)")
        row = conn.execute("SELECT data FROM dpjs WHERE ref = ?", (ref,)).fetchone()
        if row is None:
            conn.execute("INSERT INTO dpjs (ref, data) VALUES (?, ?)", (ref, dpj.to_bytes()))
        elif bytes(row[0]) != dpj.to_bytes() and DPJ.from_bytes(bytes(row[0])) != dpj:
            raise FormatError(f"DPJ reference {ref} already names another DPJ in the bank: "
                              "refused (a forged or damaged recipe)")

    @staticmethod
    def _store_exemplar(conn, ref: str, image) -> None:
        """Exemplars are shared by reference too; the PNG stored must give the reference back."""
        png = exemplar_png(image)
        read_exemplar_png(png, f"exemplar {ref}", ref)       # the reference names these pixels
        if conn.execute("SELECT 1 FROM exemplars WHERE ref = ?", (ref,)).fetchone() is None:
            conn.execute("INSERT INTO exemplars (ref, png) VALUES (?, ?)", (ref, png))

    def import_texture(self, path, *, name: str | None = None, tags=None,
                       description: str | None = None, progress=None, cancel=None) -> int:
        """Import a `.texture`: validate it, replay it (its hash must match), optimise its log,
        store it. A file that fails any check changes nothing in the bank."""
        tex = read_texture(path)
        doc = open_recipe(tex.recipe, progress=progress, cancel=cancel)
        record = make_record(doc, name or name_from_file(path),
                             tags=tex.manifest.tags if tags is None else tags,
                             description=(tex.manifest.description if description is None
                                          else description), cancel=cancel)
        return self.insert(record)

    def install_builtins(self, folder: Path = BUILTIN_DIR) -> list:
        """Add the bundled entries (resources/bank/NN-name.texture, NN their place in the
        browser) without replaying them: they are checked, and get thumbnails and attributes,
        in ``prepare_pending``."""
        records = []
        for path in sorted(Path(folder).glob("*.texture")):
            try:
                name = name_from_file(re.sub(r"^\d+[-_ ]", "", path.name))
                records.append(pending_record(read_texture(path), name))
            except TexeditorError:
                continue          # a damaged bundled file is skipped, never fatal
        return self.insert_many(records, builtin=True) if records else []

    # -- finding ---------------------------------------------------------------------------------
    def count(self, *, trash: bool = False) -> int:
        return self._read("SELECT count(*) FROM entries WHERE trashed IS "
                          + ("NOT NULL" if trash else "NULL"))[0][0]

    def find(self, text: str = "", *, tags=(), ranges=None, like: int | None = None,
             trash: bool = False, limit: int | None = None) -> list:
        """Ids of the matching entries, best first: full-text words (prefixes) on names,
        descriptions and tags, every tag given (``tag:x`` or ``#x`` in the text too), attribute
        ranges {name: (lo, hi)} (None = open), and with ``like`` the nearest entries in
        attribute space first (``like`` itself excluded). Otherwise the user's entries newest
        first, then the built-ins."""
        words, text_tags = parse_query(text)
        where, params = ["e.trashed IS " + ("NOT NULL" if trash else "NULL")], []
        if words and self.fts:       # the browser's order, not bm25: ranking 10,000 hits is slow
            where.append("e.id IN (SELECT rowid FROM search WHERE search MATCH ?)")
            params.append(fts_query(words))
        for word in words if not self.fts else ():
            pattern = "%" + re.sub(r"([%_\\])", r"\\\1", word) + "%"
            where.append("(e.name LIKE ? ESCAPE '\\' OR e.description LIKE ? ESCAPE '\\' OR "
                         "EXISTS (SELECT 1 FROM tags t WHERE t.entry = e.id "
                         "AND t.tag LIKE ? ESCAPE '\\'))")
            params += [pattern] * 3
        for tag in normalize_tags(list(tags) + text_tags):
            where.append("EXISTS (SELECT 1 FROM tags t WHERE t.entry = e.id AND t.tag = ?)")
            params.append(tag)
        for name, (lo, hi) in check_ranges(ranges).items():
            if lo is not None:
                where.append(f"e.{name} >= ?")
                params.append(lo)
            if hi is not None:
                where.append(f"e.{name} <= ?")
                params.append(hi)
        order = f" ORDER BY {_NEWEST_FIRST}" if like is None else ""   # likeness sorts itself
        ids = [r[0] for r in self._read(f"SELECT e.id FROM entries e WHERE "
                                        f"{' AND '.join(where)}{order}", params)]
        if like is not None:
            ids = self._nearest(like, ids)
        return ids if limit is None else ids[:max(0, limit)]

    def _nearest(self, like: int, ids: list) -> list:
        """``ids`` (those with attributes, ``like`` excluded) nearest to ``like`` first."""
        table, features, spread = self._features()
        target = np.searchsorted(table, like)
        if target >= len(table) or table[target] != like:
            self.get(like)                         # an unknown entry is a BankError
            raise BankError(f"entry {like} has no attributes yet: it cannot be compared")
        rows = np.searchsorted(table, ids)
        rows = rows[(rows < len(table)) & (table[np.minimum(rows, len(table) - 1)] == ids)]
        rows = rows[table[rows] != like]
        order = attrs.nearest(features[target], features[rows], spread)
        return table[rows][order].tolist()

    def _features(self) -> tuple:
        """(ids in order, feature vectors, their spread) of every entry with attributes, read
        again only after a write that changes attributes, here or in another program: such a
        write bumps the 'features' counter of the meta table. Inserts bump 'features_added'
        instead, and only the new rows are read: their ids are above every id already read."""
        stamps = dict(self._read("SELECT key, value FROM meta "
                                 "WHERE key IN ('features', 'features_added')"))
        stamp, added = stamps.get("features"), stamps.get("features_added")
        cached = self._feature_cache
        if cached is not None and cached[0] == (stamp, added):
            return cached[1]
        if cached is not None and cached[0][0] == stamp:
            ids, values = cached[2]
            after = int(ids[-1]) if len(ids) else 0
            new = self._feature_rows("AND id > ?", (after,))
            ids, values = np.concatenate([ids, new[:, 0].astype(np.int64)]), \
                np.concatenate([values, new[:, 1:]])
        else:
            table = self._feature_rows()
            ids, values = table[:, 0].astype(np.int64), table[:, 1:]
        features = attrs.feature_matrix(values)
        spread = features.std(axis=0) if len(features) else np.ones(features.shape[1])
        self._feature_cache = ((stamp, added), (ids, features, spread), (ids, values))
        return self._feature_cache[1]

    def _feature_rows(self, condition: str = "", params=()) -> np.ndarray:
        """(n, 1 + attributes) floats: id then the attributes of the entries that have them."""
        rows = self._read(f"SELECT id, {', '.join(_ATTR_COLUMNS)} FROM entries "
                          "WHERE attributes_version = ? AND "
                          f"{' AND '.join(f'{c} IS NOT NULL' for c in _ATTR_COLUMNS)} "
                          f"{condition} ORDER BY id", (attrs.VERSION, *params))
        rows = [r for r in rows if all(isinstance(v, (int, float)) and math.isfinite(v)
                                       for v in r)]      # a damaged cell: not comparable
        return np.array(rows, dtype=float).reshape(-1, len(_ATTR_COLUMNS) + 1)

    def search(self, text: str = "", **options) -> list:
        """Like ``find`` but the Entries themselves."""
        return self.entries(self.find(text, **options))

    def similar(self, entry_id: int, k: int = 10) -> list:
        """The k entries nearest to ``entry_id`` in attribute space ("more like this")."""
        return self.search(like=entry_id, limit=k)

    def entries(self, ids=None, *, strict: bool = False) -> list:
        """Entries by id, in the order given (None: every live entry, newest first). A row
        whose cells are damaged is left out and its defect added to ``skipped`` (``strict``:
        raised as a BadRow)."""
        if ids is None:
            ids = self.find()
        found = {}
        ids = list(ids)
        for start in range(0, len(ids), 500):
            chunk = ids[start:start + 500]
            rows = self._read(f"SELECT {_ENTRY_COLUMNS} FROM entries e WHERE e.id IN "
                              f"({', '.join('?' * len(chunk))})", chunk)
            for row in rows:
                try:
                    found[row[0]] = _entry(row)
                except BadRow as exc:
                    if strict:
                        raise
                    self.skipped.append(str(exc))   # listed without it; verify reports it
        return [found[i] for i in ids if i in found]

    def get(self, entry_id: int) -> Entry:
        """One entry; a row whose cells are damaged is a BadRow (a FormatError) naming it."""
        rows = self.entries([entry_id], strict=True)
        if not rows:
            raise BankError(f"the bank has no entry {entry_id}")
        return rows[0]

    def names(self, ids) -> dict:
        """id → (name, tags) for a browser's visible rows (cheaper than whole entries)."""
        ids = list(ids)
        if not ids:
            return {}
        rows = self._read(f"SELECT e.id, e.name, (SELECT group_concat(tag, '{_SEP}') FROM tags t "
                          f"WHERE t.entry = e.id) FROM entries e WHERE e.id IN "
                          f"({', '.join('?' * len(ids))})", ids)
        return {r[0]: (r[1], _split_tags(r[2])) for r in rows
                if isinstance(r[1], str) and isinstance(r[2], (str, type(None)))}

    def thumbnails(self, ids) -> dict:
        """id → PNG bytes (or None while pending), for the rows a browser is about to show."""
        ids = list(ids)
        if not ids:
            return {}
        found = dict(self._read(f"SELECT entry, png FROM thumbnails WHERE entry IN "
                                f"({', '.join('?' * len(ids))})", ids))
        return {i: (bytes(found[i]) if isinstance(found.get(i), bytes) else None) for i in ids}

    def all_tags(self) -> list:
        """(tag, number of live entries) by decreasing use."""
        return [tuple(r) for r in self._read(
            "SELECT tag, count(*) FROM tags JOIN entries e ON e.id = tags.entry "
            "WHERE e.trashed IS NULL AND typeof(tag) = 'text' GROUP BY tag "
            "ORDER BY count(*) DESC, tag")]

    # -- opening ---------------------------------------------------------------------------------
    def recipe(self, entry_id: int) -> Recipe:
        """The entry's log, DPJs, current DPJ and recorded SHA-256, validated like a file (a
        damaged row is a FormatError)."""
        rows = self._read("SELECT e.name, l.actions, e.main_dpj, e.sha256 FROM entries e "
                          "LEFT JOIN logs l ON l.entry = e.id WHERE e.id = ?", (entry_id,))
        if not rows:
            raise BankError(f"the bank has no entry {entry_id}")
        name, log, main, sha256 = rows[0]
        what = f"bank entry {entry_id} “{name}”" if isinstance(name, str) else \
            f"bank entry {entry_id}"
        actions = parse_log(log, what)
        if not isinstance(sha256, str) or not _SHA256.match(sha256):
            raise FormatError(f"{what}: its recorded SHA-256 is damaged")
        dpjs = {}
        for ref, data in self._read("SELECT d.ref, d.data FROM entry_dpjs x JOIN dpjs d "
                                    "ON d.ref = x.ref WHERE x.entry = ?", (entry_id,)):
            if not isinstance(ref, str) or not isinstance(data, bytes):
                raise FormatError(f"{what}: a DPJ row is damaged (its reference must be a "
                                  "TEXT and its data a BLOB)")
            dpjs[ref] = DPJ.from_bytes(bytes(data), f"{what}: DPJ {ref}", ref=ref)  # hash checked
        if main is not None and not isinstance(main, str):
            raise FormatError(f"{what}: its current DPJ is damaged (not a TEXT)")
        if main is not None and main not in dpjs:
            raise FormatError(f"{what}: its current DPJ {main} is missing")
        return Recipe(actions, dpjs, main, sha256, what, self._exemplars(entry_id, what))

    def _exemplars(self, entry_id: int, what: str) -> dict:
        photos = {}
        for ref, png in self._read("SELECT p.ref, p.png FROM entry_exemplars x JOIN exemplars p "
                                   "ON p.ref = x.ref WHERE x.entry = ?", (entry_id,)):
            if not isinstance(ref, str) or not isinstance(png, bytes):
                raise FormatError(f"{what}: an exemplar row is damaged (its reference must be "
                                  "a TEXT and its picture a BLOB)")
            photos[ref] = read_exemplar_png(png, f"{what}: exemplar {ref}", ref)  # hash checked
        return photos

    def open(self, entry_id: int, *, progress=None, cancel=None, **history_options) -> History:
        """Replay an entry into a History and check its hash: a texture that is not the one
        recorded is a ReplayError, never shown."""
        return open_recipe(self.recipe(entry_id), history=True, progress=progress,
                           cancel=cancel, **history_options)

    def stored_picture(self, entry: Entry):
        """The entry's texture, (levels, palette), read from ``pictures``/<its SHA-256>.npz
        without replaying anything, when that file is sound and *is* the recorded texture (its
        result hash equal to the entry's SHA-256, as a replay's must be); else None."""
        if not _SHA256.match(entry.sha256):
            return None
        return read_picture(self.pictures / f"{entry.sha256}.npz", entry.sha256,
                            (entry.height, entry.width), entry.levels)

    def stored_tone(self, entry: Entry):
        """The picture a built-in with a photo's tone shows, pictures/tones/<SHA-256>.npz (see
        read_tone), so a first start shows it toned before the tone's kernels are compiled;
        None when it has none."""
        if not _SHA256.match(entry.sha256):
            return None
        return read_tone(self.pictures / TONES / f"{entry.sha256}.npz",
                         (entry.height, entry.width))

    def open_stored(self, entry_id: int, **history_options) -> History | None:
        """``open()`` without the synthesis kernels, for a first start while they compile: an
        entry whose log is one synthesis (Synthesize or SynthesizeScales, then palette steps
        only) and that has a stored picture opens at once, the picture standing for the
        synthesis's result (a real History: its steps, undo and later replays are the log's).
        The picture is hash-checked, and so is the History's texture; ``confirm_stored`` later
        synthesises for real and compares. None when this cannot be done (then ``open()``
        replays)."""
        entry, recipe = self.get(entry_id), self.recipe(entry_id)
        first, rest = (recipe.actions[0], recipe.actions[1:]) if recipe.actions else (None, ())
        if _first_dpjs(first, recipe) is None or any(a.EFFECT != "palette" for a in rest):
            return None
        picture = self.stored_picture(entry)
        if picture is None:
            return None
        try:
            return open_recipe(recipe, history=True, prepared={0: picture[0]}, **history_options)
        except TexeditorError:
            return None

    def confirm_stored(self, entry_id: int, *, cancel=None) -> bool:
        """Synthesise the first step of an entry ``open_stored`` opened, for real (this needs
        the kernels), and compare it with the stored picture that stood for it."""
        entry, recipe = self.get(entry_id), self.recipe(entry_id)
        first, picture = recipe.actions[0], self.stored_picture(entry)
        fresh = first.render_result(_first_dpjs(first, recipe), cancel=cancel).levels
        return picture is not None and bool(np.array_equal(picture[0], fresh))

    def render(self, entry_id: int, *, progress=None, cancel=None) -> Document:
        """Replay an entry into a Document (hash checked), for export and verification."""
        return open_recipe(self.recipe(entry_id), progress=progress, cancel=cancel)

    def export_texture(self, entry_id: int, path, *, progress=None, cancel=None) -> None:
        """Write an entry as a `.texture` (replayed and checked first; atomic)."""
        entry = self.get(entry_id)
        doc = self.render(entry_id, progress=progress, cancel=cancel)
        data, _ = texture_bytes(doc, doc.actions, tags=entry.tags, description=entry.description)
        try:
            atomic_write(path, lambda f: f.write(data))
        except OSError as exc:
            raise BankError(f"{path}: cannot write ({exc.strerror or exc})") from None

    # -- checking --------------------------------------------------------------------------------
    def integrity(self) -> str:
        """SQLite's own check of the file ("ok" when sound)."""
        return "; ".join(r[0] for r in self._read("PRAGMA integrity_check"))

    def verify(self, *, progress=None, cancel=None) -> list:
        """Replay every entry (trash included) and compare hashes; one Check per entry, the
        database's own integrity first. A damaged entry never stops the others."""
        sound = self.integrity()
        checks = [Check(None, "database", sound == "ok", sound)]
        ids = [r[0] for r in self._read("SELECT id FROM entries ORDER BY id")]
        for k, entry_id in enumerate(ids):
            checks.append(self._check(entry_id, cancel))
            if progress is not None:
                progress((k + 1) / len(ids))
        return checks

    def _check(self, entry_id: int, cancel=None) -> Check:
        try:
            name = self.get(entry_id).name
        except BadRow as exc:
            return Check(entry_id, f"entry {entry_id}", False, str(exc))
        try:
            self.render(entry_id, cancel=cancel)
        except Cancelled:
            raise
        except TexeditorError as exc:
            return Check(entry_id, name, False, str(exc))
        return Check(entry_id, name, True, "replays to its recorded SHA-256")

    def pending(self) -> list:
        """Entries whose thumbnail or attributes are missing or out of date."""
        return [r[0] for r in self._read(
            "SELECT id FROM entries e WHERE attributes_version < ? OR NOT EXISTS "
            "(SELECT 1 FROM thumbnails t WHERE t.entry = e.id AND typeof(t.png) = 'blob') "
            "ORDER BY builtin DESC, id",
            (attrs.VERSION,))]

    def prepare_pending(self, *, progress=None, cancel=None) -> list:
        """Replay each pending entry (checking its hash), then store its thumbnail and
        attributes; an entry with a stored picture (the built-ins) is not replayed: the
        picture, checked against its hash, is its texture. Returns the Checks of the entries
        that failed (they stay pending)."""
        failed, ids = [], self.pending()
        for k, entry_id in enumerate(ids):
            if cancel is not None and cancel():
                raise Cancelled("preparing the bank was cancelled")
            try:
                entry = self.get(entry_id)
                picture = self.stored_picture(entry)                # a built-in: no replay
                if picture is None:
                    doc = self.render(entry_id, cancel=cancel)
                    picture = doc.levels, doc.palette
                    thumbnail = document_thumbnail(doc)
                else:
                    thumbnail = stored_thumbnail(*picture, self.stored_tone(entry))
                self._set_derived(entry_id, thumbnail, attrs.compute(*picture))
            except Cancelled:
                raise
            except BankError:
                raise
            except BadRow as exc:
                failed.append(Check(entry_id, f"entry {entry_id}", False, str(exc)))
            except TexeditorError as exc:
                failed.append(Check(entry_id, self.get(entry_id).name, False, str(exc)))
            if progress is not None:
                progress((k + 1) / len(ids))
        return failed

    def _set_derived(self, entry_id: int, thumbnail: bytes, a: attrs.Attributes) -> None:
        with self._write() as conn:
            conn.execute(f"UPDATE entries SET attributes_version = ?, "
                         f"{', '.join(f'{c} = ?' for c in _ATTR_COLUMNS)} WHERE id = ?",
                         (attrs.VERSION, *(getattr(a, c) for c in _ATTR_COLUMNS), entry_id))
            conn.execute("INSERT OR REPLACE INTO thumbnails (entry, png) VALUES (?, ?)",
                         (entry_id, thumbnail))
            _features_changed(conn)

    # -- editing ---------------------------------------------------------------------------------
    def update(self, entry_id: int, *, name: str | None = None, tags=None,
               description: str | None = None) -> None:
        """Rename, re-tag or re-describe an entry (its recipe never changes)."""
        with self._write() as conn:
            self._existing(conn, entry_id)
            if name is not None:
                conn.execute("UPDATE entries SET name = ? WHERE id = ?",
                              (check_name(name), entry_id))
            if description is not None:
                conn.execute("UPDATE entries SET description = ? WHERE id = ?",
                             (check_description(description), entry_id))
            if tags is not None:
                conn.execute("DELETE FROM tags WHERE entry = ?", (entry_id,))
                conn.executemany("INSERT INTO tags (entry, tag) VALUES (?, ?)",
                                 [(entry_id, t) for t in normalize_tags(tags)])
            conn.execute("UPDATE entries SET modified = ? WHERE id = ?", (time.time(), entry_id))
            self._index(conn, [entry_id])

    def duplicate(self, entry_id: int, name: str | None = None) -> int:
        """A copy of an entry (same recipe, a new name), e.g. to re-tag it differently."""
        with self._write() as conn:
            old = self._existing(conn, entry_id)
            now = time.time()
            columns = [r[1] for r in conn.execute("PRAGMA table_info(entries)")
                       if r[1] not in ("id", "name", "builtin", "created", "modified",
                                       "trashed", "parent")]
            new = conn.execute(
                f"INSERT INTO entries (name, builtin, created, modified, {', '.join(columns)}) "
                f"SELECT ?, 0, ?, ?, {', '.join(columns)} FROM entries WHERE id = ?",
                (check_name(name or f"{old} (copy)"), now, now, entry_id)).lastrowid
            for table, column in (("entry_dpjs", "ref"), ("entry_exemplars", "ref"),
                                  ("logs", "actions"), ("thumbnails", "png")):
                conn.execute(f"INSERT INTO {table} (entry, {column}) SELECT ?, {column} "
                             f"FROM {table} WHERE entry = ?", (new, entry_id))
            conn.execute("INSERT INTO tags (entry, tag) SELECT ?, tag FROM tags WHERE entry = ?",
                         (new, entry_id))
            self._index(conn, [new])
            _features_changed(conn, added_only=True)
        return new

    def trash(self, entry_id: int) -> None:
        """Move an entry to the trash (``restore`` brings it back; ``purge`` deletes it)."""
        self._set_trashed(entry_id, time.time())

    def restore(self, entry_id: int) -> None:
        self._set_trashed(entry_id, None)

    def _set_trashed(self, entry_id: int, when) -> None:
        with self._write() as conn:
            self._existing(conn, entry_id)
            conn.execute("UPDATE entries SET trashed = ? WHERE id = ?", (when, entry_id))

    def purge(self, entry_ids=None) -> int:
        """Delete entries for good (default: everything in the trash), and the DPJs no entry
        uses any more. Returns how many entries went."""
        with self._write() as conn:
            if entry_ids is None:
                entry_ids = [r[0] for r in conn.execute(
                    "SELECT id FROM entries WHERE trashed IS NOT NULL")]
            entry_ids = list(entry_ids)
            for entry_id in entry_ids:
                conn.execute("DELETE FROM entries WHERE id = ?", (entry_id,))
                if self.fts:
                    conn.execute("DELETE FROM search WHERE rowid = ?", (entry_id,))
            conn.execute("DELETE FROM dpjs WHERE ref NOT IN (SELECT ref FROM entry_dpjs)")
            conn.execute("DELETE FROM exemplars WHERE ref NOT IN "
                         "(SELECT ref FROM entry_exemplars)")
            _features_changed(conn)
            if not self.fts:
                self._mark_fts_stale(conn)
        return len(entry_ids)

    @staticmethod
    def _existing(conn, entry_id: int) -> str:
        row = conn.execute("SELECT name FROM entries WHERE id = ?", (entry_id,)).fetchone()
        if row is None:
            raise BankError(f"the bank has no entry {entry_id}")
        return row[0]

    def _index(self, conn, ids) -> None:
        """Keep the full-text index in step with entries (in the caller's transaction)."""
        if not self.fts:
            self._mark_fts_stale(conn)
            return
        for entry_id in ids:
            conn.execute("DELETE FROM search WHERE rowid = ?", (entry_id,))
            conn.execute("INSERT INTO search (rowid, name, description, tags) "
                         "SELECT e.id, e.name, e.description, coalesce((SELECT group_concat(tag, "
                         "' ') FROM tags t WHERE t.entry = e.id), '') FROM entries e "
                         "WHERE e.id = ?", (entry_id,))

    @staticmethod
    def _mark_fts_stale(conn) -> None:
        if conn.execute("SELECT 1 FROM sqlite_master WHERE name = 'search'").fetchone():
            conn.execute("INSERT OR REPLACE INTO meta (key, value) VALUES ('fts', 'stale')")


# -- making records --------------------------------------------------------------------------------

def make_record(source, name: str, *, tags=(), description: str = "", progress=None,
                cancel=None) -> Record:
    """Everything an entry needs from a History (its applied log) or a Document: the log
    optimised (and replayed once to prove it gives the same texture, else the log as it was),
    the DPJs it uses, the grain parameters, hash, thumbnail and attributes."""
    doc, actions = (source.document, source.applied) if isinstance(source, History) else (
        source, source.actions)
    if not isinstance(doc, Document) or not doc.levels.size:
        raise InputError("an empty texture cannot go into the bank")
    name, tags = check_name(name), normalize_tags(tags)
    description = check_description(description)
    actions = _shortest(tuple(actions), doc, progress, cancel)
    refs = _dpj_refs(actions, doc.dpjs)
    main = doc.dpj_ref if doc.dpj_ref in doc.dpjs else None
    if main is not None and main not in refs:
        refs.append(main)
    h, w = doc.shape
    return Record(name=name, description=description, tags=tags, width=w, height=h,
                  levels=doc.num_levels, actions=actions, dpjs={r: doc.dpjs[r] for r in refs},
                  main_dpj=main, grain=grain_parameters(actions), sha256=doc.result_hash(),
                  thumbnail=document_thumbnail(doc),
                  attributes=attrs.compute(doc.levels, doc.palette),
                  exemplars=_exemplars(actions, doc.exemplars))


def _shortest(actions: tuple, doc: Document, progress, cancel) -> tuple:
    if len(actions) > MAX_ACTIONS:
        raise InputError(f"a log of {len(actions)} actions is more than the bank keeps")
    shorter = tuple(optimize(actions, doc.dpjs))
    if len(shorter) == len(actions):
        return actions
    try:
        again = replay(shorter, doc.dpjs, progress=progress, cancel=cancel,
                       exemplars=doc.exemplars)
    except ReplayError:
        return actions
    return shorter if again.result_hash() == doc.result_hash() else actions


def pending_record(tex: TextureFile, name: str) -> Record:
    """A Record from a validated `.texture` without replaying it (thumbnail and attributes
    come later; the hash is the file's, checked when they are computed)."""
    m = tex.manifest
    refs = _dpj_refs(tex.actions, tex.dpjs) + ([m.dpj] if m.dpj else [])
    return Record(name=check_name(name), description=check_description(m.description),
                  tags=normalize_tags(m.tags), width=m.width, height=m.height, levels=m.levels,
                  actions=tex.actions, dpjs={r: tex.dpjs[r] for r in dict.fromkeys(refs)},
                  main_dpj=m.dpj, grain=grain_parameters(tex.actions), sha256=m.result_sha256,
                  exemplars=_exemplars(tex.actions, tex.exemplars))


def _exemplars(actions, photos: dict) -> dict:
    """The exemplar photos the log uses (one it needs but lacks shows up at replay)."""
    return {r: photos[r] for r in exemplar_refs(actions) if r in photos}


def _dpj_refs(actions, dpjs: dict) -> list:
    """The DPJs the log uses: its "ref" parameters that name a DPJ (other references, such as
    a spot placement's fingerprint, are not DPJs). A DPJ the log needs but that is missing
    shows up when the entry is replayed."""
    return [r for r in dpj_refs(actions) if r in dpjs]


def grain_parameters(actions) -> dict:
    """The grain and density parameters of the log (§5.4.2: a texture is its DPJ, its grain
    and density parameters and its actions), kept apart so the browser can show them without
    reading the log: the last RenderGrains (shape, size, explosion, compression…)."""
    found = {}
    for a in actions:
        if a.TYPE in GRAIN_TYPES:
            found[a.TYPE] = {k: v for k, v in a.to_json().items() if k not in ("type", "version")}
    return found


def thumbnail_png(levels: np.ndarray, palette, size: int = THUMB) -> bytes:
    """A PNG of the central size×size points at one pixel per point (enlarged by a whole factor
    when the texture is smaller): a thumbnail that shows the real grain, not a blur of it."""
    crop = attrs.central_crop(np.asarray(levels), size)
    palette = np.asarray(palette, dtype=np.uint8)
    if np.all(palette == palette[:, :1]):
        palette = palette[:, 0]                    # grey: a third of the bytes
    return _thumbnail(palette[crop], size)


def stored_thumbnail(levels: np.ndarray, palette, tone, size: int = THUMB) -> bytes:
    """A built-in's thumbnail from its stored picture: in its stored tone when it has one (as
    document_thumbnail draws a replayed one), else its levels in their palette."""
    if tone is None:
        return thumbnail_png(levels, palette, size)
    return _thumbnail(attrs.central_crop(tone, size), size)


def document_thumbnail(doc: Document, size: int = THUMB) -> bytes:
    """A document's thumbnail as the window shows it: laid on its colour plates, in the tone
    of the photo it was synthesised from, or its levels in their palette."""
    from ..photo import document_tone
    if doc.plates is not None:
        return _thumbnail(attrs.central_crop(document_picture(doc), size), size)
    try:
        tone = document_tone(doc)
    except TexeditorError:
        tone = None                           # a tone that does not fit: the palette shows
    if tone is None:
        return thumbnail_png(doc.levels, doc.palette, size)
    return _thumbnail(attrs.central_crop(tone, size), size)


def _thumbnail(image: np.ndarray, size: int) -> bytes:
    import imageio.v3 as iio

    k = max(1, size // max(image.shape[:2]))
    if k > 1:
        image = np.repeat(np.repeat(image, k, axis=0), k, axis=1)
    return iio.imwrite("<bytes>", image, extension=".png")


def picture_bytes(levels: np.ndarray, palette) -> bytes:
    """A stored picture: an .npz of ``levels`` (H, W) and ``palette`` (G, 3), both uint8."""
    out = io.BytesIO()
    np.savez_compressed(out, levels=np.ascontiguousarray(levels, dtype=np.uint8),
                        palette=np.ascontiguousarray(palette, dtype=np.uint8))
    return out.getvalue()


def write_picture(folder, levels: np.ndarray, palette) -> Path:
    """Store a texture as ``folder``/<its result hash>.npz (atomic); returns the path."""
    path = Path(folder) / f"{result_hash(levels, palette)}.npz"
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(path, picture_bytes(levels, palette))
    return path


def write_tone(folder, sha256: str, tone: np.ndarray) -> Path:
    """Store a built-in's tone picture (uint8 (H, W) or (H, W, 3), the photo's greys or colours
    drawn on its levels) as ``folder``/tones/<its texture's SHA-256>.npz (atomic)."""
    path = Path(folder) / TONES / f"{sha256}.npz"
    path.parent.mkdir(parents=True, exist_ok=True)
    out = io.BytesIO()
    np.savez_compressed(out, tone=np.ascontiguousarray(tone, dtype=np.uint8))
    atomic_write_bytes(path, out.getvalue())
    return path


def read_tone(path, shape: tuple):
    """A stored tone picture of an (H, W) = ``shape`` texture, or None when the file is missing,
    damaged, too large or not a uint8 (H, W) or (H, W, 3) picture (read as _read_npz does). It
    only stands for the tone until the kernels draw it, the same pixels."""
    h, w = shape
    arrays = _read_npz(path, {"tone.npy": 3 * h * w + 4096})
    tone = None if arrays is None else arrays["tone"]
    if tone is None or tone.dtype != np.uint8 or tone.shape not in ((h, w), (h, w, 3)):
        return None
    tone.flags.writeable = False
    return tone


def _read_npz(path, limits: dict) -> dict | None:
    """name → array of an .npz that holds exactly the members ``limits`` names, none larger
    than its limit (bytes); None when the file is missing, not a regular file, larger than
    MAX_PICTURE_BYTES, damaged or otherwise. Read without pickle, sizes checked before anything
    is allocated."""
    try:
        path = Path(path)
        if not path.is_file() or path.stat().st_size > MAX_PICTURE_BYTES:
            return None
        with zipfile.ZipFile(path) as zf:
            infos = {i.filename: i for i in zf.infolist()}
            if set(infos) != set(limits) or any(infos[n].file_size > limits[n] for n in limits):
                return None
            return {n[:-4]: np.load(io.BytesIO(zf.read(n)), allow_pickle=False)
                    for n in limits}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zipfile.LargeZipFile,
            NotImplementedError):
        return None


def read_picture(path, sha256: str, shape: tuple, levels: int):
    """(levels, palette) from a stored picture, or None when the file is missing, damaged,
    too large, not (H, W) = ``shape`` with G = ``levels``, or not the texture of ``sha256``
    (read as _read_npz does)."""
    h, w = shape
    arrays = _read_npz(path, {"levels.npy": h * w + 4096, "palette.npy": 3 * levels + 4096})
    if arrays is None:
        return None
    grid, palette = arrays["levels"], arrays["palette"]
    if (grid.dtype != np.uint8 or grid.shape != (h, w) or palette.dtype != np.uint8
            or palette.shape != (levels, 3) or (grid.size and int(grid.max()) >= levels)
            or result_hash(grid, palette) != sha256):
        return None
    grid.flags.writeable = False
    return grid, palette


# -- text: names, tags, queries ----------------------------------------------------------------

def check_name(name) -> str:
    if not isinstance(name, str) or not name.strip():
        raise InputError("an entry needs a name")
    name = check_unicode(" ".join(name.split()), "a name")
    if len(name) > MAX_NAME_CHARS:
        raise InputError(f"a name has at most {MAX_NAME_CHARS} characters")
    return name


def check_description(text) -> str:
    if not isinstance(text, str) or len(text) > MAX_DESCRIPTION_CHARS:
        raise InputError(f"a description is a text of at most {MAX_DESCRIPTION_CHARS} characters")
    return check_unicode(text, "a description").strip()


def normalize_tags(tags) -> tuple:
    """Tags (keys) as the bank keeps them: lower case, single spaces, no duplicates, in the
    order given. A string is split on commas."""
    if isinstance(tags, str):
        tags = tags.split(",")
    out: dict[str, None] = {}
    for tag in tags:
        if not isinstance(tag, str):
            raise InputError(f"a tag must be a text, got {tag!r}")
        tag = check_unicode(" ".join(tag.lower().split()).lstrip("#").strip(), "a tag")
        if not tag:
            continue
        if len(tag) > MAX_TAG_CHARS or any(ord(c) < 32 for c in tag):
            raise InputError(f"a tag has at most {MAX_TAG_CHARS} printable characters: {tag!r:.80}")
        out[tag] = None
    if len(out) > MAX_TAGS:
        raise InputError(f"an entry has at most {MAX_TAGS} tags")
    return tuple(out)


def parse_query(text: str) -> tuple[list, list]:
    """Split a search text into words and tags (``tag:name`` or ``#name``)."""
    if not isinstance(text, str):
        raise InputError("the search text must be a text")
    check_unicode(text, "the search text")
    words, tags = [], []
    for token in text.split():
        lower = token.lower()
        if lower.startswith("tag:") and len(token) > 4:
            tags.append(token[4:])
        elif token.startswith("#") and len(token) > 1:
            tags.append(token[1:])
        else:
            words.append(token)
    return words, tags


def fts_query(words) -> str:
    """An FTS5 query matching every word as a prefix; each word quoted, so a user's text is
    never read as FTS5 syntax."""
    return " AND ".join('"' + w.replace('"', '""') + '"*' for w in words)


def check_ranges(ranges) -> dict:
    """{attribute: (lo, hi)} with known names and numbers (None = unbounded)."""
    out = {}
    for name, bounds in (ranges or {}).items():
        if name not in _ATTR_COLUMNS:
            raise InputError(f"unknown attribute {name!r}: choose from {', '.join(_ATTR_COLUMNS)}")
        try:
            lo, hi = bounds
        except (TypeError, ValueError):
            raise InputError(f"the range of {name} must be (low, high)") from None
        for v in (lo, hi):
            if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))
                                  or not math.isfinite(v)):
                raise InputError(f"the range of {name} must hold numbers, got {v!r}")
        if lo is not None and hi is not None and lo > hi:
            raise InputError(f"the range of {name} is empty ({lo} > {hi})")
        out[name] = (lo, hi)
    return out


def parse_range(text: str) -> tuple[str, tuple]:
    """'contrast=0.2..0.8' (either bound may be left out) → ('contrast', (0.2, 0.8))."""
    name, sep, span = text.partition("=")
    lo, dots, hi = span.partition("..")
    if not sep or not dots:
        raise InputError(f"a filter looks like ATTRIBUTE=LOW..HIGH (e.g. contrast=0.2..0.8), "
                         f"got {text!r}")
    try:
        bounds = tuple(float(v) if v.strip() else None for v in (lo, hi))
    except ValueError:
        raise InputError(f"the bounds of {text!r} must be numbers") from None
    name = name.strip()
    check_ranges({name: bounds})
    return name, bounds


def _read_only(path: Path) -> bool:
    """An existing bank this user may not write: the file, or its folder (SQLite writes its
    journal beside it)."""
    try:
        return path.is_file() and not (os.access(path, os.W_OK)
                                       and os.access(path.parent, os.W_OK))
    except OSError:
        return False


def name_from_file(path) -> str:
    """'fine-gravel_2.texture' → 'Fine gravel 2'."""
    stem = re.sub(r"[-_]+", " ", Path(path).stem).strip() or "Untitled"
    return check_name(stem[:1].upper() + stem[1:])


# -- reading rows ----------------------------------------------------------------------------------

def parse_log(text, what: str) -> tuple:
    """A stored log back into Actions, validated like a file's actions.json."""
    if not isinstance(text, str):
        raise FormatError(f"{what}: its action log is damaged (not a TEXT)")
    return read_log(text, f"{what}: its action log is damaged", max_actions=MAX_ACTIONS)


def _no_constant(token):
    raise ValueError(f"{token} is not allowed")


MAX_GRAIN_CELL = 64 * 2**10        # the grain column's JSON (a few parameters: ~200 bytes)


class BadRow(FormatError):
    """A bank row whose cells are not of their column's type (a file edited by another
    program, or damaged): ``verify`` reports it, ``list`` and ``search`` skip it."""


def _cell(value, kinds, entry_id, column: str, *, null: bool = False):
    """``value`` if it is of one of ``kinds`` (None too when ``null``; a float must be finite),
    else a BadRow naming the entry, the column and what was found."""
    if value is None and null:
        return value
    if isinstance(value, kinds) and not (isinstance(value, float) and not math.isfinite(value)):
        return value
    found = {bytes: "a BLOB", BadText: "a TEXT that is not UTF-8", str: "a TEXT", int: "an INTEGER", float: "a REAL",
             type(None): "NULL"}.get(type(value), type(value).__name__)
    if isinstance(value, float):
        found = f"{value}"
    raise BadRow(f"bank entry {entry_id}: its {column} is damaged ({found} where "
                 f"{' or '.join(k.__name__ for k in kinds)} belongs)")


class BadText(bytes):
    """A TEXT cell whose bytes are not UTF-8 (written by another program): never a str, so
    every check of a cell's type finds it damaged, instead of SQLite's decoding error failing
    the whole query."""


def _text(data: bytes):
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return BadText(data)


def _entry(row) -> Entry:
    """An Entry from a row of ``_ENTRY_COLUMNS``, every cell checked (a BadRow if one is not
    of its column's type: SQLite stores whatever it is given)."""
    (entry_id, name, description, width, height, levels, count, sha, builtin, parent, created,
     modified, trashed, grain, version), rest = row[:15], row[15:]
    values, tags = rest[:len(_ATTR_COLUMNS)], rest[len(_ATTR_COLUMNS)]
    i, n = int, (int, float)
    for value, kinds, column, null in (
            (name, str, "name", False), (description, str, "description", False),
            (width, i, "width", False), (height, i, "height", False),
            (levels, i, "levels", False), (count, i, "action count", False),
            (sha, str, "SHA-256", False), (builtin, i, "built-in mark", False),
            (parent, i, "parent", True), (created, n, "creation time", False),
            (modified, n, "modification time", False), (trashed, n, "trash time", True),
            (grain, str, "grain parameters", True), (version, i, "attributes version", False),
            (tags, str, "tags", True),
            *((v, n, c, True) for v, c in zip(values, _ATTR_COLUMNS))):
        _cell(value, kinds if isinstance(kinds, tuple) else (kinds,), entry_id, column,
              null=null)
    known = version == attrs.VERSION and None not in values
    try:
        grain = load_json(grain, "JSON", limit=MAX_GRAIN_CELL) if grain else {}
    except FormatError as exc:
        raise BadRow(f"bank entry {entry_id}: its grain parameters are damaged ({exc})") from None
    if not isinstance(grain, dict):
        raise BadRow(f"bank entry {entry_id}: its grain parameters are damaged (not an object)")
    return Entry(id=entry_id, name=name, description=description, tags=_split_tags(tags),
                 width=width, height=height, levels=levels, actions=count, sha256=sha,
                 attributes=attrs.Attributes(*values) if known else None, builtin=bool(builtin),
                 parent=parent, created=created, modified=modified, trashed=trashed,
                 grain=grain if isinstance(grain, dict) else {})


def _split_tags(text) -> tuple:
    return tuple(sorted(text.split(_SEP))) if text else ()


def _what(entry: Entry) -> str:
    return f"bank entry {entry.id} “{entry.name}”"


def _features_changed(conn, *, added_only: bool = False) -> None:
    """Tell every Bank on this file that attributes changed (their likeness caches go stale),
    or, after inserts, only that entries were added (the caches read just the new rows)."""
    key = "features_added" if added_only else "features"
    conn.execute("INSERT INTO meta (key, value) VALUES (?, '1') ON CONFLICT (key) "
                 "DO UPDATE SET value = CAST(value AS INTEGER) + 1", (key,))


def _has_fts5(conn) -> bool:
    try:
        conn.execute("CREATE VIRTUAL TABLE temp.fts5_probe USING fts5(x)")
        conn.execute("DROP TABLE temp.fts5_probe")
        return True
    except sqlite3.Error:
        return False

