"""The cost counters (AOVs `fetches` and `bytes`, shaders/cost.wgsl) against analytic counts.

A linear search on a constant map at h = 0 walks the whole shell: SteepParallax(steps=n) takes
its n + 1 samples (the entry and n layers), each one fetch with the hardware filter and four
loads with exact filtering; each sample reads 4 float32 texels (16 bytes). Methods that do not
search read nothing. None of these tests is timed: speed lives in `python -m pomkit bench`."""

import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene

COST = ("fetches", "bytes", "steps", "mask")


@pytest.fixture(scope="module")
def flat0():
    return plane_scene(np.zeros((64, 64), np.float32), theta_deg=50.0, size=40)


@pytest.mark.parametrize("filtering,per_sample", [("hardware", 1), ("exact", 4)])
@pytest.mark.parametrize("n", [1, 4, 16, 33])
def test_steep_on_a_constant_floor_reads_n_plus_one_samples(renderer, flat0, n, filtering, per_sample):
    if not renderer.info["float32_filterable"]:
        per_sample = 4  # the adapter filters exactly everywhere (GL): four loads per sample
    f = renderer.render(flat0, pk.SteepParallax(steps=n, filtering=filtering), aovs=COST)
    hit = f.mask
    assert hit.mean() > 0.5
    assert np.all(f.steps[hit] == n + 1)
    assert np.all(f.fetches[hit] == per_sample * (n + 1))
    assert np.all(f.bytes[hit] == 16 * (n + 1))
    # no hit, no count
    assert np.all(f.fetches[~hit] == 0) and np.all(f.bytes[~hit] == 0)


def test_parallax_reads_one_sample(renderer, flat0):
    f = renderer.render(flat0, pk.Parallax(), aovs=COST)
    per_sample = 1 if renderer.info["float32_filterable"] else 4
    assert np.all(f.fetches[f.mask] == per_sample) and np.all(f.bytes[f.mask] == 16)


@pytest.mark.parametrize("method", [pk.Flat(), pk.Bump(), pk.Tessellated(2.0)], ids=lambda m: m.name)
def test_methods_without_a_search_read_nothing(renderer, method):
    sc = plane_scene(pk.textures.bricks(64), theta_deg=60.0, size=40)
    f = renderer.render(sc, method, aovs=COST)
    assert f.mask.any() and not f.fetches.any() and not f.bytes.any()


@pytest.mark.parametrize("method", [pk.POM(), pk.Relief(), pk.Exact(), pk.ConeStep(), pk.NCS(), pk.Prism(),
                                    pk.DistanceMapping(), pk.POM(shadows="exact"), pk.Exact(shadows="hard")],
                         ids=repr)
def test_every_search_counts_what_it_reads(renderer, method):
    """Every texel is at least 4 bytes (a gather: 4 fetches, 16 bytes; a filtered sample: one
    fetch of 16 or 32 bytes), and a search that took steps fetched something."""
    sc = plane_scene(pk.textures.bricks(64), theta_deg=60.0, size=40)
    f = renderer.render(sc, method, aovs=COST)
    hit = f.mask
    assert hit.any()
    assert np.all(f.bytes[hit] >= 4 * f.fetches[hit])
    assert np.all(f.fetches[hit] > 0)
    assert np.all(f.fetches[~hit] == 0)


def test_shadow_rays_are_counted(renderer):
    sc = plane_scene(pk.textures.bricks(64), theta_deg=60.0, size=40,
                     lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)])
    a = renderer.render(sc, pk.POM(shadows="none"), aovs=COST)
    b = renderer.render(sc, pk.POM(shadows="hard", shadow_steps=8), aovs=COST)
    # the same view march; the light ray adds its samples wherever the surface faces the light
    assert np.array_equal(a.mask, b.mask)
    assert np.all(b.fetches[b.mask] >= a.fetches[a.mask]) and b.fetches.sum() > a.fetches.sum()


def test_the_counters_are_named_not_in_all(renderer, flat0):
    f = renderer.render(flat0, pk.POM())
    assert "fetches" not in f.aovs and "bytes" not in f.aovs
    assert set(pk.COST_AOVS) <= set(pk.AOV_NAMES)
    with pytest.raises(AttributeError, match="aovs="):
        _ = f.fetches


# ---- the fragments AOV: fragment invocations of the surface pass (overdraw) ----

FRAG = ("fragments", "mask")


def _far_plane(size=48):
    # the whole plane in view, its outline inside the frame: pixels off the plane are misses
    return plane_scene(np.full((32, 32), 0.5, np.float32), theta_deg=30.0, size=size, dist=5.0)


@pytest.mark.parametrize("method", [pk.Flat(), pk.Bump(), pk.POM(), pk.Exact()], ids=lambda m: m.name)
def test_a_plane_is_one_fragment_a_pixel(renderer, method):
    """A plane of two triangles: the rasteriser's rules put each pixel centre in exactly one of
    them, so every covered pixel counts 1 and every other pixel 0 (a per-pixel method's march
    runs inside that one fragment)."""
    f = renderer.render(_far_plane(), method, aovs=FRAG)
    assert 0.2 < f.mask.mean() < 0.9
    assert np.all(f.fragments[f.mask] == 1) and np.all(f.fragments[~f.mask] == 0)


