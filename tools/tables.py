"""Measured tables for docs/tables (`make tables`: --set quick; `make tables-slow`: --set reference;
or `python tools/tables.py [--out DIR] [--set quick|reference|all] [--only NAME]`): generated, never
typed by hand, each under its provenance line (tools/provenance.py)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Callable

import numpy as np

import pomkit as pk
from pomkit import metrics

from provenance import stamp


def _plane(height, theta, size, lights=(), depth=0.08):
    return pk.scenes.tilted_plane(height, theta, size, depth=depth, lights=lights)


def references_table(size: int = 128) -> str:
    """POM, Bump, Flat (and Tessellated) against Mitsuba on bricks at 30/60/80 degrees: uv p95
    (texels) and FLIP; pyrender against Mitsuba; the time of each reference render."""
    from pomkit import reference as R
    r = pk.Renderer()
    rows = ["The colour references against each other and against pk.oracle.image, scene by scene with their times "
            "(issue 30's table), are in reference_agreement.md (`tools/reference_agreement.py`). This table: bricks "
            "128² against `render_mitsuba()`.", "",
            "| angle | method | uv p95 (texels) | FLIP | mask IoU |", "|---|---|---|---|---|"]
    times = []
    for theta in (30.0, 60.0, 80.0):
        scene = _plane(pk.textures.bricks(128), theta, size, [pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)])
        t0 = time.perf_counter()
        ref = R.render_mitsuba(scene, spp=16, cache=False)
        tm = time.perf_counter() - t0
        t0 = time.perf_counter()
        pr = R.render_pyrender(scene, cache=False)
        tp = time.perf_counter() - t0
        times.append((theta, tm, tp))
        for m in (pk.Flat(), pk.Bump(), pk.POM(shadows="none"), pk.POM(shadows="hard"), pk.Tessellated(0.5)):
            f = r.render(scene, m)
            e = metrics.uv_error(f, ref, scene)
            label = m.name + (f" ({m.shadows})" if hasattr(m, "shadows") else "")
            rows.append(f"| {theta:.0f}° | {label} | {e['p95']:.3f} | {metrics.flip(f, ref):.4f} | {e['mask_iou']:.4f} |")
        rows.append(f"| {theta:.0f}° | pyrender | - | {metrics.flip(pr, ref):.4f} | {metrics.mask_iou(pr, ref):.4f} |")
    rows += ["", "| angle | Mitsuba render (s, spp 16, incl. scene build) | pyrender render (s) |", "|---|---|---|"]
    rows += [f"| {t:.0f}° | {a:.2f} | {b:.2f} |" for t, a, b in times]
    return "\n".join(rows)


POM_ANGLES = (30.0, 60.0, 72.0, 80.0)


def pom_default_table(size: int = 128, map_size: int = 256, spp: int = 64) -> tuple[str, dict]:
    """Issue 11's evidence for POM's default: the mip-filtered march (Tatarchuk's tex2Dgrad,
    `mip_filtering=True`) against the level-0 march (`mip_filtering=False`), on every map of
    `pk.textures` at 30/60/72/80 degrees: uv p95 against the exact oracle (texels) and FLIP
    against Mitsuba's 64-spp render of the displaced mesh (cached on disk). Lit, no shadows, so
    that FLIP sees the surface's shape and not the shadow method. Returns the table and the
    medians."""
    from pomkit import reference as R
    r = pk.Renderer()
    light = [pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)]
    variants = {"mip-filtered": pk.POM(shadows="none", mip_filtering=True),
                "level 0": pk.POM(shadows="none", mip_filtering=False)}
    rows = ["| map | angle | uv p95 mip-filtered | uv p95 level 0 | FLIP mip-filtered | FLIP level 0 |",
            "|---|---|---|---|---|---|"]
    acc: dict[str, dict[str, list[float]]] = {k: {"p95": [], "flip": []} for k in variants}
    for tex in sorted(pk.textures.ALL):
        h = pk.textures.ALL[tex](map_size)
        for theta in POM_ANGLES:
            sc = _plane(h, theta, size, light)
            oracle = pk.oracle.hits(sc)
            ref = R.render_mitsuba(sc, spp=spp)
            cells = []
            for k, m in variants.items():
                f = r.render(sc, m)
                e = metrics.uv_error(f, oracle, sc)["p95"]
                fl = metrics.flip(f, ref)
                acc[k]["p95"].append(e)
                acc[k]["flip"].append(fl)
                cells.append((e, fl))
            rows.append(f"| {tex} | {theta:.0f}° | {cells[0][0]:.3f} | {cells[1][0]:.3f} | {cells[0][1]:.4f} | {cells[1][1]:.4f} |")
    med = {k: {m: float(np.median(v)) for m, v in d.items()} for k, d in acc.items()}
    wins = {m: sum(a < b for a, b in zip(acc["level 0"][m], acc["mip-filtered"][m])) for m in ("p95", "flip")}
    n = len(acc["level 0"]["p95"])
    rows += ["", "| | uv p95 median | FLIP median | cases where level 0 is better (uv / FLIP) |", "|---|---|---|---|",
             f"| mip-filtered | {med['mip-filtered']['p95']:.3f} | {med['mip-filtered']['flip']:.4f} | |",
             f"| level 0 | {med['level 0']['p95']:.3f} | {med['level 0']['flip']:.4f} | {wins['p95']}/{n} / {wins['flip']}/{n} |"]
    return "\n".join(rows), dict(medians=med, wins=wins, cases=n)


STABILITY_ANGLES = (0.0, 30.0, 60.0, 80.0, 85.0, 89.5)


def default_methods() -> dict:
    """Each method at its default settings (POM without shadows so that timings compare the
    view-ray search)."""
    return {
        "Flat": pk.Flat(), "Bump": pk.Bump(), "Parallax": pk.Parallax(), "SteepParallax": pk.SteepParallax(),
        "POM": pk.POM(shadows="none"), "Relief": pk.Relief(), "Exact": pk.Exact(), "ConeStep": pk.ConeStep(),
        "Tessellated": pk.Tessellated(shadows="none"),
    }


def stability_table(textures=("bricks", "spikes", "terrain", "gravel"), size: int = 128, map_size: int = 256) -> str:
    """p95 uv error (texels) against the oracle per method and engine preset x angle, and
    Exact's iterations, on pk.textures maps and real content (pk.textures.real: an elevation
    model, a photograph)."""
    r = pk.Renderer()
    methods = dict(default_methods(), **{f"preset {n}": fn() for n, fn in pk.presets.ALL_PRESETS.items()})
    lines = []
    for tex in textures:
        h = pk.textures.ALL[tex](map_size) if tex in pk.textures.ALL else pk.textures.real(tex, map_size)
        lines += [f"\n**{tex}** ({map_size}² map, {size}² frame, depth 0.08): uv p95 in texels\n",
                  "| method | safety | " + " | ".join(f"{a:g}°" for a in STABILITY_ANGLES) + " |",
                  "|---|---|" + "---|" * len(STABILITY_ANGLES)]
        oracles = {a: (sc, pk.oracle.hits(sc)) for a in STABILITY_ANGLES for sc in [_plane(h, a, size)]}
        iters = []
        for name, m in methods.items():
            row = []
            for a in STABILITY_ANGLES:
                sc, o = oracles[a]
                f = r.render(sc, m)
                e = metrics.uv_error(f, o, sc)
                row.append(f"{e['p95']:.3f}")
                if name == "Exact":
                    iters.append((a, float(f.steps[f.mask].mean()), int(f.steps[f.mask].max()), int((f.flags[f.mask] & 1).sum())))
            lines.append(f"| {name} | {m.safety} | " + " | ".join(row) + " |")
        lines += ["", "Exact's traversal iterations (mean / max / rays at the bound): " +
                  ", ".join(f"{a:g}°: {mn:.1f} / {mx} / {b}" for a, mn, mx, b in iters)]
    lines += ["", "## Contact refinement at equal taps", "", equal_taps_table.__doc__.strip().replace("\n    ", " "), "",
              equal_taps_table(map_size=map_size, size=size)]
    lines += ["", "## Normalising the range against more layers", "",
              normalise_or_layers_table.__doc__.strip().replace("\n    ", " "), "",
              normalise_or_layers_table(map_size=map_size, size=size)]
    return "\n".join(lines)


def _taps_and_error(r, m, sc, o) -> tuple[float, float]:
    f = r.render(sc, m, aovs=("color", "uv", "mask", "steps"))
    return float(f.steps[f.mask].mean()), metrics.uv_error(f, o, sc)["p95"]


def equal_taps_table(size: int = 128, map_size: int = 256, angles=(30.0, 60.0, 80.0)) -> str:
    """QGIS's contact refinement against POM and Relief at equal taps: each searches level 0
    along the exact ray (contact refinement also as QGIS ships it: offset-limited slide and the
    footprint's level), POM at a fixed count and Relief at linear + 5 binary taps, each count
    chosen so that its mean taps match contact refinement's on the scene. uv p95 (texels)
    against the oracle, with the mean taps (the `steps` AOV: every tap, entry and refinement)."""
    import dataclasses
    r = pk.Renderer()
    cr = pk.presets.qgis_contact_refinement()
    exact_cr = dataclasses.replace(cr, params={"steps": 15.0, "offset_limiting": 0.0}, mip_filtering=False)
    lines = ["| map | angle | contact refinement (QGIS: offset-limited, footprint level) | contact refinement (exact ray, level 0) | POM (same taps) | Relief (same taps) |",
             "|---|---|---|---|---|---|"]
    for tex in ("bricks", "terrain"):
        h = pk.textures.ALL[tex](map_size) if tex in pk.textures.ALL else pk.textures.real(tex, map_size)
        for a in angles:
            sc = _plane(h, a, size)
            o = pk.oracle.hits(sc)
            q = _taps_and_error(r, cr, sc, o)
            t, e = _taps_and_error(r, exact_cr, sc, o)
            pom = min((_taps_and_error(r, pk.POM(shadows="none", adaptive=False, min_steps=n, max_steps=n, lod_threshold=1000.0, mip_filtering=False), sc, o)
                       for n in range(2, 33)), key=lambda x: abs(x[0] - t))
            rel = min((_taps_and_error(r, pk.Relief(linear_steps=n, binary_steps=5, mip_filtering=False), sc, o)
                       for n in range(1, 28)), key=lambda x: abs(x[0] - t))
            cell = lambda x: f"{x[1]:.3f} ({x[0]:.1f} taps)"  # noqa: E731
            lines.append(f"| {tex} | {a:g}° | {cell(q)} | {cell((t, e))} | {cell(pom)} | {cell(rel)} |")
    return "\n".join(lines)


def normalise_or_layers_table(size: int = 128, map_size: int = 256, angles=(30.0, 60.0, 80.0)) -> str:
    """Godot's claim (godotengine/godot #100226: stretching a map's range helps more than raising
    the layer count to 64): a map that holds 0.55..0.85 of 0..1 (a real elevation model,
    squeezed), at depth 0.08, under SteepParallax and POM at 16, 32 and 64 layers, against the
    same relief normalised (`pk.textures.normalize`, depth 0.08 x 0.3: the same relief, its top
    moved up to the mesh) at 16 layers. uv p95 in texels against each scene's own oracle."""
    r = pk.Renderer()
    raw = 0.55 + 0.3 * pk.textures.real("terrain", map_size)
    norm = pk.textures.normalize(raw)
    lines = ["| method | " + " | ".join(f"{a:g}°" for a in angles) + " |", "|---|" + "---|" * len(angles)]
    cases = []
    for name, cls in (("SteepParallax", pk.SteepParallax), ("POM", pk.POM)):
        kw = dict(mip_filtering=False) if name == "SteepParallax" else dict(shadows="none", adaptive=False, lod_threshold=1000.0, mip_filtering=False)
        for n in (16, 32, 64):
            m = cls(steps=n, **kw) if name == "SteepParallax" else cls(min_steps=n, max_steps=n, **kw)
            cases.append((f"{name}, {n} layers, raw map (0.55..0.85)", m, raw, 0.08))
        m16 = cls(steps=16, **kw) if name == "SteepParallax" else cls(min_steps=16, max_steps=16, **kw)
        cases.append((f"{name}, 16 layers, normalised map (depth x 0.3)", m16, norm, 0.08 * 0.3))
    for label, m, h, depth in cases:
        row = []
        for a in angles:
            sc = _plane(h, a, size, depth=depth)
            row.append(f"{metrics.uv_error(r.render(sc, m), pk.oracle.hits(sc), sc)['p95']:.3f}")
        lines.append(f"| {label} | " + " | ".join(row) + " |")
    return "\n".join(lines)


