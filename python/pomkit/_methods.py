"""The methods: small frozen dataclasses with validated fields.

Each maps onto the shared surface pipeline of the Rust core (`kind` plus numeric and text
parameters). See docs/methods.md for what each implements and which paper it follows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

__all__ = ["Method", "Flat", "Bump", "POM", "Tessellated"]

_SHADOWS = ("none", "hard", "soft")
_FILTERING = ("hardware", "exact")


def _int_field(obj, name: str, lo: int = 1, hi: int = 4096) -> None:
    v = getattr(obj, name)
    if isinstance(v, bool) or not isinstance(v, int):
        if isinstance(v, float) and v.is_integer():
            object.__setattr__(obj, name, int(v))
            v = int(v)
        else:
            raise TypeError(f"{name}: expected an integer, got {type(v).__name__}")
    if not lo <= v <= hi:
        raise ValueError(f"{name}: must lie in [{lo}, {hi}], got {v}")


def _choice(obj, name: str, options) -> None:
    v = getattr(obj, name)
    if not isinstance(v, str) or v not in options:
        raise ValueError(f"{name}: must be one of {', '.join(repr(o) for o in options)}, got {v!r}")


class Method:
    """Base of all methods. `_kind` names the core implementation."""

    _kind = ""

    def _params(self) -> tuple[str, dict[str, float], dict[str, str]]:
        num: dict[str, float] = {}
        text: dict[str, str] = {}
        for f in fields(self):  # type: ignore[arg-type]
            v = getattr(self, f.name)
            if isinstance(v, str):
                text[f.name] = v
            elif isinstance(v, bool):
                num[f.name] = 1.0 if v else 0.0
            else:
                num[f.name] = float(v)
        return self._kind, num, text

    @property
    def name(self) -> str:
        return type(self).__name__


@dataclass(frozen=True)
class Flat(Method):
    """Texture at the rasterised uv, base normal, no displacement."""

    _kind = "Flat"


@dataclass(frozen=True)
class Bump(Method):
    """Bump mapping (Blinn 1978): the shading normal from the height field's central
    differences; the uv is unchanged."""

    filtering: str = "hardware"
    _kind = "Bump"

    def __post_init__(self):
        _choice(self, "filtering", _FILTERING)


@dataclass(frozen=True)
class POM(Method):
    """Parallax occlusion mapping (Brawley & Tatarchuk 2004; Tatarchuk 2006).

    A linear search in n = max_steps + (N.V)(min_steps - max_steps) equal height steps
    (max_steps at grazing angles, min_steps head-on; `adaptive=False` always takes max_steps),
    with an early out, then the exact intersection with the piecewise-linear height profile
    between the last two samples. Shadows: "none", "hard" (horizon test over `shadow_steps`
    samples toward the light) or "soft" (penumbra estimate from the light's angular diameter).
    In-shader LOD: full POM at mip levels <= lod_threshold - 1, bump mapping above
    lod_threshold, blended in between. `mip_filtering=True` samples the height field at the
    footprint's mip level (the paper's tex2Dgrad); False samples level 0, the exact bilinear
    field the oracle uses (no prefiltering: aliases under minification).
    `filtering`: "hardware" (the sampler's bilinear filter) or "exact" (four loads and a
    float32 lerp).
    """

    min_steps: int = 8
    max_steps: int = 50
    shadows: str = "soft"
    shadow_steps: int = 8
    lod_threshold: float = 4.0
    adaptive: bool = True
    filtering: str = "hardware"
    mip_filtering: bool = True
    _kind = "POM"

    def __post_init__(self):
        _int_field(self, "min_steps")
        _int_field(self, "max_steps")
        _int_field(self, "shadow_steps")
        if self.min_steps > self.max_steps:
            raise ValueError(f"min_steps: must not exceed max_steps ({self.min_steps} > {self.max_steps})")
        _choice(self, "shadows", _SHADOWS)
        _choice(self, "filtering", _FILTERING)
        if isinstance(self.lod_threshold, bool) or not isinstance(self.lod_threshold, (int, float)) or not math.isfinite(self.lod_threshold):
            raise ValueError(f"lod_threshold: must be a finite number, got {self.lod_threshold!r}")
        for name in ("adaptive", "mip_filtering"):
            if not isinstance(getattr(self, name), bool):
                raise TypeError(f"{name}: expected a bool, got {type(getattr(self, name)).__name__}")


@dataclass(frozen=True)
class Tessellated(Method):
    """The displaced mesh itself (Chen & Chang 2008's "ground truth model"), rasterised by the
    same pipeline and shaded the same way: vertices on a lattice through the texel centres,
    `texels_per_vertex` texels apart (1: one vertex per texel; 0.5: two per texel, which matches
    the exact bilinear field to about 0.001 texel). Displaced on the CPU once per
    (mesh, height map, depth, tiling, spacing) and cached on the GPU.

    shadows: "hard" (default) tests the first directional light against a 2048^2 shadow map of
    the displaced mesh itself (3x3 PCF, boundaries good to ~1.5 shadow-map texels, no area-light
    penumbra); "none" turns it off. Other lights are unshadowed."""

    texels_per_vertex: float = 1.0
    shadows: str = "hard"
    _kind = "Tessellated"

    def __post_init__(self):
        _choice(self, "shadows", ("none", "hard"))
        v = self.texels_per_vertex
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (1 / 64 <= v <= 1024):
            raise ValueError(f"texels_per_vertex: must be a number in [1/64, 1024], got {v!r}")