def test_fragments_are_counted_only_when_named(renderer):
    assert "fragments" in pk.COST_AOVS
    f = renderer.render(_far_plane(), pk.Flat())
    with pytest.raises(AttributeError, match="aovs"):
        f.fragments


def test_two_overlapping_objects_count_two(renderer):
    """Two planes, one above the other, seen from above: where both cover the pixel, two
    fragments run (the counter adds over every draw, whichever wins the depth test)."""
    h = np.full((16, 16), 0.5, np.float32)
    big = pk.Object(pk.Mesh.plane(2.0), pk.Material(h, depth=0.05))
    small = pk.Object(pk.Mesh.plane(2.0), pk.Material(h, depth=0.05), pk.scenes.translate(0.3, 0.4, 0.0) @ pk.scenes.scale(0.5, 1.0, 0.5))
    cam = pk.Camera.look_at((0.0, 6.0, 0.01), target=(0, 0, 0), up=(0, 0, -1), fov_y=30.0, width=48, height=48)
    one = renderer.render(pk.Scene(objects=[small], camera=cam), pk.Flat(), aovs=FRAG)
    both = renderer.render(pk.Scene(objects=[big, small], camera=cam), pk.Flat(), aovs=FRAG)
    assert one.mask.sum() > 20
    assert np.all(both.fragments[one.mask] == 2)
    assert np.all(both.fragments[both.mask & ~one.mask] == 1) and np.all(both.fragments[~both.mask] == 0)


def test_a_closed_convex_mesh_is_one_fragment_a_pixel(renderer):
    """A sphere: back faces are culled, and the front faces tile the disc once."""
    sc = pk.Scene(mesh=pk.Mesh.sphere(segments=32, rings=16), material=pk.Material(np.full((8, 8), 0.5, np.float32), depth=0.0),
                  camera=pk.Camera.look_at((0, 0, 4), width=48, height=48))
    f = renderer.render(sc, pk.Flat(), aovs=FRAG)
    assert f.mask.sum() > 300 and np.all(f.fragments[f.mask] == 1) and np.all(f.fragments[~f.mask] == 0)


def test_tessellated_counts_its_folds(renderer):
    """The displaced mesh of a flat map seen from above is a plane of many triangles: 1 a pixel.
    Of a steep map at a grazing view, its folds overlap: more than 1 where a ridge hides a
    valley, and never 0 where it covers."""
    top = plane_scene(np.full((32, 32), 0.5, np.float32), theta_deg=0.0, size=40, dist=5.0)
    f = renderer.render(top, pk.Tessellated(0.5, shadows="none"), aovs=FRAG)
    assert f.mask.mean() > 0.1 and np.all(f.fragments[f.mask] == 1)
    steep = plane_scene(pk.textures.pyramids(32, 4), theta_deg=70.0, size=48, depth=0.2)
    g = renderer.render(steep, pk.Tessellated(0.5, shadows="none"), aovs=FRAG)
    assert np.all(g.fragments[g.mask] >= 1) and g.fragments.max() >= 2, g.fragments[g.mask].mean()


def test_prism_counts_every_shell_face_it_enters(renderer):
    """Prism rasterises the shell's boundary, front faces: on a plane each pixel's ray enters
    the flat top once (1; the walk through the prisms runs inside that fragment), and where it
    misses the map inside the outline its fragment still ran. On a torus a ray can enter the
    shell twice (through the near tube, out, and into the far one): 2 there, hit or discarded."""
    f = renderer.render(_far_plane(), pk.Prism(), aovs=FRAG)
    assert np.all(f.fragments[f.mask] == 1)
    torus = pk.Scene(mesh=pk.Mesh.torus(segments=48, tube_segments=24),
                     material=pk.Material(pk.textures.cobblestones(64, cells=6), depth=0.1),
                     camera=pk.Camera.look_at((0.0, 1.2, 2.6), fov_y=40, width=64, height=64))
    g = renderer.render(torus, pk.Prism(), aovs=FRAG)
    assert np.all(g.fragments[g.mask] >= 1) and (g.fragments >= 2).sum() >= 10, np.bincount(g.fragments.ravel())


@pytest.mark.parametrize("method", [pk.Exact(shadows="none"), pk.ConeStep(shadows="none")], ids=lambda m: m.name)
def test_a_silhouette_ray_that_does_not_descend_is_not_walked(renderer, method):
    """On a curved mesh a silhouette fragment's view ray can point out of the shell in its
    interpolated frame: no walk can meet the field along it. The traversals end at the entry
    (0 steps) instead of walking to `max_iterations` (4096: before, 48 such pixels of a 256²
    torus held the frame at 43 ms against POM's 5). So no pixel reaches the bound, and every
    search is short."""
    sc = pk.Scene(mesh=pk.Mesh.torus(segments=48, tube_segments=24),
                  material=pk.Material(pk.textures.cobblestones(128, cells=8), depth=0.06, tiling=2.0),
                  camera=pk.Camera.look_at((0.4, 1.6, 2.8), fov_y=40, width=128, height=128))
    f = renderer.render(sc, method, aovs=("mask", "steps", "flags"))
    assert f.mask.sum() > 3000
    assert not np.any(f.flags[f.mask] & 1) and f.steps.max() < 400, (int((f.flags & 1).sum()), int(f.steps.max()))


