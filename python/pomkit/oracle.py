"""The float64 oracle: ground truth for any scene, computed on the CPU with no mesh built.

    hits = pk.oracle.hits(scene)     # each pixel's exact first hit: uv, depth, mask, object, visibility
    ref = pk.oracle.image(scene)     # the noise-free image: the reference shading on exact hits

`pk.reference` holds the independent renderers (Mitsuba, pyrender) that check it."""

from __future__ import annotations

from ._errors import ArgumentTypeError
import time

import numpy as np

from . import _core
from . import _validate as _v
from ._cache import cached, scene_hash
from ._frame import Frame
from ._scene import Scene

__all__ = ["hits", "image"]

#: the shells (prisms, bounding volumes) the oracle keeps between calls in this process: the
#: latest four by mesh content and depth, so that a sweep over one asset builds its shell once
SHELLS = _core.Shells()

#: the rule of the walk the cached images were made by (part of the cache key: images made by an
#: earlier rule are not served): a camera ray's stretch ends below the field's lowest texel, 0 too
_WALK = "ends below the lowest texel"


def hits(scene: Scene, *, light_bias: float = 0.0) -> Frame:
    """The exact first hit of each pixel's ray with the displaced surface
    S = P + depth (h - 1) N, P and N interpolated over each base triangle (N normalised) as the
    tessellator and the shaders define them, on any scene. One untransformed planar object (a
    plane, a cube) takes the closed-form walk of each triangle's plane (extended under the hit,
    as the per-pixel methods take it); any other scene (curved meshes, atlases, several objects,
    transforms) the shell walk: the ray enters through the base mesh and walks prism to prism,
    across seams, and out through open borders, exact to 1e-4 texel (docs/oracle.md, "The
    oracle on any mesh"). No mesh is built, so any map size works.

    Returns a Frame with float64 uv and depth, the mask, `object` (the index hit, -1 none),
    `steps` = cells visited, and `visibility`: the exact visibility of the first directional
    light at the hit (the fraction of its disk, 64 directions when `angular_diameter` > 0, whose
    ray leaves the shell without passing below the field; NaN without a directional light). On
    a planar object, self-shadowing only; on the shell walk, every object occludes.
    `light_bias` (in shell depths) raises the light rays so that a blocker must rise more than
    it above the ray: 1e-4 is the GPU's `shadows="exact"`; where the two oracles differ a
    blocker grazes the ray within that tolerance."""
    if not isinstance(scene, Scene):
        raise ArgumentTypeError(f"scene: expected a pomkit.Scene, got {type(scene).__name__}")
    d = _core.oracle_hits(scene, float(light_bias), SHELLS)
    vis = d["visibility"].astype(np.float32)
    return Frame(uv=d["uv"], depth=d["depth"], mask=d["mask"], steps=d["cells"], visibility=vis, object=d["object"],
                 method="oracle.hits")


def image(scene: Scene, spp: int = 16, shadows: bool = True, cache: bool = True) -> Frame:
    """The noise-free reference image, shaded with the reference shading of docs/conventions.md
    (the normal from central differences of the bilinear field at level 0, the albedo bilinear
    at level 0, each light times the fraction of 64 stratified directions over its disk that
    leave the shell, ambient times the fraction of 64 cosine-weighted directions that do).

    Every sample's hit is the float64 oracle's (`hits`), with no mesh built, at any map
    size: the shell walk on every scene (planes, curved meshes, atlases, several objects,
    transforms), exact to 1e-4 texel, whose light rays meet every object as in the world.
    `render_mitsuba(integrator="cast")` is the independent check: the same shading on Mitsuba's
    ray casts against the displaced mesh.

    `spp` samples per pixel on the grid of `render(spp=)` (a square, 1 to 256), colour
    box-filtered (a miss is black) and `coverage` the fraction that hit; uv, depth, mask,
    visibility (the first directional light's, at the pixel centre) and object are at the pixel
    centre. Deterministic, so `noise_floor` is 0.0. Cached on disk by the scene's hash.
    `Frame.wall_ms` is the time the render took (stored with it in the cache). `shadows=False`
    traces no light or ambient rays (every light fully visible, ao = 1): the colour of the
    displacement alone, for methods measured without shadows (the bench, choose)."""
    if not isinstance(scene, Scene):
        raise ArgumentTypeError(f"scene: expected a pomkit.Scene, got {type(scene).__name__}")
    spp = _v.integer("spp", spp, 1, 256, strict=True)  # a square: the core's rule
    shadows = _v.boolean("shadows", shadows)
    # the hash reads every array of the scene: only when the cache is asked for
    key = scene_hash(scene, kind="oracle_image", spp=spp, shadows=shadows, walk=_WALK) if cache else ""

    def compute():
        t0 = time.perf_counter()
        d = _core.oracle_image(scene, spp, bool(shadows), SHELLS)  # with the pixel centres' hits
        return dict(color=d["color"], coverage=d["coverage"], uv=d["uv"].astype(np.float32),
                    depth=d["depth"].astype(np.float32), mask=d["mask"], visibility=d["visibility"].astype(np.float32),
                    object=d["object"], ms=np.array(1e3 * (time.perf_counter() - t0)))

    a = cached("oracle_image", key, compute, use_cache=cache)
    arrays = {k: a[k] for k in ("color", "coverage", "uv", "depth", "mask", "visibility", "object")}
    return Frame(method=f"oracle.image spp={spp}{'' if shadows else ' unshadowed'} (took {float(a['ms']):.0f} ms)", wall_ms=float(a["ms"]), timing="wall",
                 noise_floor=0.0, **arrays)
