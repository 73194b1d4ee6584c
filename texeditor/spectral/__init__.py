"""Models beyond the 1984 thesis from the companion documents (digest §11): random-phase noise
and the texton of a micro-texture (001), histogram matching (004); their Actions make a canvas
from an exemplar photo held by the document."""

from .models import match_histogram, periodic_component, random_phase_noise, texton
from .actions import MatchHistogram, RandomPhaseNoise, Texton

__all__ = ["match_histogram", "periodic_component", "random_phase_noise", "texton",
           "MatchHistogram", "RandomPhaseNoise", "Texton"]
