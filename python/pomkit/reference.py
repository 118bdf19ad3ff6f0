"""Ground truth: the displaced mesh, Mitsuba 3 and pyrender renders of it.

These need the `reference` extra: `pip install pomkit[reference]` (mitsuba, trimesh,
flip-evaluator, scikit-image, pyrender). Results are cached on disk (see `pomkit._cache`).
"""

from __future__ import annotations

from ._errors import ArgumentError, ReferenceRendererError
import math
import os
import time

import numpy as np

from . import _validate as _v
from ._cache import cached, scene_hash
from ._displaced import displaced_arrays, require as _require
from . import _displaced, _mitsuba
from ._mitsuba import cast_render, direct_render, mitsuba_variant
from ._frame import Frame
from ._scene import DirectionalLight, Scene

__all__ = ["displaced_mesh", "render_mitsuba", "render_pyrender", "mitsuba_variant"]

def displaced_mesh(scene: Scene, resolution: float | None = None, object: int | None = None):
    """The displaced surface `S = P + depth*(h-1)*N` as a `trimesh.Trimesh`, in world space.

    For a scene of one object (or with `object=i`), one Trimesh; for a scene of several objects
    and `object=None`, a list of Trimesh, one per object in the order of `scene.objects` (the
    index is the object's id in the `object` AOV). Each object's transform is applied; its
    displacement `depth` is in object units, along the object-space normal.

    Heights are sampled bilinearly exactly as the shaders sample them (level 0). `resolution` is
    vertices per texel along each axis (default 2): on the generated meshes the vertices lie on a
    lattice through the texel centres, so that the bilinear field's creases are mesh edges; 2 per
    texel matches the exact field to about 0.001 texel. The mesh carries uvs (`visual.uv`) and
    vertex normals from the height field (central differences, as the shaders shade)."""
    trimesh = _require("trimesh")
    res = 2.0 if resolution is None else resolution

    def one(i: int):
        a = displaced_arrays(scene, res, i)
        return trimesh.Trimesh(vertices=a["positions"], faces=a["faces"], vertex_normals=a["normals"],
                               visual=trimesh.visual.TextureVisuals(uv=a["uvs"]), process=False)

    if object is not None:
        return one(object)
    if len(scene.objects) == 1:
        return one(0)
    return [one(i) for i in range(len(scene.objects))]


def render_exact(scene: Scene, spp: int = 16, shadows: bool = True, cache: bool = True) -> Frame:
    """Deprecated: `pk.oracle.image(scene, spp, shadows, cache)`, the same frame."""
    import warnings

    from . import oracle
    warnings.warn("pk.reference.render_exact is now pk.oracle.image; the old name goes in the next release",
                  DeprecationWarning, stacklevel=2)
    return oracle.image(scene, spp=spp, shadows=shadows, cache=cache)


