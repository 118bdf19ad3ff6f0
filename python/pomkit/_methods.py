"""The methods: small frozen dataclasses with validated fields.

The Rust core extracts each dataclass field by field into its typed `Method` (the class
attribute `_kind` picks the variant): the defaults a user gets are these; the ranges are checked
here, at construction, with the core's limits (`_core.MAX_STEPS_LIMIT`), and again by the core
when it reads them. See
docs/methods.md for what each implements and which paper it follows, and
docs/custom_methods.md for `Custom`.

Every per-pixel method (Parallax, SteepParallax, POM, Relief, Exact, ConeStep, NCS, Prism, CurvedRelief,
DistanceMapping, Custom) also takes, by keyword:
  shadows: "none" | "hard" (horizon test along the light ray, `shadow_steps` samples) |
           "soft" (penumbra estimate from the light's angular diameter) |
           "horizon" (max-mip horizon angle, Dachsbacher & Tatarchuk 2007) |
           "exact" (the max-mip traversal along the light ray from the height field at the hit:
           no false shadow and no false light on the bilinear field; a light with a disk is the
           fraction of the reference's 64 directions over it, shared among a pixel's samples)
  filtering: "hardware" (the sampler's bilinear filter) | "exact" (four loads, float32 lerp)
  mip_filtering: sample the footprint's mip level (True) or level 0 (False)
  ao_directions: 0 to 64 horizon directions for ambient occlusion of Scene.ambient; with
           shadows="exact", any value above 0 turns on the exact AO of the reference shading
           (64 cosine-weighted directions by exact traversals, shared among a pixel's samples)
  horizon_samples: samples at 2^k texels, k < horizon_samples, for "horizon" shadows and AO
"""

from __future__ import annotations

from ._errors import ArgumentError, ArgumentTypeError
import dataclasses
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

from . import _core
from . import _validate as _v

__all__ = ["Method", "Flat", "Bump", "POM", "Parallax", "SteepParallax", "Relief", "Exact", "ConeStep", "NCS", "Prism", "Tessellated",
           "Custom", "CurvedRelief", "DistanceMapping", "Hybrid"]

#: the option values: the checks take them from the core (`_core.SHADOW_KINDS`, ...), the one
#: source; the Literals type them for mypy and editors, and tests/test_contracts.py holds the two
#: equal
ShadowKind = Literal["none", "hard", "soft", "horizon", "exact"]
FilteringKind = Literal["hardware", "exact"]
#: how Tessellated cuts each lattice quad (`_core.PATTERN_KINDS`)
PatternKind = Literal["fan", "grid"]
_SHADOWS: tuple[str, ...] = tuple(_core.SHADOW_KINDS)
_FILTERING: tuple[str, ...] = tuple(_core.FILTERING_KINDS)


def _level0() -> Any:
    """`mip_filtering=False`, the default of the methods that march: level 0, so that the search,
    not the filtering, is what the tables compare (bricks, cobblestones, spikes at 30/60/80 deg
    against the oracle, docs/methods.md; POM: docs/tables/pom_default.md). Exact, ConeStep and
    Custom keep the base's True (their frames are pinned so)."""
    return field(default=False, kw_only=True)


def _set(obj, name: str, value) -> None:
    object.__setattr__(obj, name, value)


def _int_field(obj, name: str, lo: int = 1, hi: int = _core.MAX_STEPS_LIMIT) -> None:
    _set(obj, name, _v.integer(name, getattr(obj, name), lo, hi))


def _choice(obj, name: str, options) -> None:
    _v.choice(name, getattr(obj, name), options)


def _bool_field(obj, name: str) -> None:
    _set(obj, name, _v.boolean(name, getattr(obj, name)))


def _real_field(obj, name: str, lo: float = -1e6, hi: float = 1e6) -> None:
    _set(obj, name, _v.number(name, getattr(obj, name), lo, hi))


