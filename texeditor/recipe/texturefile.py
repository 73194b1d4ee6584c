"""The `.texture` file: a zip holding a texture's recipe (its DPJs and action log) and a manifest.

It sits between a History and the disk (the CLI and the GUI save and open these; the bank stores
the same recipe). Reading trusts nothing: names, sizes, JSON and arrays are checked, then the log
is replayed and the result's SHA-256 compared with the manifest's. See docs/formats.md.
"""

from __future__ import annotations

import dataclasses
import io
import json
import re
import zipfile
import zlib
from dataclasses import dataclass


from ..version import __version__
from .actions import (MAX_CANVAS_SIDE, Action, Synthesize, SynthesizeScales, dpj_refs,
                      exemplar_refs, palette_param)
from .codec import MAX_ACTIONS, MAX_LOG_BYTES, log_json, read_log
from .document import Document, REF_LENGTH
from .exemplars import MAX_EXEMPLARS, MAX_PNG_BYTES, exemplar_png, read_exemplar_png
from ..markov.dpj import DPJ, MAX_FILE_BYTES as MAX_DPJ_BYTES, MAX_LEVELS
from ..errors import FormatError, InputError, check_unicode
from ..fileio import load_json, read_limited, write_file
from .history import History
from .stored import Recipe, open_recipe
from .logopt import optimize_with_notes

FORMAT_NAME = "texeditor-texture"
FORMAT_VERSION = 1
# Measured at these limits (benchmarks/bench_limits.py): opening and replaying stays under 2 GiB.
# Each DPJ in memory takes about 3× its stored bytes, and a synthesis from the largest one 1.3 GB.
MAX_MANIFEST_BYTES = 2**20
MAX_ACTIONS_BYTES = MAX_LOG_BYTES
MAX_DPJ_CONTENT = 128 * 2**20           # the DPJ members together (two of the largest DPJs)
MAX_EXEMPLAR_CONTENT = MAX_EXEMPLARS * MAX_PNG_BYTES
MAX_TOTAL_BYTES = (MAX_MANIFEST_BYTES + MAX_ACTIONS_BYTES + MAX_DPJ_CONTENT      # declared sizes
                   + MAX_EXEMPLAR_CONTENT)
MAX_FILE_BYTES = MAX_TOTAL_BYTES + 2**20
MAX_DPJS = 64
MAX_RATIO = 200                         # uncompressed / compressed, above RATIO_FLOOR bytes
RATIO_FLOOR = 2**20
MAX_TAGS, MAX_TAG_CHARS, MAX_DESCRIPTION_CHARS = 256, 128, 100_000
_FIXED_TIME = (1980, 1, 1, 0, 0, 0)
_OTHER_DPJ = re.compile(rf"^dpjs/([0-9a-f]{{{REF_LENGTH}}})\.npz$")
_REF = re.compile(rf"^[0-9a-f]{{{REF_LENGTH}}}$")
_EXEMPLAR = re.compile(rf"^exemplars/([0-9a-f]{{{REF_LENGTH}}})\.png$")


@dataclass(frozen=True)
class Manifest:
    """manifest.json: what a bank or a file browser shows without replaying the log."""

    width: int
    height: int
    levels: int
    palette: tuple
    result_sha256: str
    actions: int
    dpj: str | None = None
    dpjs: tuple = ()
    tags: tuple = ()
    description: str = ""
    software: str = f"texeditor {__version__}"
    format: str = FORMAT_NAME
    format_version: int = FORMAT_VERSION
    exemplars: tuple = ()           # the exemplar photos the log uses (since 0.2)

    def to_json(self) -> dict:
        """The JSON object; ``exemplars`` only when there are some, so a file without them is
        byte for byte what earlier versions wrote and read."""
        d = dataclasses.asdict(self)
        d["palette"] = [list(c) for c in self.palette]
        d["dpjs"], d["tags"] = list(self.dpjs), list(self.tags)
        d["exemplars"] = list(self.exemplars)
        if not self.exemplars:
            del d["exemplars"]
        return d


@dataclass(frozen=True)
class TextureFile:
    """A `.texture` read and validated but not replayed (enough to list its log)."""

    manifest: Manifest
    actions: tuple[Action, ...]
    dpjs: dict[str, DPJ]
    name: str = "texture"
    exemplars: dict = dataclasses.field(default_factory=dict)    # ref → uint8 photo

    @property
    def recipe(self) -> Recipe:
        """The log, DPJs, current DPJ, recorded result and exemplars, for `stored.open_recipe`."""
        return Recipe(self.actions, self.dpjs, self.manifest.dpj, self.manifest.result_sha256,
                      self.name, self.exemplars)


