"""Mitsuba 3 for the references (`pk.reference.render_mitsuba`; the oracle, `pk.oracle.image`, is
pomkit's own and needs no Mitsuba): its variant, the displaced meshes as Mitsuba shapes, and two renders.

- `cast_render`: Mitsuba as the ray caster. Every sample's hit is Mitsuba's intersection with the
  displaced mesh; the hit is shaded with the reference shading of docs/conventions.md (the
  normal from `_core.reference_normals` at the hit's uv and base mesh's basis, Mitsuba's own albedo
  lookup and its emitters' directions and irradiance), and the light and ambient directions are
  exactly pk.oracle.image's sets (`_core.reference_directions`), each traced with Mitsuba's
  `ray_test`. Deterministic.
- `direct_render`: Mitsuba's `direct` integrator, Monte Carlo: its own light sampling and its
  interpolated vertex normals, the independent check of conventions with its own noise.
"""

from __future__ import annotations

from ._errors import ReferenceRendererError
from typing import Any

import glob
import math
import os

import numpy as np

from . import _core
from ._displaced import core_transform, displaced_arrays, require
from ._scene import DirectionalLight, Material, Scene, SphereLight

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
    mi = require("mitsuba")
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
    raise ReferenceRendererError("no usable Mitsuba variant: " + "; ".join(errors))


def _mi_mesh(mi, arrays: dict, bsdf, name: str = "displaced", object: int | None = None):
    """A Mitsuba mesh of the displaced arrays; with `object`, also the base mesh's basis as vertex
    attributes (`vertex_bn`, `vertex_tg`, `vertex_ts`: the tangent's sign and uv_scale) and the
    object's index (`vertex_object`) for `cast_render`."""
    props = mi.Properties()
    props["bsdf"] = bsdf
    n, f = len(arrays["positions"]), len(arrays["faces"])
    m = mi.Mesh(name, n, f, props=props, has_vertex_normals=True, has_vertex_texcoords=True)
    if object is not None:
        tg = np.asarray(arrays["tangents"], np.float32)
        m.add_attribute("vertex_bn", 3, _slack(arrays["base_normals"]))
        m.add_attribute("vertex_tg", 3, _slack(tg[:, :3]))
        m.add_attribute("vertex_ts", 3, _slack(np.c_[tg[:, 3], arrays["uv_scale"]]))
        m.add_attribute("vertex_object", 1, np.full(n, float(object), np.float32))
    p = mi.traverse(m)
    p["vertex_positions"] = _slack(arrays["positions"])
    p["vertex_normals"] = _slack(arrays["normals"])
    p["vertex_texcoords"] = _slack(arrays["uvs"])
    p["faces"] = _slack(arrays["faces"], np.uint32)
    p.update()
    return m


def _look_at(mi, cam):
    return mi.ScalarTransform4f().look_at(origin=list(cam.eye), target=list(cam.target), up=list(cam.up))


def _scene_radius(scene: Scene) -> tuple[np.ndarray, float]:
    """The scene's bounding sphere, the core's (`Scene::bounding_sphere`: one home for it)."""
    c, r = _core.bounding_sphere(scene)
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
                                    "irradiance": {"type": "rgb", "value": list(l.power)}}
            else:
                # a distant disk source of the same angular diameter: a sphere far away whose
                # radiance gives the same irradiance on a surface facing it, E = L pi sin^2(a)
                a = math.radians(l.angular_diameter) / 2
                dist = 1000.0 * radius
                pos = centre - d * dist
                L = np.asarray(l.power) / (math.pi * math.sin(a) ** 2)
                out[f"light{i}"] = {"type": "sphere", "center": pos.tolist(), "radius": dist * math.sin(a),
                                    "emitter": {"type": "area", "radiance": {"type": "rgb", "value": L.tolist()}}}
        elif isinstance(l, SphereLight):
            if l.radius <= 0:
                out[f"light{i}"] = {"type": "point", "position": list(l.position),
                                    "intensity": {"type": "rgb", "value": list(l.power)}}
            else:
                L = np.asarray(l.power) / (math.pi * l.radius ** 2)
                out[f"light{i}"] = {"type": "sphere", "center": list(l.position), "radius": l.radius,
                                    "emitter": {"type": "area", "radiance": {"type": "rgb", "value": L.tolist()}}}
    if max(scene.ambient) > 0:
        out["ambient"] = {"type": "constant", "radiance": {"type": "rgb", "value": list(scene.ambient)}}
    return out


#: the variants `pomkit_lambert` is registered in
_LAMBERT: set = set()