SHADOW_ANGLES = (30.0, 60.0, 72.0, 80.0)


def shadows_table(size: int = 128, map_size: int = 128, repeats: int = 3) -> str:
    """Each method x shadow mode against the float64 oracle's exact visibility (a 2-degree
    light, 64 directions over its disk) on the stability maps and a real elevation model and
    photograph, at 30/60/72/80 degrees: the shadow-mask IoU, the mean visibility error, and
    the cost above shadows="none" (GPU ms, medians of interleaved rounds, one run per scene)."""
    from pomkit.bench import time_methods
    r = pk.Renderer()
    light = pk.DirectionalLight((-0.4, -0.5, -0.3), 3.0, angular_diameter=2.0)
    maps = {"bricks": pk.textures.bricks(map_size), "spikes": pk.textures.spikes(map_size),
            "cobblestones": pk.textures.cobblestones(map_size)}
    for name in ("terrain", "gravel"):
        try:
            maps[name] = pk.textures.real(name, map_size)
        except ImportError:
            pass
    modes = ("hard", "soft", "horizon", "exact")
    methods: dict[str, Callable[..., pk.Method]] = {
        "POM": pk.POM, "Relief": pk.Relief, "Exact": pk.Exact, "ConeStep": pk.ConeStep,
        "Prism": lambda **k: pk.Prism(exact=True, **k)}
    acc: dict = {}
    for mname, h in maps.items():
        for a in SHADOW_ANGLES:
            sc = _plane(h, a, size, [light])
            o = pk.oracle.hits(sc)
            for label, make in methods.items():
                ms = [make(shadows="none")] + [make(shadows=m) for m in modes]
                ts = time_methods(r, sc, ms, min_repeats=repeats)
                for mode, m, t in zip(modes, ms[1:], ts[1:]):
                    e = metrics.shadow_error(r.render_visibility(sc, m), o, sc)
                    acc.setdefault((label, mode), []).append(
                        (mname, a, e["iou"], e["vis_error"], e["false_shadow"], e["false_light"], t["ms"] - ts[0]["ms"],
                         t["ms"] / ts[0]["ms"]))
    safe = {"exact": "safe"}
    rows = [f"{size}² frames of {map_size}² maps (depth 0.08), light (-0.4, -0.5, -0.3) with a 2° disk; reference: "
            "`pk.oracle.hits` (float64, 64 directions over the disk). Maps: " + ", ".join(maps) + "; angles: " +
            ", ".join(f"{a:g}°" for a in SHADOW_ANGLES) + ". IoU of the shadow masks (visibility < 0.5; 1.0 where "
            "neither has a shadow), mean |visibility error|, false shadow / false light (fractions of the compared "
            "pixels), cost above shadows=\"none\" (ms and ratio, medians over the maps and angles). Prism is "
            "Prism(exact=True).", "",
            "| method | shadows | kind | IoU median | IoU worst | vis error median | vis error worst | false shadow (max) | false light (max) | + ms | x none |",
            "|---|---|---|---|---|---|---|---|---|---|---|"]
    for (label, mode), xs in acc.items():
        iou = [x[2] for x in xs]
        ve = [x[3] for x in xs]
        rows.append(f"| {label} | {mode} | {safe.get(mode, 'approximate')} | {np.median(iou):.3f} | {min(iou):.3f} | "
                    f"{np.median(ve):.4f} | {max(ve):.4f} | {max(x[4] for x in xs):.4f} | {max(x[5] for x in xs):.4f} | "
                    f"{np.median([x[6] for x in xs]):.2f} | {np.median([x[7] for x in xs]):.2f} |")
    rows += ["", "Per map (POM and Exact), IoU / visibility error at each angle:", "",
             "| map | method | shadows | " + " | ".join(f"{a:g}°" for a in SHADOW_ANGLES) + " |",
             "|---|---|---|" + "---|" * len(SHADOW_ANGLES)]
    for (label, mode), xs in acc.items():
        if label not in ("POM", "Exact"):
            continue
        for mname in maps:
            cells = [f"{x[2]:.3f} / {x[3]:.4f}" for x in xs if x[0] == mname]
            rows.append(f"| {mname} | {label} | {mode} | " + " | ".join(cells) + " |")
    return "\n".join(rows)


