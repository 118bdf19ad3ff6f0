"""The two pipelines (`pk.Renderer(pipeline=...)`): the compute pipeline (a visibility pass, then
the method per pixel in compute) draws the frames the raster pipeline draws, to the bounds of
docs/cost.md, "Two pipelines", on whatever adapter the suite runs on (Vulkan and GL here)."""

from pathlib import Path

import numpy as np
import pytest

import pomkit as pk

STEEP = (Path(pk.__file__).parent / "wgsl" / "steep_custom.wgsl").read_text()
SIZE = 128
LIGHT = pk.DirectionalLight(direction=(-0.4, -1.0, -0.3), irradiance=3.0, angular_diameter=2.0)


def _scene(kind: str) -> pk.Scene:
    h = pk.textures.bricks(128)
    if kind == "plane":
        mesh, mat = pk.Mesh.plane(2.0), pk.Material(height=h, depth=0.08)
        cam = pk.Camera.look_at(eye=(0.0, 1.2, 1.6), target=(0, 0, 0), fov_y=40.0, width=SIZE, height=SIZE)
    else:
        mesh, mat = pk.Mesh.torus(), pk.Material(height=h, depth=0.05, tiling=2.0)
        cam = pk.Camera.look_at(eye=(0.0, 1.6, 2.0), target=(0, 0, 0), fov_y=40.0, width=SIZE, height=SIZE)
    return pk.Scene(mesh=mesh, material=mat, camera=cam, lights=[LIGHT], ambient=0.1)


METHODS = {
    "Flat": pk.Flat(),
    "POM": pk.POM(),
    "Exact": pk.Exact(),
    "ConeStep": pk.ConeStep(),
    "NCS": pk.NCS(),
    "CurvedRelief": pk.CurvedRelief(),
    # level 0, as the built-in marches by default (with the footprint's level, llvmpipe's GL
    # fragment stage samples each 2 x 2 quad at one level, and a stepped search can then end a
    # layer away from the compute pipeline's per-pixel level: docs/cost.md, "Two pipelines")
    "Custom": pk.Custom(wgsl=STEEP, name="steep_custom", params={"steps": 24.0}, shadows="hard", mip_filtering=False),
    "Relief": pk.Relief(),
    "DistanceMapping": pk.DistanceMapping(),
    "Tessellated": pk.Tessellated(texels_per_vertex=4),
}


@pytest.fixture(scope="module")
def pair():
    return pk.Renderer(pipeline="raster"), pk.Renderer(pipeline="compute")


def _outline(mask: np.ndarray) -> np.ndarray:
    """The pixels within one pixel of the mask's boundary (3 x 3 dilation minus erosion)."""
    p = np.pad(mask, 1, mode="edge")
    shifts = [p[1 + dy:1 + dy + mask.shape[0], 1 + dx:1 + dx + mask.shape[1]] for dy in (-1, 0, 1) for dx in (-1, 0, 1)]
    return np.logical_or.reduce(shifts) & ~np.logical_and.reduce(shifts)


@pytest.mark.parametrize("kind", ["plane", "torus"])
@pytest.mark.parametrize("name", list(METHODS))
def test_compute_draws_the_raster_frame(pair, kind, name):
    raster, compute = pair
    scene = _scene(kind)
    method = METHODS[name]
    a = raster.render(scene, method)
    b = compute.render(scene, method)
    # coverage: the same pixels, up to the outline's
    differ = a.mask != b.mask
    assert not (differ & ~_outline(a.mask)).any(), f"{differ.sum()} pixels differ, some inside the outline"
    assert differ.sum() <= 0.005 * a.mask.sum() + 2
    both = a.mask & b.mask
    texels = 128 * scene.objects[0].material.tiling
    duv = np.abs(a.uv - b.uv)[both].max(axis=-1) * texels
    # the uv of a grazing ray that marched past the mesh's border is unwrapped and may land a
    # tile away: the bound holds for 99 % of the pixels (the p99)
    assert np.percentile(duv, 99) <= 0.01, np.percentile(duv, 99)
    dc = np.abs(a.color - b.color)[both].max(axis=-1)
    assert (dc <= 1.0 / 255.0).mean() >= 0.99, (dc > 1.0 / 255.0).mean()
    assert np.percentile(np.abs(a.depth - b.depth)[both], 99) <= 1e-4
    assert (a.steps == b.steps)[both].mean() >= 0.98
    assert np.array_equal(a.object, b.object)


