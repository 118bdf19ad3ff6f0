"""Hypothesis strategies for height maps and views that users' content reaches and pk.textures
does not: plateaus at exactly 0 and 1, one-texel spikes and pits, steps and cliffs, smooth noise
normalised to exactly [0, 1], constant maps, odd and 1xN sizes, uint8/uint16 at their extremes,
tilings that are not whole numbers, grazing cameras and lights.

Each map strategy draws the map's kind, size and dtype, and returns (name, array); the name says
what was drawn (it labels failures and is printed by the suite's `event`s)."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

KINDS = ("constant", "plateaus", "spikes", "step", "checker", "noise", "terraces")


@st.composite
def sizes(draw, lo: int = 1, hi: int = 96):
    """(rows, cols): square, non-square, odd, and 1xN / Nx1 strips."""
    kind = draw(st.sampled_from(["square", "any", "strip"]))
    if kind == "square":
        n = draw(st.sampled_from([16, 31, 32, 48, 63, 64, 65]))
        return n, n
    if kind == "strip":
        n = draw(st.integers(2, hi))
        return (1, n) if draw(st.booleans()) else (n, 1)
    return draw(st.integers(max(lo, 2), hi)), draw(st.integers(max(lo, 2), hi))


def _smooth(rng, shape, cells):
    """Value noise: a coarse random grid upsampled bilinearly (periodic), normalised to exactly
    [0, 1] as users normalise their maps."""
    h, w = shape
    g = rng.random((max(cells, 1), max(cells, 1)))
    y = (np.arange(h) + 0.5) / h * g.shape[0]
    x = (np.arange(w) + 0.5) / w * g.shape[1]
    y0 = np.floor(y).astype(int)
    x0 = np.floor(x).astype(int)
    fy = (y - y0)[:, None]
    fx = (x - x0)[None, :]
    gy0, gy1 = y0 % g.shape[0], (y0 + 1) % g.shape[0]
    gx0, gx1 = x0 % g.shape[1], (x0 + 1) % g.shape[1]
    v = (g[np.ix_(gy0, gx0)] * (1 - fx) * (1 - fy) + g[np.ix_(gy0, gx1)] * fx * (1 - fy)
         + g[np.ix_(gy1, gx0)] * (1 - fx) * fy + g[np.ix_(gy1, gx1)] * fx * fy)
    lo, hi = v.min(), v.max()
    return (v - lo) / (hi - lo) if hi > lo else np.ones_like(v)


def make_map(kind: str, shape: tuple[int, int], seed: int, level: float = 1.0) -> np.ndarray:
    """A float64 map in [0, 1] of the given kind (deterministic in `seed`)."""
    rng = np.random.default_rng(seed)
    h, w = shape
    if kind == "constant":
        return np.full(shape, level)
    if kind == "plateaus":
        # blocks at exactly 0, 1 and one level between
        k = int(rng.integers(2, 9))
        levels = np.array([0.0, 1.0, round(float(rng.random()), 3)])
        cells = rng.integers(0, 3, (h // k + 1, w // k + 1))
        return levels[cells].repeat(k, 0).repeat(k, 1)[:h, :w]
    if kind == "spikes":
        # a floor at 0 with one-texel spikes to 1, or a top at 1 with one-texel pits to 0
        base = float(rng.integers(0, 2))
        m = np.full(shape, base)
        n = max(1, (h * w) // 40)
        m[rng.integers(0, h, n), rng.integers(0, w, n)] = 1.0 - base
        return m
    if kind == "step":
        # one cliff from 0 to 1 (left/right or top/bottom)
        m = np.zeros(shape)
        if rng.random() < 0.5 or h == 1:
            m[:, : max(1, w // 2)] = 1.0
        else:
            m[: max(1, h // 2), :] = 1.0
        return m if rng.random() < 0.5 else 1.0 - m
    if kind == "checker":
        k = int(rng.integers(1, 9))
        y, x = np.mgrid[0:h, 0:w]
        return (((x // k) + (y // k)) % 2).astype(np.float64)
    if kind == "noise":
        return _smooth(rng, shape, int(rng.integers(2, 9)))
    if kind == "terraces":
        # smooth noise quantised into a few flat terraces at exact levels, top at 1
        return np.round(_smooth(rng, shape, int(rng.integers(2, 6))) * 3) / 3
    raise ValueError(kind)


def encode(m: np.ndarray, dtype: str) -> np.ndarray:
    """float32, or uint8 / uint16 spanning their full range (0 and 255 / 65535 at the extremes)."""
    if dtype == "float32":
        return m.astype(np.float32)
    top = 255 if dtype == "uint8" else 65535
    return np.round(m * top).astype(dtype)


@st.composite
def height_maps(draw, max_size: int = 96):
    kind = draw(st.sampled_from(KINDS))
    shape = draw(sizes(hi=max_size))
    seed = draw(st.integers(0, 2**16))
    level = draw(st.sampled_from([0.0, 1.0, 0.5, 0.999]))
    dtype = draw(st.sampled_from(["float32", "uint8", "uint16"]))
    m = make_map(kind, shape, seed, level)
    return f"{kind}{shape[0]}x{shape[1]}/{dtype}/seed{seed}" + (f"/level{level}" if kind == "constant" else ""), encode(m, dtype)


def tilings():
    return st.sampled_from([1.0, 0.7, 1.37, 2.5])


def view_angles():
    """Degrees from the plane's normal, head-on to grazing."""
    return st.sampled_from([0.0, 30.0, 60.0, 72.0, 80.0])


@st.composite
def light_directions(draw):
    """(direction the light travels, elevation in degrees): high, oblique and grazing lights."""
    elev = draw(st.sampled_from([75.0, 45.0, 20.0, 8.0, 3.0]))
    az = draw(st.floats(0.0, 360.0, allow_nan=False).map(lambda a: round(a, 1)))
    e, a = np.radians(elev), np.radians(az)
    return (float(-np.cos(e) * np.cos(a)), float(-np.sin(e)), float(-np.cos(e) * np.sin(a))), elev
