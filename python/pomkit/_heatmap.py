"""False colours for error and cost images (the demo page's heat maps, pk.explore's views): one
ramp, one heat map."""

from __future__ import annotations

import numpy as np

#: black, purple, pink, orange, pale yellow (magma-like), for a value in [0, 1]
MAGMA_STOPS = np.array([[0, 0, 4], [80, 18, 123], [183, 55, 121], [252, 137, 97], [252, 253, 191]], np.float64)


def ramp(t: np.ndarray, stops: np.ndarray) -> np.ndarray:
    """t in [0, 1] (H, W) through the colour stops, piecewise linear: (H, W, 3)."""
    pos = np.clip(t, 0.0, 1.0)[..., None] * (len(stops) - 1)
    i = np.clip(np.floor(pos).astype(int), 0, len(stops) - 2)
    f = pos - i
    return stops[i[..., 0]] * (1 - f) + stops[i[..., 0] + 1] * f


def heat(x: np.ndarray, vmax: float, mask: np.ndarray) -> np.ndarray:
    """x / vmax through the magma-like ramp as uint8 RGB (NaN as 0); grey where not `mask`."""
    c = ramp(np.nan_to_num(np.asarray(x, np.float64) / max(vmax, 1e-12), nan=0.0), MAGMA_STOPS)
    return np.where(mask[..., None], c, 60).astype(np.uint8)