def test_compute_is_bit_identical_where_the_arithmetic_is(pair):
    """One body, two entry points. On a plane (one normal and tangent everywhere) Flat's colour
    depends on nothing the two pipelines compute differently: it is the raster frame's to the
    bit. POM's depends on the rebuilt fragment's last bits (uv, footprint), and most of its
    pixels are still the same to the bit."""
    raster, compute = pair
    scene = _scene("plane")
    a = raster.render(scene, pk.Flat())
    b = compute.render(scene, pk.Flat())
    both = a.mask & b.mask
    assert np.array_equal(a.color[both], b.color[both])
    a = raster.render(scene, pk.POM())
    b = compute.render(scene, pk.POM())
    both = a.mask & b.mask
    assert (a.color == b.color).all(axis=-1)[both].mean() >= 0.5


def test_compute_counts_the_same_fetches(pair):
    raster, compute = pair
    scene = _scene("torus")
    for method in (pk.POM(), pk.Exact()):
        a = raster.render(scene, method, aovs=("mask", "fetches", "bytes", "chain"))
        b = compute.render(scene, method, aovs=("mask", "fetches", "bytes", "chain"))
        both = a.mask & b.mask
        assert (a.fetches == b.fetches)[both].mean() >= 0.98
        assert (a.chain == b.chain)[both].mean() >= 0.98
        assert abs(float(a.fetches[both].sum()) / float(b.fetches[both].sum()) - 1.0) < 0.01


def test_compute_supersamples(pair):
    raster, compute = pair
    scene = _scene("torus")
    a = raster.render(scene, pk.POM(), spp=4)
    b = compute.render(scene, pk.POM(), spp=4)
    assert np.abs(a.coverage - b.coverage).max() <= 0.5
    both = a.mask & b.mask
    assert (np.abs(a.color - b.color)[both].max(axis=-1) <= 1.0 / 255.0).mean() >= 0.99


def test_compute_refuses_what_it_cannot_draw(pair):
    _, compute = pair
    scene = _scene("torus")
    with pytest.raises(ValueError, match="pipeline.*prisms"):
        compute.render(scene, pk.Prism())
    two = pk.Scene(objects=[scene.objects[0], pk.Object(pk.Mesh.sphere(0.3), scene.objects[0].material)],
                   camera=scene.camera, lights=scene.lights)
    with pytest.raises(ValueError, match="pipeline.*several objects"):
        compute.render(two, pk.POM())
    if compute.info["features"] and any(n.startswith("writable storage") and ok for n, ok, _ in compute.info["features"]):
        with pytest.raises(ValueError, match="pipeline.*fragments"):
            compute.render(scene, pk.POM(), aovs=("color", "fragments"))


def test_auto_rasterises_what_compute_cannot(pair):
    raster, _ = pair
    auto = pk.Renderer()
    assert auto.pipeline == "auto"
    scene = _scene("torus")
    # Prism is always rasterised: "auto" draws it as "raster" does
    assert np.array_equal(auto.render(scene, pk.Prism()).color, raster.render(scene, pk.Prism()).color)


def test_auto_follows_the_adapters_rule(pair):
    raster, compute = pair
    auto = pk.Renderer()
    scene = _scene("plane")
    same = compute if auto.info["auto_pipeline"] == "compute" else raster
    assert np.array_equal(auto.render(scene, pk.POM()).color, same.render(scene, pk.POM()).color)
    if auto.info["device_type"] == "Cpu":
        # measured (docs/cost.md, "Two pipelines"): on a CPU adapter the raster pipeline is faster
        assert auto.info["auto_pipeline"] == "raster"


def test_pipeline_is_checked():
    with pytest.raises(ValueError, match="pipeline.*'auto', 'raster', 'compute'"):
        pk.Renderer(pipeline="gpu")
    with pytest.raises(TypeError, match="pipeline"):
        pk.Renderer(pipeline=1)  # type: ignore[arg-type]
    assert pk.Renderer(pipeline="compute").info["pipeline"] == "compute"


def test_the_probe_times_both_pipelines():
    """"auto"'s probe (what `python -m pomkit info` prints): both pipelines render its frame."""
    from pomkit._info import format_info, info
    d = info(probe=True)
    t = d["pipeline"]["probe_ms"]
    assert t["raster"] > 0 and t["compute"] > 0
    assert d["pipeline"]["auto"] in ("raster", "compute")
    assert "probe (POM, plane, 512²)" in format_info(d)
