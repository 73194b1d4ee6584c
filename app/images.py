"""Arrays to Qt images: previews and thumbnails (PNG export is texeditor.export.write_png).

Photos of any supported dtype are shown as 8-bit RGB.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtGui
import skimage as ski

from texeditor.errors import ImageError
from texeditor.markov.levels import MAX_PIXELS


def qimage_from_rgb(rgb: np.ndarray) -> QtGui.QImage:
    """An owning QImage of an (H, W, 3) uint8 array."""
    rgb = np.ascontiguousarray(rgb, dtype=np.uint8)
    h, w, _ = rgb.shape
    return QtGui.QImage(rgb.data, w, h, 3 * w, QtGui.QImage.Format.Format_RGB888).copy()


def photo_rgb(image: np.ndarray) -> np.ndarray:
    """Any photo (grey, RGB, RGBA; uint8/uint16/float/bool) as (H, W, 3) uint8 for display."""
    img = np.asarray(image)
    if img.ndim == 3 and img.shape[2] in (2, 4):
        img = img[..., :-1] if img.shape[2] == 4 else img[..., 0]
    if img.ndim == 3 and img.shape[2] == 1:
        img = img[..., 0]
    if img.dtype.kind == "f":
        img = np.clip(np.nan_to_num(img), 0.0, 1.0)
    img = ski.util.img_as_ubyte(img)
    return np.repeat(img[..., None], 3, axis=2) if img.ndim == 2 else img


def pixmap(rgb: np.ndarray, box: int) -> QtGui.QPixmap:
    """A preview that fits a box×box square; small images are enlarged without smoothing."""
    image = qimage_from_rgb(rgb)
    mode = (QtCore.Qt.TransformationMode.FastTransformation if max(rgb.shape[:2]) < box
            else QtCore.Qt.TransformationMode.SmoothTransformation)
    return QtGui.QPixmap.fromImage(image.scaled(box, box, QtCore.Qt.AspectRatioMode.KeepAspectRatio,
                                                mode))


class PastedPicture:
    """A picture from the clipboard or a drop, kept as Qt gave it and checked (pixels, size)
    at once; ``photo()`` turns it into an array in the worker (0.6 s at 36 megapixels, which
    froze the window when done as it was pasted)."""

    def __init__(self, image: QtGui.QImage):
        _check_size(image)
        self.image = QtGui.QImage(image)      # an implicitly shared copy: cheap, thread-safe

    def photo(self) -> np.ndarray:
        return photo_from_qimage(self.image)


def _check_size(image: QtGui.QImage) -> None:
    if image.isNull() or image.width() * image.height() == 0:
        raise ImageError("The picture has no pixels")
    w, h = image.width(), image.height()
    if w * h > MAX_PIXELS:
        raise ImageError(f"The picture is {w}x{h}, more than "
                         f"{MAX_PIXELS // 2**20} megapixels: reduce it first")


def photo_from_qimage(image: QtGui.QImage) -> np.ndarray:
    """A pasted or dropped picture as a photo, as load_image would read it from a file: (H, W)
    uint8 when it is grey, (H, W, 3) RGB, or (H, W, 4) RGBA when it has alpha. Refused
    (ImageError) when empty or larger than a file may be."""
    _check_size(image)
    w, h = image.width(), image.height()
    alpha = image.hasAlphaChannel()
    fmt = QtGui.QImage.Format.Format_RGBA8888 if alpha else QtGui.QImage.Format.Format_RGB888
    channels = 4 if alpha else 3
    converted = image.convertToFormat(fmt)
    rows = np.frombuffer(converted.constBits(), np.uint8, converted.bytesPerLine() * h)
    pixels = rows.reshape(h, converted.bytesPerLine())[:, :w * channels]
    pixels = pixels.reshape(h, w, channels).copy()
    if alpha and (pixels[..., 3] == 255).all():
        pixels = pixels[..., :3]                 # an alpha channel that hides nothing
    rgb = pixels[..., :3]
    if pixels.shape[2] == 3 and (rgb == rgb[..., :1]).all():
        return np.ascontiguousarray(rgb[..., 0])
    return pixels
