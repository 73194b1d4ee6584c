"""Time and peak memory of inputs at the documented limits (issue 17): prints figures only.

Each case builds one input at a limit of docs/formats.md in a temporary folder, then runs the
command a user would run on it (`texeditor dpj-info`, `render`, `acquire`, `synth`, `gui
--screenshot`) in a fresh process. The peak is that process's VmHWM (its own high-water resident
memory; getrusage's maxrss of a child can report the parent's). The target is ≤ 2 GiB and a time
a user waits for with a progress bar, on the 2-core machine of the closing note.
Run: python3 benchmarks/bench_limits.py [--only NAME ...] [--keep DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from texeditor import DPJ  # noqa: E402
from texeditor.recipe.actions import SetLevels  # noqa: E402
from texeditor.markov.dpj import MAX_ENTRIES  # noqa: E402
from texeditor.recipe.document import Document  # noqa: E402
from texeditor.recipe import journal  # noqa: E402
from texeditor.recipe.texturefile import MAX_ACTIONS, MAX_DPJ_CONTENT, MAX_DPJS, texture_bytes  # noqa: E402
from texeditor.fileio import write_file  # noqa: E402

# The child runs the CLI (or a snippet), then reports its own peak resident memory on stderr.
CHILD = """\
import atexit, re, sys
def _peak():
    with open('/proc/self/status') as f:
        sys.stderr.write('\\nPEAK_KIB %s\\n' % re.search(r'VmHWM:\\s+(\\d+)', f.read())[1])
