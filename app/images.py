"""Arrays to Qt images and back: previews, thumbnails and PNG export.

Level matrices become RGB through their palette (``colourize``); photos of any supported dtype are
shown as 8-bit RGB.
"""

from __future__ import annotations

import numpy as np
from PySide6 import QtCore, QtGui
from skimage.util import img_as_ubyte

from texeditor.errors import TexeditorError

from .canvas import colourize


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
    img = img_as_ubyte(img)
    return np.repeat(img[..., None], 3, axis=2) if img.ndim == 2 else img


def pixmap(rgb: np.ndarray, box: int) -> QtGui.QPixmap:
    """A preview that fits a box×box square; small images are enlarged without smoothing."""
    image = qimage_from_rgb(rgb)
    mode = (QtCore.Qt.TransformationMode.FastTransformation if max(rgb.shape[:2]) < box
            else QtCore.Qt.TransformationMode.SmoothTransformation)
    return QtGui.QPixmap.fromImage(image.scaled(box, box, QtCore.Qt.AspectRatioMode.KeepAspectRatio,
                                                mode))


def export_png(path, levels: np.ndarray, palette, scale: int = 1) -> None:
    """Write the texture as an RGB PNG, each point drawn as a scale×scale block."""
    if not 1 <= scale <= 64:
        raise TexeditorError(f"the export scale must be 1..64, got {scale}")
    rgb = colourize(levels, palette)
    if scale > 1:
        rgb = np.repeat(np.repeat(rgb, scale, axis=0), scale, axis=1)
    if not qimage_from_rgb(rgb).save(str(path), "PNG"):
        raise TexeditorError(f"could not write {path}: check the folder exists and is writable")
