"""Shared material for the texture-source tests: one example of every texture Action and the
document they apply to."""

import numpy as np

from texeditor.recipe.actions import NewCanvas, SetLevels
from texeditor.recipe.history import History
from texeditor.recipe.sources import synthesis_recipe
from texeditor.texture.actions import DoubleLevels, Incrust, Mix, MixTextures, RenderGrains

from . import REFS, TINY


SYNTH = synthesis_recipe(REFS[0], 6, 5, 3)          # a 6×5 G = 2 texture
SYNTH3 = synthesis_recipe(REFS[1], 4, 4, 1)         # a 4×4 G = 3 texture


EXAMPLES = [
    RenderGrains(), RenderGrains("hexagon", 6, explosion_x=2, compression=0.2, overlap="max"),
    RenderGrains("bitmap", 5, bitmap="010/111/010", angle=90, lattice="honeycomb"),
    RenderGrains("polygon", 9, sides=5, aspect=0.5, explosion_y=3),
    RenderGrains("circle", 4, compression=0.3, level_grains="1: square 2, 2: hexagon 6 angle=15"),
    RenderGrains("circle", 6, explosion_x=1.5, compression=0.4, compression_x=0.1),
    Mix(SYNTH, (REFS[0],)), Mix(SYNTH3, (REFS[1],), a=0.5, op1="and", op2="xor", b=0.25, op3="add",
                             negate=True, op4="min", c=1.0),
    Incrust(SYNTH, (REFS[0],), mask="levels", levels="0"),
    Incrust(SYNTH, (REFS[0],), mask="points", points=((0, 0), (2, 3))),
    Incrust(SYNTH, (REFS[0],), mask="levels", levels="1-2", block=2),
    Incrust(SYNTH, (REFS[0],), mask="texture", levels="1", mask_source=SYNTH3, mask_dpjs=(REFS[1],),
            block=3),
    MixTextures((SYNTH, SYNTH3), (REFS[0], REFS[1])),
    MixTextures((SYNTH3, SYNTH, SYNTH3), (REFS[1], REFS[0]),
                expression="not[(0.5 multiply T1) max T2] min (T3 xor T4)"),
    DoubleLevels("0123456789abcdef", 4),
]


def history_of(levels, g: int = 3, extra=()) -> History:
    """A History whose document holds ``levels`` (one SetLevels per non-zero point)."""
    h, w = levels.shape
    history = History()
    history.document.dpjs.update(TINY)
    history.apply(NewCanvas(w, h, g))
    for (r, c), v in np.ndenumerate(levels):
        if v:
            history.apply(SetLevels(r, c, 1, 1, int(v)))
    for action in extra:
        history.apply(action)
    return history


T = np.array([[1, 2, 0], [0, 1, 2]], np.uint8)

