"""Engine presets do what their sources say. PlayCanvas v2.22's marched parallax
(pk.presets.playcanvas_pom, from playcanvas/engine #9213, #9219, #9223): at most 16 linear steps
plus the entry sample and five halvings; one mip level for the march; the offset gone where
the march covers under half a texel of that level (a minified plane renders as Flat does)."""

from __future__ import annotations

import numpy as np

import pomkit as pk


def test_playcanvas_takes_at_most_its_budget_of_taps(renderer):
    for theta in (20.0, 60.0, 85.0):
        sc = pk.scenes.tilted_plane(pk.textures.real("gravel", 128), theta, 64)
        f = renderer.render(sc, pk.presets.playcanvas_pom())
        assert f.mask.any() and f.steps[f.mask].max() <= 16 + 1 + 5, theta


def test_playcanvas_fades_out_under_minification(renderer):
    """A 512² map 0.01 deep on a plane 6 units away at 64²: a pixel covers about 20 texels, the
    march (2.6 texels of level 0) under half a texel of the level it reads (4.3), and the uv is
    Flat's."""
    sc = pk.scenes.tilted_plane(pk.textures.bricks(512), 45.0, 64, distance=6.0, depth=0.01)
    f, flat = renderer.render(sc, pk.presets.playcanvas_pom()), renderer.render(sc, pk.Flat())
    m = f.mask & flat.mask
    assert m.sum() > 100
    np.testing.assert_array_equal(f.uv[m], flat.uv[m])
    # up close the same preset does displace
    near = pk.scenes.tilted_plane(pk.textures.bricks(512), 45.0, 64)
    g, flat_near = renderer.render(near, pk.presets.playcanvas_pom()), renderer.render(near, pk.Flat())
    assert np.abs(g.uv - flat_near.uv)[g.mask & flat_near.mask].max() > 1e-3


def test_playcanvas_caps_the_slide_at_five_depths(renderer):
    """At 85° from the normal (tan 11.4) the march slides at most 5 depths along the surface:
    a hit's uv moves from the entry's by at most 5 x depth in texture units (the plane is 2
    units wide, so 0.08 of depth is 0.04 of uv)."""
    sc = pk.scenes.tilted_plane(pk.textures.real("gravel", 128), 85.0, 64)
    f, flat = renderer.render(sc, pk.presets.playcanvas_pom()), renderer.render(sc, pk.Flat())
    m = f.mask & flat.mask
    slide = np.linalg.norm(f.uv[m] - flat.uv[m], axis=-1)
    assert slide.max() <= 5 * 0.04 * 1.01 and slide.max() > 0.04, slide.max()


def _iou(a, b):
    return (a & b).sum() / (a | b).sum()


def test_silhouette_pom_cuts_the_far_border_but_not_the_near_one(renderer):
    """Outlines against the displaced mesh (Tessellated at 4 vertices a texel), bricks and the
    gravel photograph, depth 0.1. At 60° and 70° the clip at the uv bounds removes what POM
    draws beyond the far border (measured IoU: POM 0.967-0.980, silhouette POM 0.990-0.995,
    Prism 0.999-1.0). At 85° the displaced surface hangs below the near border, outside the
    base mesh's pixels, where no per-pixel method on it can draw: both POMs stay at 0.60-0.64
    while Prism, whose shell reaches there, keeps 0.96-1.0."""
    for tex in ("bricks", "gravel"):
        h = pk.textures.real("gravel", 128) if tex == "gravel" else pk.textures.bricks(128)
        for theta in (60.0, 70.0, 85.0):
            sc = pk.scenes.tilted_plane(h, theta, 96, depth=0.1)
            mesh = renderer.render(sc, pk.Tessellated(0.25, shadows="none"), aovs=("mask",)).mask
            pom, sil, prism = (_iou(renderer.render(sc, m, aovs=("mask",)).mask, mesh)
                               for m in (pk.POM(shadows="none"), pk.presets.silhouette_pom(), pk.Prism(shadows="none")))
            if theta < 80:
                assert sil >= 0.985 and sil >= pom + 0.005, (tex, theta, pom, sil)
            else:
                assert prism >= 0.95 and max(pom, sil) < 0.8, (tex, theta, pom, sil, prism)


def test_hdrp_takes_its_steps_and_fades_past_its_lod_threshold(renderer):
    """HDRP's pixel displacement (pk.presets.hdrp_pom): at most 15 linear steps, the two samples
    before the loop and three secant steps; above mip level 6 (threshold 5, faded over one
    level) the offset is gone: a 512² map tiled 64 times on a 64² plane (level 7.85) renders
    Flat's uv, untiled (level 1.85) it displaces."""
    for theta in (20.0, 60.0, 85.0):
        sc = pk.scenes.tilted_plane(pk.textures.bricks(128), theta, 64)
        f = renderer.render(sc, pk.presets.hdrp_pom())
        assert f.mask.any() and f.steps[f.mask].max() <= 2 + 15 + 3, theta
    for tiling, moved in ((64.0, False), (1.0, True)):
        sc = pk.scenes.tilted_plane(pk.textures.bricks(512), 45.0, 64, tiling=tiling)
        f, flat = renderer.render(sc, pk.presets.hdrp_pom()), renderer.render(sc, pk.Flat())
        m = f.mask & flat.mask
        assert (np.abs(f.uv - flat.uv)[m].max() > 1e-3) == moved, tiling


def test_godot_as_shipped_slides_at_most_one_depth_and_pr_97646_follows_the_ray(renderer):
    """Godot 4's shipped deep parallax slides `view_dir.xy * scale` (V.xy): at 80° the hit's uv
    moves from the entry's by at most one depth (0.04 of uv on the 2-unit plane at depth 0.08),
    and the relief is flattened; PR #97646's Z correction (V.xy / V.z) slides as far as the ray
    does (up to tan 80° = 5.7 depths) and lands nearer the oracle's hits (uv p95 against
    `pk.oracle.hits`, lower at 60° and 80°)."""
    for theta in (60.0, 80.0):
        sc = pk.scenes.tilted_plane(pk.textures.real("gravel", 128), theta, 64)
        flat = renderer.render(sc, pk.Flat())
        shipped, pr = (renderer.render(sc, m()) for m in (pk.presets.godot_deep_parallax, pk.presets.godot_deep_parallax_97646))
        m = shipped.mask & pr.mask & flat.mask
        s_shipped = np.linalg.norm(shipped.uv[m] - flat.uv[m], axis=-1).max()
        s_pr = np.linalg.norm(pr.uv[m] - flat.uv[m], axis=-1).max()
        assert s_shipped <= 0.04 * 1.01 and s_pr > 1.5 * s_shipped, (theta, s_shipped, s_pr)
        oracle = pk.oracle.hits(sc)
        e_shipped, e_pr = (pk.metrics.uv_error(f, oracle, sc)["p95"] for f in (shipped, pr))
        assert e_pr < e_shipped, (theta, e_shipped, e_pr)
