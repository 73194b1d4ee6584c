"""The `texeditor` command: the GUI with no argument, the headless engine with a subcommand.

Exit codes: 0 success, 2 bad input (one line on stderr, never a traceback, no partial output),
130 interrupted.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from .errors import InputError, TexeditorError
from .fileio import output_path

SYNTH_OUTPUTS = (".png", ".npy", ".texture")


class _Parser(argparse.ArgumentParser):
    """argparse that reports a usage error on one line, like every other error."""

    def error(self, message):
        raise InputError(message)


def _pair(text: str, what: str) -> tuple[int, int]:
    """'3x3' → (3, 3): width x height."""
    try:
        a, b = text.lower().split("x")
        return int(a), int(b)
    except ValueError:
        raise InputError(f"{what} must look like WIDTHxHEIGHT (e.g. 3x3), got {text!r}") from None


def cmd_acquire(args) -> int:
    from .markov.estimation import estimate_dpj
    from .markov.levels import load_image, quantize

    u, v = _pair(args.window, "the window")
    out = output_path(args.output, (".dpj",))
    image = load_image(args.image)
    q = quantize(image, args.levels, method=args.quantizer)
    meta = {"source": Path(args.image).name, "quantizer": args.quantizer}
    dpj = estimate_dpj(q.levels, (u, v), args.levels, wrap=args.wrap, palette=q.palette, meta=meta)
    dpj.save(out)
    print(f"{out}: {u}x{v} window, G = {args.levels}, {len(dpj)} non-zero configurations")
    return 0


def cmd_synth(args) -> int:
    from .markov.dpj import DPJ
    from .export import write_npy, write_png
    from .markov.synthesis import synthesize

    width, height = _pair(args.size, "the size")
    out = output_path(args.output, SYNTH_OUTPUTS)
    dpj = DPJ.load(args.dpj)
    if out.suffix.lower() == ".texture":
        return _synth_texture(dpj, width, height, args.seed, out)
    result = synthesize(dpj, (height, width), seed=args.seed)
    if out.suffix.lower() == ".png":
        write_png(out, result.levels, dpj.palette)
    else:
        write_npy(out, result.levels)
    print(f"{out}: {width}x{height}, seed {args.seed}, dead-end repairs {result.repairs} "
          f"(rows redrawn {result.redraws})")
    return 0


def _synth_texture(dpj, width, height, seed, out) -> int:
    from .recipe.texturefile import save_texture, synthesize_texture

    history = synthesize_texture(dpj, width, height, seed=seed)
    save_texture(out, history)
    print(f"{out}: {width}x{height}, seed {seed}, one Synthesize action in its log")
    return 0


def cmd_render(args) -> int:
    from .export import write_npy, write_png
    from .recipe.texturefile import render_texture

    out = output_path(args.output, (".png", ".npy"))
    doc = render_texture(args.texture)  # replays and checks the stored hash
    if out.suffix.lower() == ".png":
        write_png(out, doc.levels, doc.palette, scale=args.scale)
    else:
        write_npy(out, doc.levels)
    height, width = doc.shape
    print(f"{out}: {width}x{height}, {len(doc.actions)} actions replayed, hash verified")
    return 0


def cmd_log(args) -> int:
    from .recipe.texturefile import describe_log, optimize_texture, read_texture

    if args.optimize:
        if not args.output:
            raise InputError("--optimize needs -o NEW.texture")
        before, after = optimize_texture(args.texture, output_path(args.output, (".texture",)))
        print(f"{args.output}: {before} actions optimised to {after}, same result")
        return 0
    if args.output:
        raise InputError("-o is only for --optimize")
    tex = read_texture(args.texture)
    print("\n".join(describe_log(tex.actions)) or "(no actions)")
    return 0


def cmd_dpj_info(args) -> int:
    from .markov.dpj import DPJ

    report = DPJ.load(args.dpj).report()
    print(json.dumps(report.to_dict(), indent=2) if args.json else "\n".join(report.lines()))
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="texeditor", description="Interactive texture synthesis after Olejnik (1984).",
                epilog="`texeditor` alone, or `texeditor gui [--open F] [--screenshot OUT.png]`, "
                       "opens the application window (the `app` package).")
    sub = p.add_subparsers(dest="command", parser_class=_Parser)

    a = sub.add_parser("acquire", help="estimate a DPJ from a photo")
    a.add_argument("image")
    a.add_argument("--window", default="2x2", help="UxV: u columns by v rows (default 2x2)")
    a.add_argument("--levels", type=int, default=4, help="G, the number of levels (2..16)")
    a.add_argument("--quantizer", choices=("band", "lloyd"), default="band")
    a.add_argument("--wrap", action="store_true", help="count windows on the torus")
    a.add_argument("-o", "--output", required=True, help="OUT.dpj")
    a.set_defaults(func=cmd_acquire)

    s = sub.add_parser("synth", help="synthesise a texture from a DPJ")
    s.add_argument("dpj")
    s.add_argument("--size", default="512x512", help="WIDTHxHEIGHT (default 512x512)")
    s.add_argument("--seed", type=int, default=0)
    s.add_argument("-o", "--output", required=True, help="OUT.png, OUT.npy or OUT.texture")
    s.set_defaults(func=cmd_synth)

    i = sub.add_parser("dpj-info", help="the validation report of a DPJ")
    i.add_argument("dpj")
    i.add_argument("--json", action="store_true")
    i.set_defaults(func=cmd_dpj_info)

    r = sub.add_parser("render", help="replay a .texture and write the picture or the levels")
    r.add_argument("texture")
    r.add_argument("--scale", type=int, default=1, help="PNG upscale: each point as NxN pixels")
    r.add_argument("-o", "--output", required=True, help="OUT.png or OUT.npy")
    r.set_defaults(func=cmd_render)

    lg = sub.add_parser("log", help="list the actions of a .texture (or write an optimised copy)")
    lg.add_argument("texture")
    lg.add_argument("--optimize", action="store_true", help="simplify the log (same result)")
    lg.add_argument("-o", "--output", help="NEW.texture, with --optimize")
    lg.set_defaults(func=cmd_log)

    from .bank.cli import add_parser as add_bank_parser
    add_bank_parser(sub)                     # texeditor bank list|search|show|render|…

    return p


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    try:
        parser = build_parser()
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help(sys.stderr)
            return 2
        if getattr(args, "seed", 0) is not None and getattr(args, "seed", 0) < 0:
            raise InputError("the seed must be a non-negative integer")
        return args.func(args)
    except TexeditorError as exc:
        print(f"texeditor: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"texeditor: error: {exc.filename or ''}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # `texeditor dpj-info X | head`: the reader left, not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except KeyboardInterrupt:
        print("texeditor: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
