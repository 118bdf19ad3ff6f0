"""DistanceMapping (Donnelly 2005): the distance volume built on the GPU, sphere tracing against
the oracle, and its rebuild after update_height (the volume's layout and memory: the Rust test
in src/methods/distance_mapping/volume.rs)."""

import pytest
from scipy import ndimage

import pomkit as pk
from conftest import marched_past_border, plane_scene


@pytest.mark.parametrize("tex", ["bricks", "cobblestones"])
@pytest.mark.parametrize("theta", [30.0, 60.0])
def test_sphere_tracing_against_the_oracle(renderer, tex, theta):
    # the step never crosses the bounding columns; the last half-texel steps and 6 bisections
    # place the hit (measured p95 0.002-0.005 texel on 256^2 maps at 30 and 60 degrees)
    sc = plane_scene(pk.textures.ALL[tex](256), depth=0.08, theta_deg=theta, size=96)
    f = renderer.render(sc, pk.DistanceMapping())
    ref = pk.oracle.hits(sc)
    e = pk.metrics.uv_error(f, ref, sc)
    assert e["p95"] <= 0.05, e
    # the same coverage but where the march went on past the plane's far border (the oracle ends
    # the surface there; the distance volume tiles on), to a pixel beside it
    past = marched_past_border(f)
    assert ((f.mask != ref.mask) & ~ndimage.binary_dilation(past)).sum() == 0
    assert past.sum() < 0.03 * f.mask.sum()


def test_update_height_rebuilds_the_volume(renderer):
    a, b = pk.textures.bricks(64), pk.textures.spikes(64)
    sc = plane_scene(a, depth=0.1, theta_deg=60.0, size=48)
    renderer.render(sc, pk.DistanceMapping())
    new = renderer.update_height(sc.material, b)
    moved = renderer.render(sc.replace(material=new), pk.DistanceMapping(), aovs=("uv", "mask"))
    e = pk.metrics.uv_error(moved, pk.oracle.hits(sc.replace(material=new)), sc)
    assert e["p95"] <= 0.05, e


def test_more_slices_never_hurt_much(renderer):
    sc = plane_scene(pk.textures.cobblestones(128), depth=0.08, theta_deg=60.0, size=64)
    o = pk.oracle.hits(sc)
    p95 = [pk.metrics.uv_error(renderer.render(sc, pk.DistanceMapping(slices=n)), o, sc)["p95"] for n in (4, 16, 64)]
    assert max(p95) <= 0.05, p95