# -- writing ---------------------------------------------------------------------------------------

def save_texture(path, source: History | Document, *, tags=(), description: str = "") -> Manifest:
    """Write a History's applied log (or a Document's log) atomically; returns the manifest.

    Everything is serialised before the destination is touched, so a failed save leaves any
    existing file as it was.
    """
    doc, actions = _recipe(source)
    data, manifest = texture_bytes(doc, actions, tags=tags, description=description)
    write_file(path, data)
    return manifest


def texture_bytes(doc: Document, actions, *, tags=(), description="") -> tuple[bytes, Manifest]:
    """The file content for a document and the log that made it (the same bytes every time)."""
    actions = tuple(actions)
    refs = dpj_refs(actions)
    missing = sorted(r for r in refs if r not in doc.dpjs)
    if missing:
        raise InputError(f"the log refers to DPJs {missing} that the document does not hold")
    photos = tuple(sorted(exemplar_refs(actions)))
    missing = [r for r in photos if r not in doc.exemplars]
    if missing:
        raise InputError(f"the log refers to exemplars {missing} that the document does not hold")
    main = doc.dpj_ref if doc.dpj_ref in doc.dpjs else None     # the current DPJ, as it is
    others = tuple(sorted(r for r in set(refs) if r != main))
    tags = (tags,) if isinstance(tags, str) else tuple(tags)
    manifest = _checked_for_saving(Manifest(
        width=doc.shape[1], height=doc.shape[0], levels=doc.num_levels,
        palette=tuple(tuple(int(c) for c in rgb) for rgb in doc.palette),
        result_sha256=doc.result_hash(), actions=len(actions), dpj=main, dpjs=others,
        tags=tags, description=description, exemplars=photos))
    members = [("manifest.json", _json_bytes(manifest.to_json())),
               ("actions.json", _json_bytes(log_json(actions)))]
    if main is not None:
        members.append(("dpj.npz", doc.dpjs[main].to_bytes()))
    members += [(f"dpjs/{ref}.npz", doc.dpjs[ref].to_bytes()) for ref in others]
    members += [(f"exemplars/{ref}.png", exemplar_png(doc.exemplars[ref])) for ref in photos]
    return _archive(members), manifest


def _checked_for_saving(manifest: Manifest) -> Manifest:
    try:
        return _check_manifest(manifest.to_json(), "cannot save")
    except FormatError as exc:
        raise InputError(str(exc)) from None


def _recipe(source) -> tuple[Document, tuple]:
    if isinstance(source, History):
        return source.document, source.applied
    if isinstance(source, Document):
        return source, source.actions
    raise InputError(f"save a History or a Document, not {type(source).__name__}")


def _json_bytes(obj) -> bytes:
    return json.dumps(obj, indent=1, ensure_ascii=False, allow_nan=False).encode("utf-8")


def _archive(members) -> bytes:
    """The zip, refused here (InputError) if a reader would refuse it: a file saved always
    opens again. A member that compresses past MAX_RATIO (a log of one step repeated) is stored."""
    data = _zip(members)
    with zipfile.ZipFile(io.BytesIO(data)) as zf:
        dense = {i.filename for i in zf.infolist() if _too_dense(i)}
    if dense:
        data = _zip(members, stored=dense)
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as zf:
            _check_members(zf, "cannot save the texture")
    except FormatError as exc:
        raise InputError(str(exc)) from None
    if len(data) > MAX_FILE_BYTES:
        raise InputError(f"cannot save the texture: {_mib(len(data))} is more than the limit "
                         f"of {_mib(MAX_FILE_BYTES)}")
    return data


def _too_dense(info: zipfile.ZipInfo) -> bool:
    return info.file_size > RATIO_FLOOR and info.file_size > MAX_RATIO * max(info.compress_size, 1)


def _zip(members, stored=frozenset()) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        for name, data in members:
            info = zipfile.ZipInfo(name, date_time=_FIXED_TIME)
            info.create_system = 3
            info.external_attr = 0o644 << 16
            # .npz and .png members are compressed already
            info.compress_type = (zipfile.ZIP_STORED if name.endswith((".npz", ".png"))
                                  or name in stored
                                  else zipfile.ZIP_DEFLATED)
            zf.writestr(info, data)
    return buf.getvalue()


# -- reading ---------------------------------------------------------------------------------------

def read_texture(path) -> TextureFile:
    """Read and validate a `.texture` without replaying it; any defect is a FormatError."""
    data = read_limited(path, MAX_FILE_BYTES, "texture file")
    return parse_texture(data, str(path))


