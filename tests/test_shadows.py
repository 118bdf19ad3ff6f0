"""Self-shadowing against ground truth: each shadow mode's shadow-mask IoU and visibility error
against the float64 oracle's exact visibility (`pk.oracle.hits`, 64 directions over a 2-degree
light's disk), through `pk.metrics.shadow_error`. Bounds are the measured values (llvmpipe,
128² frames of a 128² map at 60 degrees, light (-0.4, -0.5, -0.3)) less a margin, each with
its reason; docs/tables/shadows.md has the full table."""

import numpy as np
import pytest

import pomkit as pk
from conftest import plane_scene

LIGHT = pk.DirectionalLight(direction=(-0.4, -0.5, -0.3), irradiance=3.0, angular_diameter=2.0)

# (map, method, shadows) -> (least IoU, largest visibility error, reason); measured IoU / error in the reason
BOUNDS = {
    ("bricks", "Exact", "exact"): (0.98, 0.002, "exact walk; only the 2-degree disk differs from its one ray (1.000 / 0.0008)"),
    ("cobblestones", "Exact", "exact"): (0.97, 0.006, "as above; rounder blockers, wider penumbrae (0.988 / 0.0048)"),
    ("bricks", "ConeStep", "exact"): (0.98, 0.002, "the same light walk from a safe hit (as Exact)"),
    ("bricks", "POM", "exact"): (0.97, 0.002, "exact light walk from POM's approximate hit (0.995 / 0.0009)"),
    ("bricks", "POM", "hard"): (0.94, 0.002, "8 samples along the light ray step over thin blockers (0.970 / 0.0012)"),
    ("bricks", "POM", "soft"): (0.94, 0.002, "the hard test's samples, penumbra estimated (0.970 / 0.0010)"),
    ("cobblestones", "POM", "hard"): (0.86, 0.013, "as above (0.890 / 0.0116)"),
    ("cobblestones", "POM", "soft"): (0.86, 0.012, "as above (0.890 / 0.0101)"),
    ("bricks", "POM", "horizon"): (0.27, 0.07, "the max of a 2^k footprint read as if at distance 2^k: false shadows (0.306 / 0.0617)"),
    ("cobblestones", "POM", "horizon"): (0.28, 0.20, "as above (0.312 / 0.1905)"),
}
METHODS = {"Exact": pk.Exact, "ConeStep": pk.ConeStep, "POM": pk.POM}


@pytest.fixture(scope="module")
def scenes():
    out = {}
    for name in ("bricks", "cobblestones"):
        sc = plane_scene(pk.textures.ALL[name](128), depth=0.08, theta_deg=60, size=128, lights=[LIGHT])
        out[name] = (sc, pk.oracle.hits(sc))
    return out


@pytest.mark.parametrize("key", list(BOUNDS), ids=["-".join(k) for k in BOUNDS])
def test_shadow_mode_against_the_oracle(renderer, scenes, key):
    tex, method, shadows = key
    lo_iou, hi_err, why = BOUNDS[key]
    sc, oracle = scenes[tex]
    e = pk.metrics.shadow_error(renderer.render_visibility(sc, METHODS[method](shadows=shadows)), oracle, sc)
    assert e["compared"] > 0.9, e["compared"]
    assert e["iou"] >= lo_iou, f"{key}: IoU {e['iou']:.3f} < {lo_iou} ({why})"
    assert e["vis_error"] <= hi_err, f"{key}: visibility error {e['vis_error']:.4f} > {hi_err} ({why})"


def test_soft_shadows_are_closer_than_hard_in_the_penumbra(renderer, scenes):
    """Tatarchuk's penumbra estimate must bring the visibility closer to the area light's than
    the hard test it refines (same samples)."""
    for tex in ("bricks", "cobblestones"):
        sc, oracle = scenes[tex]
        hard = pk.metrics.shadow_error(renderer.render_visibility(sc, pk.POM(shadows="hard")), oracle, sc)
        soft = pk.metrics.shadow_error(renderer.render_visibility(sc, pk.POM(shadows="soft")), oracle, sc)
        assert soft["vis_error"] < hard["vis_error"], (tex, soft["vis_error"], hard["vis_error"])


def test_oracle_visibility_of_a_wall_is_analytic():
    """The oracle's visibility on a floor behind a full-height wall, light from +x at 45 degrees:
    the shadow's length is the shell depth (one depth of floor per depth of height)."""
    n = 64
    h = np.zeros((n, n), np.float32)
    h[:, 40:48] = 1.0
    depth = 0.25  # 8 texels of a size-2 plane
    sc = plane_scene(h, depth=depth, theta_deg=0, size=128, fov=60.0,
                     lights=[pk.DirectionalLight((-1.0, -1.0, 0.0), 3.0)])
    o = pk.oracle.hits(sc)
    x = o.uv[..., 0] * n - 0.5  # texel-space x of each hit
    floor = o.mask & (x > 20) & (x < 39)
    # the ramp from x = 39 (h 0) to x = 40 (h 1); a 45-degree ray rises one shell depth per 8 texels
    shadowed = floor & (x > 32.05) & (x < 38.95)
    lit = floor & (x < 31.95)
    assert shadowed.any() and lit.any()
    assert (o.visibility[shadowed] == 0).all()
    assert (o.visibility[lit] == 1).all()


def test_shadow_error_needs_visibility(renderer, scenes):
    sc, oracle = scenes["bricks"]
    with pytest.raises(ValueError, match="visibility"):
        pk.metrics.shadow_error(renderer.render(sc, pk.POM()), oracle, sc)
