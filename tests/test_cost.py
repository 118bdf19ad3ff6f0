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