def parse_texture(data: bytes, name: str = "texture") -> TextureFile:
    try:
        zf = zipfile.ZipFile(io.BytesIO(data))
    except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, ValueError, EOFError,
            NotImplementedError):      # a member of a zip version Python cannot read
        raise FormatError(f"{name}: not a texture file (not a zip archive, or truncated)") from None
    with zf:
        infos = _check_members(zf, name)
        manifest = _check_manifest(_read_json(zf, infos["manifest.json"], name), name)
        actions = _read_actions(_read_json(zf, infos["actions.json"], name), name)
        dpjs = _read_dpjs(zf, infos, manifest, name)
        exemplars = _read_exemplars(zf, infos, manifest, name)
    if len(actions) != manifest.actions:
        raise FormatError(f"{name}: the manifest announces {manifest.actions} actions, "
                          f"actions.json holds {len(actions)}")
    missing = sorted(set(dpj_refs(actions)) - set(dpjs))
    if missing:
        raise FormatError(f"{name}: the log uses DPJs {missing} that the file does not hold")
    if set(exemplar_refs(actions)) != set(exemplars):
        raise FormatError(f"{name}: the exemplar photos held are not the ones the log uses")
    return TextureFile(manifest, actions, dpjs, name, exemplars)


def load_texture(path, *, progress=None, cancel=None, **history_options) -> tuple[History, Manifest]:
    """Open a `.texture`: validate, replay its log into a History and check the result hash.

    A log that fails to replay or gives another result is a ReplayError.
    """
    tex = read_texture(path)
    history = open_recipe(tex.recipe, history=True, progress=progress, cancel=cancel,
                          **history_options)
    return history, tex.manifest


def _check_members(zf: zipfile.ZipFile, name: str) -> dict[str, zipfile.ZipInfo]:
    """Only known names, no duplicates, no encryption, sizes and ratios within the limits."""
    infos = zf.infolist()
    dpj_members = sum(i.filename.endswith(".npz") for i in infos)
    photo_members = sum(bool(_EXEMPLAR.fullmatch(i.filename)) for i in infos)
    if len(infos) > 2 + 1 + MAX_DPJS + MAX_EXEMPLARS or dpj_members > 1 + MAX_DPJS \
            or photo_members > MAX_EXEMPLARS:
        raise FormatError(f"{name}: {len(infos)} members, more than a texture file holds")
    seen: dict[str, zipfile.ZipInfo] = {}
    total = dpj_total = 0
    for info in infos:
        member = info.filename
        if (member.startswith(("/", "\\")) or ".." in member.replace("\\", "/").split("/")
                or ":" in member or "\\" in member):
            raise FormatError(f"{name}: unsafe member name {member!r} (path traversal)")
        if member not in ("manifest.json", "actions.json", "dpj.npz") \
                and not _OTHER_DPJ.fullmatch(member) and not _EXEMPLAR.fullmatch(member):
            raise FormatError(f"{name}: unexpected member {member!r}")
        if member in seen:
            raise FormatError(f"{name}: member {member!r} appears twice")
        if info.flag_bits & 0x1:
            raise FormatError(f"{name}: member {member!r} is encrypted")
        if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
            raise FormatError(f"{name}: member {member!r} uses an unsupported compression")
        limit = _member_limit(member)
        if info.file_size > limit:
            raise FormatError(f"{name}: member {member!r} declares {info.file_size} bytes, "
                              f"more than the limit of {limit}")
        if _too_dense(info):
            raise FormatError(f"{name}: member {member!r} expands {info.file_size} bytes from "
                              f"{info.compress_size}: refused as a zip bomb")
        total += info.file_size
        dpj_total += info.file_size if member.endswith(".npz") else 0
        seen[member] = info
    if total > MAX_TOTAL_BYTES:
        raise FormatError(f"{name}: declared content of {total} bytes is more than the limit")
    if dpj_total > MAX_DPJ_CONTENT:
        raise FormatError(f"{name}: its DPJs take {_mib(dpj_total)} together, more than the "
                          f"limit of {_mib(MAX_DPJ_CONTENT)}")
    for required in ("manifest.json", "actions.json"):
        if required not in seen:
            raise FormatError(f"{name}: not a texture file ({required} is missing)")
    return seen


def _member_limit(member: str) -> int:
    if _EXEMPLAR.fullmatch(member):
        return MAX_PNG_BYTES
    return {"manifest.json": MAX_MANIFEST_BYTES,
            "actions.json": MAX_ACTIONS_BYTES}.get(member, min(MAX_DPJ_BYTES, MAX_DPJ_CONTENT))


def _mib(n: int) -> str:
    return f"{n / 2**20:.1f} MiB"


