"""pk.oracle.image: the noise-free reference image (issue 30). Its shading is the
definition of docs/conventions.md ("The reference shading"); these tests hold it to analytic
cases, to pomkit's own exact method on the GPU, and to Mitsuba where the conventions must meet.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import pomkit as pk

RENDERER = pk.Renderer()


def _plane(height, *, theta=45.0, size=64, light=(-0.3, -1.0, -0.2), diameter=0.0, ambient=0.0, albedo=None,
           depth=0.08, tiling=1.0):
    return pk.scenes.tilted_plane(height, theta, size, depth=depth, tiling=tiling, albedo=albedo, fov=30.0, ambient=ambient,
                                  lights=[pk.DirectionalLight(light, 3.0, angular_diameter=diameter)] if light else [])


@pytest.mark.parametrize("diameter", [0.0, 4.0])
def test_a_flat_field_is_lambert_exactly(tmp_path, monkeypatch, diameter):
    """h = 0.6 everywhere: every sample hits a plane with the base normal, no ray is blocked,
    ao = 1, so colour = albedo/pi E max(0, N.L) + albedo ambient, to float rounding."""
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    s = _plane(np.full((16, 16), 0.6, np.float32), diameter=diameter, ambient=0.1)
    f = pk.oracle.image(s, spp=4)
    l = np.array([-0.3, -1.0, -0.2])
    ndl = max(0.0, float(-l[1] / np.linalg.norm(l)))
    want = 0.5 / math.pi * 3.0 * ndl + 0.5 * 0.1
    inner = f.coverage == 1.0
    assert inner.mean() > 0.9 and f.noise_floor == 0.0
    assert np.allclose(f.color[inner], want, rtol=1e-6), (f.color[inner].min(), f.color[inner].max(), want)
    assert np.array_equal(f.mask, f.object == 0) and f.visibility[f.mask].min() == 1.0


def test_deterministic_and_cached(tmp_path, monkeypatch):
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    s = _plane(pk.textures.bricks(64), diameter=3.0, ambient=0.1, size=32)
    a = pk.oracle.image(s, spp=4)
    b = pk.oracle.image(s, spp=4, cache=False)
    assert np.array_equal(a.color, b.color) and len(list(tmp_path.glob("oracle_image-*.npz"))) == 1


def test_occlusion_darkens_the_grooves_only(tmp_path, monkeypatch):
    """Ambient alone on bricks: ao = 1 on the flat brick tops far from the mortar (colour =
    albedo ambient), and below 1 in the mortar joints."""
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    h = pk.textures.bricks(64)
    s = _plane(h, light=None, ambient=1.0, theta=0.0 + 1e-3, size=64, depth=0.1)
    f = pk.oracle.image(s, spp=1)
    col = f.color[..., 0][f.mask]
    uv = f.uv[f.mask]
    hh = h[np.clip((uv[:, 1] * 64).astype(int), 0, 63), np.clip((uv[:, 0] * 64).astype(int), 0, 63)]
    assert col.max() <= 0.5 + 1e-6
    assert np.median(col[hh < 0.4]) < 0.45 < np.median(col[hh > 0.95])


def test_on_a_curved_mesh_the_oracle_answers_for_the_displaced_surface():
    """On a torus the oracle walks the shell of the interpolated normals (S = P + depth (h - 1) N,
    N interpolated and normalised), the surface Tessellated displaces: against Tessellated(0.25)
    at depth 0.05, p95 within 0.02 texel (measured 0.004-0.01; the faceted shell the planar
    oracle would answer for was 0.539 away). A cube's hard edges take the same walk."""
    s = pk.Scene(mesh=pk.Mesh.torus(segments=24, tube_segments=12), material=pk.Material(pk.textures.bricks(32), depth=0.05),
                 camera=pk.Camera.look_at((0, 1.5, 2.5), width=64, height=64))
    ex = pk.oracle.hits(s)
    e = pk.metrics.uv_error(RENDERER.render(s, pk.Tessellated(texels_per_vertex=0.125)), ex, s)
    assert e["p95"] < 0.005 and e["mask_iou"] > 0.997, e
    assert (ex.object[ex.mask] == 0).all() and (ex.object[~ex.mask] == -1).all()
    c = s.replace(mesh=pk.Mesh.cube(1.0))
    assert pk.oracle.hits(c).mask.any()