class Method:
    """Base of all methods. `_kind` names the core implementation."""

    _kind = ""
    #: the field of the method's main quality knob, its step count (None: it has none). The one
    #: place `pk.choose`, the bench and the explorer read it from, through `with_steps`.
    steps_knob: ClassVar[str | None] = None
    #: whether it builds or walks a shell along the vertex normals, so that flipped normals and
    #: folded prisms change what it renders (render warns where a mesh has them)
    shell: ClassVar[bool] = False
    #: how tests/test_differential.py checks it against the oracle on generated maps: "planar"
    #: (a texture-space search, whose surface tiles on past the mesh's border) or "shell" (whose
    #: surface ends at the border, as the oracle's); None where it is not in that suite, with the
    #: reason in `not_differential` (a test holds every method to one or the other)
    differential: ClassVar[str | None] = None
    not_differential: ClassVar[str] = ""

    def with_steps(self, n: int) -> "Method":
        """This method at `n` steps on its main knob (`steps_knob`), the fields that follow it
        set by the method's one rule; the method itself where it has no knob."""
        if self.steps_knob is None:
            return self
        return dataclasses.replace(self, **self._knob(max(1, int(n))))  # type: ignore[type-var]

    def _knob(self, n: int) -> dict[str, int]:
        return {str(self.steps_knob): n}

    @property
    def name(self) -> str:
        return type(self).__name__

    @property
    def safety(self) -> str:
        """"safe": the method never misses a feature of the bilinear height field (it finds the
        first intersection, up to float precision); "approximate": it may step over thin
        features or stop early. Tables and charts carry this label."""
        return "approximate"


@dataclass(frozen=True)
class Flat(Method):
    """Texture at the rasterised uv, base normal, no displacement."""

    _kind = "Flat"
    not_differential = "no search: the rasterised point itself (tests/test_surface.py holds it to the oracle at depth 0)"


@dataclass(frozen=True)
class Bump(Method):
    """Bump mapping (Blinn 1978): the shading normal from the height field's central
    differences; the uv is unchanged."""

    filtering: FilteringKind = "hardware"
    _kind = "Bump"
    not_differential = "no search: the rasterised uv, only the normal changes (tests/test_methods.py)"

    def __post_init__(self):
        _choice(self, "filtering", _FILTERING)


@dataclass(frozen=True)
class _PerPixel(Method):
    """Options shared by the per-pixel methods (keyword-only)."""

    shadows: ShadowKind = field(default="none", kw_only=True)
    shadow_steps: int = field(default=8, kw_only=True)
    filtering: FilteringKind = field(default="hardware", kw_only=True)
    mip_filtering: bool = field(default=True, kw_only=True)
    ao_directions: int = field(default=0, kw_only=True)
    horizon_samples: int = field(default=8, kw_only=True)

    _shadow_options: ClassVar[tuple[str, ...]] = _SHADOWS

    def __post_init__(self):
        _choice(self, "shadows", self._shadow_options)
        _int_field(self, "shadow_steps")
        _choice(self, "filtering", _FILTERING)
        _bool_field(self, "mip_filtering")
        _int_field(self, "ao_directions", 0, 64)
        _int_field(self, "horizon_samples", 1, 16)
        self._validate()

    def _validate(self) -> None:
        pass


