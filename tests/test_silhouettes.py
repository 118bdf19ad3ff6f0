"""NCS on curved meshes: silhouettes against Mitsuba, the step-scale trade-off, degenerate cases."""

import numpy as np
import pytest

import pomkit as pk


def curved(mesh, eye=(0.0, 1.0, 2.8), size=128, depth=0.12):
    return pk.Scene(mesh=mesh, material=pk.Material(pk.textures.cobblestones(128, cells=8), depth=depth),
                    camera=pk.Camera.look_at(eye, fov_y=40, width=size, height=size),
                    lights=[pk.DirectionalLight((-0.4, -1, -0.3), 3.0)], ambient=0.05)


@pytest.mark.parametrize("name", ["torus", "sphere"])
@pytest.mark.reference
def test_ncs_silhouette_beats_pom(renderer, name):
    pytest.importorskip("mitsuba")
    # coverage against Mitsuba's render of the displaced mesh (pixel-centre AOVs). Measured at
    # 256^2 (docs/tables/silhouettes.md): torus POM 0.976 -> NCS 0.986, sphere 0.959 -> 0.975.
    mesh = pk.Mesh.torus(segments=48, tube_segments=24) if name == "torus" else pk.Mesh.sphere(segments=48, rings=24)
    scene = curved(mesh)
    ref = pk.reference.render_mitsuba(scene, spp=1)
    pom = pk.metrics.mask_iou(renderer.render(scene, pk.POM()), ref)
    ncs = pk.metrics.mask_iou(renderer.render(scene, pk.NCS()), ref)
    assert ncs > pom + 0.005, (pom, ncs)


@pytest.mark.parametrize("name", ["torus", "sphere"])
@pytest.mark.reference
def test_prism_silhouette(renderer, name):
    pytest.importorskip("mitsuba")
    # prism POM follows the displaced surface out to the true outline: coverage IoU >= 0.98 (the
    # goal; measured 0.9986 torus, 0.9989 sphere at 256^2), and better than POM and NCS
    mesh = pk.Mesh.torus(segments=48, tube_segments=24) if name == "torus" else pk.Mesh.sphere(segments=48, rings=24)
    scene = curved(mesh)
    ref = pk.reference.render_mitsuba(scene, spp=1)
    iou = {m.name: pk.metrics.mask_iou(renderer.render(scene, m), ref) for m in (pk.POM(), pk.NCS(), pk.Prism(shadows="none"))}
    assert iou["Prism"] >= 0.98 and iou["Prism"] > iou["NCS"] > iou["POM"], iou
    e = pk.metrics.uv_error(renderer.render(scene, pk.Prism(shadows="none")), ref, scene)
    assert e["p95"] < 1.5, e["p95"]
    # exact=True: the max-mip traversal between entry and exit (measured 0.9998 / 0.9994 IoU)
    ex = pk.metrics.uv_error(renderer.render(scene, pk.Prism(shadows="none", exact=True)), ref, scene)
    assert ex["mask_iou"] >= iou["Prism"] - 1e-3 and ex["p95"] <= e["p95"] + 0.05, (ex["mask_iou"], ex["p95"])


@pytest.mark.parametrize("mesh,content", [("torus", "moon"), ("sphere", "gravel")])
@pytest.mark.reference
def test_prism_tight_shell_is_the_same_surface_or_closer(renderer, mesh, content):
    pytest.importorskip("mitsuba")
    # the tight shell (each vertical edge's top at the highest height beside it) crosses less
    # empty space; it must find the same displaced surface, against Mitsuba's render of the
    # displaced mesh, as the paper's full shell: coverage IoU within 1e-3 and uv error no worse
    # (its thinner prisms bend the march's straight segments less). Real content, meshes the
    # suite does not hold. Measured at 128^2: see docs/cost_journal_2026.md, "The tight shell".
    m = pk.Mesh.torus(segments=40, tube_segments=20) if mesh == "torus" else pk.Mesh.sphere(segments=64, rings=32)
    scene = pk.Scene(mesh=m, material=pk.Material(pk.textures.real(content, 128), depth=0.1),
                     camera=pk.Camera.look_at((1.6, 1.5, 2.2), fov_y=40, width=128, height=128),
                     lights=[pk.DirectionalLight((-0.4, -1, -0.3), 3.0)], ambient=0.05)
    ref = pk.reference.render_mitsuba(scene, spp=1)
    for exact in (False, True):
        full = pk.metrics.uv_error(renderer.render(scene, pk.Prism(shadows="none", exact=exact, tight=False)), ref, scene)
        tight = pk.metrics.uv_error(renderer.render(scene, pk.Prism(shadows="none", exact=exact)), ref, scene)
        assert tight["mask_iou"] >= full["mask_iou"] - 1e-3, (exact, full["mask_iou"], tight["mask_iou"])
        assert tight["mean"] <= full["mean"] + 1e-3 and tight["p95"] <= full["p95"] + 0.02, (exact, full, tight)