def _read_member(zf: zipfile.ZipFile, info: zipfile.ZipInfo, name: str) -> bytes:
    """The member's bytes, never more than declared (a lying header cannot inflate memory)."""
    chunks, size = [], 0
    try:
        with zf.open(info) as f:
            while chunk := f.read(2**20):
                size += len(chunk)
                if size > info.file_size:
                    raise FormatError(f"{name}: member {info.filename!r} is larger than declared")
                chunks.append(chunk)
    except (zipfile.BadZipFile, zlib.error, OSError, EOFError, ValueError,
            NotImplementedError) as exc:
        raise FormatError(f"{name}: member {info.filename!r} is damaged ({_short(exc)})") from None
    return b"".join(chunks)


def _read_json(zf, info, name):
    """A JSON member, its size and nesting depth bounded before it is parsed."""
    raw = _read_member(zf, info, name)
    return load_json(raw, f"{name}: {info.filename}", limit=_member_limit(info.filename))


def _check_manifest(obj, name: str = "texture") -> Manifest:
    """The manifest's schema: exact keys, types, ranges, a palette of G colours."""
    if not isinstance(obj, dict):
        raise FormatError(f"{name}: manifest.json must be a JSON object")
    if obj.get("format") != FORMAT_NAME:
        raise FormatError(f"{name}: not a texture file (manifest format {obj.get('format')!r})")
    version = obj.get("format_version")
    if version != FORMAT_VERSION or isinstance(version, bool):
        raise FormatError(f"{name}: texture format version {version!r} is not supported "
                          f"(this program reads version {FORMAT_VERSION})")
    fields = {f.name: f for f in dataclasses.fields(Manifest)}
    unknown = sorted(set(obj) - set(fields))
    missing = sorted(k for k, f in fields.items() if k not in obj
                     and f.default is dataclasses.MISSING)
    if unknown or missing:
        raise FormatError(f"{name}: manifest.json has unexpected keys {unknown} or lacks {missing}")
    try:
        m = Manifest(**{k: v for k, v in obj.items()})
        checked = dataclasses.replace(
            m, width=_count(m.width, "width", MAX_CANVAS_SIDE),
            height=_count(m.height, "height", MAX_CANVAS_SIDE),
            levels=_count(m.levels, "levels", MAX_LEVELS, low=2),
            palette=palette_param("palette", m.palette, None, None),
            result_sha256=_text(m.result_sha256, "result_sha256", 64, r"^[0-9a-f]{64}$"),
            actions=_count(m.actions, "actions", MAX_ACTIONS),
            dpj=None if m.dpj is None else _text(m.dpj, "dpj", REF_LENGTH, _REF.pattern),
            dpjs=_texts(m.dpjs, "dpjs", MAX_DPJS, REF_LENGTH, _REF.pattern),
            tags=_texts(m.tags, "tags", MAX_TAGS, MAX_TAG_CHARS),
            exemplars=_texts(m.exemplars, "exemplars", MAX_EXEMPLARS, REF_LENGTH, _REF.pattern),
            description=_text(m.description, "description", MAX_DESCRIPTION_CHARS),
            software=_text(m.software, "software", 200))
    except InputError as exc:
        raise FormatError(f"{name}: manifest.json: {exc}") from None
    if len(checked.palette) != checked.levels:
        raise FormatError(f"{name}: manifest.json: {len(checked.palette)} colours for "
                          f"G = {checked.levels}")
    if checked.dpj in checked.dpjs or len(set(checked.dpjs)) != len(checked.dpjs):
        raise FormatError(f"{name}: manifest.json: a DPJ reference is listed twice")
    if len(set(checked.exemplars)) != len(checked.exemplars):
        raise FormatError(f"{name}: manifest.json: an exemplar reference is listed twice")
    return checked


def _count(value, what, high, low=0) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise InputError(f"{what} must be an integer {low}..{high}, got {value!r}")
    return value


def _text(value, what, max_chars, pattern=None) -> str:
    if not isinstance(value, str) or len(value) > max_chars or (
            pattern and not re.fullmatch(pattern, value)):
        raise InputError(f"{what} must be a text of at most {max_chars} characters"
                         + (f" matching {pattern}" if pattern else "") + f", got {value!r:.80}")
    return check_unicode(value, what)


def _texts(value, what, max_items, max_chars, pattern=None) -> tuple:
    if not isinstance(value, (list, tuple)) or len(value) > max_items:
        raise InputError(f"{what} must be a list of at most {max_items} texts")
    return tuple(_text(v, f"each of {what}", max_chars, pattern) for v in value)


