"""The project's goals, measured (`make bench`, after `python -m pomkit bench`): the speed goals
over suites of scenes (tools/suite.py), the cost model over every method, the cone map's build,
the call overhead, the several-objects scene, horizon AO's share and the silhouettes as the map
tiles, each in one run, written to goals.txt and goals.csv beside the bench's output. With
--tables DIR (`make tables-slow`: docs/tables) it also writes bench.md (the bench's sweep, tiling
and swimming), bench_goals.txt (goals.txt) and curved_tiling.md there, under their provenance.

Usage: python tools/goals.py [--out pomkit-out/bench] [--quick] [--tables docs/tables]"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np

import pomkit as pk
from pomkit.apps import pareto
from pomkit.bench import plane_scene, time_methods, write_csv

import suite
from costfit import ao_cost, cost_model, fit_cost
from provenance import stamp


def cone_build_cost(size: int = 512, repeats: int = 5) -> dict[str, Any]:
    """The cone map's build at `size`², in 512² POM frames: the wall time of a first ConeStep
    render on a map the renderer has not seen (upload, pyramids, cone map, frame) minus that of a
    first Exact render on another unseen map (upload, pyramids, frame), medians of `repeats`
    fresh maps each, over the wall time of a POM frame. Wall times: the build is a compute pass
    outside the render pass the timestamps measure."""
    r = pk.Renderer()
    rng = np.random.default_rng(0)
    sc = plane_scene(pk.textures.bricks(size), 60.0, 512, lights=[])

    def fresh(m: pk.Method) -> float:
        s2 = sc.replace(material=pk.Material(np.clip(pk.textures.bricks(size) + rng.random() * 1e-3, 0, 1)))
        t0 = time.perf_counter()
        r.render(s2, m, aovs=("color",))
        return time.perf_counter() - t0

    for m in (pk.ConeStep(), pk.Exact(), pk.POM(shadows="none")):
        r.render(sc, m, aovs=("color",))  # pipelines
    cone = float(np.median([fresh(pk.ConeStep()) for _ in range(repeats)]))
    exact = float(np.median([fresh(pk.Exact()) for _ in range(repeats)]))
    pom = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r.render(sc, pk.POM(shadows="none"), aovs=("color",))
        pom.append(time.perf_counter() - t0)
    build = max(cone - exact, 0.0)
    return {f"cone_map_build_{size} (goal <= 10 POM frames)":
            f"{build * 1e3:.1f} ms wall = {build / float(np.median(pom)):.2f} POM frames ({np.median(pom) * 1e3:.1f} ms)"}


def objects_cost(size: int = 512, rounds: int = 5) -> dict:
    """Issue 13's scene (a displaced sphere sunk into a displaced brick floor) at size², with the
    light's cast shadows off and on: the main pass's GPU ms, and the shadow-map pass's cost as
    the wall-time difference (the shadow pass has no timestamps of its own; it also includes the
    map's allocation). Medians of interleaved rounds after a warm-up, `render_many` of 2 frames."""
    r = pk.Renderer()
    methods: list[pk.Method] = [pk.POM(), pk.Exact(), pk.Prism(exact=True), pk.Tessellated(1.0, shadows="none")]
    scenes = {cast: pk.scenes.sunk_sphere(size, cast_shadows=cast) for cast in (False, True)}
    runs: dict = {}
    for rnd in range(rounds + 1):
        for m in methods:
            for cast, sc in scenes.items():
                fs = r.render_many([sc] * 2, m, aovs=("color",))
                if rnd:  # round 0 warms up
                    runs.setdefault((m.name, cast), []).extend(fs)
    out = {}
    for m in methods:
        off, on = runs[(m.name, False)], runs[(m.name, True)]
        g0 = float(np.median([f.time_ms for f in off]))
        g1 = float(np.median([f.time_ms for f in on]))
        w0 = float(np.median([f.wall_ms for f in off]))
        w1 = float(np.median([f.wall_ms for f in on]))
        out[f"objects_{m.name}_{size} main pass ms (no cast -> cast), shadow pass wall ms, shadow/main"] = (
            f"{g0:.1f} -> {g1:.1f}, {w1 - w0 - (g1 - g0):.1f}, x{(w1 - w0 - (g1 - g0)) / g0:.2f}")
    return out


def _paired_ratios(r: pk.Renderer, scene: pk.Scene, methods: list, rounds: int) -> tuple[list[float], list[float]]:
    """Per method: the median GPU ms and the median of per-round ratios to the first method."""
    t = time_methods(r, scene, methods, min_repeats=rounds, max_repeats=rounds, baseline=False)
    return [x["ms"] for x in t], [x["over_first"] for x in t]


#: Tessellated(1) here is the regular grid (two triangles a quad, as an engine's tessellator cuts
#: it): the mesh these cost goals were set against (the default fan has twice its triangles)
SILHOUETTE_METHODS = {"POM": lambda: pk.POM(shadows="none"), "NCS": lambda: pk.NCS(shadows="none"),
                      "Prism": lambda: pk.Prism(shadows="none"),
                      "Tessellated(1)": lambda: pk.Tessellated(1.0, shadows="none", pattern="grid")}


def curved_tiling(tiles=(1, 2, 4, 8), size: int = 512, rounds: int = 5) -> list[dict]:
    """Chen & Chang's fig. 6 on a curved mesh: the torus with a 512² map tiled 1..8 times at
    size², POM, NCS, Prism and Tessellated(1): GPU ms (median of interleaved rounds), coverage
    IoU and uv p95 (texels) against Tessellated(1) at the same tiling."""
    from pomkit import metrics
    r = pk.Renderer()
    mesh = pk.Mesh.torus(segments=48, tube_segments=24)
    rows = []
    for t in tiles:
        sc = pk.scenes.cobbled(mesh, size, float(t))
        methods = [f() for f in SILHOUETTE_METHODS.values()]
        ms, x = _paired_ratios(r, sc, methods, rounds)
        ref = r.render(sc, methods[3])
        for name, m, v, xr in zip(SILHOUETTE_METHODS, methods, ms, x):
            e = metrics.uv_error(r.render(sc, m), ref, sc)
            rows.append(dict(chart="curved_tiling", tiling=t, label=name, method=m.name, gpu_ms=v, over_pom=xr,
                             mask_iou=e["mask_iou"], uv_p95=e["p95"]))
    return rows


def curved_tiling_markdown(rows: list[dict]) -> str:
    lines = ["| tiles | method | GPU ms | x POM | x Tessellated(1) | IoU vs Tessellated(1) | uv p95 vs Tessellated(1) (texels) |",
             "|---|---|---|---|---|---|---|"]
    tess = {x["tiling"]: x["gpu_ms"] for x in rows if x["label"] == "Tessellated(1)"}
    for x in rows:
        lines.append(f"| {x['tiling']} | {x['label']} | {x['gpu_ms']:.2f} | {x['over_pom']:.2f} | {x['gpu_ms'] / tess[x['tiling']]:.3f} | "
                     f"{x['mask_iou']:.4f} | {x['uv_p95']:.3f} |")
    return "\n".join(lines)


def bench_markdown(res: dict, quick: bool) -> str:
    """docs/tables/bench.md from `pareto.run_bench`'s result: the Pareto sweep's rows, the cost
    against tiling on the plane and swimming (the charts are in the bench's output folder)."""
    params = {name: pk.bench.label(fn()) for name, fn in pk.presets.ALL_PRESETS.items()}
    size = res["size"]
    lines = [f"{size}² frames, bricks at 60°, shadows off (`python -m pomkit bench{' --quick' if quick else ''}`, "
             "run by `tools/goals.py`; the chart is pareto.png in its output). GPU ms: medians of interleaved rounds "
             "after a warm-up; uv p95 against `pk.oracle.hits`; FLIP against `pk.oracle.image` (NaN under --quick).", "",
             "| method | parameters | GPU ms | uv p95 (texels) | FLIP vs the oracle's image |", "|---|---|---|---|---|"]
    for x in res["table"]:
        lines.append(f"| {x['method']} | `{params.get(x['label'], x['label'])}` | {x['gpu_ms']:.2f} | {x['uv_p95']:.4f} | "
                     f"{x['flip']:.4f} |")
    by = {(x["tiling"], x["method"]): x["gpu_ms"] for x in res["tiling"]}
    lines += ["", "Cost against tiling on the plane (bricks at 60°, Tessellated(1) on the grid):", "",
              "| tiling | POM ms | Exact ms | Tessellated(1) ms | Tess/POM | Tess/Exact |", "|---|---|---|---|---|---|"]
    for t in sorted({k[0] for k in by}):
        pom, exact, tess = by[(t, "POM")], by[(t, "Exact")], by[(t, "Tessellated")]
        lines.append(f"| {t}x | {pom:.1f} | {exact:.1f} | {tess:.1f} | {tess / pom:.1f} | {tess / exact:.1f} |")
    lines += ["", "| method | swimming (texels/frame) |", "|---|---|"]
    lines += [f"| {x['method']} | {x['swim_texels']:.4f} |" for x in res["swimming"]]
    return "\n".join(lines)


def curved_tiling_header(tiles: tuple, size: int, rounds: int) -> str:
    return (f"The torus (48 x 24 segments), cobblestones 512² tiled {tiles[0]}-{tiles[-1]} times "
            f"({', '.join(map(str, tiles))}), depth 0.12, {size}² frame, shadows off. GPU ms: medians of {rounds} "
            "interleaved rounds after a warm-up; x POM: medians of per-round ratios. IoU and uv p95 against "
            "Tessellated(1) at the same tiling (uv error in texels of the tiled map).")


def throughput(size: int = 512, frames: int = 64) -> dict[str, Any]:
    """The call-overhead figures (issue 14), at `size`², bricks 60°: Flat with colour only
    against all AOVs (wall; the GPU figure is the suite's fixed-cost goal), wall over GPU for POM with ("color", "uv") through a single
    `render` and through `render_many`, and the frame rate of a `render_many` of `frames`
    frames against as many single renders. Interleaved, after a warm-up."""
    r = pk.Renderer()
    sc = plane_scene(pk.textures.bricks(512), 60.0, size)
    pom = pk.POM(shadows="none")
    cu: tuple[pk.AovName, ...] = ("color", "uv")
    runs: list[tuple[str, pk.Method, Any]] = [
        ("flat_all", pk.Flat(), "all"), ("flat_color", pk.Flat(), ("color",)), ("pom_single", pom, cu)]
    rows: dict[str, list[tuple[float, float]]] = {k: [] for k in ("flat_all", "flat_color", "pom_single")}
    for _ in range(2):
        r.render(sc, pk.Flat())
        r.render(sc, pom, aovs=cu)
    for _ in range(7):
        for key, m, aovs in runs:
            t0 = time.perf_counter()
            f = r.render(sc, m, aovs=aovs)
            rows[key].append((f.time_ms or 0.0, (time.perf_counter() - t0) * 1e3))
    med = {k: np.median(np.array(v), axis=0) for k, v in rows.items()}
    many_ratio, fps_many, fps_single = [], [], []
    for _ in range(3):
        t0 = time.perf_counter()
        fs = r.render_many([sc] * frames, pom, aovs=cu)
        wall = time.perf_counter() - t0
        many_ratio.append(wall * 1e3 / sum(f.time_ms or 0.0 for f in fs))
        fps_many.append(frames / wall)
        t0 = time.perf_counter()
        for _ in range(frames):
            r.render(sc, pom, aovs=cu)
        fps_single.append(frames / (time.perf_counter() - t0))
    return {
        f"flat_color_vs_all_wall_ms_at_{size}": f"{med['flat_color'][1]:.2f} vs {med['flat_all'][1]:.2f} "
                                                 f"(x{med['flat_color'][1] / med['flat_all'][1]:.2f})",
        "pom_color_uv_wall_over_gpu_render (goal <= 1.25)": round(float(med["pom_single"][1] / med["pom_single"][0]), 3),
        "pom_color_uv_wall_over_gpu_render_many (goal <= 1.10)": round(float(np.median(many_ratio)), 3),
        f"render_many_{frames}_vs_{frames}_renders_fps": f"{np.median(fps_many):.1f} vs {np.median(fps_single):.1f}",
    }


def run_goals(out: str = "pomkit-out/bench", quick: bool = False, tables: str | None = None) -> dict:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t_start = time.perf_counter()
    outdir = Path(out)
    res = pareto.run_bench(out, quick=quick)
    table, searched, size = res["table"], res["searched"], res["size"]
    r = pk.Renderer()
    # 6. the goals, measured in this run
    goals: dict[str, Any] = {}
    by = {x["label"]: x for x in table}
    pom_d, exact_d = by["POM (default)"], by["Exact (default)"]
    goals["timing"] = f"{table[0]['timing']} ms, median of interleaved rounds after a warm-up, {size}² bricks 60°, shadows off"
    goals["flat_ms"] = round(pom_d["gpu_ms"] - pom_d["march_ms"], 3)
    goals["pom_default_ms (march ms)"] = f"{pom_d['gpu_ms']:.2f} ({pom_d['march_ms']:.2f})"
    goals["exact_ms (march ms)"] = f"{exact_d['gpu_ms']:.2f} ({exact_d['march_ms']:.2f})"
    goals.update(cone_build_cost())
    tess = [x for x in table if x["method"] == "Tessellated" and x["uv_p95"] <= 0.5]
    fast = [x for x in table if x["safety"] == "safe" or x["method"] in ("POM", "Relief")]
    fast = [x for x in fast if x["uv_p95"] <= 0.5]
    if tess and fast:
        goals["speedup_vs_tessellated_at_p95<=0.5"] = round(min(x["gpu_ms"] for x in tess) / min(x["gpu_ms"] for x in fast), 3)
    goals["python_overhead_pct_exact_default"] = round(100.0 * (exact_d["call_ms"] - exact_d["gpu_ms"]) / exact_d["gpu_ms"], 1)
    goals.update(throughput(size=512, frames=16 if quick else 64))
    goals.update(objects_cost(size=512, rounds=2 if quick else 6))
    # the cost fit: GPU ms against mean fetches per pixel over the Pareto sweep's rows (one adapter)
    fit = fit_cost(searched)
    fit_m = fit_cost(searched, y="march_ms")
    goals["cost_fit gpu_ms = a + b * fetches (per-pixel methods)"] = (
        f"a {fit['a']:.2f} ms, b {fit['b'] * 1e3:.1f} us/fetch, R² {fit['r2']:.3f} (n {fit['n']})")
    goals["cost_fit march_ms = a + b * fetches (per-pixel methods)"] = (
        f"a {fit_m['a']:.2f} ms, b {fit_m['b'] * 1e3:.1f} us/fetch, R² {fit_m['r2']:.3f} (n {fit_m['n']})")
    # the cost model over every method (docs/cost.md): ms = a + sum(c_t * per-frame count t)
    cm = cost_model(r, quick=quick)
    for name, fm in cm["fits"].items():
        coefs = ", ".join(f"{t} {v * 1e6:.3g} ns" for t, v in fm["coef"].items())
        goals[f"cost_model {name}: gpu_ms = a + sum(c * count) over every method, non-negative, rows weighted 1/sqrt(ms) (goal R² >= 0.95)"] = (
            f"a {fm['a']:.2f} ms, {coefs}, R² {fm['r2']:.3f}, median row off by {100 * fm['med_rel_err']:.0f}%, "
            f"worst by {100 * fm['max_rel_err']:.0f}% (n {fm['n']})")
    # DT07's figure: horizon AO's share of the frame with 4 and 8 directions (the paper: ~35 %)
    ao = ao_cost(r, quick=quick)
    for nd in (4, 8):
        shares = [x[f"ao_share_{nd}"] for x in ao]
        goals[f"dt07_ao_share_{nd}_directions (the paper: about 35 % of the frame)"] = (
            f"{100 * min(shares):.0f}-{100 * max(shares):.0f} % (median {100 * float(np.median(shares)):.0f} %) over "
            f"{len(ao)} scene-method pairs")
    # the speed goals over suites of scenes: worst case and median (tools/suite.py)
    print("  the goals over the planar and curved suites ...")
    suite_goals, bevy_rows = suite.run(quick=quick)
    goals.update(suite_goals)
    for row in bevy_rows:
        row["chart"] = "issue11_vs_bevy_relief"
    tiles, rounds = ((1, 4), 3) if quick else ((1, 2, 4, 8), 5)
    curved = curved_tiling(tiles=tiles, size=512, rounds=rounds)
    (outdir / "curved_tiling.md").write_text(curved_tiling_markdown(curved) + "\n")
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for name in SILHOUETTE_METHODS:
        pts = [(x["tiling"], x["gpu_ms"]) for x in curved if x["label"] == name]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=name)
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("map tiles on the torus")
    ax.set_ylabel("GPU ms (512², shadows off)")
    ax.set_title("Silhouettes as the map tiles (Chen & Chang fig. 6)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(outdir / "curved_tiling.png", dpi=120)
    plt.close(fig)
    tess4 = {x["label"]: x["gpu_ms"] for x in curved if x["tiling"] == 4}
    goals["curved_tiling_4_tessellated_over_prism (goal >= 3)"] = round(tess4["Tessellated(1)"] / tess4["Prism"], 2)
    goals["curved_tiling_4_tessellated_over_ncs (goal >= 3)"] = round(tess4["Tessellated(1)"] / tess4["NCS"], 2)
    for k, v in goals.items():
        print(f"  goal {k}: {v}")

    write_csv(curved + bevy_rows + cm["rows"] + ao, outdir / "goals.csv")
    with open(outdir / "goals.txt", "w") as fh:
        from pomkit._info import machine
        for field, value in machine().items():
            fh.write(f"{field}: {value}\n")
        for k, v in goals.items():
            fh.write(f"{k}: {v}\n")
        fh.write("pareto front: " + "; ".join(res["front"]) + "\n")
        fh.write("pareto front by fetches: " + "; ".join(res["front_fetches"]) + "\n")
    print(f"wrote {outdir.resolve()}/: goals.txt, goals.csv, curved_tiling.png, curved_tiling.md "
          f"in {time.perf_counter() - t_start:.0f} s")
    if tables:
        d = Path(tables)
        head = stamp(r.info)
        (d / "bench.md").write_text(head + "\n\n" + bench_markdown(res, quick) + "\n")
        (d / "bench_goals.txt").write_text(f"provenance: {head}\n" + (outdir / "goals.txt").read_text())
        (d / "curved_tiling.md").write_text(head + "\n\n" + curved_tiling_header(tiles, 512, rounds) + "\n\n"
                                            + curved_tiling_markdown(curved) + "\n")
        print(f"wrote {d}/: bench.md, bench_goals.txt, curved_tiling.md")
    return goals


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="pomkit-out/bench")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--tables", help="also write bench.md, bench_goals.txt and curved_tiling.md here (docs/tables)")
    a = ap.parse_args()
    run_goals(a.out, a.quick, a.tables)
