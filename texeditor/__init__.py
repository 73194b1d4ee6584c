"""texeditor — the engine of an interactive texture studio after R. Olejnik (Lille, 1984).

Photo → levels (`quantize`) → DPJ (`estimate_dpj`) → 2-D Markov synthesis (`synthesize`) →
documents edited by replayable Actions (`History`), kept as recipes in files and the `Bank`.
`resynthesize` is photo → texture in one call (a multi-scale DPJ shown with the photo's tone);
`heeger_bergen` is the same from a steerable pyramid's sub-band histograms (companion 004).
One subpackage per idea of the thesis: `markov`, `regions`, `paint`, `spots`, `texture`,
`photo`, `recipe`, `bank`; beyond it, `spectral` (random-phase noise, texton, histogram
matching), `pyramid` (Heeger–Bergen synthesis), `flow` (directional textures: noise along a
photo's or a drawn orientation field) and `fractal` (IFS motifs, fractal curves, midpoint
displacement). This package never imports Qt; the GUI lives in `app`.
"""

from .version import __version__
from .errors import Cancelled, FormatError, ImageError, InputError, ReplayError, TexeditorError
from .markov import (DPJ, DPJReport, Quantization, SynthesisResult, estimate_dpj, load_image,
                     quantize, synthesize)
# Every operator package registers its Actions: importing them here makes the registry (and so
# every log reader) complete whatever module of the engine a program imports first.
from . import flow, fractal, paint, pyramid, regions, spectral, spots, texture  # noqa: F401
from .spectral import match_histogram, random_phase_noise, texton
from .recipe import Document, History, load_texture, replay, save_texture
from .bank import Bank
from .photo import PhotoModel, acquire_model, load_model, resynthesize
from .pyramid import heeger_bergen
from .fractal import ifs_attractor, midpoint_displacement
from .flow import flow_texture

__all__ = ["__version__", "DPJ", "DPJReport", "synthesize", "SynthesisResult", "estimate_dpj",
           "quantize", "load_image", "Quantization", "Document", "History", "replay",
           "load_texture", "save_texture", "Bank", "TexeditorError", "InputError", "ImageError",
           "FormatError", "ReplayError", "Cancelled", "resynthesize", "acquire_model", "load_model",
           "PhotoModel", "random_phase_noise", "texton", "match_histogram", "heeger_bergen",
           "ifs_attractor", "midpoint_displacement", "flow_texture"]
