"""Ground truth: the displaced mesh, Mitsuba 3 and pyrender renders of it.

These need the `reference` extra: `pip install pomkit[reference]` (mitsuba, trimesh,
flip-evaluator, scikit-image, pyrender). Results are cached on disk (see `pomkit._cache`).
"""

from __future__ import annotations

from typing import Any

import glob
import math
import os
import time

import numpy as np

from . import _core
from . import _validate as _v
from ._cache import cached, scene_hash
from ._frame import Frame
from ._scene import DirectionalLight, Material, Scene, SphereLight

__all__ = ["displaced_mesh", "render_mitsuba", "render_pyrender", "mitsuba_variant"]

_EXTRA = "pip install pomkit[reference]"


def _require(module: str):
    try:
        return __import__(module)
    except ImportError as e:
        raise ImportError(f"{module} is needed for references: {_EXTRA} ({e})") from None


def displaced_arrays(scene: Scene, resolution: float = 2.0, object: int = 0) -> dict:
    """positions, normals, uvs, faces of object `object`'s displaced surface in world space (its
    transform applied; normals by the inverse transpose); `resolution` vertices per texel."""
    if not isinstance(scene, Scene):
        raise TypeError(f"scene: expected a pomkit.Scene, got {type(scene).__name__}")
    resolution = _v.number("resolution", resolution, 1 / 1024, 64)  # vertices per texel
    object = _v.integer("object", object, 0, len(scene.objects) - 1, strict=True)
    t = _core.tessellate(scene._describe(), 1.0 / float(resolution), int(object))
    a = {"positions": t["positions"], "normals": t["normals"], "uvs": t["uvs"], "faces": t["faces"]}
    o = scene.objects[int(object)]
    if not o.is_identity:
        m = o.transform
        a["positions"] = (a["positions"] @ m[:3, :3].T + m[:3, 3]).astype(np.float32)
        n = a["normals"] @ np.linalg.inv(m[:3, :3])  # (M^-T n) as rows
        a["normals"] = (n / np.linalg.norm(n, axis=1, keepdims=True)).astype(np.float32)
        if np.linalg.det(m[:3, :3]) < 0:
            a["faces"] = np.ascontiguousarray(a["faces"][:, ::-1])  # a mirror flips the winding
    return a


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


# ---------------------------------------------------------------- Mitsuba

_VARIANT = None


def _llvm_path() -> str | None:
    pats = ["/usr/lib/llvm-19/lib/libLLVM.so*", "/usr/lib/*/libLLVM-19.so*", "/usr/lib/*/libLLVM.so.19*"]
    for p in pats:
        hits = sorted(glob.glob(p))
        if hits:
            return hits[0]
    return None


def mitsuba_variant(variant: str | None = None) -> str:
    """Choose and set Mitsuba's variant: `llvm_ad_rgb` when it loads (it needs LLVM >= 16, on
    Debian `apt-get install libllvm19`; the project's set-up installs it), else `scalar_rgb`."""
    global _VARIANT
    if variant is None and _VARIANT is not None:
        return _VARIANT
    if "DRJIT_LIBLLVM_PATH" not in os.environ:
        p = _llvm_path()
        if p:
            os.environ["DRJIT_LIBLLVM_PATH"] = p
    mi = _require("mitsuba")
    tried = [variant] if variant else ["llvm_ad_rgb", "scalar_rgb"]
    errors = []
    for v in tried:
        if v == "llvm_ad_rgb" and "DRJIT_LIBLLVM_PATH" not in os.environ:
            errors.append("llvm_ad_rgb: no libLLVM >= 16 found (Debian: apt-get install libllvm19)")
            continue
        try:
            mi.set_variant(v)
            _VARIANT = v
            return v
        except Exception as e:  # pragma: no cover - depends on the machine
            errors.append(f"{v}: {e}")
    raise RuntimeError("no usable Mitsuba variant: " + "; ".join(errors))


def _mi_mesh(mi, arrays: dict, bsdf, name: str = "displaced"):
    props = mi.Properties()
    props["bsdf"] = bsdf
    n, f = len(arrays["positions"]), len(arrays["faces"])
    m = mi.Mesh(name, n, f, props=props, has_vertex_normals=True, has_vertex_texcoords=True)
    p = mi.traverse(m)
    p["vertex_positions"] = np.array(arrays["positions"], np.float32).ravel()
    p["vertex_normals"] = np.ascontiguousarray(arrays["normals"], np.float32).ravel()
    p["vertex_texcoords"] = np.ascontiguousarray(arrays["uvs"], np.float32).ravel()
    p["faces"] = np.ascontiguousarray(arrays["faces"], np.uint32).ravel()
    p.update()
    return m


def _look_at(mi, cam):
    return mi.ScalarTransform4f().look_at(origin=list(cam.eye), target=list(cam.target), up=list(cam.up))