def render_mitsuba(scene: Scene, spp: int | None = None, seed: int = 0, variant: str | None = None,
                   resolution: float | None = None, cache: bool = True, integrator: str = "cast",
                   shadows: bool = True) -> Frame:
    """Mitsuba 3's render of the displaced mesh, two ways. `resolution` is the mesh's vertices per
    texel; None is 8 (on the suite's sharpest maps at 70°, hits within 0.002 texel of the
    bilinear field), fewer where an object's mesh would pass 2^21 vertices.

    - `integrator="cast"` (the default): Mitsuba as the ray caster, shaded with the reference
      shading of docs/conventions.md. Every sample's hit is Mitsuba's intersection with the
      mesh; the normal is the definition's at the hit's uv and base frame; the albedo is
      Mitsuba's lookup of its bitmap; each light's direction and irradiance are its delta
      emitter's, spread over the light's disk by render_exact's 64 directions, and ambient
      occlusion traces render_exact's 64 cosine-weighted directions, each ray with Mitsuba's
      `ray_test`. `spp` (default 16, a square) samples per pixel on the grid of `render(spp=)`,
      as render_exact. Deterministic: `noise_floor` is 0.0, and `seed` must be 0. On curved meshes and several objects, this is the exact
      reference `render_exact` returns. `shadows=False` traces no light or ambient rays.
    - `integrator="direct"`: Mitsuba's own `direct` integrator (`spp`, default 64, independent
      samples, box filter): its vertex normals, its sampling of the light's disk (a far sphere)
      and of a constant environment for ambient. The independent check of conventions, with
      Monte Carlo noise (seed against seed, docs/tables/references.md).

    Both return colour and pixel-centre `uv`, `depth` (distance along the ray), `mask` and
    `object` (the index in `scene.objects`); "cast" also `coverage` and `visibility`. Every object
    is a mesh, so objects shadow each other as they do in the world. `Frame.wall_ms` is the time
    of the render (stored with it in the cache)."""
    integrator = _v.choice("integrator", integrator, ("cast", "direct"))
    if spp is None:
        spp = 16 if integrator == "cast" else 64
    spp = _v.integer("spp", spp, 1, 256 if integrator == "cast" else 1 << 20, strict=True)
    if integrator == "cast" and math.isqrt(spp) ** 2 != spp:
        raise ArgumentError(f"spp: integrator='cast' takes a square number of samples per pixel (1, 4, 9, 16, ...), got {spp}")
    seed = _v.integer("seed", seed, 0, 2 ** 31 - 1, strict=True)
    if integrator == "cast" and seed != 0:
        raise ArgumentError("seed: integrator='cast' is deterministic (the sample grid of render(spp=) and render_exact's "
                         "direction sets), so it takes seed=0; seeds apply to integrator='direct'")
    resolution = _mitsuba.auto_resolution(scene, resolution)
    shadows = _v.boolean("shadows", shadows)
    key = scene_hash(scene, kind="mitsuba", spp=spp, seed=seed, variant=variant, resolution=resolution,
                     integrator=integrator, shadows=shadows, mesh=_displaced.MESH) if cache else ""

    def compute():
        t0 = time.perf_counter()
        if integrator == "cast":
            out = cast_render(scene, spp, variant, resolution, shadows)
        else:
            if not shadows:
                raise ArgumentError("shadows: integrator='direct' always traces shadows; use integrator='cast' for shadows=False")
            out = direct_render(scene, spp, seed, variant, resolution)
        return {**out, "ms": np.array((time.perf_counter() - t0) * 1e3)}

    t0 = time.perf_counter()
    a = cached("mitsuba", key, compute, use_cache=cache)
    # references cached before `object` existed: one object, wherever the mask is
    obj = a["object"] if "object" in a else np.where(a["mask"], 0, -1).astype(np.int32)
    extra = {k: a[k] for k in ("coverage", "visibility") if k in a}
    floor = 0.0 if integrator == "cast" else None
    return Frame(color=a["color"], uv=a["uv"], depth=a["depth"], mask=a["mask"], object=obj, wall_ms=float(a["ms"]),
                 timing="wall", noise_floor=floor, **extra,
                 method=f"mitsuba[{a['variant']}] {integrator} spp={spp} (took {float(a['ms']):.0f} ms, "
                 f"this call {1e3 * (time.perf_counter() - t0):.0f} ms)")


# ---------------------------------------------------------------- pyrender

def render_pyrender(scene: Scene, resolution: float = 2.0, cache: bool = True) -> Frame:
    """pyrender 0.1.45's render of the displaced mesh, headless (EGL, else OSMesa).

    A loose reference: pyrender shades with a metallic-roughness PBR model (here roughness 1,
    metallic 0, which is close to but not Lambertian) with shadow maps, and writes sRGB, which is
    decoded back to linear here. Its directional lights have no angular size and sphere lights
    become point lights. Texture v-flip and numpy 2's missing `np.infty` are handled here.
    uv comes from the displaced mesh by barycentric lookup of pyrender's depth (not provided):
    this Frame carries colour, depth and mask."""
    key = scene_hash(scene, kind="pyrender", resolution=resolution, mesh=_displaced.MESH)

    def compute():
        t0 = time.perf_counter()
        if not hasattr(np, "infty"):
            np.infty = np.inf  # pyrender 0.1.45 uses np.infty, removed in numpy 2
        os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
        try:
            import pyrender  # noqa: F401
            r, pr = _pyrender_render(scene, resolution)
        except Exception as first:
            if os.environ.get("PYOPENGL_PLATFORM") == "egl":
                # retry with OSMesa in a clean interpreter state is not possible once OpenGL is
                # imported; report both remedies
                raise ReferenceRendererError(
                    f"pyrender could not render headless with EGL ({first}). Install "
                    "`libegl1 libegl-mesa0 libgl1-mesa-dri` (EGL) or `libosmesa6` and set "
                    "PYOPENGL_PLATFORM=osmesa before importing pomkit.reference") from first
            raise
        color, depth = r
        mask = depth > 0
        return dict(color=color, depth=np.where(mask, depth, np.nan).astype(np.float32), mask=mask,
                    ms=np.array((time.perf_counter() - t0) * 1e3))

    a = cached("pyrender", key, compute, use_cache=cache)
    nan_uv = np.full(a["mask"].shape + (2,), np.nan, np.float32)
    return Frame(color=a["color"], uv=nan_uv, depth=a["depth"], mask=a["mask"], wall_ms=float(a["ms"]),
                 timing="wall", method="pyrender")


