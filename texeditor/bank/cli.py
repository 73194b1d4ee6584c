"""`texeditor bank …`: the texture bank from the command line (list, search, show, render, add,
import, export, verify).

A thin layer over texeditor.bank, plugged into the `texeditor` parser by texeditor.cli. Bad input
is a TexeditorError (exit 2, one line); `verify` exits 1 when an entry does not replay.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from . import attributes as attrs
from ..errors import InputError
from ..wording import counted


def add_parser(sub) -> None:
    """Add `bank` and its subcommands to the `texeditor` subparsers."""
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--bank", metavar="FILE",
                        help="the bank file (default: $TEXEDITOR_BANK or the user data folder)")
    b = sub.add_parser("bank", help="the texture bank: list, search, show, render, add, "
                                    "import, export, verify")
    bs = b.add_subparsers(dest="bank_command", required=True, parser_class=type(b))

    p = bs.add_parser("list", parents=[common], help="every entry, newest first")
    p.add_argument("--trash", action="store_true", help="list the trash instead")
    p.set_defaults(func=_run(cmd_list))

    p = bs.add_parser("search", parents=[common],
                      help="entries matching words (name, description, tags), tags, ranges")
    p.add_argument("text", nargs="?", default="", type=text,
                   help="words (prefixes); tag:x or #x for a tag")
    p.add_argument("--tag", action="append", default=[], type=text,
                   help="an exact tag (repeatable)")
    p.add_argument("--filter", action="append", default=[], metavar="ATTR=LO..HI",
                   help=f"an attribute range, either bound optional ({', '.join(attrs.NAMES)})")
    p.add_argument("--like", type=entry_id, metavar="ID", help="nearest to this entry first")
    p.add_argument("--limit", type=count, help="at most this many entries")
    p.add_argument("--trash", action="store_true", help="search the trash")
    p.set_defaults(func=_run(cmd_search))

    p = bs.add_parser("show", parents=[common], help="one entry: tags, attributes, its log")
    p.add_argument("id", type=entry_id)
    p.set_defaults(func=_run(cmd_show))

    p = bs.add_parser("render", parents=[common], help="replay an entry (hash checked) to an "
                                                       "image or a level matrix")
    p.add_argument("id", type=entry_id)
    p.add_argument("--scale", type=int, default=1, help="PNG upscale: each point as NxN pixels")
    p.add_argument("-o", "--output", required=True, help="OUT.png or OUT.npy")
    p.set_defaults(func=_run(cmd_render))

    for name, what in (("add", "add a .texture (named with --name)"),
                       ("import", "import a .texture (named after the file)")):
        p = bs.add_parser(name, parents=[common], help=what)
        p.add_argument("texture")
        p.add_argument("--name", type=text,
                       help="the entry's name (default: from the file name)")
        p.add_argument("--tags", type=text, help="comma-separated tags (default: the file's)")
        p.add_argument("--description", type=text, help="default: the file's")
        p.set_defaults(func=_run(cmd_add))

    p = bs.add_parser("export", parents=[common], help="write an entry as a .texture")
    p.add_argument("id", type=entry_id)
    p.add_argument("-o", "--output", required=True, help="OUT.texture")
    p.set_defaults(func=_run(cmd_export))

    p = bs.add_parser("verify", parents=[common], help="replay every entry and check its hash")
    p.set_defaults(func=_run(cmd_verify))


MAX_ID = 2**63 - 1          # SQLite's integers: a larger id could never name an entry


def entry_id(value: str) -> int:
    """An entry id (or a count) from the command line: a whole number 1..2^63-1."""
    try:
        n = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {value!r}") from None
    if not 1 <= n <= MAX_ID:
        raise argparse.ArgumentTypeError(f"{value} is out of range 1..{MAX_ID}")
    return n


def count(value: str) -> int:
    """A number of entries from the command line: 0..2^63-1."""
    return 0 if value.strip() in ("0", "+0", "-0") else entry_id(value)


def text(value: str) -> str:
    """A word, name or tag from the command line: text that is valid Unicode (bytes that are not
    UTF-8 reach Python as lone surrogates, which the bank cannot store or match)."""
    try:
        value.encode("utf-8")
    except UnicodeEncodeError:
        raise argparse.ArgumentTypeError(
            f"{ascii(value)} is not valid UTF-8 text") from None
    return value


def _run(command):
    """Open the bank named by --bank (or the default one) around a subcommand."""
    def run(args) -> int:
        from .store import Bank
        with Bank(args.bank) as bank:
            return command(bank, args)
    return run


def _ready(bank) -> None:
    """Compute what is pending (first run: the built-ins) so filters and likeness see it."""
    pending = bank.pending()
    if pending:
        print(f"texeditor: preparing {len(pending)} entries (replay, thumbnail, attributes)…",
              file=sys.stderr)
        for check in bank.prepare_pending():
            print(f"texeditor: {check.message}", file=sys.stderr)


# -- the subcommands ----------------------------------------------------------------------------

def cmd_list(bank, args) -> int:
    _print_table(bank.entries(bank.find(trash=args.trash)))
    _skipped(bank)
    return 0


def _skipped(bank) -> None:
    """Name the damaged rows a listing left out (``texeditor bank verify`` lists them all)."""
    for message in bank.skipped:
        print(f"texeditor: skipped: {message}", file=sys.stderr)
    bank.skipped.clear()


def cmd_search(bank, args) -> int:
    from .store import parse_range
    ranges = dict(parse_range(text) for text in args.filter)
    if ranges or args.like is not None:
        _ready(bank)
    if args.limit is not None and args.limit < 0:
        raise InputError("--limit must be a non-negative integer")
    found = bank.search(args.text, tags=args.tag, ranges=ranges, like=args.like,
                        trash=args.trash, limit=args.limit)
    if args.text and not bank.fts:
        print(f"texeditor: note: {bank.search_mode}", file=sys.stderr)
    _print_table(found)
    _skipped(bank)
    return 0


def cmd_show(bank, args) -> int:
    from ..recipe.texturefile import describe_log
    if bank.get(args.id).pending:
        _ready(bank)
    e = bank.get(args.id)
    kind = " (built-in)" if e.builtin else ""
    lines = [f"entry {e.id}: {e.name}{kind}",
             f"size {e.width}x{e.height}, G = {e.levels}, {counted(e.actions, 'action')} "
             "(optimised log)",
             f"SHA-256 {e.sha256}",
             f"tags: {', '.join(e.tags) or '—'}",
             f"created {_when(e.created)}, modified {_when(e.modified)}"
             + (f", in the trash since {_when(e.trashed)}" if e.trashed else "")]
    if e.parent is not None:
        lines.append(f"a new version of entry {e.parent}")
    if e.description:
        lines.append(f"description: {e.description}")
    lines.append("grain and density: " + (", ".join(
        f"{k} {v}" for k, v in e.grain.items()) or "as synthesised (one point, one cell)"))
    lines.append("attributes:" if e.attributes else "attributes: not computed (the entry does "
                                                     "not replay; see `texeditor bank verify`)")
    for name, value in (e.attributes.to_dict().items() if e.attributes else ()):
        lines.append(f"  {name:<12} {value:>9.3f}  {attrs.DESCRIPTIONS[name]}")
    lines.append("log:")
    lines += ["  " + line for line in describe_log(bank.recipe(e.id).actions)] or ["  (empty)"]
    print("\n".join(lines))
    return 0


def cmd_render(bank, args) -> int:
    from ..fileio import output_path
    from ..export import write_npy, write_png
    out = output_path(args.output, (".png", ".npy"))
    doc = bank.render(args.id)
    if out.suffix.lower() == ".png":
        write_png(out, doc.levels, doc.palette, scale=args.scale)
    else:
        write_npy(out, doc.levels)
    height, width = doc.shape
    print(f"{out}: {width}x{height}, entry {args.id} replayed, hash verified")
    return 0


def cmd_add(bank, args) -> int:
    from .store import name_from_file
    name = args.name
    if not name:                # a file name that is not UTF-8: its bad bytes shown as �
        shown = args.texture.encode("utf-8", "surrogateescape").decode("utf-8", "replace")
        name = name_from_file(shown)
    entry_id = bank.import_texture(Path(args.texture), name=name, tags=args.tags,
                                   description=args.description)
    e = bank.get(entry_id)
    print(f"entry {e.id}: {e.name} ({e.width}x{e.height}, {e.actions} actions, "
          f"tags: {', '.join(e.tags) or '—'})")
    return 0


def cmd_export(bank, args) -> int:
    from ..fileio import output_path
    out = output_path(args.output, (".texture",))
    bank.export_texture(args.id, out)
    print(f"{out}: entry {args.id} ({bank.get(args.id).name}), hash verified")
    return 0


def cmd_verify(bank, args) -> int:
    _ready(bank)
    checks = bank.verify()
    database, entries = checks[0], checks[1:]
    bad = [c for c in entries if not c.ok]
    for check in bad:
        print(check.message)
    print(f"database integrity: {database.message}")
    print(f"{len(entries)} entries replayed: {len(entries) - len(bad)} match their recorded "
          f"SHA-256, {len(bad)} do not")
    return 0 if database.ok and not bad else 1


# -- output --------------------------------------------------------------------------------------

def _print_table(entries) -> None:
    if not entries:
        print("(no entries)")
        return
    width = min(32, max(len(e.name) for e in entries))
    print(f"{'ID':>5}  {'NAME':<{width}}  {'SIZE':>9}  {'G':>2}  {'STEPS':>5}  TAGS")
    for e in entries:
        name = e.name if len(e.name) <= width else e.name[:width - 1] + "…"
        print(f"{e.id:>5}  {name:<{width}}  {f'{e.width}x{e.height}':>9}  {e.levels:>2}  "
              f"{e.actions:>5}  {', '.join(e.tags)}")


def _when(stamp: float) -> str:
    """A bank time as the user reads it; one past what the platform's clock can show (a
    damaged row: 1e300, NaN) is an unknown time, not a traceback."""
    try:
        return time.strftime("%Y-%m-%d %H:%M", time.localtime(stamp))
    except (OverflowError, OSError, ValueError):
        return "at an unknown time"