def test_a_curved_mesh_is_shaded_as_the_definition_says():
    # depth 0 on a sphere: the base mesh itself; a flat map lit from the camera's side gives
    # albedo/pi * E * n.l with n the sphere's normal, checked against the analytic sphere
    s = pk.Scene(mesh=pk.Mesh.sphere(segments=64, rings=32), material=pk.Material(np.full((8, 8), 0.5, np.float32), depth=0.0),
                 camera=pk.Camera.look_at((0, 0, 3), width=24, height=24), lights=[pk.DirectionalLight((0, 0, -1), 3.0)])
    f = pk.oracle.image(s, spp=1, cache=False)
    assert f.noise_floor == 0.0
    eye = np.asarray(s.camera.eye, float)
    rays = s.camera.rays()
    # the unit sphere's hit along each ray, and its normal's z: the colour is 0.5/pi * 3 * n.z
    b = rays @ eye
    c = eye @ eye - 1.0
    t = -b - np.sqrt(np.maximum(b * b - c, 0))
    nz = (eye + t[..., None] * rays)[..., 2]
    inner = (b * b - c > 0.05) & f.mask
    assert inner.sum() > 150
    want = 0.5 / np.pi * 3.0 * nz
    # the mesh is a 64 x 32 polygon sphere: normals interpolated within 1%
    err = np.abs(f.color[..., 0] - want)[inner]
    assert err.max() < 0.01 * want[inner].max(), err.max()


def _suite_scene(name: str, theta: float, ambient: float, size: int = 96) -> pk.Scene:
    """The agreement suite's scenes (tools/reference_agreement.py): 30° with the light
    overhead, 70° with it grazing; a 2° light."""
    h = pk.textures.real(name, 128) if name in pk.textures.REAL else getattr(pk.textures, name)(128)
    light = (-1.0, -0.35, -0.2) if theta > 45 else (-0.3, -1.0, -0.2)
    return _plane(h, theta=theta, size=size, light=light, diameter=2.0, ambient=ambient)


EXACT_OPTS = dict(shadows="exact", ao_directions=64, mip_filtering=False)


@pytest.mark.parametrize("name", ["bricks", "cobblestones", "terrain", "gravel"])
@pytest.mark.parametrize("theta", [30.0, 70.0])
@pytest.mark.parametrize("ambient", [0.0, 0.15])
def test_the_gpu_methods_that_follow_the_definition_meet_it(tmp_path, monkeypatch, name, theta, ambient):
    """Exact with the reference shading's options (level-0 normal and albedo; exact shadows over
    the light's disk and exact AO, each by the reference's 64 directions shared among a pixel's
    samples) and the mesh with exact self-shadows, both at spp 16, against pk.oracle.image at spp
    16: the same hits and the same shading. Interior FLIP (measured: docs/tables/reference_agreement.md):
    - Exact <= 0.003 (issue 30's bound) on every scene: at most 0.0009 at 144² (the gravel
      photograph at 70° under the grazing light), since its light rays start 1e-6 shell depths
      above the hit, the walk keeping its start as a whole cell and an offset (with a start bias
      of 1e-4 it was 0.0072 there, 3e-5: 0.0040);
    - Tessellated(0.5) <= 0.005 (issue 30's bound) on every scene but the gravel photograph at
      70°: the mesh's error is its chord error, the bilinear field's twist inside a lattice quad.
      With the default pattern ("fan": four triangles about each quad's centre) it is at most
      0.0029 elsewhere at 96²; on gravel at 70° it is 0.0048-0.0058, held at 0.007, and
      Tessellated(0.25) meets 0.005 there (0.0023-0.0025). The regular grid (two triangles a
      quad) left four times the chord error: 0.0274 on gravel at 70°, 0.0108 on cobblestones."""
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    s = _suite_scene(name, theta, ambient)
    ref = pk.oracle.image(s, spp=16)
    ex = pk.metrics.compare(RENDERER.render(s, pk.Exact(**EXACT_OPTS), spp=16), ref, s)["flip_interior"]
    assert ex <= 0.003, ex
    tess = pk.metrics.compare(RENDERER.render(s, pk.Tessellated(0.5, shadows="exact"), spp=16), ref, s)["flip_interior"]
    gravel_grazing = name == "gravel" and theta > 45
    assert tess <= (0.007 if gravel_grazing else 0.005), tess
    if gravel_grazing:
        finer = RENDERER.render(s, pk.Tessellated(0.25, shadows="exact"), spp=16)
        assert pk.metrics.compare(finer, ref, s)["flip_interior"] <= 0.005