def _pyrender_render(scene: Scene, resolution: float):
    import pyrender
    import trimesh
    from ._color import srgb_to_linear

    ps = pyrender.Scene(ambient_light=np.array(list(scene.ambient)) if max(scene.ambient) > 0 else np.zeros(3),
                        bg_color=[0, 0, 0, 0])
    for i, o in enumerate(scene.objects):
        tm = displaced_mesh(scene, resolution, object=i)
        m = o.material
        if m.albedo is not None:
            from PIL import Image
            srgb = np.round(np.clip(_linear_to_srgb(m.albedo), 0, 1) * 255).astype(np.uint8)
            # pyrender samples images with v flipped (OpenGL's origin is the bottom row)
            img = Image.fromarray(srgb[::-1])
            uv = np.asarray(tm.visual.uv) * m.tiling
            mat = pyrender.MetallicRoughnessMaterial(baseColorTexture=img, metallicFactor=0.0, roughnessFactor=1.0)
            tm.visual = trimesh.visual.TextureVisuals(uv=uv)
        else:
            mat = pyrender.MetallicRoughnessMaterial(baseColorFactor=[0.5, 0.5, 0.5, 1.0], metallicFactor=0.0,
                                                     roughnessFactor=1.0)
        ps.add(pyrender.Mesh.from_trimesh(tm, material=mat, smooth=True))
    cam = scene.camera
    pc = pyrender.PerspectiveCamera(yfov=math.radians(cam.fov_y), aspectRatio=cam.width / cam.height, znear=0.01)
    f, r, u = cam.basis()
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = r, u, -f, cam.eye
    ps.add(pc, pose=pose)
    for l in scene.lights:
        if isinstance(l, DirectionalLight):
            d = np.asarray(l.direction, float)
            d /= np.linalg.norm(d)
            z = -d
            x = np.cross([0, 1, 0], z) if abs(z[1]) < 0.99 else np.cross([1, 0, 0], z)
            x /= np.linalg.norm(x)
            lp = np.eye(4)
            lp[:3, 0], lp[:3, 1], lp[:3, 2] = x, np.cross(z, x), z
            ps.add(pyrender.DirectionalLight(color=np.ones(3), intensity=float(np.mean(l.power))), pose=lp)
        else:
            lp = np.eye(4)
            lp[:3, 3] = l.position
            ps.add(pyrender.PointLight(color=np.ones(3), intensity=float(np.mean(l.power)) * 4 * math.pi), pose=lp)
    rend = pyrender.OffscreenRenderer(cam.width, cam.height)
    try:
        flags = pyrender.RenderFlags.SHADOWS_DIRECTIONAL | pyrender.RenderFlags.RGBA
        color, zbuf = rend.render(ps, flags=flags)
    finally:
        rend.delete()
    lin = srgb_to_linear(np.ascontiguousarray(color[..., :3], np.uint8))
    # z-buffer depth -> distance along the ray
    rays = cam.rays()
    dist = np.where(zbuf > 0, zbuf / np.maximum((rays * f).sum(-1), 1e-9), 0.0).astype(np.float32)
    return (lin, dist), pyrender


def _linear_to_srgb(x):
    from ._scene import linear_to_srgb
    return linear_to_srgb(x)