def test_prism_has_no_pinholes_on_smooth_content(renderer):
    # a pixel Prism misses while its four neighbours hit is a pinhole on smooth content (no
    # feature to see past): a fragment within rounding of its face's edge, whose ray missed its
    # own prism. Measured over these 96 frames before prism.wgsl's walk_origin: 53 (tight shell,
    # POM and exact segments alike) and 63 (full shell); after: 0, 0 and 4 (the full shell's,
    # on the torus from one eye, are not at a face's edge).
    maps = {"zero": np.zeros((16, 16), np.float32), "one": np.ones((16, 16), np.float32),
            "ramp": np.tile(np.linspace(0, 1, 50, dtype=np.float32), (40, 1))}
    meshes = {"sphere": pk.Mesh.sphere(segments=16, rings=8), "torus": pk.Mesh.torus(segments=24, tube_segments=12)}
    eyes = [(0, 0.4, 3.0), (2.2, 1.8, 0.6), (0.05, 3.0, 0.05), (3.0, 0.05, 0.2)]

    def holes(m):
        bb = np.pad(m, 1)
        return int((~m & bb[:-2, 1:-1] & bb[2:, 1:-1] & bb[1:-1, :-2] & bb[1:-1, 2:]).sum())

    found = {"tight": 0, "tight exact": 0, "full": 0}
    for mesh in meshes.values():
        for h in maps.values():
            for eye in eyes:
                for depth in (0.05, 0.2):
                    for outward in (False, True):
                        sc = pk.Scene(mesh=mesh, material=pk.Material(h, depth=depth),
                                      camera=pk.Camera.look_at(eye, fov_y=45, width=96, height=96))
                        for name, kw in (("tight", {}), ("tight exact", {"exact": True}), ("full", {"tight": False})):
                            m = pk.Prism(shadows="none", outward=outward, **kw)
                            found[name] += holes(renderer.render(sc, m, aovs=("mask",)).mask)
    assert found["tight"] == 0 and found["tight exact"] == 0 and found["full"] <= 8, found


def test_prism_outward_shell_rises_above_the_base(renderer):
    # the paper's set-up: a constant height 1 with outward=True lies `depth` above the base sphere
    scene = pk.Scene(mesh=pk.Mesh.sphere(segments=32, rings=16), material=pk.Material(pk.textures.constant(16, 1.0), depth=0.2),
                     camera=pk.Camera.look_at((0, 0, 4.0), fov_y=40, width=64, height=64))
    inward = renderer.render(scene, pk.Prism(shadows="none"))
    outward = renderer.render(scene, pk.Prism(shadows="none", outward=True))
    assert outward.mask.sum() > 1.2 * inward.mask.sum()
    m = inward.mask & outward.mask
    assert (outward.depth[m] < inward.depth[m] - 0.1).mean() > 0.9


def test_step_scale_trades_early_terminations_for_error(renderer):
    # Chen & Chang's fig. 7 with the paper's fixed step (adaptive=False): a small c leaves many
    # rays inside the shell after max_steps (early terminations); a large c overshoots. The
    # early-termination rate must fall as c grows.
    scene = curved(pk.Mesh.torus(segments=48, tube_segments=24), size=96)
    rates = []
    for c in (1.0, 1.5, 2.5, 10.0):
        f = renderer.render(scene, pk.NCS(step_scale=c, adaptive=False))
        rates.append(((f.flags & 2) > 0)[f.mask].mean())
    assert rates[0] > rates[1] > rates[2] > rates[3], rates
    # the adaptive step (POM's layer density where longer) leaves fewer rays inside than the
    # paper's step at the same c (measured 256^2: 895 -> 0 on the torus, 2816 -> 0 on the sphere)
    f = renderer.render(scene, pk.NCS())
    assert ((f.flags & 2) > 0)[f.mask].mean() < 0.25 * rates[2], rates