@dataclass(frozen=True)
class POM(_PerPixel):
    """Parallax occlusion mapping (Brawley & Tatarchuk 2004; Tatarchuk 2006).

    A linear search in n = max_steps + (N.V)(min_steps - max_steps) equal height steps
    (max_steps at grazing angles, min_steps head-on; `adaptive=False` always takes max_steps,
    e.g. POM(adaptive=False, min_steps=8, max_steps=8) is Brawley & Tatarchuk 2004's fixed
    profile), an early out, then the exact intersection with the piecewise-linear height
    profile between the last two samples. In-shader LOD: full POM at mip levels <=
    lod_threshold - 1, bump mapping above lod_threshold, blended in between. Default shadows:
    "soft". The march samples level 0 of the height map (`mip_filtering=False`, the default by
    measurement); `mip_filtering=True` samples the footprint's level (Tatarchuk's tex2Dgrad).

    Follows the displaced surface (docs/conventions.md) but at open borders and seams: it marches
    the fragment's tangent plane, tiled without end, so it goes on past a plane's border and
    does not see the wall that closes a step at a seam whose heights disagree.
    """

    min_steps: int = 8
    max_steps: int = 50
    shadows: ShadowKind = field(default="soft", kw_only=True)
    # the level-0 march: closer to the exact surface and to Mitsuba than the mip-filtered one in
    # 28 of 28 measured cases (docs/methods.md, docs/tables/pom_default.md)
    mip_filtering: bool = _level0()
    lod_threshold: float = 4.0
    adaptive: bool = True
    _kind = "POM"
    differential = "planar"
    steps_knob = "max_steps"

    def _knob(self, n: int) -> dict[str, int]:
        # head-on a quarter of the grazing count
        return {"max_steps": n, "min_steps": max(1, n // 4)}

    def _validate(self):
        _int_field(self, "min_steps")
        _int_field(self, "max_steps")
        if self.min_steps > self.max_steps:
            raise ArgumentError(f"min_steps: must not exceed max_steps ({self.min_steps} > {self.max_steps})")
        _real_field(self, "lod_threshold")
        _bool_field(self, "adaptive")


@dataclass(frozen=True)
class Parallax(_PerPixel):
    """Parallax mapping (Kaneko 2001): one sample, s += (scale * (1 - h) + bias) * P, P the
    parallax vector per unit of height. With `offset_limiting` (Welsh 2004) P is not divided by
    V.z, which bounds the offset at grazing angles.

    Follows the displaced surface (docs/conventions.md) but at open borders and seams: it marches
    the fragment's tangent plane, tiled without end, so it goes on past a plane's border and
    does not see the wall that closes a step at a seam whose heights disagree.
    """

    offset_limiting: bool = True
    scale: float = 1.0
    bias: float = 0.0
    mip_filtering: bool = _level0()
    _kind = "Parallax"
    differential = "planar"

    def _validate(self):
        _bool_field(self, "offset_limiting")
        _real_field(self, "scale", -100, 100)
        _real_field(self, "bias", -100, 100)


@dataclass(frozen=True)
class SteepParallax(_PerPixel):
    """Steep parallax mapping (McGuire & McGuire 2005): `steps` fixed height steps, the first
    sample below the surface is the hit, no refinement (stair-steps expected).

    Follows the displaced surface (docs/conventions.md) but at open borders and seams: it marches
    the fragment's tangent plane, tiled without end, so it goes on past a plane's border and
    does not see the wall that closes a step at a seam whose heights disagree.
    """

    steps: int = 32
    mip_filtering: bool = _level0()
    _kind = "SteepParallax"
    differential = "planar"
    steps_knob = "steps"

    def _validate(self):
        _int_field(self, "steps")


@dataclass(frozen=True)
class Relief(_PerPixel):
    """Relief mapping (Policarpo et al. 2005): `linear_steps` fixed steps, then `binary_steps`
    bisections. `depth_bias` scales the search by 1 - (1 - N.V)^8, flattening toward the horizon
    (Tatarchuk 2006 fig. 2b).

    Follows the displaced surface (docs/conventions.md) but at open borders and seams: it marches
    the fragment's tangent plane, tiled without end, so it goes on past a plane's border and
    does not see the wall that closes a step at a seam whose heights disagree.
    """

    linear_steps: int = 16
    binary_steps: int = 6
    depth_bias: bool = False
    mip_filtering: bool = _level0()
    _kind = "Relief"
    differential = "planar"
    steps_knob = "linear_steps"

    def _validate(self):
        _int_field(self, "linear_steps")
        _int_field(self, "binary_steps", 0, 64)
        _bool_field(self, "depth_bias")


@dataclass(frozen=True)
class Exact(_PerPixel):
    """Maximum mipmaps (Tevs, Ihrke & Seidel 2008): hierarchical traversal of the max-reduced
    pyramid (built on the GPU), the exact ray/bilinear-patch intersection at the finest level.
    No step count to tune; `max_iterations` bounds the traversal and `Frame.flags & 1` marks rays
    that hit the bound. Always samples level 0 with exact filtering. shadows="exact" (every
    per-pixel method has it) is the same traversal along the light ray.

    Follows the displaced surface (docs/conventions.md) but at open borders and seams: it marches
    the fragment's tangent plane, tiled without end, so it goes on past a plane's border and
    does not see the wall that closes a step at a seam whose heights disagree.
    """

    max_iterations: int = 4096
    _kind = "Exact"
    differential = "planar"

    @property
    def safety(self) -> str:
        return "safe"

    def _validate(self):
        _int_field(self, "max_iterations", 1, 1 << 24)


ConeKind = Literal["conservative", "relaxed"]
RefineKind = Literal["exact", "binary", "none"]


@dataclass(frozen=True)
class ConeStep(_PerPixel):
    """Cone step mapping (Dummer 2006) over a cone map built on the GPU from the max-mip pyramid
    (base and w per cell in two R32Float textures: twice the map's float32 size), cached with the
    height map and rebuilt after `update_height`; a build over a second is kept on disk by content
    (docs/assets.md, "Large maps").

    cones: "conservative" cones bound the bilinear field pomkit renders, not only its texel
    centres (Ban & Valasek 2024): no cone step crosses the surface. "relaxed" cones are wider
    (measured at the far end of each distance band, base at the cell's own max): faster, may
    step into a feature (Policarpo & Oliveira 2007).
    refine: "exact" hands over to the max-mip walk with the exact patch intersection where the
    cones stop carrying the ray a cell per step: with conservative cones the result is exact
    (the cones only skip empty space). "binary" bisects `binary_steps` times between the last
    point above and the first below the surface (for relaxed cones). "none" is the raw march.
    max_steps: cone steps before the refinement takes over ("exact") or the march stops, flagged
    in `Frame.flags & 1` ("binary", "none"); `max_iterations` bounds the max-mip walk.

    Follows the displaced surface (docs/conventions.md) but at open borders and seams: it marches
    the fragment's tangent plane, tiled without end, so it goes on past a plane's border and
    does not see the wall that closes a step at a seam whose heights disagree.
    """

    cones: ConeKind = "conservative"
    refine: RefineKind = "exact"
    max_steps: int = 64
    binary_steps: int = 8
    max_iterations: int = 4096
    _kind = "ConeStep"
    differential = "planar"
    steps_knob = "max_steps"

    def _knob(self, n: int) -> dict[str, int]:
        # a bisection step for every four cone steps
        return {"max_steps": n, "binary_steps": max(2, n // 4)}

    def _validate(self):
        _choice(self, "cones", tuple(_core.CONE_KINDS))
        _choice(self, "refine", tuple(_core.REFINE_KINDS))
        _int_field(self, "max_steps")
        _int_field(self, "binary_steps", 0, 64)
        _int_field(self, "max_iterations", 1, 1 << 24)

    @property
    def safety(self) -> str:
        return "safe" if (self.cones, self.refine) == ("conservative", "exact") else "approximate"


@dataclass(frozen=True)
class NCS(_PerPixel):
    """Normal-based curved silhouettes (Chen & Chang 2008): no prisms. The base mesh's normals,
    tangents and scale factors (S_tangent, S_binormal) are rendered into 512^2 texture-space
    maps on the GPU once per mesh (and dilated past the charts); the view ray is marched in
    texture space, looking up the local frame at each step: P += c * delta * S * TBN * V with
    delta = depth / max_steps and c = `step_scale` (the paper's 2.5). `adaptive=True` (default)
    lengthens a step to POM's layer density where that is longer: each step descends at least
    one of the shell's max_steps + N.V (8 - max_steps) layers (N.V of the local frame), and
    spans at most one shell depth, so that it still follows the curved surface; `adaptive=False`
    is the paper's fixed step. The frame is fetched again when the ray enters another texel cell
    of the map. A ray leaving the shell through its top is discarded (`mask` false: the
    silhouette); a ray still inside after `max_steps` is an early termination, flagged in
    `Frame.flags & 2` (the paper's red pixels). Level 0 by default (`mip_filtering=False`).

    Where the walk loses the surface rather than finding a silhouette (the interpolated normal faces
    away from the viewer on a front face, or the ray leaves through the top where the view meets
    the normal at N.V > 0.6), the fragment keeps the base mesh's point (AOV flags & 4): never
    less coverage than the base mesh.
    """

    step_scale: float = 2.5
    max_steps: int = 64
    adaptive: bool = True
    # level 0, as POM and Prism
    mip_filtering: bool = _level0()
    _kind = "NCS"
    differential = "shell"
    shell = True
    steps_knob = "max_steps"

    def _validate(self):
        _real_field(self, "step_scale", 1e-6, 1000)
        _int_field(self, "max_steps")
        _bool_field(self, "adaptive")


@dataclass(frozen=True)
class Prism(_PerPixel):
    """Prism POM (Dachsbacher & Tatarchuk 2007). Each base triangle is extruded along its vertex
    normals into a prism; neighbouring prisms share their sides. The rasteriser draws only the
    shell's boundary (the tops, and the sides and bottoms where the mesh is open or creased), so
    a fragment is where a view ray enters the shell, and from there the ray walks through the
    prisms: in each it is marched between entry and exit with a constant texture gradient
    (POM's search at POM's layer density: `min_steps`..`max_steps` layers per shell height by
    N.V, and its refinement), and leaving through a side it enters the neighbour. Prisms whose
    highest height lies below the ray are crossed without a march. With several objects the
    hit's depth is the fragment depth. `outward=True` builds the shell above the base mesh (the
    paper's set-up: h = 0 on the base mesh, h = 1 `depth` above it); the default is pomkit's
    inward convention. `tight=True` (default) lowers each vertical edge's top to the highest
    height of the field under the prisms beside it (never below 1/256 of the depth), so that a
    ray crosses no empty shell above the field: neighbours share the edge, so the shell stays
    closed, and every prism's top stays above its field. Thinner prisms also bend the march's
    straight segments less (docs/cost_journal_2026.md, "The tight shell"). `tight=False` is the paper's
    shell, every top at the full depth. `exact=True` marches each segment with the max-mip
    traversal (exact patch intersection) instead of POM's search. Level 0 by default (`mip_filtering=False`, as POM).
    Shadows: "none", "hard", "soft" (default), "horizon" or "exact", and `ao_directions`."""

    min_steps: int = 8
    max_steps: int = 50
    outward: bool = False
    exact: bool = False
    tight: bool = True
    shadows: ShadowKind = field(default="soft", kw_only=True)
    # level 0, as POM: the footprint of the grazing top face a silhouette ray enters through is
    # no footprint for its walk down through the shell (mask IoU against Mitsuba, 256^2:
    # torus 0.9924 mip-filtered -> 0.9988 level 0, sphere 0.9931 -> 0.9981)
    mip_filtering: bool = _level0()
    _kind = "Prism"
    differential = "shell"
    shell = True

    @property
    def safety(self) -> str:
        # exact=True marches each prism's segment with the max-mip traversal
        return "safe" if self.exact else "approximate"

    def _validate(self):
        _bool_field(self, "exact")
        _int_field(self, "min_steps")
        _int_field(self, "max_steps")
        if self.min_steps > self.max_steps:
            raise ArgumentError(f"min_steps: must not exceed max_steps ({self.min_steps} > {self.max_steps})")
        _bool_field(self, "outward")
        _bool_field(self, "tight")


@dataclass(frozen=True)
class CurvedRelief(_PerPixel):
    """Curved relief mapping (Oliveira & Policarpo 2005), a baseline of the NCS paper (Chen &
    Chang 2008): relief mapping against the quadric z = a x² + b y² that approximates the base
    mesh around the fragment (a, b fitted per vertex on the CPU from its neighbours, and
    interpolated), instead of the tangent plane. The ray's depth below the curved base grows as
    q t² + c t along it; a ray that leaves the shell through its top without a hit is discarded:
    the silhouette, with no prisms. `linear_steps` fixed steps over the ray's span in the shell,
    then `binary_steps` bisections. Shaded in the entry's frame. Fails, as the paper shows, where
    a quadric does not describe the surface: saddles (a and b of opposite sign), changing
    curvature, thin parts. Level 0 by default (`mip_filtering=False`).

    Where the walk loses the surface rather than finding a silhouette (the interpolated normal faces
    away from the viewer on a front face, or the ray leaves through the top where the view meets
    the normal at N.V > 0.6), the fragment keeps the base mesh's point (AOV flags & 4): never
    less coverage than the base mesh.
    """

    linear_steps: int = 32
    binary_steps: int = 6
    mip_filtering: bool = _level0()
    _kind = "CurvedRelief"
    differential = "shell"
    shell = True
    steps_knob = "linear_steps"

    def _validate(self):
        _int_field(self, "linear_steps")
        _int_field(self, "binary_steps", 0, 64)


@dataclass(frozen=True)
class DistanceMapping(_PerPixel):
    """Distance mapping (Donnelly 2005, GPU Gems 2 ch. 8), the space-leaping baseline of the NCS
    paper (Chen & Chang 2008, fig. 1g): sphere tracing through a 3-D distance texture over the
    shell. The volume (`slices` over the shell's height, at most 128 voxels a side: finer maps are
    read at the max-pyramid level that fits) is built on the GPU from the max pyramid, cached
    with the height map and rebuilt after `update_height`: each voxel holds the distance to the
    nearest column box bounding the surface (within 8 voxels). From the entry the ray advances by
    the voxel's distance less its half diagonal; within about a voxel of the bounding columns it
    tests the height field itself in half-texel steps; the first sample below the surface is
    refined by `binary_steps` bisections. `max_steps` bounds the walk (`Frame.flags & 1`).
    Memory: (4 + W' H' slices) floats, e.g. 1 MiB for a 256² map (4x the map's float32 level 0).
    Level 0 by default (`mip_filtering=False`).

    Follows the displaced surface (docs/conventions.md) but at open borders and seams: it marches
    the fragment's tangent plane, tiled without end, so it goes on past a plane's border and
    does not see the wall that closes a step at a seam whose heights disagree.
    """

    max_steps: int = 64
    binary_steps: int = 6
    slices: int = 16
    mip_filtering: bool = _level0()
    _kind = "DistanceMapping"
    differential = "planar"
    steps_knob = "max_steps"

    def _validate(self):
        _int_field(self, "max_steps")
        _int_field(self, "binary_steps", 0, 64)
        _int_field(self, "slices", 2, 256)


@dataclass(frozen=True)
class Tessellated(Method):
    """The displaced mesh itself (Chen & Chang 2008's "ground truth model"), rasterised by the
    same pipeline and shaded the same way: vertices on a lattice through the texel centres,
    `texels_per_vertex` texels apart (1: one vertex per texel; 0.5: two per texel). Displaced on
    the CPU once per (mesh, height map, depth, tiling, spacing, pattern) and cached on the GPU.

    pattern: how each quad of the lattice is cut. "fan" (default) adds a vertex at the quad's
    centre, on the field, and cuts it into four triangles about it; "grid" cuts it along one
    diagonal into two, as a regular tessellator would. Inside a texel cell the field is
    bilinear, and its twist leaves a chord error of |d| L^2/4 in a quad of side L cut in two but
    |d| L^2/16 cut in four: the fan at spacing L is as close to the field as the grid at L/2,
    with half the triangles (docs/conventions.md, "The tessellated mesh"). At the same spacing
    the fan draws twice the grid's triangles and costs up to about twice its time; "grid" is
    the cheaper mesh where its chords do not matter. Meshes from arrays are subdivided
    barycentrically with either pattern.

    shadows: "hard" (default) tests the first directional light against a 2048^2 shadow map of
    the displaced mesh itself (3x3 PCF, boundaries good to ~1.5 shadow-map texels, no area-light
    penumbra; other lights unshadowed; no ambient occlusion); "exact" gives the mesh the
    reference's exact self-shadows and AO (docs/conventions.md, "The reference shading": every
    light's disk and the ambient by exact max-mip walks from each fragment's point of the field),
    so that against `pk.oracle.image` a shadow difference is the method's, not the
    shadow map's; "none" turns shadows off."""

    texels_per_vertex: float = 1.0
    shadows: Literal["none", "hard", "exact"] = "hard"
    pattern: PatternKind = "fan"
    _kind = "Tessellated"
    not_differential = "a mesh, not a search: the reference mesh the suites measure others by (tests/test_surface.py, test_wild.py, test_reference.py hold it to the oracle)"

    def __post_init__(self):
        _choice(self, "shadows", ("none", "hard", "exact"))
        _choice(self, "pattern", tuple(_core.PATTERN_KINDS))
        _real_field(self, "texels_per_vertex", 1 / 64, 1024)


def _tessellated_default() -> "Tessellated":
    return Tessellated(texels_per_vertex=8.0)


def _pom_default() -> "Method":
    return POM()


@dataclass(frozen=True)
class Hybrid(Method):
    """A coarse mesh displaced at its vertices and a per-pixel method that marches only the
    rest, as engines ship vertex displacement plus parallax (Unreal's Nanite displacement with
    pixel depth offset, HDRP's vertex and pixel displacement, PlayCanvas #9246).

    coarse: a `pk.Tessellated` (its `texels_per_vertex` and `pattern`: the coarse lattice; its
    shadows are not used) or `pk.Flat()` (no coarse displacement: the fine method alone, on the
    base mesh). fine: `pk.POM`, `pk.SteepParallax`, `pk.Relief`, `pk.Exact` or `pk.ConeStep`, with its own
    options (shadows, filtering, steps). Over each coarse triangle the residual (the height
    minus the coarse surface's interpolated height) lies within bounds the method computes once
    per mesh and map; the coarse mesh (never coarser than the base mesh; at hard edges each side
    on its own normals, meeting on the base mesh) is drawn at the top of that window and the
    fine method searches down to a floor that holds along its ray, so its steps resolve
    (window / shell) times finer than on the base mesh, and it is never worse than alone
    (docs/hybrid.md). Depth, shadows and every AOV are the fine method's."""

    coarse: Method = field(default_factory=_tessellated_default)
    fine: Method = field(default_factory=_pom_default)
    _kind = "Hybrid"

    def __post_init__(self):
        if not isinstance(self.coarse, (Tessellated, Flat)):
            raise ArgumentTypeError(f"coarse: expected pk.Tessellated(texels_per_vertex=...) or pk.Flat(), got {type(self.coarse).__name__}")
        windowed = isinstance(self.fine, Custom) and self.fine.windowed
        if not isinstance(self.fine, Method) or (self.fine._kind not in _core.HYBRID_FINE_KINDS and not windowed):
            raise ArgumentError(f"fine: expected one of pk.{', pk.'.join(_core.HYBRID_FINE_KINDS)}, or a pk.Custom with "
                                f"windowed=True (a search that marches a window of the shell), got {type(self.fine).__name__}")

    @property
    def safety(self) -> str:
        return self.fine.safety

    @property
    def label(self) -> str:
        c = self.coarse
        tpv = f"{c.texels_per_vertex:g}" if isinstance(c, Tessellated) else "flat"
        return f"Hybrid({tpv}, {label(self.fine)})"


@dataclass(frozen=True)
class Custom(_PerPixel):
    """A method you write in WGSL, run by pomkit's surface pass (docs/custom_methods.md).

    `wgsl` defines `fn march(r: Ray) -> Hit`, importing what it uses from pomkit's modules, e.g.
    `#import pomkit::march::{Ray, Hit, planar_hit}` and `#import pomkit::height::height_at`.
    pomkit supplies the geometry, the LOD, shading, shadows (`shadows=` as for the built-ins),
    the AOVs and the timing. `params` become the uniform block `params` (f32 fields, in order):
    `params={"steps": 24.0}` is read as `params.steps`. `name` names the method in labels and in
    compile errors, which raise a ValueError naming `wgsl` with naga's message and line numbers.

    Follows the displaced surface (docs/conventions.md) but at open borders and seams: it marches
    the fragment's tangent plane, tiled without end, so it goes on past a plane's border and
    does not see the wall that closes a step at a seam whose heights disagree.

    windowed: the march searches the Ray's window, from `r.s` at height `r.top` down to
    `r.floor` (what `view_segment(r)` spans; alone, [0, 1] from the fragment), so that
    `pk.Hybrid` can take it as its fine method (docs/custom_methods.md, "Windows").
    """

    wgsl: str = ""
    name: str = "custom"
    params: dict = field(default_factory=dict)
    windowed: bool = False
    _kind = "Custom"

    def _validate(self):
        if not isinstance(self.wgsl, str) or "fn march" not in self.wgsl:
            raise ArgumentError("wgsl: must be WGSL source defining `fn march(r: Ray) -> Hit` (see docs/custom_methods.md)")
        if not isinstance(self.name, str) or not self.name.isidentifier() or self.name.startswith("__") or not self.name.isascii():
            raise ArgumentError(f"name: must be an identifier (letters, digits, _), got {self.name!r}")
        if not isinstance(self.params, dict):
            raise ArgumentTypeError(f"params: expected a dict of name -> number, got {type(self.params).__name__}")
        for k, v in self.params.items():
            if not isinstance(k, str) or not k.isidentifier() or not k.isascii() or k[-1].isdigit() or k.startswith("_"):
                raise ArgumentError(f"params: names must be identifiers that neither start with _ nor end in a digit (WGSL naming rules of the composer), got {k!r}")
            _v.number(f"params[{k!r}]", v)
        _set(self, "params", {k: float(v) for k, v in self.params.items()})
        _bool_field(self, "windowed")

    def __hash__(self):
        return hash((self.wgsl, self.name, tuple(self.params.items()), self.windowed, self.shadows, self.filtering))

    @property
    def label(self) -> str:
        return self.name


def label(m) -> str:
    """The method with only the fields that differ from its defaults, e.g. POM(max_steps=16);
    a Custom method by its name and parameters."""
    if isinstance(m, Custom):
        return f"{m.name}({', '.join(f'{k}={v:g}' for k, v in m.params.items())})"
    if isinstance(m, Hybrid):
        return m.label
    default = type(m)()
    diff = [f"{f.name}={getattr(m, f.name)!r}" for f in dataclasses.fields(m) if getattr(m, f.name) != getattr(default, f.name)]
    return f"{m.name}({', '.join(diff)})"



#: every built-in method class, for sweeps
ALL_METHODS = (Flat, Bump, Parallax, SteepParallax, POM, Relief, Exact, ConeStep, NCS, Prism, Tessellated, CurvedRelief, DistanceMapping)