@pytest.mark.parametrize("name,theta", [("bricks", 30.0), ("bricks", 70.0), ("gravel", 30.0), ("gravel", 70.0)])
def test_methods_rank_alike_by_colour_and_by_geometry(tmp_path, monkeypatch, name, theta):
    """Against the noise-free reference, with every method shading by the same definition, the
    order by interior FLIP is the order by interior uv p95 (Spearman >= 0.9; measured 0.94-1.0
    over the suite): a colour score now measures displacement, not the reference's noise."""
    from scipy.stats import spearmanr
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    s = _suite_scene(name, theta, 0.15)
    ref = pk.oracle.image(s, spp=16)
    methods = [pk.Flat(), pk.Parallax(**EXACT_OPTS), pk.SteepParallax(steps=8, **EXACT_OPTS),
               pk.POM(min_steps=4, max_steps=8, **EXACT_OPTS), pk.Relief(**EXACT_OPTS), pk.Exact(**EXACT_OPTS)]
    fl, uv = [], []
    for m in methods:
        c = pk.metrics.compare(RENDERER.render(s, m, spp=16), ref, s)
        fl.append(c["flip_interior"])
        uv.append(c["uv_p95_interior"])
    rho = spearmanr(fl, uv)[0]
    assert rho >= 0.9, (rho, fl, uv)


def test_any_map_size_without_a_mesh(tmp_path, monkeypatch):
    """pk.oracle.image builds no mesh: an 8192² map renders at the cost of its rays."""
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    h = np.kron(pk.textures.bricks(256), np.ones((32, 32), np.float32))
    f = pk.oracle.image(_plane(h, size=24, diameter=2.0, ambient=0.1), spp=4)
    assert f.mask.mean() > 0.9 and np.isfinite(f.color).all()


def test_assert_close_refuses_a_tolerance_below_the_floor():
    c = np.full((8, 8, 3), 0.2, np.float32)
    ref = pk.Frame(color=c, mask=np.ones((8, 8), bool), noise_floor=0.04)
    with pytest.raises(ValueError, match="below the reference's own noise"):
        pk.testing.assert_close(pk.Frame(color=c, mask=np.ones((8, 8), bool)), ref, flip=0.01)
    got = pk.testing.assert_close(pk.Frame(color=c, mask=np.ones((8, 8), bool)), ref, flip=0.05)
    assert got["flip_floor"] == 0.04 and got["flip"] == 0.0


def test_each_failing_test_writes_its_own_diff_image(tmp_path, monkeypatch):
    monkeypatch.setenv("POMKIT_DIFF_DIR", str(tmp_path))
    ref = pk.Frame(color=np.zeros((8, 8, 3), np.float32), mask=np.ones((8, 8), bool))
    bad = pk.Frame(color=np.ones((8, 8, 3), np.float32), mask=np.ones((8, 8), bool))
    with pytest.raises(AssertionError, match="test_each_failing_test_writes_its_own_diff_image"):
        pk.testing.assert_close(bad, ref, flip=0.1)
    assert [p.name for p in tmp_path.iterdir()] == ["test_each_failing_test_writes_its_own_diff_image.png"]


def test_unshadowed_is_never_darker(tmp_path, monkeypatch):
    """shadows=False (the bench's and choose's reference for methods without shadows) drops the
    light and ambient rays only: the same hits, every pixel at least as bright, and brighter
    where the bricks shadow and occlude."""
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    s = _suite_scene("bricks", 70.0, 0.15)
    a = pk.oracle.image(s, spp=4)
    b = pk.oracle.image(s, spp=4, shadows=False)
    assert np.array_equal(a.mask, b.mask) and (b.color >= a.color - 1e-7).all()
    assert (b.color - a.color).max() > 0.05