def _read_actions(obj, name: str) -> tuple[Action, ...]:
    return read_log(obj, f"{name}: actions.json", max_actions=MAX_ACTIONS)


def _read_dpjs(zf, infos, manifest: Manifest, name: str) -> dict[str, DPJ]:
    """dpj.npz is the manifest's ``dpj``; dpjs/<ref>.npz are the other references."""
    stored = {_OTHER_DPJ.fullmatch(m).group(1) for m in infos if _OTHER_DPJ.fullmatch(m)}
    if ("dpj.npz" in infos) != (manifest.dpj is not None) or stored != set(manifest.dpjs):
        raise FormatError(f"{name}: the DPJ members do not match the manifest's dpj and dpjs")
    members = {manifest.dpj: "dpj.npz"} if manifest.dpj else {}
    members.update({ref: f"dpjs/{ref}.npz" for ref in manifest.dpjs})
    return {ref: _parse_dpj(_read_member(zf, infos[m], name), f"{name}: {m}", ref)
            for ref, m in members.items()}


def _read_exemplars(zf, infos, manifest: Manifest, name: str) -> dict:
    """exemplars/<ref>.png, exactly the manifest's ``exemplars``, each hashing to its ref."""
    stored = {_EXEMPLAR.fullmatch(m).group(1) for m in infos if _EXEMPLAR.fullmatch(m)}
    if stored != set(manifest.exemplars):
        raise FormatError(f"{name}: the exemplar members do not match the manifest's exemplars")
    return {ref: read_exemplar_png(_read_member(zf, infos[f"exemplars/{ref}.png"], name),
                                   f"{name}: exemplars/{ref}.png", ref)
            for ref in manifest.exemplars}


def _parse_dpj(data: bytes, name: str, ref: str) -> DPJ:
    """A DPJ member; its bytes must hash to the reference it is stored under."""
    return DPJ.from_bytes(data, name, ref=ref)


def _short(exc: Exception) -> str:
    text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    return text[:160]


# -- what the CLI needs ----------------------------------------------------------------------------

def render_texture(path, *, progress=None, cancel=None) -> Document:
    """Replay a `.texture` and check its hash (`texeditor render`); returns the Document."""
    return open_recipe(read_texture(path).recipe, progress=progress, cancel=cancel)


def describe_log(actions) -> list[str]:
    """One numbered line per action (`texeditor log`, the history dock)."""
    width = len(str(len(actions)))
    return [f"{k:>{width}}. {a.label()}" for k, a in enumerate(actions, 1)]


def synthesize_texture(dpj: DPJ, width: int, height: int, *, seed: int = 0, progress=None,
                       cancel=None, tileable: bool = False, scan: str = "rows") -> History:
    """A History whose log is one synthesis (`texeditor synth ... -o OUT.texture`)."""
    history = History()
    ref = history.add_dpj(dpj)
    action = Synthesize(ref, width, height, seed, tileable, scan)
    history.apply(action, prepared=action.render_result(dpj, progress, cancel).levels)
    return history


def synthesize_scales_texture(dpjs, width: int, height: int, *, seed: int = 0, progress=None,
                              cancel=None, tileable: bool = False, tone=None) -> History:
    """A History whose log is one multi-scale synthesis (`texeditor synth MODEL.dpj -o
    OUT.texture`): the scales' DPJs travel in the file, the log replays the same levels;
    ``tone`` (PhotoModel.tone_pictures: photo, levels) travels too, as two exemplars."""
    history = History()
    refs = tuple(history.add_dpj(dpj) for dpj in dpjs)
    photo, levels = (None, None) if tone is None else map(history.add_exemplar, tone)
    action = SynthesizeScales(refs, width, height, seed, tileable, tone_photo=photo,
                              tone_levels=levels)
    history.apply(action, prepared=action.render_result(dpjs, progress, cancel).levels)
    return history


def optimize_texture(src, dst=None, *, progress=None, cancel=None) -> tuple[int, int, tuple]:
    """Write ``src``'s log optimised to ``dst`` (`texeditor log --optimise -o`), checking that it
    replays to the same result; returns the action counts (before, after) and the optimiser's
    notes. Without ``dst`` nothing is replayed or written: it says what it would do."""
    tex = read_texture(src)
    shorter = optimize_with_notes(tex.actions, tex.dpjs)
    if dst is not None:
        doc = open_recipe(dataclasses.replace(tex.recipe, actions=shorter.actions,
                                              name=f"{src} (optimised)"),
                          progress=progress, cancel=cancel)
        save_texture(dst, doc, tags=tex.manifest.tags, description=tex.manifest.description)
    return len(tex.actions), len(shorter.actions), shorter.notes
