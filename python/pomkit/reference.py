"""Ground truth: the displaced mesh, Mitsuba 3 and pyrender renders of it.

These need the `reference` extra: `pip install pomkit[reference]` (mitsuba, trimesh,
flip-evaluator, scikit-image, pyrender). Results are cached on disk (see `pomkit._cache`).
"""

from __future__ import annotations

from ._errors import ArgumentError, MissingExtraError, ReferenceRendererError
import hashlib
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from . import _validate as _v
from ._cache import cached, scene_hash
from ._displaced import displaced_arrays, require as _require
from . import _displaced, _mitsuba
from ._mitsuba import cast_render, direct_render, mitsuba_variant
from ._frame import Frame
from ._scene import DirectionalLight, Scene

__all__ = ["displaced_mesh", "render_mitsuba", "render_pyrender", "render_cycles", "mitsuba_variant", "blender_python"]

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


def render_mitsuba(scene: Scene, spp: int | None = None, seed: int = 0, variant: str | None = None,
                   resolution: float | None = None, cache: bool = True, integrator: str = "cast",
                   shadows: bool = True) -> Frame:
    """Mitsuba 3's render of the displaced mesh, two ways. `resolution` is the mesh's vertices per
    texel; None is 8 (on the suite's sharpest maps at 70°, hits within 0.002 texel of the
    bilinear field), fewer where an object's mesh would pass 2^21 vertices.

    - `integrator="cast"` (the default): Mitsuba as the ray caster, shaded with the reference
      shading of docs/conventions.md. Every sample's hit is Mitsuba's intersection with the
      mesh; the normal is the definition's at the hit's uv and base mesh's basis; the albedo is
      Mitsuba's lookup of its bitmap; each light's direction and irradiance are its delta
      emitter's, spread over the light's disk by pk.oracle.image's 64 directions, and ambient
      occlusion traces pk.oracle.image's 64 cosine-weighted directions, each ray with Mitsuba's
      `ray_test`. `spp` (default 16, a square) samples per pixel on the grid of `render(spp=)`,
      as pk.oracle.image. Deterministic: `noise_floor` is 0.0, and `seed` must be 0. On curved meshes and several objects, this is the exact
      reference `pk.oracle.image` returns. `shadows=False` traces no light or ambient rays.
    - `integrator="direct"`: Mitsuba's own `direct` integrator (`spp`, default 64, independent
      samples, box filter) with a Lambert BSDF lit from the shading normal's side whatever side
      the viewer is on (pomkit's rule; Mitsuba's `diffuse` blackens a face whose vertex normal
      faces away from the viewer): its vertex normals, its sampling of the light's disk (a far sphere)
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
        raise ArgumentError("seed: integrator='cast' is deterministic (the sample grid of render(spp=) and pk.oracle.image's "
                         "direction sets), so it takes seed=0; seeds apply to integrator='direct'")
    resolution = _mitsuba.auto_resolution(scene, resolution)
    shadows = _v.boolean("shadows", shadows)
    # `direct` shades with pomkit_lambert (lit from the shading normal's side whatever the viewer's)
    bsdf = "pomkit_lambert" if integrator == "direct" else "diffuse"
    key = scene_hash(scene, kind="mitsuba", spp=spp, seed=seed, variant=variant, resolution=resolution,
                     integrator=integrator, shadows=shadows, mesh=_displaced.MESH, winding=_displaced.WINDING, bsdf=bsdf,
                     faces=_mitsuba.CAST_FACES if integrator == "cast" else "both",
                     **_displaced.mirrors_key(scene)) if cache else ""

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
    key = scene_hash(scene, kind="pyrender", resolution=resolution, mesh=_displaced.MESH, winding=_displaced.WINDING,
                     **_displaced.mirrors_key(scene))

    def compute():
        t0 = time.perf_counter()
        if not hasattr(np, "infty"):
            np.infty = np.inf  # pyrender 0.1.45 uses np.infty, removed in numpy 2
        os.environ.setdefault("PYOPENGL_PLATFORM", "egl")
        color, depth = _pyrender_render(scene, resolution)
        mask = depth > 0
        return dict(color=color, depth=np.where(mask, depth, np.nan).astype(np.float32), mask=mask,
                    ms=np.array((time.perf_counter() - t0) * 1e3))

    a = cached("pyrender", key, compute, use_cache=cache)
    nan_uv = np.full(a["mask"].shape + (2,), np.nan, np.float32)
    return Frame(color=a["color"], uv=nan_uv, depth=a["depth"], mask=a["mask"], wall_ms=float(a["ms"]),
                 timing="wall", method="pyrender")


def _pyrender_render(scene: Scene, resolution: float):
    pyrender = _require("pyrender")
    import trimesh
    from ._color import linear_to_srgb8, srgb_to_linear

    ps = pyrender.Scene(ambient_light=np.array(list(scene.ambient)) if max(scene.ambient) > 0 else np.zeros(3),
                        bg_color=[0, 0, 0, 0])
    for i, o in enumerate(scene.objects):
        tm = displaced_mesh(scene, resolution, object=i)
        m = o.material
        if m.albedo is not None:
            from PIL import Image
            srgb = linear_to_srgb8(m.albedo)
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
    try:
        rend = pyrender.OffscreenRenderer(cam.width, cam.height)
    except Exception as first:
        if os.environ.get("PYOPENGL_PLATFORM") == "egl":
            # OSMesa cannot be tried once OpenGL is imported with EGL: report both remedies
            raise ReferenceRendererError(
                f"pyrender could not render headless with EGL ({first}). Install "
                "`libegl1 libegl-mesa0 libgl1-mesa-dri` (EGL) or `libosmesa6` and set "
                "PYOPENGL_PLATFORM=osmesa before importing pomkit.reference") from first
        raise
    try:
        flags = pyrender.RenderFlags.SHADOWS_DIRECTIONAL | pyrender.RenderFlags.RGBA
        color, zbuf = rend.render(ps, flags=flags)
    finally:
        rend.delete()
    lin = srgb_to_linear(np.ascontiguousarray(color[..., :3], np.uint8))
    # z-buffer depth -> distance along the ray
    rays = cam.rays()
    dist = np.where(zbuf > 0, zbuf / np.maximum((rays * f).sum(-1), 1e-9), 0.0).astype(np.float32)
    return lin, dist


# ---------------------------------------------------------------- Blender's Cycles

def blender_python() -> str:
    """The Python that runs Cycles: `$POMKIT_BLENDER_PYTHON`, else this interpreter if it
    imports `bpy`. bpy 5.0.1 (the `blender` extra's) is built for CPython 3.11 and wants numpy
    < 2, so it usually lives in a venv of its own: `scripts/setup.sh blender` makes
    `.venv-blender` and `make test` points `POMKIT_BLENDER_PYTHON` at it."""
    env = os.environ.get("POMKIT_BLENDER_PYTHON")
    if env:
        if not Path(env).exists():
            raise MissingExtraError(f"POMKIT_BLENDER_PYTHON: {env}: no such interpreter")
        return env
    import importlib.util

    if importlib.util.find_spec("bpy") is not None:
        return sys.executable
    raise MissingExtraError("render_cycles needs Blender as a module (bpy 5.0.1, CPython 3.11, numpy < 2): "
                            "make a venv with `pip install bpy==5.0.1` and set POMKIT_BLENDER_PYTHON to its python "
                            "(scripts/setup.sh blender makes .venv-blender)")


def render_cycles(scene: Scene, spp: int = 16, shadows: bool = True, dicing: float = 0.25, seed: int = 0,
                  cache: bool = True, timeout: float = 900.0) -> Frame:
    """Blender's Cycles (bpy 5.0.1) with true displacement: the independent reference whose
    displacement pomkit did not tessellate. One object, directional lights, constant ambient.

    The same arrays, map, camera, lights and material: a Displacement node (midlevel 1, scale =
    depth, object space) on the height map (linear, repeating) over a simple adaptive subdivision
    at `dicing` pixels, so S = P + depth (h - 1) N along the interpolated vertex normals; the
    mesh welded by position with per-corner uvs (a seam is one surface, pomkit's rule,
    docs/conventions.md). Cycles' adaptive subdivision displaces along vertex normals, not
    per-corner ones, so a hard edge's vertices stay split and its sides part there (pomkit welds
    them: docs/references.md measures the difference). `uv`, `depth` (distance from the eye) and `mask` come from one sample
    per pixel through a 0.01-pixel box filter (pixel centres, as `pk.oracle.hits`); `color` from
    `spp` samples of Cycles' path tracer with no bounces (direct light: a Diffuse BSDF, sun lights
    of the lights' irradiance and angular diameter, a constant world of `scene.ambient`), box
    filtered over the pixel like the oracle image. `shadows=False` turns the lights' and the
    world's shadows off. Monte Carlo: `seed` picks the sampling; `noise_floor` is None.

    Cached by scene hash like the other references. Runs in `blender_python()` (a subprocess)."""
    spp = _v.integer("spp", spp, 1, 1 << 16, strict=True)
    shadows = _v.boolean("shadows", shadows)
    dicing = float(dicing)
    if not (0.01 <= dicing <= 16.0):
        raise ArgumentError(f"dicing: the subdivision's micro-polygon size in pixels, from 0.01 to 16, got {dicing}")
    seed = _v.integer("seed", seed, 0, 2 ** 31 - 1, strict=True)
    if len(scene.objects) != 1 or not scene.objects[0].is_identity:
        raise ArgumentError("scene: render_cycles takes one untransformed object (bake the transform into the mesh)")
    if any(not isinstance(light, DirectionalLight) for light in scene.lights):
        raise ArgumentError("scene: render_cycles takes directional lights only (a sun in Cycles)")
    cam = scene.camera
    if getattr(cam, "window", None) is not None:
        raise ArgumentError("scene: render_cycles renders the whole camera (no window)")
    worker = Path(__file__).with_name("_cycles_worker.py")
    # the worker's own source is part of the key: a new worker renders anew
    source = hashlib.sha256(worker.read_bytes()).hexdigest()[:16]
    key = scene_hash(scene, kind="cycles", spp=spp, shadows=shadows, dicing=dicing, seed=seed, worker=source) if cache else ""

    def compute():
        o = scene.objects[0]
        m, mat = o.mesh, o.material
        a = dict(positions=m.positions, normals=m.normals, uvs=m.uvs, indices=m.indices,
                 height=np.asarray(mat.height, np.float32), depth=mat.depth, tiling=mat.tiling,
                 eye=np.asarray(cam.eye, np.float64), target=np.asarray(cam.target, np.float64),
                 up=np.asarray(cam.up, np.float64), fov_y=cam.fov_y, width=cam.width, height_px=cam.height,
                 ambient=scene.ambient, spp=spp, shadows=shadows, dicing=dicing, seed=seed,
                 lights=len(scene.lights))
        a["height"] = np.asarray(mat.height, np.float32)
        if mat.albedo is not None:
            a["albedo"] = np.asarray(mat.albedo, np.float32)
        for k, light in enumerate(scene.lights):
            a[f"light{k}_direction"] = np.asarray(light.direction, np.float64)
            a[f"light{k}_irradiance"] = np.asarray(light.power, np.float64)
            a[f"light{k}_angular_diameter"] = float(light.angular_diameter)
        t0 = time.perf_counter()
        with tempfile.TemporaryDirectory() as d:
            src, dst = os.path.join(d, "scene.npz"), os.path.join(d, "out.npz")
            np.savez(src, **a)
            env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
            try:
                p = subprocess.run([blender_python(), str(worker), src, dst], capture_output=True, text=True,
                                   timeout=timeout, env=env)
            except subprocess.TimeoutExpired:
                raise ReferenceRendererError(f"render_cycles: Cycles took longer than {timeout} s") from None
            if p.returncode != 0 or not os.path.exists(dst):
                raise ReferenceRendererError(f"render_cycles: Blender failed ({p.returncode}): {(p.stderr or p.stdout)[-2000:]}")
            with np.load(dst) as z:
                out = {k: z[k] for k in z.files}
        out["ms"] = np.array((time.perf_counter() - t0) * 1e3)
        return out

    a = cached("cycles", key, compute, use_cache=cache)
    return Frame(color=a["color"], uv=a["uv"], depth=a["depth"], mask=a["mask"],
                 object=np.where(a["mask"], 0, -1).astype(np.int32), wall_ms=float(a["ms"]), timing="wall",
                 noise_floor=None, method=f"cycles[{a['version']}] spp={spp} dicing={dicing} (took {float(a['ms']):.0f} ms: "
                 f"scene, geometry and colour {', '.join(f'{x:.1f}' for x in a['seconds'])} s)")
