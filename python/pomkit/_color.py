"""sRGB transfer functions that give the same bits on every machine.

numpy dispatches `power` by CPU: with AVX-512 it runs SVML's vectorised pow, without it another
kernel, and the two differ in the last bits. An albedo decoded with `x ** 2.4` therefore had other
float32 bytes, and its scene another hash, on a CPU without AVX-512. Here only exactly
rounded IEEE operations are used (+, -, *, /, sqrt, frexp/ldexp): the powers are Newton
iterations for a root, with a fixed count, from a start made exactly by frexp, in float64, then
rounded once to float32. 8- and 16-bit inputs go through a table made the same way.

    decode: x <= 0.04045: x / 12.92, else ((x + 0.055) / 1.055) ** 2.4
    encode: x <= 0.0031308: 12.92 x, else 1.055 x ** (1 / 2.4) - 0.055

Encoding to 8 bits (`linear_to_srgb8`, what PNGs and `Frame.to_srgb8` hold) compares against the
decoded code boundaries, so it too evaluates no power.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["srgb_to_linear", "linear_to_srgb", "linear_to_srgb8", "srgb8_table", "srgb16_table"]


def _root(a: np.ndarray, n: int) -> np.ndarray:
    """a ** (1/n) for a in (0, 1] (float64), by Newton's iteration y <- ((n-1) y + a / y^(n-1)) / n
    from 2^(e/n) (exact, by ldexp), a fixed number of times: the result depends only on a."""
    m, e = np.frexp(a)  # a = m 2^e, m in [0.5, 1)
    # start: 2^(ceil(e / n)) >= the root (Newton's iteration for a convex function decreases
    # monotonically to the root from above)
    y = np.ldexp(np.ones_like(a), -((-e) // n))
    for _ in range(40):
        y = ((n - 1) * y + a / _ipow(y, n - 1)) / n
    return y


def _ipow(y: np.ndarray, k: int) -> np.ndarray:
    """y ** k for a small integer k by repeated multiplication (numpy's integer power of a float
    may call pow)."""
    out = y
    for _ in range(k - 1):
        out = out * y
    return out


def _decode64(x: np.ndarray) -> np.ndarray:
    """sRGB to linear in float64 for x in [0, 1]: t^2.4 = t^2 * (t^2)^(1/5)."""
    x = np.asarray(x, np.float64)
    t = (x + 0.055) / 1.055
    t2 = t * t
    hi = np.where(t2 > 0, t2 * _root(np.where(t2 > 0, t2, 1.0), 5), 0.0)
    return np.where(x <= 0.04045, x / 12.92, hi)


@lru_cache(maxsize=None)
def srgb8_table() -> np.ndarray:
    """The linear float32 value of each 8-bit sRGB code (read-only)."""
    t = _decode64(np.arange(256, dtype=np.float64) / 255.0).astype(np.float32)
    t.flags.writeable = False
    return t


@lru_cache(maxsize=None)
def srgb16_table() -> np.ndarray:
    """The linear float32 value of each 16-bit sRGB code (read-only)."""
    t = _decode64(np.arange(65536, dtype=np.float64) / 65535.0).astype(np.float32)
    t.flags.writeable = False
    return t


def srgb_to_linear(x) -> np.ndarray:
    """sRGB-encoded values to linear float32: uint8 and uint16 codes by table, floats in [0, 1]
    (clipped) by the float64 formula. The same bits on every CPU."""
    a = np.asarray(x)
    if a.dtype == np.uint8:
        return srgb8_table()[a]
    if a.dtype == np.uint16:
        return srgb16_table()[a]
    a = np.clip(np.asarray(a, np.float64), 0.0, 1.0)
    return _decode64(a).astype(np.float32)


@lru_cache(maxsize=None)
def _code_bounds() -> np.ndarray:
    """The linear values at which the 8-bit code changes: code c for x in [b[c-1], b[c])."""
    mid = (np.arange(255, dtype=np.float64) + 0.5) / 255.0
    return _decode64(mid)


def linear_to_srgb(x) -> np.ndarray:
    """Linear values to sRGB-encoded float32 in [0, 1] (clipped), for metrics (FLIP's input):
    float64 pow, fast; its last float32 bit may differ between CPUs, so nothing hashed or
    shipped goes through it (`linear_to_srgb8` is exact)."""
    a = np.clip(np.asarray(x, np.float64), 0.0, 1.0)
    return np.where(a <= 0.0031308, a * 12.92, 1.055 * np.power(a, 1 / 2.4) - 0.055).astype(np.float32)


def linear_to_srgb8(x) -> np.ndarray:
    """Linear values to 8-bit sRGB codes: the code whose interval of linear values holds x (a
    search in the 255 decoded boundaries, so that no power is evaluated per pixel)."""
    a = np.clip(np.asarray(x, np.float64), 0.0, 1.0)
    return np.searchsorted(_code_bounds(), a, side="right").astype(np.uint8)