@pytest.mark.parametrize("name", ["torus", "sphere"])
@pytest.mark.reference
def test_silhouette_coverage_against_mitsuba(renderer, name):
    pytest.importorskip("mitsuba")
    # issue 12's bars at 256^2, every method at its defaults: Prism >= 0.998 (measured torus
    # 0.9990, sphere 0.9983), NCS >= 0.98 (0.9934, 0.9892; the sphere was 0.9745 with the
    # paper's fixed step, which left 2816 rays inside the shell near the poles and silhouettes)
    mesh = pk.Mesh.torus(segments=48, tube_segments=24) if name == "torus" else pk.Mesh.sphere(segments=48, rings=24)
    scene = pk.Scene(mesh=mesh, material=pk.Material(pk.textures.cobblestones(256, cells=8), depth=0.12),
                     camera=pk.Camera.look_at((0.0, 1.0, 2.8), fov_y=40, width=256, height=256),
                     lights=[pk.DirectionalLight((-0.4, -1, -0.3), 3.0)])
    ref = pk.reference.render_mitsuba(scene, spp=1)
    prism = pk.metrics.uv_error(renderer.render(scene, pk.Prism()), ref, scene)
    ncs = pk.metrics.uv_error(renderer.render(scene, pk.NCS()), ref, scene)
    assert prism["mask_iou"] >= 0.998, prism["mask_iou"]
    assert ncs["mask_iou"] >= 0.98, ncs["mask_iou"]
    # uv p95 no worse than before the walk (0.794 torus, 0.266 sphere, at 16 spp)
    assert prism["p95"] <= {"torus": 0.8, "sphere": 0.27}[name], prism["p95"]


@pytest.mark.parametrize("exact", [True, False])
def test_prism_walk_follows_grazing_rays_through_many_prisms(renderer, exact):
    """Rays that skim the sphere's shell near its outline cross many prisms (the shell is 0.15
    deep, a prism 0.13 wide, a skimming ray up to 1.0 long) before they hit: the walk from prism
    to prism must reach the same point as the displaced mesh (Tessellated), uv within 0.5 texel
    at p95, and stopping at a prism's side would lose those pixels."""
    size, depth = 192, 0.15
    scene = pk.Scene(mesh=pk.Mesh.sphere(segments=48, rings=24),
                     material=pk.Material(pk.textures.cobblestones(128, cells=6), depth=depth),
                     camera=pk.Camera.look_at((0.0, 0.6, 3.0), fov_y=42, width=size, height=size))
    # per pixel, the ray's closest approach to the sphere's centre
    cam = np.array([0.0, 0.6, 3.0])
    fwd = -cam / np.linalg.norm(cam)
    right = np.cross(fwd, [0, 1, 0]); right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    t = np.tan(np.radians(42) / 2)
    x = ((np.arange(size) + 0.5) / size * 2 - 1) * t
    y = (1 - (np.arange(size) + 0.5) / size * 2) * t
    d = fwd + x[None, :, None] * right + y[:, None, None] * up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    b = np.linalg.norm(np.cross(d, -cam), axis=-1)
    # rays that pass through the shell only (never below it): they walk sideways through it
    skim = (b > 1.0 - depth + 0.01) & (b < 1.0)
    prism = renderer.render(scene, pk.Prism(exact=exact, shadows="none"))
    tess = renderer.render(scene, pk.Tessellated(0.5, shadows="none"))
    band_t, band_p = tess.mask & skim, prism.mask & skim
    assert band_t.sum() > 300, band_t.sum()
    iou = (band_t & band_p).sum() / (band_t | band_p).sum()
    both = band_t & band_p
    du = np.linalg.norm((prism.uv - tess.uv)[both] * 128, axis=-1)
    assert iou >= 0.97, iou
    assert np.quantile(du, 0.95) <= 0.5, np.quantile(du, 0.95)


@pytest.mark.parametrize("case", ["torus_inner_grazing", "sphere_pole", "cube_overlapping_uvs", "sphere_seam"])
def test_degenerate_views_stay_finite(renderer, case):
    if case == "torus_inner_grazing":
        # the view across the torus's hole, nearly in its plane: the case where CRM fails
        scene = curved(pk.Mesh.torus(), eye=(0.0, 0.08, 2.5), size=96)
    elif case == "sphere_pole":
        scene = curved(pk.Mesh.sphere(), eye=(0.0, 3.0, 0.01), size=96)
    elif case == "sphere_seam":
        # u = 0/1 is on +X: look at it
        scene = curved(pk.Mesh.sphere(), eye=(3.0, 0.3, 0.0), size=96)
    else:
        # every cube face carries the whole uv square: the baked maps hold one face's frame per
        # texel (the last drawn); documented behaviour, the render must stay finite
        scene = curved(pk.Mesh.cube(), eye=(2.0, 1.6, 2.4), size=96)
    for m in (pk.NCS(), pk.NCS(step_scale=1.0, shadows="soft"), pk.POM(), pk.Prism(shadows="horizon", ao_directions=4)):
        f = renderer.render(scene, m)
        # on the cube NCS follows another face's frame, the ray leaves the shell and the pixel
        # is discarded: measured, the whole cube vanishes (documented in docs/methods.md)
        assert f.mask.any() or (case == "cube_overlapping_uvs" and m.name == "NCS"), (case, m)
        for a in (f.color, f.uv, f.depth):
            assert np.isfinite(a[f.mask]).all(), (case, m)