@pytest.mark.parametrize("name", ["cobblestones", "terrain", "gravel"])
def test_the_fan_meets_the_field_closer_than_the_grid(name):
    """The displaced mesh's hits against the float64 oracle's on the bilinear field (geometry
    only, 96² at 70°, the half-texel lattice): cutting each lattice quad in four about a centre
    vertex leaves a quarter of the chord error of cutting it in two (the Rust test holds |d|/16
    against |d|/4 on a checkerboard), and the uv error follows: p95 0.24-0.25 of the grid's on
    these maps (cobblestones 0.010 against 0.040 texel, gravel 0.014 against 0.058); bound 0.3."""
    s = _suite_scene(name, 70.0, 0.0)
    o = pk.oracle.hits(s)
    err = {p: pk.metrics.uv_error(RENDERER.render(s, pk.Tessellated(0.5, shadows="none", pattern=p)), o, s)["p95"]
           for p in ("fan", "grid")}
    assert err["fan"] <= 0.3 * err["grid"], err


def _floors_and_plateaus(n: int = 128, cells: int = 4) -> np.ndarray:
    """Square cells with flat floors at h = 0 and flat plateaus at h = 1 along their walls, joined
    by ramps 0.3 cell wide: a field that touches the shell's bottom and its top over whole areas."""
    t = (np.arange(n) + 0.5) / n * cells
    f = np.abs((t % 1.0) - 0.5) * 2.0
    return np.clip((np.maximum.outer(f, f) - 0.45) / 0.3, 0.0, 1.0).astype(np.float32)


def _floor_scene(h, mesh: str, shadows: bool) -> pk.Scene:
    lights = [pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0, angular_diameter=2.0 if shadows else 0.0)]
    if mesh == "plane":
        return pk.Scene(mesh=pk.Mesh.plane(2.0), material=pk.Material(h, depth=0.08), lights=lights,
                        camera=pk.Camera.look_at((0.0, 1.38, 1.03), fov_y=40, width=128, height=128),
                        ambient=0.15 if shadows else 0.0)
    return pk.Scene(mesh=pk.Mesh.sphere(), material=pk.Material(h, depth=0.06, tiling=2.0), lights=lights,
                    camera=pk.Camera.look_at((0.0, 1.2, 2.4), fov_y=40, width=128, height=128),
                    ambient=0.15 if shadows else 0.0)


@pytest.mark.parametrize("mesh,shadows", [("plane", True), ("plane", False), ("sphere", False)])
def test_floors_at_zero_and_plateaus_at_one_are_noise_free(tmp_path, monkeypatch, mesh, shadows):
    """A field that touches h = 0 and h = 1 over whole areas: the oracle's image is as smooth there
    as anywhere (issue 73 §0). A camera ray's walk ended exactly at h = 0, so its last chord ended
    on the floor itself and rounding dropped the hit of one sample in a few: the floors were
    speckled with misses (452 pixels' coverage changed by lifting the map 1e-3 off the floor, FLIP
    0.017 over the image; Exact 0.016 from it). Held three ways, at spp 4 on 128²:
    - against the same map lifted 1e-3 (the speckle test): the same coverage everywhere, FLIP
      <= 0.005 (measured 0.0010-0.0013, the lift's own change);
    - Tessellated(0.5) (shadows exact on the plane) within FLIP 0.005;
    - on the plane, Exact with the reference's options within 0.003 (measured 0.0000), the
      agreement suite's bounds above; on the sphere its per-pixel methods are not exact."""
    monkeypatch.setenv("POMKIT_CACHE", str(tmp_path))
    h = _floors_and_plateaus()
    s = _floor_scene(h, mesh, shadows)
    ref = pk.oracle.image(s, spp=4, shadows=shadows)
    lifted = pk.oracle.image(_floor_scene((h * 0.999 + 0.001).astype(np.float32), mesh, shadows), spp=4, shadows=shadows)
    assert np.array_equal(ref.coverage, lifted.coverage), int((ref.coverage != lifted.coverage).sum())
    assert pk.metrics.flip(ref, lifted) <= 0.005
    tess = RENDERER.render(s, pk.Tessellated(0.5, shadows="exact" if shadows else "none"), spp=4)
    assert pk.metrics.flip(tess, ref) <= 0.005
    if mesh == "plane":
        ex = RENDERER.render(s, pk.Exact(**(EXACT_OPTS if shadows else dict(shadows="none", mip_filtering=False))), spp=4)
        assert pk.metrics.flip(ex, ref) <= 0.003