atexit.register(_peak)
"""
CLI = """\
sys.argv = ['texeditor'] + sys.argv[1:]
from app.main import main
sys.exit(main())
"""

LIMIT_KIB = 2 * 2**20


def run(args: list[str], timeout: float = 600) -> dict:
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    start = time.perf_counter()
    try:
        code = CHILD + (args[1] if args[0] == "--python" else CLI)
        args = [] if args[0] == "--python" else args
        proc = subprocess.run([sys.executable, "-c", code, *map(str, args)], env=env, cwd=ROOT,
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"seconds": timeout, "peak_mib": None, "rc": "timeout", "message": ""}
    seconds = time.perf_counter() - start
    peaks = [int(line.split()[1]) for line in proc.stderr.splitlines() if line.startswith("PEAK_KIB")]
    message = [line for line in proc.stderr.splitlines() if line.strip() and
               not line.startswith("PEAK_KIB")]
    return {"seconds": seconds, "peak_mib": peaks[-1] // 1024 if peaks else None,
            "rc": proc.returncode, "message": (message[-1] if message else proc.stdout.strip()[-120:])}


# -- inputs at the limits -----------------------------------------------------------------------

def big_dpj(entries: int, seed: int, window=(3, 3), levels: int = 16) -> DPJ:
    """`entries` distinct random configurations with random probabilities."""
    rng = np.random.default_rng(seed)
    u, v = window
    codes = np.unique(rng.integers(0, levels ** (u * v), int(entries * 1.02), dtype=np.int64))
    codes = rng.permutation(codes)[:entries]
    probs = rng.random(len(codes))
    return DPJ.from_codes(codes, probs / probs.sum(), levels, window)


def photo_png(path: Path, side: int, channels: int) -> None:
    """A side² photo-like PNG (smooth blobs plus noise): compresses as a photo does."""
    import imageio.v3 as iio
    rng = np.random.default_rng(7)
    small = rng.random((side // 64, side // 64, channels))
    coarse = np.kron(small, np.ones((64, 64, 1)))
    rows = []
    for y in range(0, side, 1024):   # noise added by bands: the builder stays small
        band = coarse[y:y + 1024] * 200 + rng.integers(0, 56, (min(1024, side - y), side, channels))
        rows.append(band.astype(np.uint8))
    iio.imwrite(path, np.concatenate(rows))


def case_dpj_info(folder: Path) -> list:
    path = folder / "entries.dpj"
    big_dpj(MAX_ENTRIES, 1).save(path)
    return [f"dpj-info, {MAX_ENTRIES:,}-entry 3×3 G=16 DPJ ({path.stat().st_size / 2**20:.0f} MiB)",
            ["dpj-info", path]]


def case_texture_dpjs(folder: Path) -> list:
    """As many of the largest DPJs as a .texture may carry, each synthesised once."""
    from texeditor.recipe.actions import Synthesize
    dpjs, total = [], 0
    while len(dpjs) < MAX_DPJS:
        dpj = big_dpj(MAX_ENTRIES, 100 + len(dpjs))
        if total + len(dpj.to_bytes()) > MAX_DPJ_CONTENT:
            break
        dpjs.append(dpj)
        total += len(dpj.to_bytes())
    doc = Document()
    for i, dpj in enumerate(dpjs):
        doc.apply(Synthesize(doc.add_dpj(dpj), 64, 64, seed=i))
    path = folder / "dpjs.texture"
    write_file(path, texture_bytes(doc, doc.actions)[0])
    return [f"render, .texture with {len(dpjs)} DPJs of {MAX_ENTRIES:,} entries "
            f"({path.stat().st_size / 2**20:.0f} MiB)", ["render", path, "-o", folder / "d.png"]]


def case_journal(folder: Path) -> list:
    """A crash journal at its size limit, filled with distinct DPJs of the largest size."""
    import base64
    path = folder / "big.journal"
    with open(path, "wb") as f:
        f.write(json.dumps({"kind": "start", "format": journal.FORMAT, "time": 0,
                            "source": None}).encode() + b"\n")
        for seed in range(1000):
            dpj = big_dpj(MAX_ENTRIES, 300 + seed)
            record = json.dumps({"kind": "dpj", "ref": dpj.ref,
                                 "data": base64.b64encode(dpj.to_bytes()).decode()}).encode()
            if f.tell() + len(record) + 1 > journal.MAX_JOURNAL_BYTES:
                break
            f.write(record + b"\n")
    return [f"journal recovery, {path.stat().st_size / 2**20:.0f} MiB: {seed} distinct DPJs of "
            f"{MAX_ENTRIES:,} entries", ["--python", "from texeditor.recipe import journal; "
                                        f"print(len(journal.recover({str(path)!r}).dpjs))"]]


def case_long_log(folder: Path) -> list:
    n = int(os.environ.get("BENCH_ACTIONS", MAX_ACTIONS))
    rng = np.random.default_rng(3)
    doc = Document.new(256, 256, 4)
    for _ in range(n - 1):
        y, x = (int(v) for v in rng.integers(0, 253, 2))
        doc.apply(SetLevels(y, x, 4, 4, int(rng.integers(0, 4))))
    path = folder / "long.texture"
    write_file(path, texture_bytes(doc, doc.actions)[0])
    return [f"render, .texture of {n:,} actions ({path.stat().st_size / 2**20:.0f} MiB)",
            ["render", path, "-o", folder / "l.png"]]


def case_acquire(folder: Path, channels: int = 4) -> list:
    path = folder / "photo.png"
    photo_png(path, 8192, channels)
    return [f"acquire, 8192² (64 MP) RGBA PNG ({path.stat().st_size / 2**20:.0f} MiB), 3×3 G=8 lloyd",
            ["acquire", path, "--window", "3x3", "--levels", "8", "--quantizer", "lloyd",
             "-o", folder / "p.dpj"]]


def case_acquire_model(folder: Path) -> list:
    path = folder / "photo-rgb.png"
    photo_png(path, 8192, 3)
    return [f"acquire --scales, 8192² (64 MP) RGB PNG ({path.stat().st_size / 2**20:.0f} MiB), "
            "photo model (CIELAB classes)", ["acquire", path, "--scales", "auto",
                                            "-o", folder / "m.dpj"]]


def case_synth(folder: Path) -> list:
    dpj = sorted((ROOT / "resources" / "dpj").glob("*.dpj"))[0]    # acquired from a photo
    return [f"synth, 8192×8192 (2^26 points, the canvas limit) from {dpj.name}",
            ["synth", dpj, "--size", "8192x8192", "-o", folder / "s.texture"]]


def case_synth_png(folder: Path) -> list:
    dpj = sorted((ROOT / "resources" / "dpj").glob("*.dpj"))[0]
    return ["synth, 16384×16384 (2^28 points, the synthesis limit) to PNG",
            ["synth", dpj, "--size", "16384x16384", "-o", folder / "s.png"]]


def case_screenshot(folder: Path) -> list:
    return ["gui --screenshot at 7680×4320", ["gui", "--screenshot", folder / "shot.png",
                                             "--size", "7680x4320"]]


CASES = {"dpj-info": case_dpj_info, "texture-dpjs": case_texture_dpjs, "long-log": case_long_log,
         "journal": case_journal,
         "acquire": case_acquire, "acquire-model": case_acquire_model, "synth": case_synth,
         "synth-png": case_synth_png,
         "screenshot": case_screenshot}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", choices=sorted(CASES))
    parser.add_argument("--keep", type=Path, help="build the inputs in this folder and keep them")
    args = parser.parse_args()
    print(f"# {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"numpy {np.__version__}")
    print(f"{'input at the limit':<78} {'time':>8} {'peak':>9}  result")
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.keep or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        for name in args.only or CASES:
            title, command = CASES[name](folder)
            r = run(command)
            peak = f"{r['peak_mib']:,} MiB" if r["peak_mib"] is not None else "?"
            flag = "" if r["peak_mib"] is not None and r["peak_mib"] * 1024 <= LIMIT_KIB else " (!)"
            print(f"{title:<78} {r['seconds']:7.1f}s {peak:>9}{flag}  rc={r['rc']} {r['message'][:70]}",
                  flush=True)


if __name__ == "__main__":
    main()