def test_mesh_without_uvs_is_refused():
    trimesh = pytest.importorskip("trimesh")
    with pytest.raises(ValueError, match="uv"):
        pk.Mesh.from_trimesh(trimesh.creation.icosphere(subdivisions=1))


def _wild_views(mesh, size=96, fov=35.0):
    """tools/wild.py's three views: two from 35 degrees above, one from 30 below."""
    lo, hi = mesh.positions.min(0), mesh.positions.max(0)
    c, r = 0.5 * (lo + hi), 0.5 * float(np.linalg.norm(hi - lo))
    d = r / np.sin(np.radians(fov) / 2.0) * 1.05
    for a, e in ((0.4, 35.0), (0.4 + 2.0 * np.pi / 3, 35.0), (0.4 + 4.0 * np.pi / 3, -30.0)):
        e = np.radians(e)
        eye = c + d * np.array([np.cos(e) * np.cos(a), np.sin(e), np.cos(e) * np.sin(a)])
        yield pk.Camera.look_at(tuple(eye), tuple(c), fov_y=fov, width=size, height=size)


def test_walking_methods_cover_a_box_whose_normals_are_averaged(renderer):
    """A 12-triangle box with averaged normals (zoo.smooth_box, as modelling tools export their
    default cube smooth-shaded): the normals curve where the faces are flat, so NCS's and curved
    relief's walks bend out of the shell inside the box's outline. Where the walk leaves the
    shell with its normals far from their faces, with the straight ray still under the mesh, or
    under it at all where the walk has not left the plane of the face it entered (curved
    relief's quadrics, fitted per vertex, bend its search out of a flat face: 2 holes before that
    rule), the base mesh covers the pixel: no interior hole, and IoU against the oracle within
    0.002 of POM's (the base mesh's outline). Before: IoU 0.857 (NCS) and 0.817 (CurvedRelief)
    against POM's 0.964, 313 and 452 holes at 96^2."""
    import zoo
    mesh, h = zoo.smooth_box(128)
    for cam in _wild_views(mesh):
        scene = pk.Scene(mesh=mesh, material=pk.Material(h, depth=0.02), camera=cam,
                         lights=[pk.DirectionalLight((-0.4, -1, -0.3), 3.0)], ambient=0.1)
        ref = pk.oracle.hits(scene)
        pom = pk.metrics.uv_error(renderer.render(scene, pk.POM(), aovs=("uv", "mask")), ref, scene)["mask_iou"]
        for m in (pk.NCS(), pk.CurvedRelief()):
            f = renderer.render(scene, m, aovs=("uv", "mask"))
            iou = pk.metrics.uv_error(f, ref, scene)["mask_iou"]
            n = zoo.interior_holes(f.mask, ref.mask)
            assert n == 0 and iou >= pom - 0.002, (m.name, n, iou, pom)


def test_the_oracle_follows_a_sphere_whose_every_edge_is_hard(renderer):
    """zoo.faceted_sphere at 200 segments (about 40k flat-shaded triangles, as assimp's
    SphereWithLightUvScaling4X.ac is; each narrower than the shell is deep at depth 0.04). A
    flat-shaded quad's two halves carry normals that agree only to float32's rounding, so the
    shell walk crosses their diagonal as a shared side, where the two walls part by that
    rounding times the depth: the oracle took the point it located across as outside the
    neighbour and lost the ray, missing 161-169 interior pixels of about 2000 that Prism and
    Tessellated(1) cover (IoU 0.887-0.896). Measured now: Prism 1.0000 and Tessellated(1)
    0.9995 against it, no interior pixel missed. Held: no interior pixel of either that the
    oracle misses, IoU >= 0.998."""
    import zoo
    mesh, h = zoo.faceted_sphere(200)
    for cam in list(_wild_views(mesh))[::2]:
        scene = pk.Scene(mesh=mesh, material=pk.Material(h, depth=0.04), camera=cam)
        ref = pk.oracle.hits(scene)
        for m in (pk.Prism(), pk.Tessellated(texels_per_vertex=1)):
            f = renderer.render(scene, m, aovs=("uv", "mask"))
            iou = pk.metrics.mask_iou(f, ref)
            missed = zoo.interior_holes(ref.mask, f.mask)
            assert missed == 0 and iou >= 0.998, (m.name, missed, iou)