def timing_table(size: int = 512, repeats: int = 7) -> str:
    """GPU time of each method at size^2, bricks at 60 degrees: medians of interleaved rounds
    (one run), as ratios to Flat, with the cost above Flat ("march ms")."""
    from pomkit.bench import time_methods
    r = pk.Renderer()
    sc = _plane(pk.textures.bricks(512), 60.0, size, [pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)])
    ms = {**default_methods(), "POM (soft shadows)": pk.POM(), "Exact (exact shadows)": pk.Exact(shadows="exact"),
          "POM (horizon shadows, AO 8)": pk.POM(shadows="horizon", ao_directions=8)}
    ts = time_methods(r, sc, list(ms.values()), min_repeats=repeats)
    flat = ts[list(ms).index("Flat")]["ms"]
    rows = [f"| method | safety | ms (median, IQR; {ts[0]['timing']}) | march ms | x Flat | mean steps |",
            "|---|---|---|---|---|---|"]
    for (name, m), t in zip(ms.items(), ts):
        f = r.render(sc, m, aovs=("steps", "mask"))
        steps = float(f.steps[f.mask].mean()) if f.mask.any() else 0.0
        rows.append(f"| {name} | {m.safety} | {t['ms']:.2f} ({t['ms_p25']:.2f}-{t['ms_p75']:.2f}) | {t['march_ms']:.2f} | "
                    f"{t['ms'] / flat:.2f} | {steps:.1f} |")
    return "\n".join(rows)


