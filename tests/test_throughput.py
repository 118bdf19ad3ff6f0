"""AOVs on demand, frames in batches, and scene data converted once (issue 14). None of these
tests is timed: speed lives in `python -m pomkit bench`."""

import pickle

import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene

LIGHT = pk.DirectionalLight((-0.3, -1.0, -0.4), 3.0, angular_diameter=2.0)


def _same(a, b):
    """Bit-identical arrays (NaN where NaN)."""
    return a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")


@pytest.fixture(scope="module")
def scene():
    return plane_scene(pk.textures.bricks(64), theta_deg=60.0, size=48, lights=[LIGHT], ambient=0.1)


@pytest.mark.parametrize("method", [pk.POM(), pk.Exact(), pk.Flat(), pk.Prism(), pk.NCS(), pk.Tessellated()],
                         ids=lambda m: m.name)
@pytest.mark.parametrize("aovs", [("color",), ("uv",), ("mask",), ("color", "uv"), ("steps", "flags"),
                                  ("depth", "lod"), ("color", "steps"), ("fetches",), ("color", "bytes", "object")])
def test_aov_subsets_equal_the_full_frame(renderer, scene, method, aovs):
    # every AOV, the cost counters too: counting changes no other AOV
    full = renderer.render(scene, method, aovs=pk.AOV_NAMES)
    part = renderer.render(scene, method, aovs=aovs)
    assert part.aovs == tuple(a for a in pk.AOV_NAMES if a in aovs)
    for a in aovs:
        assert _same(getattr(part, a), getattr(full, a)), a
    for a in set(pk.AOV_NAMES) - set(aovs):
        with pytest.raises(AttributeError, match="aovs="):
            getattr(part, a)


@pytest.mark.parametrize("bad", [(), ("colour",), "uv", 3])
def test_bad_aovs_name_the_argument(renderer, scene, bad):
    with pytest.raises((ValueError, TypeError), match="aovs"):
        renderer.render(scene, pk.POM(), aovs=bad)


def test_render_many_equals_one_by_one(renderer, scene):
    # one scene under many cameras, two sizes interleaved (the target pool must not mix them)
    cams = [pk.Camera.look_at((0.0, 2 * np.cos(t), 2 * np.sin(t)), up=(0, 0, -1), fov_y=30, width=w, height=w)
            for t, w in zip(np.radians([0, 20, 40, 60, 75, 85]), [48, 48, 32, 48, 32, 32])]
    scenes = [scene.replace(camera=c) for c in cams]
    for method, aovs in [(pk.POM(), "all"), (pk.Exact(shadows="hard"), ("color", "uv")), (pk.Prism(), ("uv",))]:
        batch = renderer.render_many(scenes, method, aovs=aovs)
        assert len(batch) == len(scenes)
        for sc, f in zip(scenes, batch):
            one = renderer.render(sc, method, aovs=aovs)
            assert f.aovs == one.aovs
            for a in f.aovs:
                assert _same(getattr(f, a), getattr(one, a)), (method.name, a)


def test_render_many_sweeps_a_parameter(renderer):
    # a sweep of the material's depth: a different material per frame
    h = pk.textures.noise(64)
    scenes = [plane_scene(h, depth=d, theta_deg=55.0, size=32) for d in (0.02, 0.05, 0.1, 0.2)]
    batch = renderer.render_many(scenes, pk.Relief(), aovs=("uv", "mask"))
    for sc, f in zip(scenes, batch):
        assert _same(f.uv, renderer.render(sc, pk.Relief()).uv)
    assert renderer.render_many([], pk.POM()) == []


def test_scenes_pickle_without_their_core_handles(renderer, scene):
    f = renderer.render(scene, pk.POM(), aovs=("color", "uv"))
    assert "_core_height" in scene.material.__dict__  # made by the first render
    back = pickle.loads(pickle.dumps(scene))
    assert "_core_height" not in back.material.__dict__
    g = renderer.render(back, pk.POM(), aovs=("color", "uv"))
    assert _same(f.color, g.color) and _same(f.uv, g.uv)
    assert back.material._height_data().key == scene.material._height_data().key


def test_bad_albedo_is_refused_once_converted(renderer):
    # the albedo's values are checked when the core converts it, not on every render
    al = np.full((8, 8, 3), 0.5, np.float32)
    al[2, 3, 1] = np.nan
    with pytest.raises(ValueError, match="albedo"):
        renderer.render(plane_scene(pk.textures.bricks(8), size=8, albedo=al), pk.Flat())


def test_subset_targets_are_cleared_on_fresh_targets(renderer):
    """A frame of only uv and mask, at a size no earlier frame used (fresh targets): the pixels
    without a hit are cleared, not read as hits. On wgpu's GL backend the geo target alone (at
    location 1, no colour target) was not cleared: every pixel of a new target read as a hit."""
    sc = plane_scene(pk.textures.bricks(64), depth=0.1, theta_deg=70.0, size=37)
    sc = sc.replace(camera=pk.Camera.look_at(sc.camera.eye, (0, 0, 0), up=(0, 0, -1), fov_y=30.0, width=37, height=29))
    part = renderer.render(sc, pk.POM(), aovs=("uv", "mask"))
    full = renderer.render(sc, pk.POM())
    assert 0 < full.mask.sum() < full.mask.size
    assert np.array_equal(part.mask, full.mask)