def _scene_radius(scene: Scene) -> tuple[np.ndarray, float]:
    """The scene's bounding sphere, the core's (`Scene::bounding_sphere`: one home for it)."""
    c, r = _core.bounding_sphere(scene._describe())
    return np.asarray(c, np.float64), float(r)


def _emitters(mi, scene: Scene) -> dict:
    out = {}
    centre, radius = _scene_radius(scene)
    for i, l in enumerate(scene.lights):
        if isinstance(l, DirectionalLight):
            d = np.asarray(l.direction, float)
            d = d / np.linalg.norm(d)
            if l.angular_diameter <= 0:
                out[f"light{i}"] = {"type": "directional", "direction": d.tolist(),
                                    "irradiance": {"type": "rgb", "value": list(l.irradiance)}}
            else:
                # a distant disk source of the same angular diameter: a sphere far away whose
                # radiance gives the same irradiance on a surface facing it, E = L pi sin^2(a)
                a = math.radians(l.angular_diameter) / 2
                dist = 1000.0 * radius
                pos = centre - d * dist
                L = np.asarray(l.irradiance) / (math.pi * math.sin(a) ** 2)
                out[f"light{i}"] = {"type": "sphere", "center": pos.tolist(), "radius": dist * math.sin(a),
                                    "emitter": {"type": "area", "radiance": {"type": "rgb", "value": L.tolist()}}}
        elif isinstance(l, SphereLight):
            if l.radius <= 0:
                out[f"light{i}"] = {"type": "point", "position": list(l.position),
                                    "intensity": {"type": "rgb", "value": list(l.intensity)}}
            else:
                L = np.asarray(l.intensity) / (math.pi * l.radius ** 2)
                out[f"light{i}"] = {"type": "sphere", "center": list(l.position), "radius": l.radius,
                                    "emitter": {"type": "area", "radiance": {"type": "rgb", "value": L.tolist()}}}
    if max(scene.ambient) > 0:
        out["ambient"] = {"type": "constant", "radiance": {"type": "rgb", "value": list(scene.ambient)}}
    return out


def _bsdf(mi, m: Material):
    refl: dict[str, Any]
    if m.albedo is None:
        refl = {"type": "rgb", "value": [0.5, 0.5, 0.5]}
    else:
        refl = {"type": "bitmap", "bitmap": mi.Bitmap(np.array(m.albedo, np.float32, copy=True)), "raw": True,
                "filter_type": "bilinear", "wrap_mode": "repeat",
                "to_uv": mi.ScalarTransform3f().scale([m.tiling, m.tiling])}
    return mi.load_dict({"type": "diffuse", "reflectance": refl})


def render_exact(scene: Scene, spp: int = 16, shadows: bool = True, cache: bool = True) -> Frame:
    """The noise-free reference image of a planar scene: every sample's hit is the float64
    oracle's (`pk.exact_uv`), shaded in float64 with the reference shading of
    docs/conventions.md (the normal from central differences of the bilinear field at level 0,
    the albedo bilinear at level 0, each light times the fraction of 64 stratified directions
    over its disk that leave the shell, ambient times the fraction of 64 cosine-weighted
    directions that do). `spp` samples per pixel on the grid of `render(spp=)` (a square, 1 to
    256), colour box-filtered (a miss is black) and `coverage` the fraction that hit; uv, depth,
    mask, visibility (the first directional light's, at the pixel centre) and object (0 where
    hit, -1 elsewhere) are the oracle's at the pixel centre. Deterministic, so `noise_floor` is
    0.0; no mesh is built, so any map size the oracle walks works. Cached on disk by the scene's
    hash. Planar meshes of one untransformed object; a curved mesh raises a ValueError naming
    `render_mitsuba`. `Frame.wall_ms` is the time the render took (stored with it in the cache).
    `shadows=False` traces no light or ambient rays (every light fully visible, ao = 1): the
    colour of the displacement alone, for methods measured without shadows (the bench, choose)."""
    spp = _v.integer("spp", spp, 1, 256, strict=True)  # a square: the core's rule
    shadows = _v.boolean("shadows", shadows)
    # the hash reads every array of the scene: only when the cache is asked for
    key = scene_hash(scene, kind="exact", spp=spp, shadows=shadows) if cache else ""

    def compute():
        t0 = time.perf_counter()
        d = _core.render_exact(scene._describe(), spp, bool(shadows))
        o = _core.exact_uv(scene._describe(), 0.0)
        return dict(color=d["color"], coverage=d["coverage"], uv=o["uv"].astype(np.float32),
                    depth=o["depth"].astype(np.float32), mask=o["mask"], visibility=o["visibility"].astype(np.float32),
                    object=np.where(o["mask"], 0, -1).astype(np.int32), ms=np.array(1e3 * (time.perf_counter() - t0)))

    a = cached("exact", key, compute, use_cache=cache)
    arrays = {k: a[k] for k in ("color", "coverage", "uv", "depth", "mask", "visibility", "object")}
    return Frame(method=f"render_exact spp={spp}{'' if shadows else ' unshadowed'} (took {float(a['ms']):.0f} ms)", wall_ms=float(a["ms"]), timing="wall",
                 noise_floor=0.0, **arrays)