def silhouettes_table(size: int = 256) -> str:
    """POM, NCS, CurvedRelief, Prism and Tessellated against Mitsuba on the torus and the sphere
    (IoU, uv p95 against Mitsuba and against the float64 oracle, FLIP, time relative to POM), and
    NCS's step_scale sweep on the torus (early terminations, error)."""
    from pomkit import reference as R
    from pomkit.bench import time_methods
    r = pk.Renderer()
    rows = ["Each method at its defaults (soft shadows where it has them; issue 12's shadow-free costs are in the bench's goals.txt).", "", "| mesh | method | mask IoU | uv p95 (texels) | uv p95 vs oracle | FLIP | time / POM | early terminations |", "|---|---|---|---|---|---|---|---|"]
    sweep_rows = []
    for name, mesh in (("torus", pk.Mesh.torus(segments=48, tube_segments=24)), ("sphere", pk.Mesh.sphere(segments=48, rings=24))):
        sc = pk.scenes.cobbled(mesh, size, 1.0, 256)
        ref = R.render_mitsuba(sc, spp=16)
        oracle = pk.oracle.hits(sc)
        sil: list[pk.Method] = [pk.POM(), pk.NCS(), pk.CurvedRelief(), pk.Prism(), pk.Prism(exact=True), pk.Tessellated(0.5)]
        times = time_methods(r, sc, sil, min_repeats=3)
        base = times[0]["ms"]
        for m, t in zip(sil, times):
            f = r.render(sc, m)
            e = metrics.uv_error(f, ref, sc)
            eo = metrics.uv_error(f, oracle, sc)
            early = int(((f.flags & 2) > 0).sum())
            label = m.name + (" (exact)" if getattr(m, "exact", False) else "")
            rows.append(f"| {name} | {label} | {e['mask_iou']:.4f} | {e['p95']:.3f} | {eo['p95']:.3f} | {metrics.flip(f, ref):.4f} | {t['ms'] / base:.2f} | {early} |")
        if name == "torus":
            for c in (1.0, 1.1, 1.5, 2.0, 2.5, 3.0, 10.0):
                f = r.render(sc, pk.NCS(step_scale=c, adaptive=False))
                e = metrics.uv_error(f, ref, sc)
                sweep_rows.append(f"| {c:g} | {((f.flags & 2) > 0)[f.mask].mean():.3f} | {e['p95']:.3f} | {e['mask_iou']:.4f} |")
    rows += ["", "NCS step_scale c on the torus (64 steps, the paper's fixed step: adaptive=False):", "", "| c | early-termination rate | uv p95 | mask IoU |", "|---|---|---|---|"] + sweep_rows
    from pomkit import _core
    tris = len(pk.Mesh.torus(segments=48, tube_segments=24).indices) // 3
    # a closed shell draws its tops only: 3 vertices a prism, and its data
    vb, pb = _core.PRISM_VERTEX_BYTES, _core.PRISM_BYTES
    prism_bytes = tris * (3 * vb + pb)
    wb = _core.WALK_BYTES_PER_TRIANGLE
    rows += ["", f"NCS's (and curved relief's) extra GPU memory: {wb} bytes of walk data per triangle, and the mesh drawn unindexed (3 vertices of 72 bytes a triangle) = {tris * (wb + 3 * 72) / 2**20:.2f} MiB for this {tris}-triangle torus.",
             f"Prism's extra GPU memory: 3 boundary vertices of {vb} bytes (a closed shell) + {pb} bytes of prism data per triangle = {prism_bytes / 2**20:.2f} MiB for this {tris}-triangle torus."]
    return "\n".join(rows)


