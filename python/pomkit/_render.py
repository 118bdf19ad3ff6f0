"""The Renderer: one wgpu device per process (created lazily, shared), GIL released while the
GPU works."""

from __future__ import annotations

import os
import threading
from typing import Optional

import numpy as np

from . import _core
from ._frame import Frame
from ._methods import Method
from ._scene import Material, Scene

__all__ = ["Renderer", "adapters", "exact_uv"]


def adapters() -> list[dict]:
    """The adapters wgpu can open here (name, backend, device_type, driver).
    POMKIT_BACKEND=vulkan|gl restricts the backends."""
    return list(_core.adapters())


class Renderer:
    """Renders a Scene with a method into a Frame.

    adapter: None for the best adapter, or an index / a substring of the adapter's name / a
    backend name ("vulkan", "gl") from `pomkit.adapters()`. All Renderers share one device per
    process; renders from several threads are serialised on it.
    """

    def __init__(self, adapter: Optional[str | int] = None):
        if adapter is not None and not isinstance(adapter, (str, int)):
            raise TypeError(f"adapter: expected a name or an index, got {type(adapter).__name__}")
        self._r = _core.Renderer(None if adapter is None else str(adapter))
        self.info = dict(self._r.info())

    def __repr__(self) -> str:
        i = self.info
        return f"Renderer({i['name']!r}, backend={i['backend']!r}, timestamps={i['timestamps']})"

    def render(self, scene: Scene, method: Method) -> Frame:
        if not isinstance(scene, Scene):
            raise TypeError(f"scene: expected a pomkit.Scene, got {type(scene).__name__}")
        if not isinstance(method, Method):
            raise TypeError(f"method: expected a pomkit method such as pomkit.POM(), got {type(method).__name__}")
        d = self._r.render(scene._describe(), method)
        return Frame(
            color=d["color"], uv=d["uv"], depth=d["depth"], mask=d["mask"], steps=d["steps"], lod=d["lod"], flags=d["flags"],
            gpu_ms=d["gpu_ms"], wall_ms=d["wall_ms"], method=repr(method),
        )

    def update_height(self, material: Material, height) -> Material:
        """Dynamic height fields: a new Material with `height` in place of `material.height` (same
        depth, albedo, tiling). When the old map is resident on the GPU and the sizes match, the new
        texels are written into the same texture and the mean and max pyramids are rebuilt by
        compute passes: no pipeline is rebuilt and nothing is allocated. Otherwise the new map
        uploads on the next render. Normals need no update: they are computed per pixel from the
        height field."""
        if not isinstance(material, Material):
            raise TypeError(f"material: expected a pomkit.Material, got {type(material).__name__}")
        new = Material(height, depth=material.depth, albedo=material.albedo, tiling=material.tiling)
        if new.height.shape == material.height.shape:
            self._r.update_height(material.height, new.height)
        return new


def exact_uv(scene: Scene) -> Frame:
    """CPU float64 oracle: the exact first hit of each pixel's ray against the bilinear height
    field, for planar meshes (each triangle's plane is taken as the base surface under it).
    Returns a Frame with float64 uv and depth, the mask, and `steps` = cells visited."""
    if not isinstance(scene, Scene):
        raise TypeError(f"scene: expected a pomkit.Scene, got {type(scene).__name__}")
    d = _core.exact_uv(scene._describe())
    return Frame(uv=d["uv"], depth=d["depth"], mask=d["mask"], steps=d["cells"], method="exact_uv")
