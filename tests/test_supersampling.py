"""Supersampling (`spp=`): k x k stratified samples per pixel in one pass at k² the pixels,
colour box-filtered, coverage the fraction of samples that hit; the other AOVs from a
one-sample pass (the plain frame's)."""

import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene

LIGHT = pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)


@pytest.fixture(scope="module")
def scene():
    # the plane's outline is in view: the top rows see past its far edge
    return plane_scene(pk.textures.bricks(64), theta_deg=62.0, size=48, lights=[LIGHT], ambient=0.1)


@pytest.mark.parametrize("method", [pk.Flat(), pk.POM(), pk.Exact(), pk.Prism(), pk.Tessellated(2.0)], ids=lambda m: m.name)
def test_spp_1_is_the_plain_frame_bit_for_bit(renderer, scene, method):
    a = renderer.render(scene, method)
    b = renderer.render(scene, method, spp=1)
    assert a.aovs == b.aovs
    for name in a.aovs:
        x, y = getattr(a, name), getattr(b, name)
        assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name


@pytest.mark.parametrize("spp", [4, 9])
@pytest.mark.parametrize("method", [pk.Flat(), pk.Exact(), pk.Prism()], ids=lambda m: m.name)
def test_geometric_aovs_are_the_plain_frames(renderer, scene, method, spp):
    """uv, depth, mask, steps, lod, flags, object and the counters come from a one-sample pass:
    the plain frame's, bit for bit."""
    names = ("uv", "depth", "mask", "steps", "lod", "flags", "object", "fetches")
    a = renderer.render(scene, method, aovs=names)
    b = renderer.render(scene, method, aovs=("color", "coverage") + names, spp=spp)
    assert b.color.shape[:2] == a.uv.shape[:2]
    for n in names:
        x, y = getattr(a, n), getattr(b, n)
        assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), n


def test_coverage_and_the_box_filter(renderer, scene):
    f1 = renderer.render(scene, pk.Flat())
    f = renderer.render(scene, pk.Flat(), spp=16)
    cov = f.coverage
    assert cov.dtype == np.float32 and cov.min() == 0.0 and cov.max() == 1.0
    assert np.array_equal(np.unique(f1.coverage), [0.0, 1.0]) and np.array_equal(f1.coverage > 0, f1.mask)
    # the outline's pixels are partly covered, in multiples of 1/16
    part = (cov > 0) & (cov < 1)
    assert part.sum() >= scene.camera.width // 2
    assert np.allclose(cov * 16, np.round(cov * 16))
    # colour is the mean of the samples: a partly covered pixel is darker than its covered
    # neighbour by about its coverage (the background is black)
    big = renderer.render(scene.replace(camera=pk.Camera.look_at(
        eye=scene.camera.eye, target=scene.camera.target, up=scene.camera.up, fov_y=scene.camera.fov_y,
        width=scene.camera.width * 4, height=scene.camera.height * 4)), pk.Flat())
    mean = big.color.reshape(48, 4, 48, 4, 3).mean(axis=(1, 3))
    assert np.abs(mean - f.color).max() < 1e-5
    assert np.array_equal(big.mask.reshape(48, 4, 48, 4).mean(axis=(1, 3)), cov)


@pytest.mark.parametrize("bad,err", [(8, ValueError), (0, ValueError), (True, TypeError), (2.0, TypeError), (289, ValueError)])
def test_bad_spp_names_the_argument(renderer, scene, bad, err):
    with pytest.raises(err, match="spp"):
        renderer.render(scene, pk.Flat(), spp=bad)


def test_render_many_takes_spp(renderer, scene):
    fs = renderer.render_many([scene, scene], pk.POM(), aovs=("color", "coverage"), spp=4)
    one = renderer.render(scene, pk.POM(), aovs=("color", "coverage"), spp=4)
    for f in fs:
        assert np.array_equal(f.color, one.color) and np.array_equal(f.coverage, one.coverage)