def seed002_meshes() -> dict:
    """The NCS paper's comparison meshes: a torus, a sphere, and a mesh with saddles (a closed
    surface of revolution whose profile's curvature changes sign), each with its camera."""
    return {
        "torus": (pk.Mesh.torus(segments=48, tube_segments=24), (0.0, 1.0, 2.8)),
        "sphere": (pk.Mesh.sphere(segments=48, rings=24), (0.0, 1.0, 2.8)),
        # closed, so that no method meets an open rim (Prism draws the shell's side there)
        "wavy sphere (saddles)": (pk.scenes.wavy_sphere(), (0.0, 1.0, 2.8)),
    }


def seed002_table(size: int = 256) -> str:
    """Chen & Chang 2008 (the NCS paper), reproduced against ground truth: its Table 1 (speed of
    NCS, curved relief mapping and the shell method on the same base mesh) and its Fig. 2
    (robustness: silhouette IoU and uv error against Mitsuba on a torus, a sphere and a mesh
    with saddles). POM and distance mapping (fig. 1g, planar: no silhouettes) for scale."""
    from pomkit import reference as R
    from pomkit.bench import time_methods
    r = pk.Renderer()
    methods: dict[str, pk.Method] = {
        "POM": pk.POM(shadows="none"), "DistanceMapping": pk.DistanceMapping(), "CurvedRelief": pk.CurvedRelief(),
        "NCS": pk.NCS(shadows="none"), "Prism": pk.Prism(shadows="none"), "Prism (exact)": pk.Prism(shadows="none", exact=True),
    }
    rows = [f"{size}² frames, cobblestones (128², 8 cells), depth 0.12, no shadows; references: Mitsuba 3 (16 spp, "
            "pixel-centre AOVs) on the displaced mesh; time: GPU ms, medians of interleaved rounds (one run per mesh), "
            "and as a ratio to NCS.", "",
            "| mesh | method | mask IoU | uv p95 (texels) | ms | time / NCS |", "|---|---|---|---|---|---|"]
    summary = []
    for name, (mesh, eye) in seed002_meshes().items():
        sc = pk.Scene(mesh=mesh, material=pk.Material(pk.textures.cobblestones(128, cells=8), depth=0.12),
                      camera=pk.Camera.look_at(eye, fov_y=40, width=size, height=size),
                      lights=[pk.DirectionalLight((-0.4, -1, -0.3), 3.0)], ambient=0.05)
        ref = R.render_mitsuba(sc, spp=16)
        ts = time_methods(r, sc, list(methods.values()), min_repeats=5)
        ncs = ts[list(methods).index("NCS")]["ms"]
        res = {}
        for (label, m), t in zip(methods.items(), ts):
            e = metrics.uv_error(r.render(sc, m), ref, sc)
            res[label] = (e["mask_iou"], e["p95"], t["ms"])
            rows.append(f"| {name} | {label} | {e['mask_iou']:.4f} | {e['p95']:.3f} | {t['ms']:.2f} | {t['ms'] / ncs:.2f} |")
        summary.append((name, res))
    rows += ["", "The paper's claims, against these numbers:", ""]
    for name, res in summary:
        n, c = res["NCS"], res["CurvedRelief"]
        rows.append(f"- {name}: NCS takes {n[2] / c[2]:.2f}x CurvedRelief's time (the paper: NCS runs at about 1/3 of "
                    f"CRM's speed, i.e. 3x); IoU NCS {n[0]:.4f} vs CRM {c[0]:.4f}, uv p95 {n[1]:.3f} vs {c[1]:.3f} "
                    f"(the paper: NCS more robust than CRM).")
    return "\n".join(rows)


