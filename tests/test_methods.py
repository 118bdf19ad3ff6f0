"""The methods of the field: analytic cases, the max-mip traversal, shadows, AO, dynamic height
fields, and stability where methods fail (grazing angles, spikes)."""


import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene, raster_floor
from test_analytic import analytic_plane_hits

W = 64


def err_texels(f, o, scene):
    return pk.metrics.uv_error(f, o, scene)


@pytest.mark.parametrize("theta", [30.0, 60.0])
def test_parallax_is_exact_on_constant_heights(renderer, theta):
    # s += (1 - h) * P with P the exact parallax vector: exact on a constant map; with offset
    # limiting the shift is multiplied by N.V (cos theta at the centre of the view).
    c = 0.3
    scene = plane_scene(pk.textures.constant(W, c), depth=0.1, theta_deg=theta, size=64)
    uv, _, inside = analytic_plane_hits(scene, c)
    f = renderer.render(scene, pk.Parallax(offset_limiting=False))
    m = inside & f.mask
    assert np.abs(f.uv[m] - uv[m]).max() * W < 0.05
    flat = renderer.render(scene, pk.Flat())
    g = renderer.render(scene, pk.Parallax(offset_limiting=True))
    ratio = np.linalg.norm(g.uv[m] - flat.uv[m], axis=-1) / np.linalg.norm(f.uv[m] - flat.uv[m], axis=-1)
    cos = -scene.camera.rays()[..., 1][m]  # N.V per pixel (plane normal +Y)
    assert np.allclose(ratio, cos, atol=1e-3)


def test_steep_parallax_stair_steps(renderer):
    # a constant height between two layers: the first sample below the surface is one layer
    # below it, so the hit sinks to the next layer (h = 0.5 with 4 steps for c = 0.6)
    c, steps = 0.6, 4
    scene = plane_scene(pk.textures.constant(W, c), depth=0.1, theta_deg=45, size=48)
    f = renderer.render(scene, pk.SteepParallax(steps=steps))
    uv_layer, _, inside = analytic_plane_hits(scene, 0.5)
    m = inside & f.mask
    assert np.abs(f.uv[m] - uv_layer[m]).max() * W < 0.05
    # and each pixel took entry sample + 2 layers (1.0 -> 0.75 -> 0.5)
    assert set(np.unique(f.steps[m])) == {3}


def test_pom_fixed_profile_counts(renderer):
    # Brawley & Tatarchuk 2004's fixed 8-sample profile: adaptive=False, 8 layers; on a floor at
    # h = 0 every ray takes the entry sample and all 8 layers, whatever the angle
    for theta in (0.0, 70.0):
        scene = plane_scene(pk.textures.constant(W, 0.0), theta_deg=theta, size=32)
        f = renderer.render(scene, pk.POM(adaptive=False, min_steps=8, max_steps=8, shadows="none", lod_threshold=100))
        assert set(np.unique(f.steps[f.mask])) == {9}
    # adaptive: n = n_max + (N.V)(n_min - n_max): more samples at grazing angles
    a = renderer.render(plane_scene(pk.textures.constant(W, 0.0), theta_deg=0.0, size=32), pk.POM(shadows="none", lod_threshold=100))
    b = renderer.render(plane_scene(pk.textures.constant(W, 0.0), theta_deg=75.0, size=32), pk.POM(shadows="none", lod_threshold=100))
    # head-on (rays within 21 degrees of the normal): n <= 50 - 42 cos(21) + 1 entry sample = 12
    assert a.steps[a.mask].max() <= 12 and b.steps[b.mask].mean() > 30


