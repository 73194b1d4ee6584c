"""The 2-D Markov model (thesis ch. 4, §5.2): levels, the DPJ, its estimation and editing,
synthesis, and grey-level doubling.

A photo becomes levels (`quantize`), the levels a DPJ — the joint probability of the points of a
window — (`estimate_dpj`), the DPJ a texture of any size (`synthesize`).
"""

from .dpj import DPJ, DPJReport, MAX_LEVELS, grey_ramp
from .estimation import estimate_dpj
from .levels import Quantization, load_image, quantize
from .synthesis import SynthesisResult, synthesize
from . import doubling, dpj_edit  # noqa: F401  (submodules: hand editing, §4.5 doubling)

__all__ = ["DPJ", "DPJReport", "MAX_LEVELS", "grey_ramp", "estimate_dpj", "Quantization",
           "load_image", "quantize", "SynthesisResult", "synthesize", "doubling", "dpj_edit"]
