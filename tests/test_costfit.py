"""The cost model's fitting and its quad counter (tools/costfit.py, tools/quads.py; run from the
repository's root, as `make check` runs pytest): the fits recover known lines and planes, and
the counts match triangles and frames whose counts are known."""

import numpy as np
import pytest

import pomkit as pk
from tools.costfit import fit_cost, fit_model
from tools.quads import group_total, primitives, quad_count, quads, rasterised


def test_fit_cost_recovers_a_line():
    rows = [dict(fetches_mean=x, gpu_ms=2.0 + 0.5 * x) for x in (1, 4, 9, 30)]
    fit = fit_cost(rows)
    assert abs(fit["a"] - 2.0) < 1e-9 and abs(fit["b"] - 0.5) < 1e-9 and abs(fit["r2"] - 1.0) < 1e-12
    noisy = rows + [dict(fetches_mean=4, gpu_ms=9.0)]
    assert fit_cost(noisy)["r2"] < 0.9


def test_fit_model_recovers_a_plane_and_says_how_well():
    """ms = 2 + 3e-6 fetches + 1e-7 bytes + 5e-5 fragments + 2e-5 quads, sampled where the terms
    vary independently (per-frame totals in the millions, as a real frame's): the weighted,
    non-negative fit gives the coefficients back and R² 1; noise lowers R² below 1, and the
    median and worst relative errors say how far rows are off. A count that only lowers the time
    (here, against the truth, a negative cost) gets 0, not a negative coefficient."""
    rng = np.random.default_rng(0)
    rows = [dict(fetches=float(f), bytes=float(b), fragments=float(g), quads=float(q), noise=float(e))
            for f, b, g, q, e in zip(rng.uniform(0, 4e6, 40), rng.uniform(0, 6e7, 40), rng.uniform(6e4, 3e5, 40),
                                     rng.uniform(1e4, 6e5, 40), rng.uniform(0, 1e5, 40))]
    for x in rows:
        x["gpu_ms"] = 2.0 + 3e-6 * x["fetches"] + 1e-7 * x["bytes"] + 5e-5 * x["fragments"] + 2e-5 * x["quads"]
    fit = fit_model(rows)
    assert fit["r2"] > 1 - 1e-9 and abs(fit["a"] - 2.0) < 1e-6 and fit["n"] == 40 and fit["max_rel_err"] < 1e-6
    assert np.allclose([fit["coef"][k] for k in ("fetches", "bytes", "fragments", "quads")],
                       [3e-6, 1e-7, 5e-5, 2e-5], rtol=1e-6)
    for x in rows:
        x["gpu_ms"] -= 1e-5 * x["noise"]
    signed = fit_model(rows, ("fetches", "bytes", "fragments", "quads", "noise"))
    assert signed["coef"]["noise"] == 0.0 and signed["r2"] < 1 - 1e-6
    for x in rows:
        x["gpu_ms"] = (x["gpu_ms"] + 1e-5 * x["noise"]) * rng.uniform(0.8, 1.2)
    noisy = fit_model(rows)
    assert 0.5 < noisy["r2"] < 0.999 and 0.01 < noisy["med_rel_err"] < noisy["max_rel_err"] and noisy["max_rel_err"] > 0.05
    # too few rows for the terms: NaN, not a fit that means nothing
    assert np.isnan(fit_model(rows[:4])["r2"])


