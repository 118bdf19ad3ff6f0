"""Analytic cases: a constant height field, a near-normal view, sample counts, LOD, shadows."""

import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene

W = 64  # height-map resolution of the analytic cases


def analytic_plane_hits(scene, c):
    """Per-pixel exact hit of each camera ray with the plane y = -depth*(1-c) under the size-2
    base plane: (uv (H,W,2), distance (H,W), inside (H,W) pixels well inside the plane)."""
    cam = scene.camera
    d = cam.rays()
    eye = np.asarray(cam.eye)
    t0 = -eye[1] / d[..., 1]
    p0 = eye + d * t0[..., None]
    uv0 = np.stack([p0[..., 0] / 2 + 0.5, p0[..., 2] / 2 + 0.5], -1)
    lam = scene.material.depth * (1 - c) / (-d[..., 1])
    p = p0 + d * lam[..., None]
    uv = np.stack([p[..., 0] / 2 + 0.5, p[..., 2] / 2 + 0.5], -1)
    inside = np.all((uv0 > 0.02) & (uv0 < 0.98), axis=-1) & (d[..., 1] < 0)
    return uv, t0 + lam, inside


@pytest.mark.parametrize("c", [0.0, 0.4, 0.9])
@pytest.mark.parametrize("theta", [0.0, 30.0, 60.0, 80.0])
def test_constant_height_shift(renderer, c, theta):
    # a constant height h = c shifts the uv by depth*(1-c)*tan(theta) along the view direction;
    # POM's piecewise-linear refinement is exact on a constant profile, so 0.05 texel holds.
    # LOD is disabled (threshold 100): above the threshold POM hands over to bump mapping by design.
    scene = plane_scene(pk.textures.constant(W, c), depth=0.1, theta_deg=theta, size=96)
    f = renderer.render(scene, pk.POM(shadows="none", lod_threshold=100.0))
    uv, dist, inside = analytic_plane_hits(scene, c)
    m = inside & f.mask
    assert m.sum() > 500
    err_texels = np.abs(f.uv[m] - uv[m]).max(axis=-1) * W
    assert err_texels.max() < 0.05, f"max uv error {err_texels.max():.4f} texels"
    rel = np.abs(f.depth[m] - dist[m]) / dist[m]
    assert rel.max() < 1e-4, f"max relative depth error {rel.max():.2e}"


@pytest.mark.parametrize("c", [0.0, 0.5, 1.0])
def test_oracle_matches_analytic(c):
    scene = plane_scene(pk.textures.constant(W, c), depth=0.1, theta_deg=70.0, size=64)
    o = pk.oracle.hits(scene)
    uv, dist, inside = analytic_plane_hits(scene, c)
    m = inside & o.mask
    assert m.sum() > 300
    assert np.abs(o.uv[m] - uv[m]).max() * W < 1e-6
    # the core stores depth as float32 (0.1 -> 0.10000000149): relative 1e-7 covers that
    assert (np.abs(o.depth[m] - dist[m]) / dist[m]).max() < 1e-7


def test_near_normal_view_shift_is_bounded(renderer):
    # camera straight above with a 2 degree field of view: every ray is within 1 degree of the
    # normal, so no hit can move further than depth * tan(1 deg) from the rasterised point.
    depth = 0.1
    scene = pk.Scene(
        mesh=pk.Mesh.plane(2.0),
        material=pk.Material(pk.textures.bricks(128), depth=depth),
        camera=pk.Camera.look_at(eye=(0.0, 3.0, 0.0), target=(0, 0, 0), up=(0, 0, -1), fov_y=2.0, width=96, height=96),
    )
    f_pom = renderer.render(scene, pk.POM(shadows="none"))
    f_flat = renderer.render(scene, pk.Flat())
    assert f_pom.mask.all()
    shift = np.linalg.norm(f_pom.uv - f_flat.uv, axis=-1) * 2.0  # world units (plane size 2)
    bound = depth * np.tan(np.radians(1.0))
    assert shift.max() <= bound * 1.001 + 1e-6, f"{shift.max()} > {bound}"
    assert shift.max() > 0.2 * bound  # and the method does displace


def test_pyramid_steps_grow_at_grazing_angles(renderer):
    h = pk.textures.pyramids(128, count=4)
    s0 = renderer.render(plane_scene(h, theta_deg=0.0, size=64), pk.POM(shadows="none", lod_threshold=100))
    s70 = renderer.render(plane_scene(h, theta_deg=70.0, size=64), pk.POM(shadows="none", lod_threshold=100))
    m0 = s0.steps[s0.mask].mean()
    m70 = s70.steps[s70.mask].mean()
    assert m70 > 1.5 * m0, (m0, m70)


def test_lod_rises_with_distance_without_a_seam(renderer):
    # a plane receding to the horizon: the mip level grows with distance, and the POM -> bump
    # hand-over (blended across one level) leaves no seam: the largest colour step between
    # vertical neighbours where the level crosses the band is no larger than the largest step
    # within the rows around it.
    h = pk.textures.noise(256, octaves=4, seed=3)
    scene = pk.Scene(
        mesh=pk.Mesh.plane(40.0),
        material=pk.Material(h, depth=0.3, tiling=20.0),
        camera=pk.Camera.look_at(eye=(0.0, 0.6, 18.0), target=(0, 0, 0), fov_y=40.0, width=128, height=128),
        lights=[pk.DirectionalLight((-0.3, -1.0, -0.4), 3.0)],
    )
    thr = 3.0
    f = renderer.render(scene, pk.POM(shadows="none", lod_threshold=thr))
    lod = f.lod
    col = f.mask.all(axis=0)
    rows = np.where(f.mask[:, 64])[0]
    med = np.array([np.nanmedian(lod[r][f.mask[r]]) for r in rows])
    # rows go from the horizon (top, far) to the bottom (near): level falls toward the bottom
    assert med[0] > med[-1] + 2.0
    assert np.all(np.diff(med) <= 0.05), "median lod per row must not rise toward the camera"
    assert (lod[f.mask] > thr).any() and (lod[f.mask] < thr - 1).any(), "the threshold band must be crossed"
    c = f.color.max(axis=-1)
    d = np.abs(np.diff(c, axis=0))
    both = f.mask[1:] & f.mask[:-1]
    crosses = both & (((lod[1:] > thr - 1) != (lod[:-1] > thr - 1)) | ((lod[1:] > thr) != (lod[:-1] > thr)))
    assert crosses.sum() > 20
    near = both & ~crosses
    assert d[crosses].max() <= d[near].max() + 1e-6, (d[crosses].max(), d[near].max())
    del col


