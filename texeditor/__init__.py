"""texeditor — the engine of an interactive texture studio after R. Olejnik (Lille, 1984).

Photo → levels (`quantize`) → DPJ (`estimate_dpj`) → 2-D Markov synthesis (`synthesize`) →
documents edited by replayable actions. This package never imports Qt; the GUI lives in `app`.
"""

from .markov.dpj import DPJ, DPJReport
from .errors import Cancelled, FormatError, ImageError, InputError, TexeditorError

from .version import __version__

# Every operator package registers its Actions: importing them here makes the registry (and so
# every log reader) complete whatever module of the engine a program imports first.
from . import paint, regions, spots, texture  # noqa: E402,F401  (registration)


def __getattr__(name):
    # The numba-backed modules load on first use so `import texeditor` stays instant.
    if name in ("synthesize", "SynthesisResult"):
        from .markov import synthesis
        return getattr(synthesis, name)
    if name == "estimate_dpj":
        from .markov.estimation import estimate_dpj
        return estimate_dpj
    if name in ("quantize", "load_image", "Quantization"):
        from .markov import levels
        return getattr(levels, name)
    raise AttributeError(f"module 'texeditor' has no attribute {name!r}")


__all__ = ["DPJ", "DPJReport", "synthesize", "SynthesisResult", "estimate_dpj", "quantize",
           "load_image", "Quantization", "TexeditorError", "InputError", "ImageError",
           "FormatError", "Cancelled"]