def render_mitsuba(scene: Scene, spp: int = 64, seed: int = 0, variant: str | None = None,
                   resolution: float = 2.0, cache: bool = True) -> Frame:
    """Mitsuba 3's render of the displaced mesh: colour from the `direct` integrator (`spp`
    samples, box filter) and pixel-centre `uv`, `depth` (distance along the ray), `mask` and
    `object` (the index in `scene.objects` of the nearest object, from each object's depth) from
    the `aov` integrator (a `stratified` sampler, one sample, no jitter). Every object is a
    mesh, so objects shadow each other as they do in the world. Same camera, emitters
    and Lambertian shading as pomkit; see docs/references.md for each convention's test.
    `Frame.wall_ms` is the time of the render (0 when it came from the cache)."""
    spp = _v.integer("spp", spp, 1, 1 << 20, strict=True)
    key = scene_hash(scene, kind="mitsuba", spp=spp, seed=seed, variant=variant, resolution=resolution)

    def compute():
        t0 = time.perf_counter()
        v = mitsuba_variant(variant)
        mi = _require("mitsuba")
        shapes = {f"object{i}": _mi_mesh(mi, displaced_arrays(scene, resolution, i), _bsdf(mi, o.material),
                                         f"object{i}")
                  for i, o in enumerate(scene.objects)}
        cam = scene.camera
        film = {"type": "hdrfilm", "width": cam.width, "height": cam.height, "rfilter": {"type": "box"},
                "pixel_format": "rgb", "component_format": "float32"}
        base = {"type": "scene", **shapes, **_emitters(mi, scene)}
        sensor = {"type": "perspective", "fov": cam.fov_y, "fov_axis": "y", "to_world": _look_at(mi, cam),
                  "near_clip": 1e-3, "far_clip": 1e5, "film": film}
        sc = mi.load_dict({**base, "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 1,
                                                          # pomkit's background is black: emitters
                                                          # seen directly (the constant ambient,
                                                          # sphere lights) are hidden
                                                          "hide_emitters": True},
                           "sensor": {**sensor, "sampler": {"type": "independent", "sample_count": spp}}})
        color = np.array(mi.render(sc, spp=spp, seed=seed), dtype=np.float32)[..., :3]
        aov_sensor = {**sensor, "sampler": {"type": "stratified", "sample_count": 1, "jitter": False}}
        sc2 = mi.load_dict({**base, "integrator": {"type": "aov", "aovs": "dd:depth,uv:uv"}, "sensor": aov_sensor})
        aov = np.array(mi.render(sc2, spp=1, seed=seed), dtype=np.float32)
        depth = aov[..., 0]
        mask = depth > 0
        uv = np.where(mask[..., None], aov[..., 1:3], np.nan).astype(np.float32)
        # the object each pixel sees: the nearest of the objects rendered one at a time
        # (Mitsuba's `shape_index` AOV holds registry ids, not indices into the scene)
        obj = np.where(mask, 0, -1).astype(np.int32)
        if len(shapes) > 1:
            ds = []
            for name in shapes:
                one = mi.load_dict({"type": "scene", name: shapes[name],
                                    "integrator": {"type": "aov", "aovs": "dd:depth"}, "sensor": aov_sensor})
                d = np.array(mi.render(one, spp=1, seed=seed), dtype=np.float32)[..., 0]
                ds.append(np.where(d > 0, d, np.inf))
            obj = np.where(mask, np.argmin(np.stack(ds), axis=0), -1).astype(np.int32)
        return dict(color=color, uv=uv, depth=np.where(mask, depth, np.nan).astype(np.float32), mask=mask,
                    object=obj, ms=np.array((time.perf_counter() - t0) * 1e3), variant=np.array(v))

    t0 = time.perf_counter()
    a = cached("mitsuba", key, compute, use_cache=cache)
    # references cached before `object` existed: one object, wherever the mask is
    obj = a["object"] if "object" in a else np.where(a["mask"], 0, -1).astype(np.int32)
    return Frame(color=a["color"], uv=a["uv"], depth=a["depth"], mask=a["mask"], object=obj, wall_ms=float(a["ms"]),
                 timing="wall", method=f"mitsuba[{a['variant']}] spp={spp} (took {float(a['ms']):.0f} ms, "
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
    key = scene_hash(scene, kind="pyrender", resolution=resolution)

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
                raise RuntimeError(
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
    from ._scene import srgb_to_linear

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
            ps.add(pyrender.DirectionalLight(color=np.ones(3), intensity=float(np.mean(l.irradiance))), pose=lp)
        else:
            lp = np.eye(4)
            lp[:3, 3] = l.position
            ps.add(pyrender.PointLight(color=np.ones(3), intensity=float(np.mean(l.intensity)) * 4 * math.pi), pose=lp)
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
