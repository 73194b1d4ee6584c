"""Shared material for the manual-acquisition tests: a textured document and one example of
every paint Action."""

import numpy as np

from texeditor.paint.actions import (DominanceTree, DuplicateZone, LayAlongOrder, PeanoLevels,
                                     PlaceGrains, ScrambleFrontier, Stroke)
from texeditor.recipe.document import Document


SPRAY = dict(size=7, shape="disc", distribution="cloud", density=0.4)


def textured(h=40, w=48, levels=4, seed=0):
    """A document with a random texture on it (through an ordinary action log)."""
    doc = Document.new(w, h, levels)
    rng = np.random.default_rng(seed)
    doc.apply(PlaceGrains(points=tuple(map(tuple, rng.integers(0, [h, w], size=(150, 2)))),
                          level=1, shape="circle", size=5))
    doc.apply(Stroke(points=((3, 2), (30, 40), (5, 44)), level=2, **SPRAY, seed=3))
    doc.apply(Stroke(points=((h - 1, 0), (0, w - 1)), level=3, size=3, shape="square"))
    return doc


EXAMPLES = [
    Stroke(points=((1, 1), (4, 9)), level=2, size=3, shape="square"),
    Stroke(points=((5, 5), (0, 20), (-3, 22)), level=1, **SPRAY, concentration=1.5,
           level_choices="1, 3", wrap=True, seed=99),
    Stroke(points=((2, 2),), level=3, size=5, shape="bitmap", bitmap="10101/01010/10101"),
    PlaceGrains(points=((4, 4), (10, 12)), level=3, shape="hexagon", size=6),
    PlaceGrains(points=((2, 2), (2, 30)), level=2, shape="polygon", sides=5, size=5,
                spacing=4.0, jitter=1.5, seed=5, wrap=True),
    PlaceGrains(points=((8, 8),), level=0, shape="bitmap", size=6, own_levels=True,
                bitmap="0120/1231/0120"),
    DuplicateZone(points=((0, 0), (9, 9)), offset_row=12, offset_col=20),
    DuplicateZone(points=((2, 2), (2, 15), (14, 8)), offset_row=-5, offset_col=40, zone="lasso",
                  wrap=True),
    ScrambleFrontier(points=((10, 10), (25, 30)), band=3, density=0.5, seed=1),
    PeanoLevels(cell=4, expression="6:7(2(1,2(2,3)),6:7(4,5,6:7(6,7),8))"),
    PeanoLevels(cell=3, expression="3(1,2)", low=0, high=2, top=5, left=7, grain="circle",
                grain_size=3),
    PeanoLevels(cell=5, expression="4(1,2(3))", order="spiral"),
    DominanceTree(points=((10, 10), (14, 18), (6, 20), (16, 26)), expression="1(2(4),3)",
                  grains="circle 7, hexagon 6, square 3, polygon 5 sides=5 angle=30"),
    DominanceTree(points=((30, 40), (38, 2)), expression="1:2", grains="diamond 9, line 7",
                  low=2, high=3, mix="brighter", wrap=True),
    LayAlongOrder("spiral", zone="rectangle", points=((20, 20), (30, 44))),
    LayAlongOrder("polar", zone="lasso", points=((2, 2), (2, 30), (25, 15)), centre_row=9,
                  centre_col=15),
    LayAlongOrder("peano", zone="rectangle", points=((4, 4), (20, 33))),
]