def wall_scene(shadows, steps=32):
    # floor at h = 0 with a wall (h = 1) across u in [0.45, 0.5); light travelling toward +x at
    # 26.6 degrees elevation: the wall's shadow on the floor is depth / tan(26.6 deg) = 2 depth
    # long in world units, i.e. depth in uv units on the size-2 plane.
    n = 128
    h = np.zeros((n, n), np.float32)
    h[:, int(0.45 * n):int(0.5 * n)] = 1.0
    return pk.Scene(
        mesh=pk.Mesh.plane(2.0),
        material=pk.Material(h, depth=0.2),
        camera=pk.Camera.look_at(eye=(0.0, 3.0, 0.0), target=(0, 0, 0), up=(0, 0, -1), fov_y=40.0, width=128, height=128),
        lights=[pk.DirectionalLight((1.0, -0.5, 0.0), 2.0)],
        ambient=0.0,
    ), pk.POM(shadows=shadows, shadow_steps=steps, lod_threshold=100)


def test_hard_shadow_behind_the_wall_only(renderer):
    scene, method = wall_scene("hard")
    f = renderer.render(scene, method)
    u = f.uv[..., 0]
    lum = f.color.mean(-1)
    behind = f.mask & (u > 0.52) & (u < 0.65)     # shadow spans u in [0.5, 0.7)
    front = f.mask & (u > 0.25) & (u < 0.43)
    far = f.mask & (u > 0.75) & (u < 0.95)
    assert behind.sum() > 100 and front.sum() > 100
    assert lum[behind].max() < 1e-6, "floor behind the wall must be in shadow"
    assert lum[front].min() > 0.1, "floor in front of the wall must be lit"
    assert lum[far].min() > 0.1, "floor beyond the shadow's length must be lit"
    # without shadows the same texels are lit
    g = renderer.render(scene, pk.POM(shadows="none", lod_threshold=100))
    assert g.color.mean(-1)[behind].min() > 0.1


def test_tessellated_shadow_map_behind_the_wall_only(renderer):
    scene, _ = wall_scene("hard")
    f = renderer.render(scene, pk.Tessellated(texels_per_vertex=0.5))
    u = f.uv[..., 0]
    lum = f.color.mean(-1)
    # the wall's top edge is 0.45..0.5 in u; its shadow on the floor reaches u = 0.7. Margins of
    # 0.02 uv (2.5 map texels, 1.3 shadow-map texels) keep PCF edges out of the test.
    behind = f.mask & (u > 0.52) & (u < 0.68)
    front = f.mask & (u > 0.25) & (u < 0.43)
    far = f.mask & (u > 0.72) & (u < 0.95)
    assert lum[behind].max() < 1e-6
    assert lum[front].min() > 0.1 and lum[far].min() > 0.1


def test_soft_shadow_penumbra_grows_with_angular_diameter(renderer):
    scene, _ = wall_scene("soft")
    dark = []
    for diam in (0.0, 10.0):
        s = scene.replace(lights=[pk.DirectionalLight((1.0, -0.5, 0.0), 2.0, angular_diameter=diam)])
        f = renderer.render(s, pk.POM(shadows="soft", shadow_steps=32, lod_threshold=100))
        u = f.uv[..., 0]
        band = f.mask & (u > 0.5) & (u < 0.75)
        lum = f.color.mean(-1)[band]
        dark.append(((lum > 0.01) & (lum < 0.9 * lum.max())).mean())
    # a point light gives an (almost) sharp edge; a 10 degree source a wide penumbra
    assert dark[1] > dark[0] + 0.05, dark


def _uv_err(f, o, scene):
    m = f.mask & o.mask
    h, w = scene.material.height.shape
    return np.linalg.norm((f.uv[m] - o.uv[m]) * np.array([w, h]) * scene.material.tiling, axis=-1)


@pytest.mark.parametrize("theta", [30.0, 60.0])
def test_pom_converges_to_the_oracle_on_bricks(renderer, theta):
    # sampling level 0 (no prefiltering) with many steps, POM must approach the exact first hit;
    # the error must fall (within noise) as the step count rises.
    scene = plane_scene(pk.textures.bricks(256), depth=0.08, theta_deg=theta, size=96, dist=1.6, fov=40.0)
    o = pk.oracle.hits(scene)
    p99 = []
    for steps in (8, 32, 128):
        f = renderer.render(scene, pk.POM(min_steps=steps, max_steps=steps, shadows="none", lod_threshold=100, mip_filtering=False))
        p99.append(np.percentile(_uv_err(f, o, scene), 99))
    assert p99[2] < 0.1, p99
    assert p99[0] >= p99[1] - 0.02 and p99[1] >= p99[2] - 0.02, p99
