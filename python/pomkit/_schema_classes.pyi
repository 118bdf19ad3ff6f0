"""Static types of the scene classes the core declares (src/scene/schema.rs), which
pomkit._schema builds at import. Written by tools/schema_stub.py (make stubs); do not edit."""

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

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
