"""The argument checks the scene model and the methods share.

Each check names the argument in its message and returns the value normalised to a plain Python
type, so that NumPy scalars (``np.int64(32)``, ``np.float32(0.5)``, ``np.bool_(True)``) are
accepted wherever a Python number or bool is.
"""

from __future__ import annotations

from ._errors import ArgumentError, ArgumentTypeError
import math
from typing import Any, Sequence

import numpy as np

from . import _core
from ._color import srgb_to_linear

_INTS = (int, np.integer)
_REALS = (int, float, np.integer, np.floating)


def is_number(v: Any) -> bool:
    """A real number (Python or NumPy), not a bool."""
    return isinstance(v, _REALS) and not isinstance(v, (bool, np.bool_))


def integer(name: str, v: Any, lo: int = 1, hi: int = _core.MAX_STEPS_LIMIT, *, strict: bool = False) -> int:
    """An integer in [lo, hi]. Integer-valued floats (``32.0``) are accepted, unless ``strict``."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, _REALS) or (strict and not isinstance(v, _INTS)):
        raise ArgumentTypeError(f"{name}: expected an integer, got {v!r}" if strict else f"{name}: expected an integer, got {type(v).__name__}")
    if not isinstance(v, _INTS):
        if not (math.isfinite(float(v)) and float(v).is_integer()):
            raise ArgumentTypeError(f"{name}: expected an integer, got {v!r}")
    i = int(v)
    if not lo <= i <= hi:
        raise ArgumentError(f"{name}: must lie in [{lo}, {hi}], got {i}")
    return i


def number(name: str, v: Any, lo: float = -math.inf, hi: float = math.inf, *, lo_open: bool = False) -> float:
    """A finite real number in [lo, hi] (or (lo, hi] with ``lo_open``)."""
    if not is_number(v):
        raise ArgumentTypeError(f"{name}: expected a number, got {type(v).__name__}")
    x = float(v)
    low_ok = x > lo if lo_open else x >= lo
    if not (math.isfinite(x) and low_ok and x <= hi):
        interval = f"{'(' if lo_open else '['}{lo:g}, {hi:g}]"
        raise ArgumentError(f"{name}: must be a finite number in {interval}, got {v!r}")
    return x


def boolean(name: str, v: Any) -> bool:
    if not isinstance(v, (bool, np.bool_)):
        raise ArgumentTypeError(f"{name}: expected a bool, got {type(v).__name__}")
    return bool(v)


def choice(name: str, v: Any, options: Sequence[str]) -> str:
    if not isinstance(v, str) or v not in options:
        raise ArgumentError(f"{name}: must be one of {', '.join(repr(o) for o in options)}, got {v!r}")
    return v


def vec3(name: str, v: Any) -> tuple[float, float, float]:
    """Three finite numbers."""
    try:
        a = np.asarray(v, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name}: expected three numbers, got {v!r}") from None
    if a.shape != (3,):
        raise ArgumentError(f"{name}: expected three numbers, got {a.size}")
    if not np.all(np.isfinite(a)):
        raise ArgumentError(f"{name}: must be finite, got {tuple(a)}")
    return (float(a[0]), float(a[1]), float(a[2]))


def rgb(name: str, v: Any) -> tuple[float, float, float]:
    """A colour: one number (grey) or three, all >= 0."""
    if is_number(v):
        v = (v, v, v)
    c = vec3(name, v)
    if min(c) < 0:
        raise ArgumentError(f"{name}: must be >= 0, got {c}")
    return c


def float_array(name: str, a: Any, ncols: int, dtype: Any = np.float32) -> np.ndarray:
    """An (n, ncols) finite numeric array, C-contiguous in `dtype`."""
    try:
        arr = np.asarray(a)
    except Exception:
        raise ArgumentTypeError(f"{name}: expected an array") from None
    if arr.dtype.kind not in "fiu":
        raise ArgumentTypeError(f"{name}: expected a numeric array, got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.shape[1] != ncols:
        raise ArgumentError(f"{name}: expected shape (n, {ncols}), got {arr.shape}")
    arr = np.ascontiguousarray(arr, dtype=dtype)
    if not np.all(np.isfinite(arr)):
        raise ArgumentError(f"{name}: contains NaN or Inf")
    return arr


def height_map(name: str, h: Any) -> np.ndarray:
    """A height map as float32 in [0, 1], read-only: uint8 and uint16 normalised."""
    if isinstance(h, np.ndarray):
        arr = h
    else:
        try:
            arr = np.asarray(h)
        except Exception:
            raise ArgumentTypeError(f"{name}: expected a 2-D numpy array") from None
    if arr.dtype == np.uint8:
        out = arr.astype(np.float32) / 255.0
    elif arr.dtype == np.uint16:
        out = arr.astype(np.float32) / 65535.0
    elif arr.dtype in (np.float32, np.float64, np.float16):
        out = arr.astype(np.float32)
    else:
        raise ArgumentTypeError(f"{name}: dtype {arr.dtype} is not supported; pass float32 in [0, 1], uint8 or uint16")
    if out.ndim != 2:
        raise ArgumentError(f"{name}: expected a 2-D array (H, W), got shape {arr.shape}")
    if out.size == 0:
        raise ArgumentError(f"{name}: the array is empty (shape {arr.shape})")
    if not np.all(np.isfinite(out)):
        bad = np.argwhere(~np.isfinite(out))[0]
        raise ArgumentError(f"{name}: contains NaN or Inf (first at row {bad[0]}, column {bad[1]}); clean it, e.g. np.nan_to_num")
    lo, hi = float(out.min()), float(out.max())
    if lo < 0.0 or hi > 1.0:
        raise ArgumentError(f"{name}: float values must lie in [0, 1], found [{lo}, {hi}]; normalise the map")
    out = np.ascontiguousarray(out)
    out.flags.writeable = False
    return out


def albedo(name: str, a: Any) -> np.ndarray | None:
    """An albedo as linear float32 (H, W, 3), read-only: sRGB uint8 decoded; None stays None."""
    if a is None:
        return None
    arr = np.asarray(a)
    if arr.ndim != 3 or arr.shape[2] not in (3, 4):
        raise ArgumentError(f"{name}: expected shape (H, W, 3), got {arr.shape}")
    if arr.size == 0:
        raise ArgumentError(f"{name}: the array is empty")
    arr = arr[..., :3]
    if arr.dtype == np.uint8:
        out = srgb_to_linear(arr)  # by table: the same bits on every CPU (_color.py)
    elif arr.dtype.kind == "f":
        out = arr.astype(np.float32)
        if not np.all(np.isfinite(out)):
            raise ArgumentError(f"{name}: contains NaN or Inf")
        if out.min() < 0:
            raise ArgumentError(f"{name}: linear values must be >= 0")
    else:
        raise ArgumentTypeError(f"{name}: dtype {arr.dtype} is not supported; pass sRGB uint8 or linear float32")
    out = np.ascontiguousarray(out)
    out.flags.writeable = False
    return out
