"""The log codec: an action log to JSON and back — the one reader of logs.

Files (`actions.json`), bank rows, the recipes a composition step names and the crash journal all
hold the same ``{"actions": [...]}`` object; each is read here, bounded and checked step by step,
so a log means the same wherever it is stored. A stored Action is found by its type string.
"""

from __future__ import annotations

import dataclasses
import json

from ..errors import FormatError, InputError
from ..fileio import load_json
from .actions import REGISTRY, Action

MAX_ACTIONS = 250_000                 # measured: a log this long replays within 2 GiB
MAX_LOG_BYTES = 64 * 2**20            # its JSON text


def log_json(actions) -> dict:
    """The log as a JSON object ``{"actions": [...]}``."""
    return {"actions": [a.to_json() for a in actions]}


def log_text(actions) -> str:
    """The canonical text of a log (compact JSON): a bank row, a recipe named by a step."""
    return json.dumps(log_json(actions), separators=(",", ":"), ensure_ascii=False,
                      allow_nan=False)


def read_log(source, what: str, *, max_actions: int = MAX_ACTIONS,
             max_bytes: int = MAX_LOG_BYTES, min_actions: int = 0,
             error: type[Exception] = FormatError) -> tuple[Action, ...]:
    """The Actions of a log given as JSON text (bounded before it is parsed) or as the parsed
    object; any defect is an ``error`` naming ``what`` and, for a step, its number."""
    if isinstance(source, (str, bytes)):
        if len(source) > max_bytes:
            raise error(f"{what}: a log is a JSON text of at most {max_bytes} bytes")
        try:
            source = load_json(source, "JSON", limit=max_bytes)      # size and depth bounded
        except FormatError as exc:
            raise error(f"{what}: not an action log ({exc})") from None
    if not isinstance(source, dict) or set(source) != {"actions"} \
            or not isinstance(source["actions"], list):
        raise error(f'{what}: must be an object {{"actions": [...]}}')
    items = source["actions"]
    if not min_actions <= len(items) <= max_actions:
        raise error(f"{what}: {len(items)} actions, outside {min_actions}..{max_actions}")
    actions = []
    for k, item in enumerate(items):
        try:
            actions.append(action_from_json(item))
        except (FormatError, RecursionError) as exc:
            raise error(f"{what}: action {k + 1}: {exc}") from None
    return tuple(actions)


def action_from_json(obj) -> Action:
    """Build an Action from its JSON object, checking type, version and every parameter."""
    if not isinstance(obj, dict):
        raise FormatError(f"an action must be a JSON object, got {type(obj).__name__}")
    kind, version = obj.get("type"), obj.get("version")
    known = REGISTRY
    cls = known.get(kind) if isinstance(kind, str) else None
    if cls is None:
        raise FormatError(f"unknown action type {kind!r}: this program knows "
                          f"{', '.join(sorted(known))}")
    if isinstance(version, bool) or not isinstance(version, int):
        raise FormatError(f"action {kind!r} has no integer version")
    params = {k: v for k, v in obj.items() if k not in ("type", "version")}
    if version != cls.VERSION:
        if not 1 <= version < cls.VERSION:
            raise FormatError(f"action {kind!r} version {version} is not supported "
                              f"(this program reads version {cls.VERSION})")
        params = cls.upgrade(version, params)
    names = {f.name for f in dataclasses.fields(cls)}
    unknown = sorted(set(params) - names)
    if unknown:
        raise FormatError(f"action {kind!r} has unexpected parameters {unknown}")
    try:
        return cls(**params)
    except InputError as exc:
        raise FormatError(f"action {kind!r}: {exc}") from None
    except TypeError:
        missing = sorted(f.name for f in dataclasses.fields(cls)
                         if f.name not in params and f.default is dataclasses.MISSING)
        raise FormatError(f"action {kind!r} lacks parameters {missing}") from None
