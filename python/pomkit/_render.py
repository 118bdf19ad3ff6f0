"""The Renderer: one wgpu device per process (created lazily, shared), GIL released while the
GPU works."""

from __future__ import annotations

import dataclasses

from ._errors import ArgumentError, ArgumentTypeError
from typing import Any, Iterable, Literal, Optional, Sequence, Union

import weakref

import numpy as np

from . import _core, _progress
from . import _validate as _v
from ._frame import AOV_NAMES, AovName, Frame
from ._methods import ALL_METHODS, Method
from ._scene import Material, Scene

__all__ = ["Renderer", "adapters"]


def adapters() -> list["_core.AdapterDict"]:
    """The adapters wgpu can open here (name, backend, device_type, driver).
    POMKIT_BACKEND=vulkan|gl restricts the backends."""
    return list(_core.adapters())


class Renderer:
    """Renders a Scene with a method into a Frame.

    adapter: None for the best adapter, or an index / a substring of the adapter's name / a
    backend name ("vulkan", "gl") from `pomkit.adapters()`. All Renderers share one device per
    process; renders from several threads are serialised on it.

    pipeline: "raster" draws the method's fragment shader over the rasterised mesh; "compute"
    rasterises only the nearest triangle's index (a visibility pass) and runs the same method
    in a compute shader per pixel, which uses the whole chip where the graphics units are few
    (datacenter GPUs); "auto" (the default) takes the adapter's rule (`pipeline_rule`, printed by
    `python -m pomkit info`). The two agree (docs/cost.md, "Two pipelines"). Prism, frames of
    several objects and the `fragments` AOV are always rasterised: "compute" refuses them,
    "auto" rasterises them.
    """

    def __init__(self, adapter: Optional[str | int] = None, pipeline: str = "auto"):
        if adapter is not None and not isinstance(adapter, (str, int)):
            raise ArgumentTypeError(f"adapter: expected a name or an index, got {type(adapter).__name__}")
        if not isinstance(pipeline, str):
            raise ArgumentTypeError(f"pipeline: expected one of {', '.join(map(repr, _core.PIPELINES))}, got {type(pipeline).__name__}")
        self._r = _core.Renderer(None if adapter is None else str(adapter), pipeline)
        self.pipeline = pipeline
        self.info: _core.RendererInfo = self._r.info()
        _progress.install()

    def __repr__(self) -> str:
        i = self.info
        return f"Renderer({i['name']!r}, backend={i['backend']!r}, pipeline={self.pipeline!r}, timestamps={i['timestamps']})"

    def render(self, scene: Scene, method: Method, aovs: Aovs = "all", spp: int = 1) -> Frame:
        """Render `scene` with `method`. `aovs`: "all" (the default: every AOV but the cost
        counters) or the AOVs to return, e.g. ("color", "uv"). The render targets no requested AOV
        needs are neither written nor read back, and the Frame holds only what was asked for. The
        cost counters (`COST_AOVS`: "fetches", "bytes", "chain", "fragments") are counted only when named, e.g.
        aovs=("color", "steps", "fetches"): counting costs the search a little.

        `spp`: samples per pixel, a square number (1, 4, 9, 16, ...): k x k stratified samples on
        a regular grid in each pixel, rendered as one pass at k² the pixels. Colour is their mean
        (a box filter over the pixel, as `pk.reference.render_mitsuba`'s), `coverage` the fraction
        that hit; uv, depth, mask, steps, lod, flags, object and the counters come from a second,
        one-sample pass: they are the plain frame's, bit for bit, and `time_ms` is both passes'.
        spp=1 is the plain frame."""
        _check(scene, method)
        return _frame(self._r.render(scene, method, _aovs(aovs), _spp(spp)), method)

    def render_many(self, scenes: Iterable[Scene], method: Method, aovs: Aovs = "all", spp: int = 1) -> list[Frame]:
        """Render many scenes (one scene under many cameras, a sweep of one parameter...) with one
        method. Submissions and readbacks are pipelined: frame i+1 renders on the GPU while
        frame i is read back and unpacked. The frames equal those of `render`, one by one
        (`spp` as in `render`)."""
        scenes = list(scenes)
        for sc in scenes:
            _check(sc, method)
        ds = self._r.render_many(list(scenes), method, _aovs(aovs), _spp(spp))
        return [_frame(d, method) for d in ds]

    def render_visibility(self, scene: Scene, method: Method, aovs: Aovs = ("color", "uv", "mask")) -> Frame:
        """The frame of `render(scene, method, aovs)` plus `visibility`: what the method's shadow
        test lets through of the scene's first directional light at each hit, in [0, 1].

        Measured, not modelled: the same scene is rendered twice more with only that light, no
        ambient and a constant albedo, once with the method as given and once with its
        self-shadowing off (`shadows="none"`; cast shadows off too). The march, and so the hit,
        is the same in both; the colour's ratio is the light's visibility. NaN where there is no
        hit or the light is behind the shading normal (both renders black). For Tessellated it
        is its shadow map's verdict."""
        _check(scene, method)
        names = _aovs(aovs)
        frame = self.render(scene, method, aovs if names is None else tuple(dict.fromkeys(names + ("mask",))))
        lit, free = _visibility_twins(scene, method)
        # a scene that is already its own shadowed twin (one light, no ambient, constant albedo):
        # its frame is that render
        a = frame if lit is scene and frame.has("color") else self.render(lit, method, aovs=("color", "mask"))
        b = self.render(free, _unshadowed(method), aovs=("color", "mask"))
        ca = a.color.mean(-1, dtype=np.float64)
        cb = b.color.mean(-1, dtype=np.float64)
        ok = a.mask & b.mask & (cb > 1e-12)
        vis = np.full(ca.shape, np.nan, np.float32)
        vis[ok] = np.clip(ca[ok] / cb[ok], 0.0, 1.0)
        arrays: dict[str, Any] = {k: frame._arrays[k] for k in frame.aovs}
        return Frame(**arrays, visibility=vis, gpu_ms=frame.gpu_ms, wall_ms=frame.wall_ms, timing=frame.timing,
                     method=frame.method)

    def update_height(self, material: Material, height) -> Material:
        """Dynamic height fields: a new Material with `height` in place of `material.height` (every
        other field the same). When the old map is resident on the GPU and the sizes match, the new
        texels are written into the same texture and the mean and max pyramids are rebuilt by
        compute passes: no pipeline is rebuilt and nothing is allocated. Otherwise the new map
        uploads on the next render. Normals need no update: they are computed per pixel from the
        height field."""
        if not isinstance(material, Material):
            raise ArgumentTypeError(f"material: expected a pomkit.Material, got {type(material).__name__}")
        new = dataclasses.replace(material, height=height)
        if new.height.shape == material.height.shape:
            self._r.update_height(material._height_data(), new._height_data())
        return new