def test_relief_against_pom_at_80_degrees(renderer):
    # Equal sample budgets N on pyramids at 80 degrees, level-0 sampling: POM with N fixed layers
    # against Relief with N - 5 linear steps + 5 bisections, under both filterings. Measured
    # (llvmpipe): p95 POM 0.662 vs Relief 0.197 texels at N = 16, 0.101 vs 0.067 at N = 32;
    # POM's p50 is 0 (its refinement is exact on planar facets), Relief's is not; at N = 8
    # relief's 3 linear steps miss features (p95 23). Hardware and exact filtering agree to the
    # last digit here: lavapipe filters with float weights, so Tatarchuk's 8-bit-weight
    # explanation of relief's stair-stepping cannot show on this adapter.
    scene = plane_scene(pk.textures.pyramids(256, 8), depth=0.08, theta_deg=80, size=128, dist=1.6, fov=40)
    o = pk.oracle.hits(scene)
    res = {}
    for filt in ("hardware", "exact"):
        for n in (16, 32):
            pom = pk.POM(min_steps=n, max_steps=n, adaptive=False, shadows="none", lod_threshold=100, mip_filtering=False, filtering=filt)
            rel = pk.Relief(linear_steps=n - 5, binary_steps=5, mip_filtering=False, filtering=filt)
            res[filt, n] = (err_texels(renderer.render(scene, pom), o, scene), err_texels(renderer.render(scene, rel), o, scene))
    for n in (16, 32):
        pom, rel = res["exact", n]
        assert rel["p95"] < pom["p95"], (n, pom["p95"], rel["p95"])
        assert pom["p50"] < rel["p50"]
    if "llvmpipe" in renderer.info["name"]:
        for n in (16, 32):
            assert abs(res["hardware", n][0]["p95"] - res["exact", n][0]["p95"]) < 1e-3


TEXTURES = sorted(pk.textures.ALL)


@pytest.mark.parametrize("tex", TEXTURES)
@pytest.mark.parametrize("method", [pk.Exact(), pk.ConeStep()], ids=["Exact", "ConeStep"])
def test_safe_methods_match_the_oracle_up_to_88_degrees(renderer, tex, method):
    # Exact: the max-mip traversal with the exact patch intersection (measured: p99 <= 0.002
    # texel on 256^2 maps). ConeStep's default: conservative cones only skip empty space and
    # every cell the walk enters is intersected exactly (measured: p99 <= 0.001 on 128^2 maps).
    # p99 <= 0.1 texel at every angle up to 88 degrees on every map, no ray at its bound.
    assert method.safety == "safe"
    h = pk.textures.ALL[tex](128)
    for theta in (0.0, 30.0, 60.0, 80.0, 85.0, 88.0):
        scene = plane_scene(h, depth=0.08, theta_deg=theta, size=64, dist=1.6, fov=40)
        f = renderer.render(scene, method)
        e = err_texels(f, pk.oracle.hits(scene), scene)
        assert e["p99"] <= 0.1, (tex, theta, e["p99"])
        assert not (f.flags[f.mask] & 1).any()


def test_exact_flags_rays_that_hit_the_iteration_bound(renderer):
    scene = plane_scene(pk.textures.spikes(128), theta_deg=80, size=48)
    f = renderer.render(scene, pk.Exact(max_iterations=3))
    assert (f.flags[f.mask] & 1).mean() > 0.5
    assert f.steps[f.mask].max() <= 3 + 0  # view-ray iterations only (no shadows)


def wall():
    n = 128
    h = np.zeros((n, n), np.float32)
    h[:, int(0.45 * n):int(0.5 * n)] = 1.0
    return pk.Scene(
        mesh=pk.Mesh.plane(2.0), material=pk.Material(h, depth=0.2),
        camera=pk.Camera.look_at(eye=(0.0, 3.0, 0.0), target=(0, 0, 0), up=(0, 0, -1), fov_y=40.0, width=128, height=128),
        lights=[pk.DirectionalLight((1.0, -0.5, 0.0), 2.0)])


@pytest.mark.parametrize("method", [pk.POM(shadows="horizon", lod_threshold=100, mip_filtering=False),
                                    pk.Relief(shadows="horizon", mip_filtering=False),
                                    pk.Exact(shadows="exact"), pk.Exact(shadows="horizon")])
