"""Fractal models from the companion documents (digest §11): IFS motifs drawn by the chaos game
and projected-IFS (fractal Bézier) curves for rough spot outlines (002, Guérin), 2-D midpoint
displacement heights for the relief (003); their Actions make a relief canvas or stamp a motif."""

from .ifs import BUILTINS, IFS, ifs_attractor, ifs_points
from .curves import fractal_curve, fractal_outline
from .midpoint import midpoint_displacement
from .actions import FractalRelief, IFSMotif

__all__ = ["BUILTINS", "IFS", "ifs_attractor", "ifs_points", "fractal_curve", "fractal_outline",
           "midpoint_displacement", "FractalRelief", "IFSMotif"]
