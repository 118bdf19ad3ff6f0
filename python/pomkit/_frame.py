"""The Frame: colour and per-pixel AOVs of one render, as numpy arrays."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

import numpy as np

from ._scene import linear_to_srgb

__all__ = ["Frame"]


@dataclass
class Frame:
    """Arrays are (H, W, ...) with row 0 at the top of the image.

    color: (H, W, 3) float32 linear RGB (None for the geometric oracle)
    uv:    (H, W, 2) hit texture coordinate in the mesh's uv space (not wrapped), NaN where no hit
    depth: (H, W) distance from the eye to the hit point, NaN where no hit
    mask:  (H, W) bool, the pixel shows the surface
    steps: (H, W) uint32 height-map samples taken (view ray + shadow rays)
    lod:   (H, W) float32 mip level the LOD system used, NaN where no hit
    flags: (H, W) uint8, bit 0: the march hit its iteration bound (Exact)
    gpu_ms: GPU time of the render pass from timestamp queries, None where the adapter has none
    wall_ms: wall time of submit-and-wait (always measured)
    timing: "gpu" when gpu_ms holds a timestamp measurement, "wall" when only wall_ms exists;
            `time_ms` gives whichever is there.
    """

    color: Optional[np.ndarray]
    uv: np.ndarray
    depth: np.ndarray
    mask: np.ndarray
    steps: Optional[np.ndarray] = None
    lod: Optional[np.ndarray] = None
    flags: Optional[np.ndarray] = None
    gpu_ms: Optional[float] = None
    wall_ms: Optional[float] = None
    timing: str = "gpu"
    method: str = ""

    @property
    def shape(self) -> tuple[int, int]:
        return self.mask.shape  # type: ignore[return-value]

    @property
    def time_ms(self) -> Optional[float]:
        return self.gpu_ms if self.gpu_ms is not None else self.wall_ms

    def to_srgb8(self) -> np.ndarray:
        """(H, W, 3) uint8 sRGB for display (clamped to [0, 1])."""
        if self.color is None:
            raise ValueError("color: this frame has no colour (geometric oracle)")
        return np.round(linear_to_srgb(self.color) * 255.0).astype(np.uint8)

    def save(self, path) -> Path:
        """Write the colour as PNG (sRGB) or, for a .npz path, every AOV."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".npz":
            arrays: dict[str, Any] = {k: v for k, v in dict(color=self.color, uv=self.uv, depth=self.depth, mask=self.mask,
                                             steps=self.steps, lod=self.lod).items() if v is not None}
            np.savez_compressed(path, **arrays)
        else:
            from PIL import Image
            Image.fromarray(self.to_srgb8()).save(path)
        return path