def test_shadow_kinds_behind_the_wall(renderer, method):
    f = renderer.render(wall(), method)
    u = f.uv[..., 0]
    lum = f.color.mean(-1)
    # the shadow spans u in [0.5, 0.7). The horizon estimate samples at 2^k texels with the
    # max of a 2^k footprint placed at the nominal distance, which shortens far shadows (here
    # lit from u = 0.64 on): it is tested on the near part only; exact shadows on all of it.
    end = 0.65 if method.shadows == "exact" else 0.6
    behind = f.mask & (u > 0.52) & (u < end)
    front = f.mask & (u > 0.25) & (u < 0.43)
    far = f.mask & (u > 0.8) & (u < 0.95)
    assert lum[behind].max() < 1e-6, method
    assert lum[front].min() > 0.1 and lum[far].min() > 0.1, method


@pytest.mark.reference
def test_ambient_occlusion_against_mitsuba():
    pytest.importorskip("mitsuba")
    # ambient light only (Mitsuba: a constant environment with the direct integrator, the AO
    # ground truth). Horizon AO over 8 rotated directions must bring pomkit closer to it than no
    # AO. Measured (llvmpipe): FLIP 0.339 without AO, 0.237 with 4 and 0.236 with 8 directions
    # (the remaining error: the horizon estimate is taken around the base tangent plane, not the
    # shading normal, and Mitsuba keeps some Monte Carlo noise at 256 spp).
    scene = plane_scene(pk.textures.cobblestones(128, cells=6), depth=0.1, theta_deg=40, size=96, dist=1.6, fov=40,
                        ambient=1.0)
    ref = pk.reference.render_mitsuba(scene, spp=256)
    r = pk.Renderer()
    fl = {n: pk.metrics.flip(r.render(scene, pk.Exact(ao_directions=n)), ref) for n in (0, 4, 8)}
    assert fl[8] < fl[0] and fl[4] < fl[0], fl


def bump_map(n, cx):
    u, v = np.meshgrid((np.arange(n) + 0.5) / n, (np.arange(n) + 0.5) / n)
    return (0.2 + 0.8 * np.exp(-((u - cx) ** 2 + (v - 0.5) ** 2) / 0.01)).astype(np.float32)


def test_dynamic_height_field(renderer):
    # a bump moving across the map, 10 frames: each frame's map is written into the same GPU
    # texture and its pyramids rebuilt by compute passes; Exact must match the oracle each time
    scene = plane_scene(bump_map(128, 0.3), depth=0.1, theta_deg=60, size=64)
    renderer.render(scene, pk.Exact())
    mat = scene.material
    for i in range(10):
        mat = renderer.update_height(mat, bump_map(128, 0.3 + 0.04 * i))
        s = scene.replace(material=mat)
        f = renderer.render(s, pk.Exact())
        e = err_texels(f, pk.oracle.hits(s), s)
        assert e["p99"] < 0.1, (i, e["p99"])
    with pytest.raises(ValueError, match="height"):
        renderer.update_height(mat, np.full((4, 4), np.nan, np.float32))


# ---- stability: every method, every map, view angles up to 89.5 degrees ----

ANGLES = [0.0, 30.0, 60.0, 80.0, 85.0, 89.5]
METHODS = [pk.Flat(), pk.Bump(), pk.Parallax(), pk.SteepParallax(), pk.POM(), pk.Relief(), pk.Exact(),
           pk.POM(shadows="horizon", ao_directions=4), pk.Tessellated(), pk.NCS(), pk.Prism()]


def grazing_scene(h, theta):
    # a large plane filling the lower image, camera 0.5 above it: at 89.5 degrees rays skim it
    t = np.radians(theta)
    return pk.Scene(mesh=pk.Mesh.plane(40.0), material=pk.Material(h, depth=0.05, tiling=20.0),
                    camera=pk.Camera.look_at(eye=(0.0, 0.5 * np.cos(t), 0.5 * np.sin(t)), target=(0, 0, 0),
                                             up=(0, 0, -1) if theta < 1 else (0, 1, 0), fov_y=30.0, width=48, height=48),
                    lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 2.0, 1.0)], ambient=0.1)


