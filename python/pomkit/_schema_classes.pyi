"""Static types of the classes the core declares (src/scene/schema.rs, src/assets/report.rs),
which pomkit builds at import. Written by tools/schema_stub.py (make stubs); do not edit."""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

from ._assets import _AssetReportBase
from ._scene import _CameraBase, _DirectionalBase, _LightBase, _MaterialBase


@dataclass(frozen=True)
class Camera(_CameraBase):
    #: the eye's position
    eye: tuple[float, float, float]
    #: the point looked at
    target: tuple[float, float, float] = ...
    #: the up direction (not parallel to the view direction)
    up: tuple[float, float, float] = ...
    #: the vertical field of view in degrees
    fov_y: float = ...
    #: the image's width in pixels
    width: int = ...
    #: the image's height in pixels
    height: int = ...

@dataclass(frozen=True, eq=False)
class Material(_MaterialBase):
    #: the height map, h = 1 at the base surface
    height: np.ndarray
    #: the distance between h = 1 (the base surface) and h = 0, in object units
    depth: float = ...
    #: the albedo (None: a constant linear 0.5 grey)
    albedo: Optional[np.ndarray] = ...
    #: repetitions of the maps over the mesh's uv square
    tiling: float = ...

@dataclass(frozen=True)
class DirectionalLight(_DirectionalBase):
    #: the way the light travels (a non-zero vector)
    direction: tuple[float, float, float]
    #: linear RGB irradiance on a surface facing the light (a scalar for grey)
    irradiance: Any = ...
    #: the source's apparent size in degrees (0: a point-like source)
    angular_diameter: float = ...
    #: objects shadow each other from this light through a shadow map
    cast_shadows: bool = ...
    #: the shadow map's size in texels (square; clamped to the device's limit)
    shadow_map_size: int = ...
    #: a linear RGB tint that multiplies `irradiance` (glTF KHR_lights_punctual's `color`)
    color: Any = ...

@dataclass(frozen=True)
class SphereLight(_LightBase):
    #: the sphere's centre
    position: tuple[float, float, float]
    #: the sphere's radius (0: a point light)
    radius: float = ...
    #: linear RGB radiant intensity in W/sr (a scalar for grey)
    intensity: Any = ...
    #: a linear RGB tint that multiplies `intensity` (glTF KHR_lights_punctual's `color`)
    color: Any = ...

@dataclass(frozen=True)
class AssetReport(_AssetReportBase):
    vertices: int
    triangles: int
    #: distinct positions
    welded_vertices: int
    #: groups of triangles joined by edges whose uvs and handedness agree
    charts: int
    #: charts whose uv map is mirrored (most of their triangles have handedness w = +1)
    mirrored_charts: int
    mirrored_triangles: int
    #: triangles with zero uv area (no tangent basis of their own)
    degenerate_uv_triangles: int
    #: triangles with zero area in space
    degenerate_triangles: int
    #: geometric edges whose sides carry other uvs
    seam_edges: int
    #: edges whose sides share their uvs but not their handedness (a mirror axis inside a chart folded onto itself: the tangent basis flips there)
    mirror_edges: int
    #: mirror-axis edges whose two sides share a vertex (not only its position): one tangent serves both handednesses there, and the frame between the sides' corners collapses
    mirror_shared_edges: int
    #: edges with one side: the displaced surface ends there
    open_edges: int
    open_length: float
    #: edges whose sides carry other normals (split normals)
    hard_edges: int
    #: edges with more than two sides
    nonmanifold_edges: int
    #: any uv outside [0, 1] (the map repeats there)
    uvs_outside_unit_square: bool
    #: with a height map: the lowest and highest height it holds (of 0..1; h = 1 is the mesh's surface, 0 lies the material's depth below it)
    height_min: Optional[float]
    height_max: Optional[float]
    #: with a height map and the material's depth: the relief's own depth, depth × (max − min). A map that holds less than 0..1 spends the shell's depth on heights it never takes: `pk.textures.normalize` stretches it to 0..1, and this depth then keeps the relief
    relief_depth: Optional[float]
    #: with a height map: the largest and mean difference of the height field across a seam (in height units, 0..1), sampled along each seam edge on its sides
    seam_height_max: Optional[float]
    seam_height_mean: Optional[float]
    #: texels (of the height map) covered by two or more charts
    overlapping_texels: Optional[int]
    #: the fewest empty texels between two charts (the map repeats)
    min_chart_gap_texels: Optional[int]
    #: the highest mip level whose bilinear footprint stays within a chart's half of the narrowest gap (None: charts touch, even level 0 reads a neighbour)
    max_clean_mip: Optional[int]
    #: triangles with a vertex normal more than 60 degrees from the face's normal (normals averaged across a thin part or a sharp edge): the shell leans far from the surface there
    normals_off_faces: int
    #: triangles with a vertex normal more than 90 degrees from the face's (flipped): the shell turns inside out there
    normals_flipped: int
    #: with the material's depth: prisms whose bottom (the corners sunk by the depth along their normals) is turned over against their top, where the depth exceeds the local radius of curvature or the normals cross: the shell folds there
    folded_prisms: Optional[int]
    #: (finding, position in the mesh's space) for up to `EXAMPLES` places of each finding
    examples: list[tuple[str, tuple[float, float, float]]]
    #: the largest height mismatch across a seam in world units (with a material's depth)
    seam_world_max: Optional[float] = ...
    #: what the findings break, and the remedy
    warnings: list[str] = ...
