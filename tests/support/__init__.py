"""Shared test material: tiny DPJs, random actions and histories, the History settings the
history tests sweep, a thread with a timeout, and the repository's paths.

Test modules import what they share from here (and from the submodules: ``regions``, ``paint``,
``spots``, ``texture``, ``bank``, ``fuzz``), never from one another (tests/test_layout.py checks).
It holds no tests itself.
"""

from __future__ import annotations

import itertools
import threading
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from texeditor.recipe.actions import (CropCanvas, NewCanvas, ResizeCanvas, SetLevels, SetPalette,
                               Synthesize, registry)
from texeditor.recipe.document import Document, dpj_ref
from texeditor.markov.dpj import DPJ
from texeditor.errors import InputError
from texeditor.recipe.history import History

ROOT = Path(__file__).resolve().parents[2]      # the repository (child processes run there)
DATA = ROOT / "tests" / "data"

PROPERTY = settings(max_examples=75, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def all_windows_dpj(levels: int, window=(2, 2), seed: int = 0) -> DPJ:
    """Every u×v configuration with a random positive probability: synthesis never dead-ends."""
    u, v = window
    configs = np.array(list(itertools.product(range(levels), repeat=u * v)), np.uint8)
    probs = np.random.default_rng(seed).random(len(configs)) + 0.1
    return DPJ(configs.reshape(-1, v, u), probs / probs.sum(), levels)


TINY_DPJS = [all_windows_dpj(2), all_windows_dpj(3, (2, 1), seed=1)]
TINY = {dpj_ref(d): d for d in TINY_DPJS}
REFS = [dpj_ref(d) for d in TINY_DPJS]     # REFS[k] names TINY_DPJS[k]


def engine_types() -> set[str]:
    """The names in ``registry()`` of the engine's own Actions: a test module may register one
    of its own (test_history's ``test_invert``), which no example or old file can hold."""
    return {name for name, cls in registry().items() if cls.__module__.split(".")[0] == "texeditor"}


def palettes(levels: int):
    colour = st.tuples(*[st.integers(0, 255)] * 3)
    return st.tuples(*[colour] * levels)


def draw_action(data, doc: Document):
    """One random action, mostly valid for the document as it stands."""
    h, w = doc.shape
    g = doc.num_levels
    kind = data.draw(st.sampled_from(
        ["new", "synth", "palette", "levels", "levels", "levels", "crop", "resize"]))
    if kind == "new" or (h == 0 and kind not in ("synth",)):
        levels = data.draw(st.integers(2, 5))
        palette = data.draw(st.none() | palettes(levels))
        return NewCanvas(data.draw(st.integers(1, 10)), data.draw(st.integers(1, 10)), levels,
                         palette)
    if kind == "synth":
        return Synthesize(data.draw(st.sampled_from(REFS)), data.draw(st.integers(2, 9)),
                          data.draw(st.integers(2, 9)), data.draw(st.integers(0, 3)))
    if kind == "palette":
        return SetPalette(data.draw(palettes(g)))
    if kind == "levels":
        return SetLevels(data.draw(st.integers(-2, h)), data.draw(st.integers(-2, w)),
                         data.draw(st.integers(1, h + 2)), data.draw(st.integers(1, w + 2)),
                         data.draw(st.integers(0, g - 1)))
    if kind == "crop":
        return CropCanvas(data.draw(st.integers(0, h - 1)), data.draw(st.integers(0, w - 1)),
                          data.draw(st.integers(1, h)), data.draw(st.integers(1, w)))
    return ResizeCanvas(data.draw(st.integers(1, 12)), data.draw(st.integers(1, 12)),
                        data.draw(st.integers(0, g - 1)))


def random_history(data, max_steps: int = 14, **options) -> History:
    """A History built live from random actions (an action the document refuses is skipped)."""
    history = History(**options)
    for d in TINY_DPJS:
        history.document.store_dpj(d)
    for _ in range(data.draw(st.integers(1, max_steps))):
        try:
            history.apply(draw_action(data, history.document))
        except InputError:
            pass
    return history


# As in test_history: records kept; no records (snapshots only); snapshots squeezed by memory.
SETTINGS = [dict(), dict(undo_memory=0, snapshot_every=3),
            dict(undo_memory=200, snapshot_every=2, snapshot_memory=600)]


def long_log(n: int = 60) -> list:
    """A synthesis, then level patches and palettes: every later step depends on the first."""
    rng = np.random.default_rng(3)
    actions = [Synthesize(REFS[0], 24, 20, 1)]
    for k in range(n - 1):
        if k % 7 == 6:
            actions.append(SetPalette(tuple((g, g, g) for g in sorted(rng.integers(0, 256, 2)))))
        else:
            r, c = (int(x) for x in rng.integers(0, 18, 2))
            actions.append(SetLevels(r, c, 3, 4, int(rng.integers(0, 2))))
    return actions



def within(seconds, fn, *args):
    """fn(*args) in a thread; its exception or its result, or a failure if it does not end."""
    box = {}

    def target():
        try:
            box["result"] = fn(*args)
        except BaseException as exc:          # handed to the test
            box["error"] = exc
    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    thread.join(seconds)
    assert not thread.is_alive(), f"{getattr(fn, '__name__', fn)} did not end in {seconds} s"
    if "error" in box:
        raise box["error"]
    return box.get("result")

