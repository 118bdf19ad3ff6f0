"""CurvedRelief (Oliveira & Policarpo 2005), the NCS paper's baseline: exact-ish on a plane (its
quadric is zero there, and it is relief mapping), prism-free silhouettes on curved meshes, and
every feature a method has (shadows, AOVs, objects, render_many)."""

import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene
from test_silhouettes import curved


@pytest.mark.parametrize("filtering", ["hardware", "exact"])
def test_plane_matches_the_oracle(renderer, filtering):
    # on a plane the fitted quadric is 0: a linear search of 32 and 6 bisections (measured p95
    # 0.0047 texel on bricks at 60 degrees)
    sc = plane_scene(pk.textures.bricks(128), depth=0.08, theta_deg=60, size=128)
    f = renderer.render(sc, pk.CurvedRelief(filtering=filtering))
    oracle = pk.oracle.hits(sc)
    e = pk.metrics.uv_error(f, oracle, sc)
    assert e["p95"] <= 0.05, e
    # the surface ends at the plane's open border: the rays the oracle (an infinite plane) hits
    # beyond it are no hit (measured: the masks differ at 1 pixel of 13353)
    inside = oracle.mask & np.all((oracle.uv >= 0.0) & (oracle.uv <= 1.0), axis=-1)
    assert int((f.mask != inside).sum()) <= 2, int((f.mask != inside).sum())


@pytest.mark.parametrize("name", ["torus", "sphere"])
@pytest.mark.reference
def test_silhouettes_without_prisms(renderer, name):
    pytest.importorskip("mitsuba")
    # coverage against Mitsuba's displaced mesh (128^2): the curved reference surface lets rays
    # leave the shell (measured at 256^2: torus 0.9917 vs POM 0.9745, sphere 0.9841 vs 0.9571)
    mesh = pk.Mesh.torus(segments=48, tube_segments=24) if name == "torus" else pk.Mesh.sphere(segments=48, rings=24)
    scene = curved(mesh)
    ref = pk.reference.render_mitsuba(scene, spp=1)
    crm = pk.metrics.mask_iou(renderer.render(scene, pk.CurvedRelief()), ref)
    pom = pk.metrics.mask_iou(renderer.render(scene, pk.POM()), ref)
    assert crm >= 0.975 and crm > pom + 0.01, (crm, pom)


def test_quadrics_bend_the_ray_on_a_sphere(renderer):
    """A constant map at h = 1 on a sphere: every hit is at the entry (the curved base), and the
    silhouette rays that leave through the top are discarded, not drawn at the floor."""
    sc = pk.Scene(mesh=pk.Mesh.sphere(segments=48, rings=24), material=pk.Material(pk.textures.constant(16, 1.0), depth=0.2),
                  camera=pk.Camera.look_at((0, 0, 3.0), fov_y=40, width=64, height=64))
    f = renderer.render(sc, pk.CurvedRelief(shadows="none"))
    flat = renderer.render(sc, pk.Flat())
    assert np.array_equal(f.mask, flat.mask)
    m = f.mask
    assert np.nanmax(np.abs(f.depth[m] - flat.depth[m])) < 1e-3


def test_features_of_every_method(renderer):
    sc = curved(pk.Mesh.torus(segments=32, tube_segments=16), size=48)
    sc = sc.replace(ambient=0.2)
    for shadows in ("hard", "soft", "horizon", "exact"):
        f = renderer.render(sc, pk.CurvedRelief(shadows=shadows, ao_directions=4))
        assert np.isfinite(f.color[f.mask]).all() and f.mask.any()
    cams = [pk.Camera.look_at((x, 1.0, 2.8), fov_y=40, width=48, height=48) for x in (-0.5, 0.0, 0.5)]
    many = renderer.render_many([sc.replace(camera=c) for c in cams], pk.CurvedRelief())
    for c, f in zip(cams, many):
        one = renderer.render(sc.replace(camera=c), pk.CurvedRelief())
        assert np.array_equal(one.color, f.color) and np.array_equal(one.uv, f.uv, equal_nan=True)
    two = pk.Scene(objects=[sc.objects[0], pk.Object(pk.Mesh.sphere(0.4), sc.material, pk.scenes.translate(0, 0.6, 0))],
                   camera=sc.camera, lights=sc.lights)
    f = renderer.render(two, pk.CurvedRelief())
    assert set(np.unique(f.object)) >= {0, 1}