def _walkers_cover_the_crack(renderer, scene_args):
    """NCS and CurvedRelief on a plane with a crack at x = 0, at three views: no more interior
    holes than POM's, IoU at least POM's, at least 20 fallback pixels from the side."""
    import zoo
    for eye in [(2.2, 1.2, 0.3), (-2.2, 1.0, -0.5), (0.4, 1.4, 2.0)]:
        cam = pk.Camera.look_at(eye, (0, 0, 0), fov_y=40, width=96, height=96)
        scene = pk.Scene(**scene_args, camera=cam)
        ref = pk.oracle.hits(scene)
        pom = renderer.render(scene, pk.POM(), aovs=("mask",))
        base_holes, base_iou = zoo.interior_holes(pom.mask, ref.mask), pk.metrics.mask_iou(pom, ref)
        for m in (pk.NCS(), pk.CurvedRelief()):
            f = renderer.render(scene, m, aovs=("mask", "flags"))
            fallback = int(((np.asarray(f.flags).astype(np.int64) & 4) > 0).sum())
            holes, iou = zoo.interior_holes(f.mask, ref.mask), pk.metrics.mask_iou(f, ref)
            assert holes <= base_holes and iou >= base_iou, (m.name, eye, holes, base_holes, iou, base_iou)
            if eye[2] < 1.0:
                assert fallback >= 20, (m.name, eye, fallback)


def test_the_walking_methods_cover_a_crack_with_their_fallback(renderer):
    """zoo.cracked_plane: two halves of a plane that meet along x = 0 in T-junctions (4 rows
    against 6, no edge shared), with uvs that go on across. A march that walks out of one half
    through the crack has not left the surface, which goes on in the other half (the oracle
    follows it there), but the walk cannot reach that triangle: NCS and CurvedRelief take their
    fallback, the base mesh's point, where they discarded the pixel (measured: 134-142 such
    pixels from the side, 29-30 along the crack, at 96²; none on the same plane welded). Held:
    no more interior holes than POM's, IoU at least POM's, and at least 20 fallback pixels from
    the side."""
    import zoo
    mesh, h = zoo.cracked_plane()
    _walkers_cover_the_crack(renderer, dict(objects=[pk.Object(mesh, pk.Material(h, depth=0.1))]))


def test_the_walking_methods_cover_a_crack_between_objects_with_their_fallback(renderer):
    """zoo.split_plane: cracked_plane's halves as two objects, the right one under a transform
    that scales and moves it, as a model split into primitives by material is. The crack lies
    between the objects' meshes, so that the renderer finds it from the other object's open
    borders (scene contacts). Held as for the crack inside one mesh: no more interior holes than
    POM's, IoU at least POM's, at least 20 fallback pixels from the side (measured without the
    contacts: 125-132 interior holes from the side and 27-28 along the crack for NCS and CurvedRelief; with them 0-1, as POM, and 134-142 and 29-30 fallback pixels)."""
    import zoo
    objs = zoo.split_plane()
    _walkers_cover_the_crack(renderer, dict(objects=objs))


def test_planar_searches_stay_at_the_entry_where_the_ray_does_not_descend(renderer):
    """On zoo.smooth_box the averaged normals face away from the view at fragments well inside
    the outline: there the ray does not descend in its fragment's basis, its slope is 0, and the
    linear searches fall straight down at the entry as the traversals end there. Before, the
    slope was clamped to 1e6 texture units per height and the searches sampled texels anywhere
    in the map (TexturedCube_ImageGlob_248.blend: POM's uv p95 48 million texels). Held: uv p99
    against the oracle under 40 texels (12-17 measured; Flat 1.6-2.8) for each planar search."""
    import zoo
    mesh, h = zoo.smooth_box(128)
    for cam in zoo.views(mesh, elevations=(35.0, 35.0, -30.0)):
        scene = pk.Scene(mesh=mesh, material=pk.Material(h, depth=0.02), camera=cam)
        ref = pk.oracle.hits(scene)
        for m in (pk.SteepParallax(), pk.POM(), pk.Relief(), pk.DistanceMapping()):
            e = pk.metrics.uv_error(renderer.render(scene, m, aovs=("uv", "mask")), ref, scene)
            assert e["p99"] < 40.0, (m.name, e["p99"])
