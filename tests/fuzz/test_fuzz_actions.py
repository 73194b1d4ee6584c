"""Fuzzing actions that escape the canvas (issue 17, class 2): spots, scatters, strokes and grain
placements far off a small canvas, huge, or with tiny spacings along long paths. Each must replay
or be refused with a TexeditorError, within 2 GiB of address space and a time limit: the cases run
in a child process under RLIMIT_AS, so a blow-up fails the test instead of the machine.
"""

import json
import os
import subprocess
import sys

import numpy as np

from texeditor.spots.envelope import Envelope

CASES = int(os.environ.get("TEXEDITOR_FUZZ_EXAMPLES", "300")) // 10
FAR = 2**20


def escaping_action(rng: np.random.Generator) -> dict:
    """One action (JSON) meant to reach far beyond a 64×64 canvas."""
    kind = rng.choice(["place_spot", "scatter_spots", "stroke", "place_grains"])
    where = lambda: float(rng.choice([rng.uniform(-16384, 16384), rng.uniform(-80, 140), 32.0]))
    path = lambda: [[int(rng.integers(-FAR, FAR)), int(rng.integers(-FAR, FAR))]
                    for _ in range(int(rng.integers(1, 6)))]
    if kind in ("place_spot", "scatter_spots"):
        length = float(rng.choice([10, 400, 4000, 16000]))
        env = Envelope.ellipse(length, length * float(rng.uniform(0.05, 1.0))).dumps()
        extra = {"fractal": float(rng.uniform(0, 1)), "contour": float(rng.uniform(0, 1))} \
            if rng.random() < 0.5 else {}
        if rng.random() < 0.3:
            extra.update(interior=str(rng.choice(["holes", "levels", "relief"])),
                         density=float(rng.uniform(0, 1)))
        extra["wrap"] = bool(rng.random() < 0.15)
        if kind == "place_spot":
            return {"type": kind, "version": 1, "envelope": env, "row": where(), "col": where(),
                    "scale": float(rng.choice([1.0, 0.02, 3.0])), "level": 1, **extra}
        return {"type": kind, "version": 1, "envelope": env, "count": int(rng.integers(1, 4)),
                "top": int(rng.integers(-16384, 16384)), "left": int(rng.integers(-16384, 16384)),
                "height": int(rng.integers(1, 16384)), "width": int(rng.integers(1, 16384)),
                "level": 1, **extra}
    if kind == "stroke":
        return {"type": kind, "version": 1, "points": path(), "level": 1,
                "size": int(rng.choice([1, 9, 64])), "spacing": float(rng.choice([0.05, 1.0])),
                "distribution": str(rng.choice(["solid", "cloud"])), "wrap": bool(rng.random() < 0.2)}
    return {"type": kind, "version": 1, "points": path(), "level": 1,
            "size": int(rng.choice([1, 3, 32])), "spacing": float(rng.choice([1e-6, 0.5, 0.0, 7.0])),
            "jitter": float(rng.choice([0.0, 3.0])), "wrap": bool(rng.random() < 0.2)}


CHILD = r"""
import json, resource, sys
resource.setrlimit(resource.RLIMIT_AS, (2 * 2**30, 2 * 2**30))
from texeditor.recipe.codec import action_from_json
from texeditor.errors import TexeditorError
from texeditor.recipe.replay import replay
canvas = {"type": "new_canvas", "version": 1, "width": 64, "height": 64, "levels": 4,
          "palette": None}
for line in sys.stdin:
    case = json.loads(line)
    try:
        replay([action_from_json(canvas), action_from_json(case)], {})
    except TexeditorError:
        pass
    print("done", flush=True)
"""


def test_fuzz_canvas_escaping_actions():
    rng = np.random.default_rng(None if os.environ.get("CI_FUZZ_RANDOM") else 17)
    cases = [escaping_action(rng) for _ in range(CASES)]
    out = subprocess.run([sys.executable, "-c", CHILD], input="\n".join(map(json.dumps, cases)),
                         capture_output=True, text=True, timeout=60 + 6 * CASES)
    done = out.stdout.count("done")
    assert out.returncode == 0 and done == len(cases), \
        f"case {done + 1}: {json.dumps(cases[done])[:400]}\n{out.stderr[-2000:]}"
