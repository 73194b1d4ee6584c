"""Exemplars: the photos a document's models are made from (random-phase noise, the texton,
histogram matching — digest §11), held by reference as DPJs are.

A step names its exemplar by a reference, 16 hex digits of SHA-256 of a tag, the shape and the
raw pixels — not of an encoding, so it is the same with every library version; `.texture` files
and the bank keep each exemplar once, as a PNG, and check on reading that it still hashes to its
reference. An exemplar is a uint8 grey (h, w) or colour (h, w, 3) picture of at most 1024 × 1024.
"""

from __future__ import annotations

import hashlib
import io
import struct
import warnings

import numpy as np
from PIL import Image

from ..errors import FormatError, InputError

EXEMPLAR_TAG = b"texeditor-exemplar-v1"
MIN_SIDE, MAX_SIDE = 2, 1024
MAX_PNG_BYTES = 4 * 2**20       # a 1024² RGB photo is 3 MiB raw; PNG adds little to the worst
MAX_EXEMPLARS = 16              # in one file or bank entry


def is_picture(image: np.ndarray) -> bool:
    """Whether an array is what exemplars and thumbnails hold: uint8 grey or RGB."""
    return image.dtype == np.uint8 and (image.ndim == 2 or (image.ndim == 3
                                                            and image.shape[2] == 3))


def check_exemplar(image) -> np.ndarray:
    """The picture as a read-only C-contiguous uint8 copy, or an InputError saying why not."""
    image = np.asarray(image)
    if not is_picture(image):
        raise InputError(f"an exemplar is a uint8 grey (h, w) or colour (h, w, 3) picture, "
                         f"not an array of shape {image.shape} and type {image.dtype}")
    h, w = image.shape[:2]
    if not (MIN_SIDE <= h <= MAX_SIDE and MIN_SIDE <= w <= MAX_SIDE):
        raise InputError(f"an exemplar of {w}×{h} is out of range: each side "
                         f"{MIN_SIDE}..{MAX_SIDE} (take a smaller part of the photo)")
    image = np.array(image, dtype=np.uint8, order="C", copy=True)
    image.flags.writeable = False
    return image


def exemplar_ref(image: np.ndarray) -> str:
    """16 hex digits of SHA-256 of the tag, (h, w, channels) as little-endian uint32 and the
    pixels in C order."""
    h, w = image.shape[:2]
    digest = hashlib.sha256(EXEMPLAR_TAG)
    digest.update(struct.pack("<3I", h, w, 1 if image.ndim == 2 else 3))
    digest.update(np.ascontiguousarray(image, dtype=np.uint8).tobytes())
    return digest.hexdigest()[:16]


def exemplar_png(image: np.ndarray) -> bytes:
    buf = io.BytesIO()
    Image.fromarray(image, "L" if image.ndim == 2 else "RGB").save(buf, "PNG", optimize=False)
    return buf.getvalue()


def read_exemplar_png(data: bytes, what: str, ref: str) -> np.ndarray:
    """A stored exemplar: a PNG of mode L or RGB within the limits, whose pixels hash to
    ``ref``; anything else is a FormatError."""
    if not isinstance(data, bytes) or len(data) > MAX_PNG_BYTES:
        raise FormatError(f"{what}: not an exemplar (more than {MAX_PNG_BYTES} bytes, or no data)")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(io.BytesIO(data), formats=["PNG"]) as im:
                w, h = im.size
                if im.mode not in ("L", "RGB") or max(w, h) > MAX_SIDE or min(w, h) < MIN_SIDE:
                    raise FormatError(f"{what}: an exemplar must be a grey or RGB PNG of "
                                      f"{MIN_SIDE}..{MAX_SIDE} pixels a side, got {im.mode} "
                                      f"{w}×{h}")
                image = np.asarray(im.convert(im.mode))
    except FormatError:
        raise
    except (OSError, ValueError, SyntaxError, Image.DecompressionBombWarning,
            Image.DecompressionBombError) as exc:
        raise FormatError(f"{what}: the exemplar's PNG is damaged ({exc})") from None
    image = check_exemplar(image)
    if exemplar_ref(image) != ref:
        raise FormatError(f"{what}: the exemplar's pixels do not hash to its reference {ref}: "
                          "refused (a forged or damaged file)")
    return image
