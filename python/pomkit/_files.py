"""Height maps and albedos from image files, decoded by the Rust core (the `image` crate): PNG
and TIFF at 8 or 16 bits, float TIFF, and OpenEXR."""

from __future__ import annotations

from ._errors import ArgumentTypeError
import os
from typing import Union

import numpy as np

from . import _core
from ._color import srgb_to_linear

__all__ = ["load_height", "load_albedo"]

PathLike = Union[str, "os.PathLike[str]"]


def _path(path: PathLike) -> str:
    if not isinstance(path, (str, os.PathLike)):
        raise ArgumentTypeError(f"path: expected a file path, got {type(path).__name__}")
    return os.fspath(path)


def load_height(path: PathLike) -> np.ndarray:
    """A height map from a greyscale image file, as an (H, W) float32 array at the file's own
    precision: 8- and 16-bit values become value / 255 or value / 65535 (every 16-bit level
    stays distinct); float files (OpenEXR, float TIFF) keep their values, which `pk.Material`
    then expects in [0, 1]. A colour file is accepted when its channels are equal. A missing,
    unreadable or unsupported file raises a ValueError naming the path and the reason."""
    a, _bits = _core.load_image(_path(path), "height")
    return a


def load_albedo(path: PathLike) -> np.ndarray:
    """An albedo from an image file, as an (H, W, 3) float32 array of linear RGB (what
    `pk.Material(albedo=...)` takes): 8- and 16-bit files are read as sRGB and decoded to
    linear; float files (OpenEXR, float TIFF) are taken as linear. Alpha is dropped; a grey file
    gives three equal channels."""
    a, bits = _core.load_image(_path(path), "albedo")
    if bits < 32:  # the file's codes, decoded by table (the same bits on every CPU)
        codes = np.rint(np.asarray(a, np.float64) * (255 if bits == 8 else 65535))
        a = srgb_to_linear(codes.astype(np.uint8 if bits == 8 else np.uint16))
    return np.ascontiguousarray(a, dtype=np.float32)
