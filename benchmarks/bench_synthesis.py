"""Warm synthesis time, MPix/s and dead-end figures for DPJs acquired from scikit-image's gravel.

Run: python benchmarks/bench_synthesis.py [--photo gravel] [--repeat 5] [--compile]
Targets (2-core machine): 512², 2x2, G = 8 in <= 80 ms; 3x3, G = 4 in <= 150 ms; time linear in
pixels; memory O(non-zero entries + width · G^u).
"""

import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np
from skimage import data

from texeditor import estimate_dpj, quantize, synthesize
from texeditor.markov.synthesis import _tables

CASES = [((2, 2), 2, False), ((2, 2), 4, False), ((2, 2), 8, False), ((3, 3), 4, True)]


def table_bytes(dpj) -> int:
    return sum(a.nbytes for a in _tables(dpj) if isinstance(a, np.ndarray))


def first_compile_seconds() -> float:
    """A first start's wait: the kernels compiled into an empty numba cache, in a fresh process."""
    code = ("import time; from app.resources import default_dpj; from texeditor import synthesize;"
            "d = default_dpj(); t = time.perf_counter(); synthesize(d, (64, 64));"
            "print(time.perf_counter() - t)")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": root}
        out = subprocess.run([sys.executable, "-c", code], env=env, cwd=root, check=True,
                             capture_output=True, text=True).stdout
    return float(out.split()[-1])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--photo", default="gravel")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--compile", action="store_true",
                    help="also time a first compile of the kernels (an empty numba cache)")
    args = ap.parse_args()
    if args.compile:
        print(f"first compile of the kernels (empty numba cache): {first_compile_seconds():.1f} s")
    photo = getattr(data, args.photo)()
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, {platform.python_version()}; "
          f"photo: {args.photo}; best of {args.repeat} warm runs "
          "(ms: wall clock; cpu ms: this thread's CPU time, steadier on a shared machine)")
    print(f"{'window':>6} {'G':>2} {'wrap':>4} {'size':>9} {'entries':>7} {'ms':>8} {'cpu ms':>8} {'MPix/s':>7} "
          f"{'repairs':>7} {'redraws':>7} {'tables KiB':>10}")
    for window, levels, wrap in CASES:
        dpj = estimate_dpj(quantize(photo, levels).levels, window, levels, wrap=wrap)
        synthesize(dpj, (64, 64))  # compile / load the numba cache, build the tables
        for side in (512, 1024):
            times, cpu, result = [], [], None
            for seed in range(args.repeat):
                t0, c0 = time.perf_counter(), time.thread_time()
                result = synthesize(dpj, (side, side), seed=seed)
                times.append(time.perf_counter() - t0)
                cpu.append(time.thread_time() - c0)
            best = min(times)
            u, v = window
            print(f"{u}x{v:<4} {levels:>2} {str(wrap):>4} {side:>4}x{side:<4} {len(dpj):>7} "
                  f"{best * 1e3:>8.1f} {min(cpu) * 1e3:>8.1f} {side * side / best / 1e6:>7.2f} {result.repairs:>7} "
                  f"{result.redraws:>7} {table_bytes(dpj) / 1024:>10.1f}")


if __name__ == "__main__":
    main()
