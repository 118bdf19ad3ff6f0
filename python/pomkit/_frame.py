"""The Frame: colour and per-pixel AOVs of one render, as numpy arrays."""

from __future__ import annotations

from ._errors import ArgumentTypeError
from pathlib import Path
from typing import TYPE_CHECKING, Literal, Optional

import numpy as np

from . import _core
from ._color import linear_to_srgb8

__all__ = ["Frame", "AovName", "AOV_NAMES", "COST_AOVS"]

#: the AOVs a render can return (`Renderer.render(..., aovs=...)`): the core's list, the one
#: source; the Literal types them (tests/test_contracts.py holds the two equal)
AovName = Literal["color", "uv", "depth", "mask", "coverage", "steps", "lod", "flags", "object", "fetches", "bytes", "chain", "fragments"]
AOV_NAMES: tuple[str, ...] = tuple(_core.AOV_NAMES)
#: the cost counters: counted only when named in `aovs=` (not in "all")
COST_AOVS: tuple[str, ...] = tuple(_core.COST_AOV_NAMES)
#: arrays a Frame may also hold that no render target writes: `visibility` comes from the CPU
#: oracle (`pk.oracle.hits`) or from `Renderer.render_visibility` (a shadowed and an unshadowed render)
DERIVED_NAMES: tuple[str, ...] = ("visibility",)


class Frame:
    """Arrays are (H, W, ...) with row 0 at the top of the image.

    The AOVs (`AOV_NAMES`, the core's table, src/render/aovs.rs) are attributes:
    {aov_docs}
    visibility: (H, W) float32, the first directional light's visibility at the hit (1 lit,
           0 shadowed, between in a penumbra), NaN where there is no hit or the light is behind
           the shading normal. Not a render target: `pk.oracle.hits` (the exact oracle) and
           `Renderer.render_visibility` fill it.
    gpu_ms: GPU time of the render pass from timestamp queries, None where the adapter has none
    wall_ms: wall time of submit-and-wait (always measured)
    timing: "gpu" when gpu_ms holds a timestamp measurement, "wall" when only wall_ms exists;
            `time_ms` gives whichever is there.
    noise_floor: a reference's own FLIP noise, the floor under any score against it: 0.0 for
            `pk.oracle.image` and the matched `render_mitsuba()` (deterministic),
            None where it is unknown (a rendered frame, Mitsuba's Monte Carlo
            `integrator="direct"`: measure its seed against seed).

    A frame holds the AOVs it was rendered with (`aovs`); reading another raises an
    AttributeError that names the `aovs=` argument of `Renderer.render`.
    """

    # the AOVs, typed for mypy (a misspelt one fails type checking); at run time __getattr__
    # reads them from the arrays the frame holds (tests/test_contracts.py holds these names equal
    # to AOV_NAMES)
    color: np.ndarray
    uv: np.ndarray
    depth: np.ndarray
    mask: np.ndarray
    coverage: np.ndarray
    steps: np.ndarray
    lod: np.ndarray
    flags: np.ndarray
    object: np.ndarray
    fetches: np.ndarray
    bytes: np.ndarray
    chain: np.ndarray
    fragments: np.ndarray

    def __init__(self, *, method: str = "", gpu_ms: Optional[float] = None, wall_ms: Optional[float] = None,
                 timing: Optional[str] = None, noise_floor: Optional[float] = None, **arrays: Optional[np.ndarray]):
        unknown = set(arrays) - set(AOV_NAMES) - set(DERIVED_NAMES)
        if unknown:
            raise ArgumentTypeError(f"Frame: unknown AOVs {sorted(unknown)}; known: {AOV_NAMES + DERIVED_NAMES}")
        self._arrays: dict[str, np.ndarray] = {k: v for k, v in arrays.items() if v is not None}
        self.method = method
        self.gpu_ms = gpu_ms
        self.wall_ms = wall_ms
        self.timing = timing if timing is not None else ("gpu" if gpu_ms is not None else "wall")
        self.noise_floor = noise_floor

    @classmethod
    def _of(cls, arrays: dict[str, Optional[np.ndarray]], *, method: str = "", gpu_ms: Optional[float] = None,
            wall_ms: Optional[float] = None) -> "Frame":
        """A frame of the core's arrays by AOV name (None: not rendered)."""
        f = cls(method=method, gpu_ms=gpu_ms, wall_ms=wall_ms)
        unknown = set(arrays) - set(AOV_NAMES)
        if unknown:
            raise ArgumentTypeError(f"Frame: unknown AOVs {sorted(unknown)}; known: {AOV_NAMES}")
        f._arrays = {k: v for k, v in arrays.items() if v is not None}
        return f

    @property
    def aovs(self) -> tuple[str, ...]:
        """The AOVs this frame holds, in the order of `AOV_NAMES`."""
        return tuple(k for k in AOV_NAMES if k in self._arrays)

    def has(self, name: str) -> bool:
        return name in self._arrays

    def _get(self, name: str) -> np.ndarray:
        try:
            return self._arrays[name]
        except KeyError:
            raise AttributeError(
                f"{name}: this frame holds only {', '.join(self.aovs) or 'no AOVs'}; "
                f"render with aovs=(..., {name!r}) (or aovs='all') to get it") from None

    if not TYPE_CHECKING:
        def __getattr__(self, name: str) -> np.ndarray:
            # the AOVs, by the core's table (attributes set in __init__ are found before this)
            if name in AOV_NAMES:
                return self._get(name)
            raise AttributeError(f"'Frame' object has no attribute {name!r}")

    @property
    def visibility(self) -> np.ndarray:
        """(H, W) float32 visibility of the first directional light at the hit (see the class doc)."""
        try:
            return self._arrays["visibility"]
        except KeyError:
            raise AttributeError("visibility: this frame has none; take it from pk.oracle.hits(scene) (the exact "
                                 "oracle) or renderer.render_visibility(scene, method)") from None

    @property
    def shape(self) -> tuple[int, int]:
        a = next(iter(self._arrays.values()))
        return (int(a.shape[0]), int(a.shape[1]))

    @property
    def time_ms(self) -> Optional[float]:
        return self.gpu_ms if self.gpu_ms is not None else self.wall_ms

    def __repr__(self) -> str:
        h, w = self.shape if self._arrays else (0, 0)
        return f"Frame({w}x{h}, aovs={self.aovs}, {self.timing} {self.time_ms} ms, method={self.method!r})"

    def to_srgb8(self) -> np.ndarray:
        """(H, W, 3) uint8 sRGB for display (clamped to [0, 1])."""
        if not self.has("color"):
            raise AttributeError("color: this frame has no colour (the geometric oracle, or rendered without "
                                 "'color' in aovs=)")
        return linear_to_srgb8(self.color)

    def save(self, path) -> Path:
        """Write the colour as PNG (sRGB) or, for a .npz path, every AOV the frame holds."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".npz":
            np.savez_compressed(path, **self._arrays)  # type: ignore[arg-type]
        else:
            from PIL import Image
            Image.fromarray(self.to_srgb8()).save(path)
        return path


Frame.__doc__ = (Frame.__doc__ or "").replace(
    "{aov_docs}", "\n    ".join(f"{n}: {_core.AOV_DOCS[n]}" for n in AOV_NAMES))