def _register_lambert(mi) -> None:
    """`pomkit_lambert`: Lambert's BSDF lit by max(0, N.L) whatever side of the shading normal the
    viewer is on (docs/conventions.md, "The displaced surface"). Mitsuba's `diffuse` returns 0
    where the shading normal faces away from the viewer (a vertex normal averaged across a thin
    part, on a front face), which pomkit's shading, engines and the oracle light."""
    if mi.variant() in _LAMBERT:
        return
    import drjit as dr

    class Lambert(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.refl = props.get_texture("reflectance")
            self.m_flags = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
            self.m_components = [self.m_flags]

        def sample(self, ctx, si, sample1, sample2, active=True):
            wo = mi.warp.square_to_cosine_hemisphere(sample2)
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = wo
            bs.pdf = mi.warp.square_to_cosine_hemisphere_pdf(wo)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.DiffuseReflection)
            bs.sampled_component = mi.UInt32(0)
            return bs, self.refl.eval(si, active) & (bs.pdf > 0)

        def eval(self, ctx, si, wo, active=True):
            return self.refl.eval(si, active) * dr.inv_pi * dr.maximum(mi.Frame3f.cos_theta(wo), 0.0)

        def pdf(self, ctx, si, wo, active=True):
            return mi.warp.square_to_cosine_hemisphere_pdf(wo)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def eval_diffuse_reflectance(self, si, active=True):
            return self.refl.eval(si, active)

        def to_string(self):
            return "PomkitLambert"

    mi.register_bsdf("pomkit_lambert", lambda props: Lambert(props))
    _LAMBERT.add(mi.variant())


def _bsdf(mi, m: Material, kind: str = "diffuse"):
    """The material's BSDF: Mitsuba's `diffuse`, or `pomkit_lambert` (lit from the shading
    normal's side whatever the viewer's, for the `direct` integrator)."""
    if kind == "pomkit_lambert":
        _register_lambert(mi)
    refl: dict[str, Any]
    if m.albedo is None:
        refl = {"type": "rgb", "value": [0.5, 0.5, 0.5]}
    else:
        refl = {"type": "bitmap", "bitmap": mi.Bitmap(np.array(m.albedo, np.float32, copy=True)), "raw": True,
                "filter_type": "bilinear", "wrap_mode": "repeat",
                "to_uv": mi.ScalarTransform3f().scale([m.tiling, m.tiling])}
    return mi.load_dict({"type": kind, "reflectance": refl})




def _sensor(mi, scene: Scene) -> dict:
    cam = scene.camera
    film = {"type": "hdrfilm", "width": cam.width, "height": cam.height, "rfilter": {"type": "box"},
            "pixel_format": "rgb", "component_format": "float32"}
    return {"type": "perspective", "fov": cam.fov_y, "fov_axis": "y", "to_world": _look_at(mi, cam),
            "near_clip": 1e-3, "far_clip": 1e5, "film": film}


def _shapes(mi, scene: Scene, resolution: float, frames: bool = False, bsdf: str = "diffuse") -> dict:
    return {f"object{i}": _mi_mesh(mi, displaced_arrays(scene, resolution, i), _bsdf(mi, o.material, bsdf), f"object{i}",
                                   i if frames else None)
            for i, o in enumerate(scene.objects)}


#: `resolution=None`: vertices per texel, and the most vertices an object's mesh gets from it.
AUTO_RESOLUTION, AUTO_VERTICES = 8.0, 1 << 21


def auto_resolution(scene: Scene, resolution: float | None) -> float:
    """`resolution`, or for None 8 vertices per texel (hits within about 0.002 texel of the
    bilinear field at 70° on the sharpest maps of the suite) lowered so that no object's mesh
    exceeds 2^21 vertices."""
    if resolution is not None:
        return float(resolution)
    # texels an object's mesh covers: the map times the tiling squared, per chart (a cube has 6)
    worst = max(o.material.height.shape[0] * o.material.height.shape[1] * float(o.material.tiling) ** 2
                * max(1, len(o.mesh.charts)) for o in scene.objects)
    # the fan adds a vertex at each lattice quad's centre: two vertices per lattice point
    return float(min(AUTO_RESOLUTION, max(1.0, math.sqrt(AUTO_VERTICES / (2.0 * worst)))))