# ---------------------------------------------------------------- the chain of dependent fetches

CHAIN = ("fetches", "chain", "steps", "mask")


@pytest.mark.parametrize("n", [4, 33])
def test_a_linear_search_is_one_round(renderer, flat0, n):
    """Steep's and POM's addresses all follow from the ray: one round however many fetches."""
    for m in (pk.SteepParallax(steps=n), pk.POM(min_steps=n, max_steps=n, shadows="none")):
        f = renderer.render(flat0, m, aovs=CHAIN)
        assert np.all(f.chain[f.mask] == 1) and f.fetches[f.mask].min() > n / 2
        assert np.all(f.chain[~f.mask] == 0)


def test_a_shadow_ray_is_a_round_of_its_own(renderer):
    sc = plane_scene(pk.textures.bricks(64), theta_deg=50.0, size=40, lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)])
    f = renderer.render(sc, pk.POM(shadows="hard"), aovs=CHAIN)
    assert np.all(f.chain[f.mask] == 2)


def test_each_binary_step_waits_on_the_last(renderer, flat0):
    """Relief on a constant floor: the linear search ends below it, then every midpoint of the
    binary search follows from the last verdict."""
    f = renderer.render(flat0, pk.Relief(linear_steps=8, binary_steps=6), aovs=CHAIN)
    assert np.all(f.chain[f.mask] == 1 + 6)


@pytest.mark.parametrize("method", [pk.Exact(), pk.ConeStep(), pk.DistanceMapping(), pk.NCS()], ids=lambda m: m.name)
def test_a_walk_is_as_long_as_its_steps(renderer, method):
    """The traversals and walks wait on every step: their chain grows with their steps, and is
    far longer than a linear search's at the same fetches."""
    sc = plane_scene(pk.textures.bricks(128), theta_deg=60.0, size=48)
    f = renderer.render(sc, method, aovs=CHAIN)
    hit = f.mask & (f.fetches > 0)
    assert np.all(f.chain[hit] >= 1)
    assert np.all(f.chain[hit] <= f.fetches[hit])
    assert np.corrcoef(f.chain[hit], f.steps[hit])[0, 1] > 0.8
    assert f.chain[hit].max() >= 4


def test_prefetch_reads_a_round_early_and_changes_no_bit(tmp_path):
    """The max-mip walk's latency hiding (POMKIT_PREFETCH, on by default on GPUs): the node a walk
    goes on to is read a round early, with the start cell's max and with a candidate's patch.
    The frames are the same to the bit; the chain of dependent fetches is shorter; the reads
    spent early on a walk that ends there are the extra fetches."""
    import os
    import subprocess
    import sys

    script = tmp_path / "walk.py"
    script.write_text(
        "import sys, numpy as np, pomkit as pk\n"
        "sc = pk.Scene(mesh=pk.Mesh.torus(), material=pk.Material(height=pk.textures.bricks(128), depth=0.05, tiling=2.0),\n"
        "              camera=pk.Camera.look_at((0.0, 1.6, 2.0), fov_y=40.0, width=96, height=96),\n"
        "              lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)], ambient=0.1)\n"
        "r = pk.Renderer(pipeline='raster')\n"
        "out = {}\n"
        "for i, m in enumerate([pk.Exact(), pk.Exact(shadows='exact'), pk.Prism(exact=True)]):\n"
        "    f = r.render(sc, m, aovs=('color', 'uv', 'mask', 'steps', 'fetches', 'chain'))\n"
        "    out.update({f'{i}_{k}': getattr(f, k) for k in ('color', 'uv', 'mask', 'steps', 'fetches', 'chain')})\n"
        "np.savez(sys.argv[1], **out)\n"
    )
    runs = {}
    for flag in ("0", "1"):
        path = tmp_path / f"prefetch{flag}.npz"
        subprocess.run([sys.executable, str(script), str(path)], check=True, env={**os.environ, "POMKIT_PREFETCH": flag})
        runs[flag] = np.load(path)
    off, on = runs["0"], runs["1"]
    for i in range(3):
        for k in ("color", "uv", "mask", "steps"):
            assert np.array_equal(off[f"{i}_{k}"], on[f"{i}_{k}"], equal_nan=True), (i, k)
        hit = off[f"{i}_mask"]
        assert np.all(on[f"{i}_chain"][hit] <= off[f"{i}_chain"][hit])
        assert on[f"{i}_chain"][hit].mean() < 0.9 * off[f"{i}_chain"][hit].mean()
        assert np.all(on[f"{i}_fetches"][hit] >= off[f"{i}_fetches"][hit])
