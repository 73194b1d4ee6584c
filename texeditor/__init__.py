"""texeditor — the engine of an interactive texture studio after R. Olejnik (Lille, 1984).

Photo → levels (`quantize`) → DPJ (`estimate_dpj`) → 2-D Markov synthesis (`synthesize`) →
documents edited by replayable actions. This package never imports Qt; the GUI lives in `app`.
"""

from .dpj import DPJ, DPJReport
from .errors import Cancelled, FormatError, ImageError, InputError, TexeditorError

__version__ = "0.1.0"


def __getattr__(name):
    # The numba-backed modules load on first use so `import texeditor` stays instant.
    if name in ("synthesize", "SynthesisResult"):
        from . import synthesis
        return getattr(synthesis, name)
    if name == "estimate_dpj":
        from .estimation import estimate_dpj
        return estimate_dpj
    if name in ("quantize", "load_image", "Quantization"):
        from . import levels
        return getattr(levels, name)
    raise AttributeError(f"module 'texeditor' has no attribute {name!r}")


__all__ = ["DPJ", "DPJReport", "synthesize", "SynthesisResult", "estimate_dpj", "quantize",
           "load_image", "Quantization", "TexeditorError", "InputError", "ImageError",
           "FormatError", "Cancelled"]