def direct_render(scene: Scene, spp: int, seed: int, variant: str | None, resolution: float) -> dict:
    """Mitsuba's `direct` integrator (`spp` independent samples, box filter), and pixel-centre
    uv, depth, mask and object from its `aov` integrator."""
    v = mitsuba_variant(variant)
    mi = require("mitsuba")
    shapes = _shapes(mi, scene, auto_resolution(scene, resolution), bsdf="pomkit_lambert")
    sensor = _sensor(mi, scene)
    base = {"type": "scene", **shapes, **_emitters(mi, scene)}
    sc = mi.load_dict({**base, "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 1,
                                              # pomkit's background is black: emitters seen
                                              # directly (the constant ambient, sphere lights)
                                              # are hidden
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
                object=obj, variant=np.array(v))


# ---------------------------------------------------------------- Mitsuba as the ray caster

def _slack(a: np.ndarray, dtype=np.float32) -> np.ndarray:
    """`a` as a flat contiguous array whose buffer has 256 bytes to spare after its end. Twice
    in CI a Dr.Jit worker thread segfaulted in notebook 06 on a 64-byte (AVX-512) load that ran
    past the end of a buffer into an unmapped page; where an array handed to Mitsuba is read as
    it is, a vector read at its end then stays in memory the array owns."""
    a = np.asarray(a, dtype).ravel()
    buf = np.zeros(a.size + 256 // a.itemsize, dtype)
    buf[:a.size] = a
    return buf[:a.size]


def _vec(mi, cls, a: np.ndarray):
    a = np.asarray(a, np.float32)
    return cls(*[_slack(a[:, c]) for c in range(a.shape[1])])


def _np(x) -> np.ndarray:
    """A Dr.Jit array as numpy: (N,) or (N, C)."""
    a = np.array(x)
    return a.T if a.ndim == 2 and a.shape[0] in (2, 3) and a.shape[1] not in (2, 3) else a


def _delta_emitters(scene: Scene) -> dict:
    """Each light as Mitsuba's delta emitter: a directional light's direction and irradiance, a
    sphere light's centre and intensity. `cast_render` asks them for the direction to the light
    and the irradiance at a hit (`sample_direction`), and spreads its disk itself."""
    out = {}
    for i, l in enumerate(scene.lights):
        if isinstance(l, DirectionalLight):
            out[f"light{i:02d}"] = {"type": "directional", "direction": list(map(float, l.direction)),
                                    "irradiance": {"type": "rgb", "value": list(l.power)}}
        elif isinstance(l, SphereLight):
            out[f"light{i:02d}"] = {"type": "point", "position": list(l.position),
                                    "intensity": {"type": "rgb", "value": list(l.power)}}
    return out


#: back faces a camera ray passes through before its hit (an open mesh seen into: its inside)
_BACK_FACES = 8
#: what the caster's camera rays see (part of reference.py's cache key)
CAST_FACES = "front faces"


class _Caster:
    """One Mitsuba scene of the displaced meshes, cast against in batches."""

    def __init__(self, mi, scene: Scene, resolution: float):
        self.mi, self.scene = mi, scene
        self.sc = mi.load_dict({"type": "scene", **_shapes(mi, scene, resolution, frames=True),
                                **_delta_emitters(scene), "sensor": _sensor(mi, scene)})
        # the emitters in the order of scene.lights (Mitsuba sorts a dict's keys)
        self.emitters = list(self.sc.emitters())
        self.eye = np.asarray(scene.camera.eye, np.float64)

    def hits(self, fx: np.ndarray, fy: np.ndarray) -> dict:
        """Cast the camera rays through film positions (fx, fy) in [0, 1]² (x right, y down)."""
        mi = self.mi
        sensor = self.sc.sensors()[0]
        ray, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(_slack(fx), _slack(fy)),
                                   mi.Point2f(0.5, 0.5))
        si = self.sc.ray_intersect(ray)
        # a back face shows nothing (the oracle's rule: a ray enters the shell through its top,
        # docs/conventions.md): a ray that meets a face of the displaced mesh from behind (an open
        # mesh seen into) goes on through it. (The base normal is not asked: at a curved mesh's
        # silhouette it turns away where the displaced faces still face the viewer.)
        import drjit as dr
        for _ in range(_BACK_FACES):
            back = si.is_valid() & (dr.dot(si.n, ray.d) > 0)
            if not dr.any(back):
                break
            si = dr.select(back, self.sc.ray_intersect(si.spawn_ray(ray.d)), si)
        valid = np.array(si.is_valid(), bool)
        p_hit = _np(si.p).astype(np.float64)
        origin = _np(ray.o).astype(np.float64).reshape(-1, 3)
        t_hit = np.where(valid, np.linalg.norm(p_hit - origin, axis=-1), np.array(si.t, np.float64))
        out: dict[str, Any] = {"si": si, "valid": valid, "t": t_hit,
                               "p": _np(si.p).astype(np.float64), "ng": _np(si.n).astype(np.float64),
                               "uv": _np(si.uv).astype(np.float64)}
        shape = si.shape
        out["object"] = np.where(valid, np.rint(np.array(shape.eval_attribute_1("vertex_object", si))), -1).astype(np.int32)
        bn = _np(shape.eval_attribute_3("vertex_bn", si)).astype(np.float64)
        tg = _np(shape.eval_attribute_3("vertex_tg", si)).astype(np.float64)
        ts = _np(shape.eval_attribute_3("vertex_ts", si)).astype(np.float64)
        normals = np.zeros((len(valid), 3))
        for i, o in enumerate(self.scene.objects):
            sel = valid & (out["object"] == i)
            if not sel.any():
                continue
            n = _core.reference_normals(self.scene, i, np.ascontiguousarray(out["uv"][sel]),
                                        np.ascontiguousarray(bn[sel]), np.ascontiguousarray(np.c_[tg[sel], ts[sel, 0]]),
                                        np.ascontiguousarray(ts[sel, 1:]))
            if not o.is_identity:
                n = n @ np.linalg.inv(core_transform(o)[:3, :3])
                n /= np.linalg.norm(n, axis=1, keepdims=True)
            normals[sel] = n
        out["n"] = normals
        out["albedo"] = np.where(valid[:, None], _np(si.bsdf().eval_diffuse_reflectance(si)).astype(np.float64), 0.0)
        return out

    def lights(self, h: dict) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """Per light: (direction to it, irradiance E, tan of its disk's angular radius, distance)
        at each hit, from Mitsuba's emitter."""
        mi = self.mi
        out = []
        for l, em in zip(self.scene.lights, self.emitters):
            ds, spec = em.sample_direction(h["si"], mi.Point2f(0.5, 0.5))
            m = len(h["valid"])  # a directional emitter's answers come as one value: broadcast
            d = np.broadcast_to(_np(ds.d).astype(np.float64).reshape(-1, 3), (m, 3)).copy()
            e = np.broadcast_to(_np(spec).astype(np.float64).reshape(-1, 3), (m, 3)).copy()
            dist = np.broadcast_to(np.array(ds.dist, np.float64).reshape(-1), (m,)).copy()
            if isinstance(l, DirectionalLight):
                tan_r = np.full(len(d), math.tan(math.radians(l.angular_diameter) / 2))
            else:
                r2 = np.maximum(dist * dist, 1e-24)
                tan_r = l.radius / np.sqrt(np.maximum(r2 - l.radius ** 2, 1e-24))
            out.append((d, e, tan_r, dist))
        return out

    def escapes(self, p: np.ndarray, ng: np.ndarray, d: np.ndarray, maxt: np.ndarray | None = None) -> np.ndarray:
        """Whether rays from hits p (geometric normals ng) along d reach maxt (infinity if None)
        unblocked; the origin is offset off the surface as Mitsuba's `spawn_ray` offsets it."""
        mi = self.mi
        # a tenth of Mitsuba's RayEpsilon (2^-24 * 1500, what its spawn_ray offsets by): shadows
        # on a displaced mesh under a grazing light are that sensitive (terrain at a 19° light:
        # FLIP 0.0067 from pk.oracle.image at Mitsuba's own epsilon, 0.0024 at a tenth, 0.0021 at
        # a hundredth)
        eps = 2.0 ** -24 * 150
        side = np.where((ng * d).sum(1) >= 0, 1.0, -1.0)[:, None]
        o = p + ng * side * ((1 + np.abs(p).max(1, keepdims=True)) * eps)
        ray = mi.Ray3f(_vec(mi, mi.Point3f, o), _vec(mi, mi.Vector3f, d))
        if maxt is not None:
            ray.maxt = mi.Float(_slack(maxt * (1 - 1e-4)))
        return ~np.array(self.sc.ray_test(ray), bool)


def _fraction(caster: _Caster, h: dict, sel: np.ndarray, axes: np.ndarray, tan_r: np.ndarray, q: np.ndarray,
              n: int, maxt: np.ndarray | None = None) -> np.ndarray:
    """The fraction of each selected hit's share of a direction set that escapes."""
    idx = np.flatnonzero(sel)
    out = np.ones(len(sel))
    if not len(idx):
        return out
    dirs, owner = _core.reference_directions(np.ascontiguousarray(axes[idx]), np.ascontiguousarray(tan_r[idx]),
                                             np.ascontiguousarray(q[idx], dtype=np.uint32), int(n))
    owner = owner.astype(np.int64)
    free = caster.escapes(h["p"][idx][owner], h["ng"][idx][owner], dirs,
                          None if maxt is None else maxt[idx][owner])
    out[idx] = np.bincount(owner, free, len(idx)) / np.maximum(np.bincount(owner, None, len(idx)), 1)
    return out


def _shade(caster: _Caster, scene: Scene, h: dict, q: np.ndarray, n: int, shadows: bool,
           ambient_rays: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """The reference shading of hits `h` (sample q of n each); returns (colour, the first
    directional light's visibility, NaN where it does not apply). `ambient_rays=False` leaves
    out the ambient occlusion rays (ao = 1), for a pass that wants the visibility alone."""
    valid, nrm = h["valid"], h["n"]
    direct = np.zeros((len(valid), 3))
    vis0 = np.full(len(valid), np.nan)
    first = next((i for i, l in enumerate(scene.lights) if isinstance(l, DirectionalLight)), None)
    for i, (d, e, tan_r, dist) in enumerate(caster.lights(h)):
        ndl = (nrm * d).sum(1)
        lit = valid & (ndl > 0)
        vis = np.ones(len(valid))
        if shadows:
            far = None if isinstance(scene.lights[i], DirectionalLight) else dist - scene.lights[i].radius
            vis = _fraction(caster, h, lit, d, tan_r, q, n, far)
        direct += e * np.where(lit, ndl * vis, 0.0)[:, None]
        if i == first:
            vis0 = np.where(lit, vis, np.nan)
    ambient = np.asarray(scene.ambient, np.float64)
    ao = np.ones(len(valid))
    if shadows and ambient_rays and ambient.max() > 0:
        ao = _fraction(caster, h, valid, nrm, np.full(len(valid), -1.0), q, n)
    alb = h["albedo"]
    color = np.where(valid[:, None], alb / math.pi * direct + alb * ambient * ao[:, None], 0.0)
    return color, vis0


def cast_render(scene: Scene, spp: int, variant: str | None, resolution: float | None, shadows: bool = True,
                rows_per_batch: int | None = None) -> dict:
    """The reference shading on Mitsuba's hits: k x k samples per pixel on the grid of
    `render(spp=)` (the pixel centres of a k-times finer camera, as pk.oracle.image), colour their mean, and pixel-centre uv, depth, mask, object and
    visibility. See the module's doc."""
    v = mitsuba_variant(variant)
    if not v.startswith(("llvm", "cuda")):
        raise ReferenceRendererError(f"the matched render casts rays in batches, which needs a JIT variant of Mitsuba (llvm_ad_rgb: "
                           f"Debian's libllvm19), not {v}; or use integrator='direct'")
    mi = require("mitsuba")
    resolution = auto_resolution(scene, resolution)
    k = math.isqrt(spp)
    n = k * k
    caster = _Caster(mi, scene, resolution)
    cam = scene.camera
    w, hgt = cam.width, cam.height
    color = np.zeros((hgt, w, 3), np.float32)
    coverage = np.zeros((hgt, w), np.float32)
    batch = rows_per_batch or max(1, (1 << 19) // max(1, w * n))
    for r0 in range(0, hgt, batch):
        rows = np.arange(r0, min(hgt, r0 + batch))
        ii, jj, qq = np.meshgrid(rows, np.arange(w), np.arange(n), indexing="ij")
        fx = (jj * k + qq % k + 0.5) / (w * k)
        fy = (ii * k + qq // k + 0.5) / (hgt * k)
        h = caster.hits(fx.ravel(), fy.ravel())
        c, _ = _shade(caster, scene, h, qq.ravel(), n, shadows)
        color[rows] = c.reshape(len(rows), w, n, 3).mean(2)
        coverage[rows] = h["valid"].reshape(len(rows), w, n).mean(2)
    # the pixel centres: uv, depth, mask, object, and the first light's visibility over its disk
    px, py = np.meshgrid(np.arange(w), np.arange(hgt))
    h = caster.hits(((px + 0.5) / w).ravel(), ((py + 0.5) / hgt).ravel())
    _, vis = _shade(caster, scene, h, np.zeros(w * hgt, np.uint32), 1, shadows, ambient_rays=False)
    mask = h["valid"].reshape(hgt, w)
    uv = np.where(mask[..., None], h["uv"].reshape(hgt, w, 2), np.nan).astype(np.float32)
    return dict(color=color, coverage=coverage, uv=uv, depth=np.where(mask, h["t"].reshape(hgt, w), np.nan).astype(np.float32),
                mask=mask, object=h["object"].reshape(hgt, w), visibility=vis.reshape(hgt, w).astype(np.float32),
                variant=np.array(v))