def test_quad_count_is_the_triangle_grown_by_a_quad():
    """`quads`: a triangle touches (A + 2 (w + h) + 4) / 4 quads of 2 x 2 pixels on average over
    its placement (its area grown by the quad, over the quad's area). A right triangle with legs
    of 8 pixels: (32 + 32 + 4) / 4 = 17; a triangle far smaller than a pixel: one quad; half of it
    off the image: the clipped area and box; wholly off: none. A plane seen from above through
    Flat (two triangles over the view) touches about the image's quads; the displaced mesh on it
    adds about 2 (2 + 1) / 4 + 1 quads for each triangle on the image."""
    right = np.array([[[10.0, 10.0], [18.0, 10.0], [10.0, 18.0]]])
    assert quad_count(right, 64, 64) == pytest.approx(17.0)
    tiny = np.array([[[10.0, 10.0], [10.01, 10.0], [10.0, 10.01]]])
    assert quad_count(tiny, 64, 64) == pytest.approx(1.0 + 0.01, abs=1e-4)
    # moved 14 pixels left, the part on the image (x >= 0) is the right triangle with legs of 4
    # at (0, 10): area 8, box 4 x 4, so (8 + 16 + 4) / 4 = 7
    assert quad_count(right - np.array([14.0, 0.0]), 64, 64) == pytest.approx(7.0)
    assert quad_count(right + 100.0, 64, 64) == 0.0
    h = pk.textures.bricks(32)
    top = pk.Scene(mesh=pk.Mesh.plane(size=4.0), material=pk.Material(h, depth=0.02),
                   camera=pk.Camera.look_at((0.0, 2.0, 0.0), up=(0, 0, -1), fov_y=40, width=48, height=48))
    q = quads(top, pk.Flat())
    assert 48 * 48 / 4 <= q <= 1.2 * 48 * 48 / 4
    # Tessellated(0.5) on the 32² map: lattice quads of 2 x 2 pixels, four triangles each of
    # about a pixel, so each triangle touches (1 + 2 (2 + 1) + 4) / 4 ~ 2.75 quads: the image's
    # 576 quads grown by ~2 for each of its ~2300 triangles; Tessellated(2) (8 x 8 pixel lattice
    # quads, ~144 triangles on the image) by ~7 a triangle
    fine, coarse = quads(top, pk.Tessellated(0.5)), quads(top, pk.Tessellated(2.0))
    assert 576 + 2 * 2000 < fine < 576 + 2.5 * 2600 and 576 + 5 * 120 < coarse < 576 + 8 * 170, (fine, coarse)


def test_group_total_charges_each_block_its_longest_lane():
    a = np.zeros((4, 8))
    a[0, 0] = 100  # one slow lane: its 4 x 8 block of 32 waits for it
    assert group_total(a) == 3200 and a.sum() == 100
    # a partial block at the edge counts its own pixels
    b = np.ones((5, 9))
    assert group_total(b) == 45


def test_rasterised_counts_the_triangles_that_face_the_camera():
    """The cost model's `rasterised` term: back faces are culled, so a plane seen from above sends
    all its triangles, from below none; a sphere from outside about half (its front hemisphere,
    less the sliver the eye's finite distance hides); Tessellated its displaced mesh's faces that
    face the eye; Prism one per base triangle (a top facing the eye or a bottom facing it)."""
    h = pk.textures.bricks(64)
    above = pk.Scene(mesh=pk.Mesh.plane(), material=pk.Material(h, depth=0.05),
                     camera=pk.Camera.look_at((0.0, 2.0, 0.5), target=(0, 0, 0), fov_y=40, width=32, height=32))
    below = above.replace(camera=pk.Camera.look_at((0.0, -2.0, 0.5), target=(0, 0, 0), fov_y=40, width=32, height=32))
    n = len(above.mesh.indices) // 3
    assert rasterised(above, pk.POM()) == n and rasterised(below, pk.POM()) == 0
    assert rasterised(above, pk.Prism()) == n == primitives(above, pk.Prism()) // 2
    tess = pk.Tessellated(2.0)
    assert rasterised(below, tess) < 0.01 * primitives(below, tess) < rasterised(above, tess) <= primitives(above, tess)
    sphere = pk.Scene(mesh=pk.Mesh.sphere(segments=32, rings=16), material=pk.Material(h, depth=0.02),
                      camera=pk.Camera.look_at((0.0, 0.0, 3.0), fov_y=40, width=32, height=32))
    m = len(sphere.mesh.indices) // 3
    # the eye at distance 3 sees the cap up to cos = 1/3 from the axis: (1 - 1/3) / 2 of the area
    assert 0.25 * m < rasterised(sphere, pk.Flat()) < 0.5 * m
