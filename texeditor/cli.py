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
from .version import __version__
from .wording import counted

SYNTH_OUTPUTS = (".png", ".npy", ".texture")
COMPILING_NOTE = ("texeditor: preparing the synthesis engine (first run only, a minute or so; "
                  "later runs start at once)…")


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
    from .markov.multiscale import scales_phrase

    out = output_path(args.output, (".dpj",))
    if args.scales is not None and (args.scan or args.stationary):
        raise InputError("--scan and --stationary acquire one DPJ: leave out --scales")
    image = load_image(args.image)
    if args.scales is not None:
        model = _acquire_model(image, args)
        model.save(out)
        windows = ", ".join(f"{d.window[0]}x{d.window[1]}" for d in model.scales.dpjs)
        print(f"{out}: photo model, {scales_phrase(model.scales.scales)} ({windows}), "
              f"G = {model.levels}, tone {'kept' if model.tone is not None else 'off'}, "
              f"{len(out.read_bytes())} bytes")
        return 0
    u, v = _pair(args.window or "2x2", "the window")
    method = args.quantizer or "band"
    q = quantize(image, args.levels, method=method)
    meta = {"source": Path(args.image).name, "quantizer": method}
    scan = args.scan or "rows"
    dpj = estimate_dpj(q.levels, (u, v), args.levels, wrap=args.wrap, scan=scan,
                       stationary=args.stationary, palette=q.palette, meta=meta)
    dpj.save(out)
    print(f"{out}: {u}x{v} window, G = {args.levels}, {len(dpj)} non-zero configurations, "
          f"scan {scan}{', made stationary' if args.stationary else ''}")
    return 0


def cmd_synth(args) -> int:
    from .export import write_npy, write_png
    from .markov.scan import synthesize
    from .photo import load_model

    width, height = _pair(args.size, "the size")
    out = output_path(args.output, SYNTH_OUTPUTS)
    dpj = load_model(args.dpj)
    if hasattr(dpj, "scales"):
        if args.scan not in (None, "rows"):
            raise InputError("a photo model is drawn in the rows scan only: leave out --scan")
        return _synth_model(dpj, width, height, args.seed, out, tone=not args.no_tone,
                            tileable=args.tileable)
    scan = args.scan or dpj.meta.get("scan", "rows")      # the scan it was acquired in
    if out.suffix.lower() == ".texture":
        return _synth_texture(dpj, width, height, args.seed, out, args.tileable, scan)
    result = synthesize(dpj, (height, width), seed=args.seed, tileable=args.tileable, scan=scan)
    if out.suffix.lower() == ".png":
        write_png(out, result.levels, dpj.palette)
    else:
        write_npy(out, result.levels)
    print(f"{out}: {width}x{height}, seed {args.seed}{', tileable' if args.tileable else ''}, "
          f"scan {scan}, dead-end repairs {result.repairs} (rows redrawn {result.redraws})")
    return 0


def _acquire_model(image, args, shape=None):
    """The photo model the flags ask for; ``shape``: the texture to draw (auto scales fit it)."""
    from .photo import acquire_model, auto_scales

    options = {"levels": args.levels, "quantizer": args.quantizer or "lab",
               "tone": not args.no_tone}
    if args.window:
        options["window"] = _pair(args.window, "the window")
    if args.coarse_window:
        options["coarse_window"] = _pair(args.coarse_window, "the coarse window")
    if args.coarse_levels is not None:
        options["coarse_levels"] = args.coarse_levels
    scales = None if args.scales in (None, "auto") else _count(args.scales, "--scales")
    if scales is None and shape is not None:
        scales = auto_scales(image, shape, **options)
    return acquire_model(image, scales=scales, **options)