@pytest.mark.slow
@pytest.mark.parametrize("tex", TEXTURES)
def test_stability_no_nan_and_full_coverage(renderer, tex):
    h = pk.textures.ALL[tex](64)
    for theta in ANGLES:
        scene = grazing_scene(h, theta)
        flat = renderer.render(scene, pk.Flat())
        for m in METHODS:
            f = renderer.render(scene, m)
            for name in ("color", "uv", "depth", "lod"):
                a = getattr(f, name)[f.mask]
                assert np.isfinite(a).all(), (tex, theta, m, name)
            if not isinstance(m, (pk.Tessellated, pk.NCS, pk.Prism)):
                # the per-pixel methods on the base mesh cover exactly the rasterised plane
                assert np.array_equal(f.mask, flat.mask), (tex, theta, m)


@pytest.mark.parametrize("tex", ["bricks", "spikes", "noise"])
@pytest.mark.parametrize("theta", [30.0, 60.0, 80.0])
def test_stability_error_falls_as_steps_rise(renderer, tex, theta):
    # level-0 sampling isolates the search from prefiltering; "within noise": each doubling may
    # not raise p95 by more than 0.05 texel
    scene = plane_scene(pk.textures.ALL[tex](128), depth=0.08, theta_deg=theta, size=64, dist=1.6, fov=40)
    o = pk.oracle.hits(scene)
    for make in (lambda n: pk.POM(min_steps=n, max_steps=n, shadows="none", lod_threshold=100, mip_filtering=False),
                 lambda n: pk.SteepParallax(steps=n, mip_filtering=False),
                 lambda n: pk.Relief(linear_steps=n, binary_steps=5, mip_filtering=False)):
        p95 = [err_texels(renderer.render(scene, make(n)), o, scene)["p95"] for n in (8, 16, 32, 64, 128)]
        assert all(b <= a + 0.05 for a, b in zip(p95, p95[1:])), (tex, theta, make(8).name, p95)
        assert p95[-1] < p95[0] or p95[0] < 0.01


@pytest.mark.parametrize("tex", ["noise", "sine", "bricks"])
def test_relaxed_cones_with_binary_refinement_converge(renderer, tex):
    # relaxed cones step into the surface; the bisection between the last point above and the
    # first below halves the error with every step, down to the oracle, or to the rasterizer's
    # floor (conftest.raster_floor: about 0.0015 texel here on an H200, where p50 then wanders
    # by 3e-4). With filtering="exact" (float32 lerps); the sampler's filter ("hardware") weighs
    # texels in fixed point (8 fractional bits on D3D11-class GPUs), so its bisection need only
    # reach 0.01 texel.
    scene = plane_scene(pk.textures.ALL[tex](128), depth=0.08, theta_deg=50.0, size=64, dist=1.6, fov=40)
    oracle = pk.oracle.hits(scene)
    p50 = []
    for n in (0, 2, 4, 8, 16):
        f = renderer.render(scene, pk.ConeStep(cones="relaxed", refine="binary", binary_steps=n, filtering="exact"))
        p50.append(err_texels(f, oracle, scene)["p50"])
    slack = max(1e-4, raster_floor(oracle, scene))
    assert all(b <= a + slack for a, b in zip(p50, p50[1:])), (p50, slack)
    assert p50[-1] <= 0.01 and p50[0] > 4 * p50[-1], p50
    hw = err_texels(renderer.render(scene, pk.ConeStep(cones="relaxed", refine="binary", binary_steps=16)), oracle, scene)
    assert hw["p50"] <= 0.01, hw


def test_cone_map_follows_update_height(renderer):
    # update_height rebuilds the cone map: the frame of the new map equals a fresh renderer's
    a, b = pk.textures.bricks(64), pk.textures.spikes(64)
    scene = plane_scene(a, depth=0.1, theta_deg=70.0, size=48)
    renderer.render(scene, pk.ConeStep())
    new = renderer.update_height(scene.material, b)
    moved = renderer.render(scene.replace(material=new), pk.ConeStep(), aovs=("uv", "mask"))
    fresh = pk.Renderer().render(plane_scene(b, depth=0.1, theta_deg=70.0, size=48), pk.ConeStep(), aovs=("uv", "mask"))
    assert np.array_equal(moved.uv, fresh.uv, equal_nan=True) and np.array_equal(moved.mask, fresh.mask)
    e = err_texels(moved, pk.oracle.hits(scene.replace(material=new)), scene)
    assert e["p99"] <= 0.1