Aovs = Union[Literal["all"], Sequence[AovName]]


def _aovs(aovs: Aovs) -> Optional[Any]:
    if isinstance(aovs, str):
        if aovs == "all":
            return None
        raise ArgumentError(f"aovs: expected 'all' or a sequence of AOV names such as ('color', 'uv'), got {aovs!r}")
    try:
        names = tuple(aovs)
    except TypeError:
        raise ArgumentTypeError(f"aovs: expected 'all' or a sequence of AOV names such as ('color', 'uv'), got {aovs!r}") from None
    for n in names:
        if n not in AOV_NAMES:
            raise ArgumentError(f"aovs: unknown AOV {n!r}; the AOVs are {', '.join(AOV_NAMES)}")
    if not names:
        raise ArgumentError("aovs: name at least one AOV, e.g. aovs=('color',)")
    return names


def _spp(spp: int) -> int:
    """The type and sign here; which counts are allowed (squares up to 256) is the core's rule
    (`Renderer::render_many_spp`), raised as a ValueError naming spp."""
    return _v.integer("spp", spp, 1, 2 ** 32 - 1, strict=True)


def _first_directional(scene: Scene):
    from ._scene import DirectionalLight
    for l in scene.lights:
        if isinstance(l, DirectionalLight):
            return l
    raise ArgumentError("scene: visibility is that of the first directional light, and this scene has none; "
                     "add a pk.DirectionalLight to scene.lights")


def _visibility_twins(scene: Scene, method: Method) -> tuple[Scene, Scene]:
    """The scene with only its first directional light, no ambient and constant albedo: with its
    cast shadows as given (for the shadowed render) and without (for the unshadowed one). The
    shadowed twin is `scene` itself where it already has that form."""
    import dataclasses
    light = _first_directional(scene)
    plain = all(o.material.albedo is None for o in scene.objects)
    if plain and tuple(scene.lights) == (light,) and not np.any(scene.ambient):
        return scene, scene.replace(lights=[dataclasses.replace(light, cast_shadows=False)])
    objects = [o if o.material.albedo is None else dataclasses.replace(o, material=dataclasses.replace(o.material, albedo=None))
               for o in scene.objects]
    lit = scene.replace(objects=objects, lights=[light], ambient=0.0)
    free = scene.replace(objects=objects, lights=[dataclasses.replace(light, cast_shadows=False)], ambient=0.0)
    return lit, free


def _unshadowed(method: Method) -> Method:
    import dataclasses
    if hasattr(method, "shadows"):
        return dataclasses.replace(method, shadows="none")  # type: ignore[type-var]
    return method


def _check(scene: Any, method: Any) -> None:
    if not isinstance(scene, Scene):
        raise ArgumentTypeError(f"scene: expected a pomkit.Scene, got {type(scene).__name__}")
    if not isinstance(method, Method):
        raise ArgumentTypeError(f"method: expected a pomkit method such as pomkit.POM(), got {type(method).__name__}")
    if isinstance(method, _SHELL_METHODS):
        for o in scene.objects:
            _warn_shell(o.mesh, float(o.material.depth), type(method).__name__)


#: the methods that build or walk a shell along the vertex normals (their `shell` trait): flipped
#: normals and folded prisms change what they render (docs/conventions.md, "The displaced surface")
_SHELL_METHODS = tuple(c for c in ALL_METHODS if c.shell)
#: per mesh, the depths already checked (a mesh is checked once per depth)
_SHELL_CHECKED: "weakref.WeakKeyDictionary[Any, set[float]]" = weakref.WeakKeyDictionary()


def _warn_shell(mesh: Any, depth: float, name: str) -> None:
    """Warn, once per mesh and depth, where the shell the method follows is not the surface:
    normals flipped against their faces, or prisms that fold at this depth."""
    seen = _SHELL_CHECKED.setdefault(mesh, set())
    if depth <= 0.0 or depth in seen:
        return
    seen.add(depth)
    flipped, folded = _core.shell_findings(mesh._core_data(), depth)
    if flipped or folded:
        import warnings

        warnings.warn(f"{name}: {flipped} triangles have flipped normals and {folded} prisms fold at depth {depth:g}: "
                      "the shell this method follows leaves the displaced surface there (pk.check_asset says where; "
                      "lower the depth or load with normals=\"recompute\")", RuntimeWarning, stacklevel=4)


def _frame(r: "_core.RenderedFrame", method: Method) -> Frame:
    return Frame._of(r.arrays, gpu_ms=r.gpu_ms, wall_ms=r.wall_ms, method=repr(method))


