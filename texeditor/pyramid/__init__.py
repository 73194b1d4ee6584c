"""Heeger–Bergen pyramid-based texture synthesis (companion document 004): a photo's steerable
pyramid sub-band histograms imposed on noise — a source for continuous-tone textures.

``heeger_bergen(photo, (H, W), seed=S)`` is photo → texture; ``steerable_pyramid`` is the
transform it works in, exact and periodic (the texture tiles); ``HeegerBergen`` the step.
"""

from .actions import HeegerBergen
from .steerable import SteerablePyramid, pyramid_levels, steerable_pyramid
from .synthesis import heeger_bergen, match_quantiles, quantiles

__all__ = ["HeegerBergen", "SteerablePyramid", "steerable_pyramid", "pyramid_levels", "heeger_bergen",
           "match_quantiles", "quantiles"]
