"""pk.Hybrid (issue 68): a coarse mesh displaced at its vertices (Tessellated's lattice) and a
per-pixel method that marches the rest, in the window the coarse triangles bound the field to.

- With a flat coarse mesh (pk.Flat()) it is its fine method, bit for bit.
- At one texel a vertex it is within Tessellated's uv p95 (+ 0.01 texel) against the oracle,
  and with Exact or ConeStep (the safe searches) as its fine method it is exact at every spacing.
- The coarse mesh leaves no crack along its edges or across seams: no interior hole on the zoo's
  assets, against the oracle's coverage.
The window itself holds the field over every coarse triangle: src/methods/hybrid's Rust test."""

from __future__ import annotations

import numpy as np
import pytest

import pomkit as pk
import zoo
from pomkit.bench import plane_scene


def _pom(n: int = 16) -> pk.POM:
    return pk.POM(shadows="none", adaptive=False, min_steps=n, max_steps=n, mip_filtering=False, lod_threshold=1000.0)


def test_a_flat_coarse_mesh_is_the_fine_method_alone(renderer):
    """The same mesh drawn through the method's own vertex buffer (with its window attribute):
    the same pixels, and colour and uv the same to float32 rounding of the interpolation."""
    mesh = pk.Mesh.torus()
    cam = pk.Camera.look_at((0.0, 2.2, 2.4), width=96, height=96)
    sc = pk.Scene(mesh=mesh, material=pk.Material(pk.textures.bricks(128), depth=0.05), camera=cam,
                  lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)], ambient=0.1)
    for fine in (pk.POM(), pk.Exact(shadows="soft")):
        a = renderer.render(sc, fine, aovs=("color", "uv", "mask", "depth"))
        b = renderer.render(sc, pk.Hybrid(coarse=pk.Flat(), fine=fine), aovs=("color", "uv", "mask", "depth"))
        assert a.mask.sum() > 1000
        assert (a.mask != b.mask).sum() <= 2
        both = a.mask & b.mask
        np.testing.assert_allclose(a.color[both], b.color[both], atol=1e-4)
        np.testing.assert_allclose(a.uv[both] * 128, b.uv[both] * 128, atol=1e-3)  # texels


@pytest.mark.parametrize("tex", ["bricks", "terrain"])
def test_one_texel_a_vertex_converges_to_tessellated_and_exact_is_exact(renderer, tex):
    h = pk.textures.bricks(128) if tex == "bricks" else pk.textures.real("terrain", 128)
    for angle in (30.0, 70.0):
        sc = plane_scene(h, angle, 96)
        o = pk.oracle.hits(sc)
        tess = pk.metrics.uv_error(renderer.render(sc, pk.Tessellated(texels_per_vertex=1.0, shadows="none")), o, sc)["p95"]
        hyb = pk.metrics.uv_error(renderer.render(sc, pk.Hybrid(coarse=pk.Tessellated(texels_per_vertex=1.0), fine=_pom())), o, sc)["p95"]
        assert hyb <= tess + 0.01, (tex, angle, hyb, tess)
        for tpv in (1.0, 8.0, 32.0):
            for fine in (pk.Exact(), pk.ConeStep()):  # the safe searches stay exact
                f = renderer.render(sc, pk.Hybrid(coarse=pk.Tessellated(texels_per_vertex=tpv), fine=fine))
                assert pk.metrics.uv_error(f, o, sc)["p95"] <= 0.01, (tex, angle, tpv, fine.name)


@pytest.mark.parametrize("name", ["rock", "crate", "mirrored_slab"])
def test_no_crack_along_coarse_edges_or_seams_on_the_zoo(renderer, name):
    mesh, _ = zoo.ZOO[name]()
    for cam in zoo.views(mesh, n=2):
        sc = zoo.scene(name, cam)
        o = pk.oracle.hits(sc)
        for tpv in (4.0, 16.0):
            f = renderer.render(sc, pk.Hybrid(coarse=pk.Tessellated(texels_per_vertex=tpv), fine=pk.Exact()))
            assert zoo.interior_holes(f.mask, o.mask) == 0, (name, tpv)


def test_the_arguments_are_checked():
    with pytest.raises(pk.ArgumentTypeError, match="coarse"):
        pk.Hybrid(coarse=pk.POM())
    with pytest.raises(pk.ArgumentError, match="fine"):
        pk.Hybrid(fine=pk.NCS())