#: the tables of `make tables` (no extra beyond the library; each a few minutes at most on llvmpipe)
QUICK: dict[str, Callable[[], str]] = {"stability.md": stability_table, "shadows.md": shadows_table,
                                       "timing.md": timing_table}
#: the tables of `make tables-slow` that need the test setup's Mitsuba (the `reference` extra)
REFERENCE: dict[str, Callable[[], str]] = {"references.md": references_table, "silhouettes.md": silhouettes_table,
                                           "pom_default.md": lambda: pom_default_table()[0], "seed002.md": seed002_table}
SETS = {"quick": QUICK, "reference": REFERENCE, "all": {**QUICK, **REFERENCE}}


def _head() -> str:
    """The provenance line (tools/provenance.py) on this machine's default adapter."""
    return stamp(pk.Renderer().info) + "\n\n"


def write_table(d: Path, name: str) -> None:
    t0 = time.perf_counter()
    body = SETS["all"][name]()
    (d / name).write_text(_head() + body + "\n")
    print(f"wrote {d / name} in {time.perf_counter() - t0:.0f} s", flush=True)


def run_tables(out: str = "docs/tables", which: str = "all") -> None:
    d = Path(out)
    d.mkdir(parents=True, exist_ok=True)
    for name in SETS[which]:
        try:
            write_table(d, name)
        except ImportError as e:
            if name not in REFERENCE:
                raise
            print(f"skipped {name}: {e}")


if __name__ == "__main__":
    import argparse
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default="docs/tables")
    ap.add_argument("--set", choices=sorted(SETS), default="all",
                    help="quick: stability, shadows, timing (`make tables`); reference: the tables against Mitsuba "
                         "(`make tables-slow`); all: both")
    ap.add_argument("--only", choices=sorted(SETS["all"]), help="write this table alone")
    a = ap.parse_args()
    if a.only:
        Path(a.out).mkdir(parents=True, exist_ok=True)
        write_table(Path(a.out), a.only)
    else:
        run_tables(a.out, a.set)