def _count(text: str, what: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise InputError(f"{what} must be a number or 'auto', got {text!r}") from None


def _synth_model(model, width, height, seed, out, tone=True, tileable=False) -> int:
    """A photo model: its picture (PNG: tone or palette), its levels (.npy) or a .texture whose
    log draws the same levels from the scales' DPJs."""
    from .export import write_npy, write_picture
    from .markov.multiscale import scales_phrase
    from .recipe.texturefile import save_texture, synthesize_scales_texture

    suffix = out.suffix.lower()
    if suffix == ".texture":
        pictures = model.tone_pictures() if tone else None
        save_texture(out, synthesize_scales_texture(model.scales.dpjs, width, height, seed=seed,
                                                    tileable=tileable, tone=pictures))
        print(f"{out}: {width}x{height}, seed {seed}, one multi-scale synthesis in its log"
              + (", with the photo's tone" if pictures is not None else ""))
        return 0
    result = model.synthesize((height, width), seed=seed, tone=tone, tileable=tileable)
    if suffix == ".png":
        write_picture(out, result.image)
    else:
        write_npy(out, result.levels)
    print(f"{out}: {width}x{height}, seed {seed}{', tileable' if tileable else ''}, "
          f"{scales_phrase(model.scales.scales)}, "
          f"{'photographic tone' if tone and model.tone is not None else 'palette'}, "
          f"dead-end repairs {result.repairs}"
          + (f", level shares rebalanced ({result.moved} border moves)" if result.moved else ""))
    return 0


def cmd_resynth(args) -> int:
    """Photo → texture in one command (a photo model acquired and drawn, not saved)."""
    import time
    from .markov.levels import load_image

    width, height = _pair(args.size, "the size")
    out = output_path(args.output, (".png", ".npy", ".texture"))
    start = time.perf_counter()
    model = _acquire_model(load_image(args.photo), args, (height, width))
    code = _synth_model(model, width, height, args.seed, out, tone=not args.no_tone,
                        tileable=args.tileable)
    print(f"({time.perf_counter() - start:.2f} s)")
    return code


def _synth_texture(dpj, width, height, seed, out, tileable=False, scan="rows") -> int:
    from .recipe.texturefile import save_texture, synthesize_texture

    history = synthesize_texture(dpj, width, height, seed=seed, tileable=tileable, scan=scan)
    save_texture(out, history)
    print(f"{out}: {width}x{height}, seed {seed}, scan {scan}, one Synthesize action in its log")
    return 0


def cmd_render(args) -> int:
    from .export import write_npy, write_picture, write_png
    from .recipe.texturefile import render_texture
    from .photo import document_tone
    from .texture.plates import document_picture

    out = output_path(args.output, (".png", ".npy"))
    doc = render_texture(args.texture)  # replays and checks the stored hash
    plates = doc.plates is not None and not args.no_plates
    tone = None if plates or args.no_tone else document_tone(doc)
    shown = ""
    if out.suffix.lower() == ".npy":
        write_npy(out, doc.levels)
    elif plates:                        # RGB: the texture's greys laid on its colour plates
        write_picture(out, document_picture(doc), scale=args.scale)
        shown = ", on its colour plates"
    elif tone is not None:              # the greys and colours of the photo it was made from
        write_picture(out, tone, scale=args.scale)
        shown = ", with its photo's tone"
    else:
        write_png(out, doc.levels, doc.palette, scale=args.scale)
    height, width = doc.shape
    print(f"{out}: {width}x{height}, {counted(len(doc.actions), 'action')} replayed, hash "
          f"verified{shown}")
    return 0


def cmd_export(args) -> int:
    """A .texture replayed, then its relief maps written: the height map (16-bit grey PNG) and
    the tangent-space normal map (RGB PNG, OpenGL's green unless --directx)."""
    from .recipe.texturefile import render_texture
    from .relief import write_height_map, write_normal_map
    from .relief.shading import check_strength

    if not (args.height or args.normal):
        raise InputError("say what to export: --height H.png, --normal N.png, or both")
    outs = [output_path(p, (".png",)) if p else None for p in (args.height, args.normal)]
    if None not in outs and outs[0].resolve() == outs[1].resolve():
        raise InputError("--height and --normal name the same file")
    strength = check_strength(args.strength)
    doc = render_texture(args.texture)   # replays and checks the stored hash
    if not doc.levels.size:
        raise InputError(f"{args.texture}: its log draws no texture: nothing to export")
    height, normal = outs
    if height is not None:
        write_height_map(height, doc.levels, doc.palette)
        print(f"{height}: height map, {doc.shape[1]}x{doc.shape[0]}, 16-bit grey")
    if normal is not None:
        write_normal_map(normal, doc.levels, doc.palette, strength=strength,
                         directx=args.directx, wrap=not args.no_wrap)
        print(f"{normal}: normal map, strength {strength:g}, "
              f"{'DirectX' if args.directx else 'OpenGL'} green, "
              f"{'one-sided at the border' if args.no_wrap else 'seamless (wrapped)'}")
    return 0


def cmd_log(args) -> int:
    from .recipe.texturefile import describe_log, optimize_texture, read_texture

    if args.optimise:
        out = args.output and output_path(args.output, (".texture",))
        before, after, notes = optimize_texture(args.texture, out)
        print(f"{args.output}: {before} actions optimised to {after}, same result" if out else
              f"{before} actions would be optimised to {after} (-o NEW.texture writes them)")
        print("\n".join(f"  {note}" for note in notes) or "  (nothing to do)")
        return 0
    if args.output:
        raise InputError("-o is only for --optimise")
    tex = read_texture(args.texture)
    print("\n".join(describe_log(tex.actions)) or "(no actions)")
    return 0


def cmd_dpj_info(args) -> int:
    from .photo import load_model

    model = load_model(args.dpj)
    dpjs = model.scales.dpjs if hasattr(model, "scales") else (model,)
    reports = [d.report() for d in dpjs]
    if args.json:
        print(json.dumps(reports[0].to_dict() if len(reports) == 1
                         else {"scales": [r.to_dict() for r in reports]}, indent=2))
        return 0
    for k, report in enumerate(reports):
        if len(reports) > 1:
            print(f"scale {k} of {len(reports)} (coarsest first)"
                  + (", conditional on the scale under it" if k else ""))
        print("\n".join(report.lines()))
    return 0


def _model_options(p) -> None:
    p.add_argument("--coarse-window", help="UxV of the coarsest scale (default 5x5)")
    p.add_argument("--coarse-levels", type=int, help="G of the coarsest scale (default 2)")
    p.add_argument("--no-tone", action="store_true", help="keep no tone (flat palette colours)")


def _scan_option(p, text: str) -> None:
    from .markov.scan import SCANS
    p.add_argument("--scan", choices=SCANS, default=None, help=text)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="texeditor", description="Interactive texture synthesis after Olejnik (1984).",
                epilog="`texeditor` alone, or `texeditor gui [--open F] [--screenshot OUT.png]`, "
                       "opens the application window (the `app` package).")
    p.add_argument("--version", action="version", version=f"texeditor {__version__}")
    sub = p.add_subparsers(dest="command", parser_class=_Parser)

    a = sub.add_parser("acquire", help="estimate a DPJ from a photo")
    a.add_argument("image")
    a.add_argument("--window", help="UxV: u columns by v rows (default 2x2; with --scales, "
                   "the finer scales' window, default 3x2)")
    a.add_argument("--levels", type=int, default=4, help="G, the number of levels (2..16)")
    a.add_argument("--quantizer", choices=("band", "lloyd", "lab"), default=None,
                   help="default: band (lloyd with --scales); lab: colour classes in CIELAB")
    a.add_argument("--wrap", action="store_true", help="count windows on the torus")
    _scan_option(a, "the order the window sweeps the photo: rows (top to bottom, the default), "
                    "rows-up, columns (left to right) or columns-left; the DPJ records it")
    a.add_argument("--stationary", action="store_true", help="make the DPJ stationary (its "
                   "left/right and top/bottom sub-windows equally likely, thesis §5.2.2)")
    a.add_argument("--scales", help="N or auto: a photo model of N scales with the photo's tone "
                   "(a .dpj of format 2) instead of one DPJ")
    _model_options(a)
    a.add_argument("-o", "--output", required=True, help="OUT.dpj")
    a.set_defaults(func=cmd_acquire)

    s = sub.add_parser("synth", help="synthesise a texture from a DPJ")
    s.add_argument("dpj")
    s.add_argument("--size", default="512x512", help="WIDTHxHEIGHT (default 512x512)")
    s.add_argument("--seed", type=int, default=0)
    s.add_argument("--no-tone", action="store_true",
                   help="a photo model's PNG in its palette's flat colours, not the photo's tone")
    s.add_argument("--tileable", action="store_true", help="repeat without a seam (the Markov "
                   "process drawn on the torus)")
    _scan_option(s, "the order the texture is drawn in (default: the scan the DPJ was "
                    "acquired in, else rows)")
    s.add_argument("-o", "--output", required=True, help="OUT.png, OUT.npy or OUT.texture")

    rs = sub.add_parser("resynth", help="photo → texture: a multi-scale DPJ drawn with the "
                        "photo's tone (defaults chosen for quality)")
    rs.add_argument("photo")
    rs.add_argument("--size", default="512x512", help="WIDTHxHEIGHT (default 512x512)")
    rs.add_argument("--seed", type=int, default=0)
    rs.add_argument("--scales", default="auto", help="N or auto (about 64 points a side at the "
                    "photo's coarsest; fewer when the texture is too small to hold them)")
    rs.add_argument("--window", help="UxV of the finer scales (default 3x2)")
    rs.add_argument("--levels", type=int, default=4, help="G of the finer scales (default 4)")
    rs.add_argument("--quantizer", choices=("band", "lloyd", "lab"), default="lab",
                    help="lab (default): colour classes in CIELAB, Lloyd–Max on a grey photo")
    rs.add_argument("--tileable", action="store_true", help="repeat without a seam")
    _model_options(rs)
    rs.add_argument("-o", "--output", required=True, help="OUT.png, OUT.npy or OUT.texture")
    rs.set_defaults(func=cmd_resynth)
    s.set_defaults(func=cmd_synth)

    i = sub.add_parser("dpj-info", help="the validation report of a DPJ")
    i.add_argument("dpj")
    i.add_argument("--json", action="store_true")
    i.set_defaults(func=cmd_dpj_info)

    r = sub.add_parser("render", help="replay a .texture and write the picture or the levels")
    r.add_argument("texture")
    r.add_argument("--scale", type=int, default=1, help="PNG upscale: each point as NxN pixels")
    r.add_argument("--no-plates", action="store_true",
                   help="PNG: the levels in their palette, without the colour plates")
    r.add_argument("--no-tone", action="store_true",
                   help="PNG: the levels in their palette, not in the tone of the photo a "
                        "multi-scale synthesis was made from")
    r.add_argument("-o", "--output", required=True, help="OUT.png or OUT.npy")
    r.set_defaults(func=cmd_render)

    e = sub.add_parser("export", help="replay a .texture and write its relief: a height map "
                       "and a normal map")
    e.add_argument("texture")
    e.add_argument("--height", metavar="H.png", help="the height map: the texture's greys as a "
                   "16-bit grey PNG")
    e.add_argument("--normal", metavar="N.png", help="the tangent-space normal map, an RGB PNG")
    e.add_argument("--strength", type=float, default=4.0,
                   help="heights are the greys (0..1) times this (default 4)")
    e.add_argument("--directx", action="store_true",
                   help="green points down the picture (DirectX); default up (OpenGL)")
    e.add_argument("--no-wrap", action="store_true", help="one-sided differences at the border "
                   "(default: on the torus, seamless when the texture tiles)")
    e.set_defaults(func=cmd_export)

    lg = sub.add_parser("log", help="list the actions of a .texture (or write an optimised copy)")
    lg.add_argument("texture")
    lg.add_argument("--optimise", "--optimize", action="store_true",
                    help="simplify and reorder the log (same result) and say what was done")
    lg.add_argument("-o", "--output", help="NEW.texture, with --optimise")
    lg.set_defaults(func=cmd_log)

    from .bank.cli import add_parser as add_bank_parser
    add_bank_parser(sub)                     # texeditor bank list|search|show|render|…

    return p


def _run(args) -> int:
    """Run a command; a person at a terminal is told why a first run is silent for a minute."""
    if not sys.stderr.isatty():
        return args.func(args)
    from .warmup import on_first_compile
    forget = on_first_compile(lambda: print(COMPILING_NOTE, file=sys.stderr, flush=True))
    try:
        return args.func(args)
    finally:
        forget()


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
        return _run(args)
    except TexeditorError as exc:
        print(f"texeditor: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # `texeditor bank list | head`: the reader left, not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())   # (an OSError: first)
        return 1
    except OSError as exc:
        print(f"texeditor: error: {exc.filename or ''}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("texeditor: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
