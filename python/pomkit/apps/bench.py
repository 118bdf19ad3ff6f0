"""`python -m pomkit bench [--quick]`: the standard sweep, its table (CSV), charts and goals.

The library it drives is `pomkit.bench` (sweep, timing, Pareto front)."""

from __future__ import annotations

import csv
import time
from pathlib import Path

import pomkit as pk
from pomkit.bench import pareto_front, plane_scene, sweep, swimming, time_method

def _rows(t):
    return t.to_dict("records") if hasattr(t, "to_dict") else list(t)


def run_bench(out: str = "pomkit-out/bench", quick: bool = False) -> dict:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from pomkit import presets

    t_start = time.perf_counter()
    outdir = Path(out)
    outdir.mkdir(parents=True, exist_ok=True)
    r = pk.Renderer()
    print(f"pomkit bench on {r.info['name']} ({r.info['backend']}), timestamps={r.info['timestamps']}")
    size = 256 if quick else 512
    reps = 3 if quick else 5
    steps_grid = [4, 8, 16, 32, 64] if quick else [4, 8, 16, 32, 64, 128]
    families: dict[str, list[pk.Method]] = {
        "POM": [pk.POM(min_steps=max(1, n // 4), max_steps=n, shadows="none", lod_threshold=1000.0, mip_filtering=False) for n in steps_grid],
        "SteepParallax": [pk.SteepParallax(steps=n, mip_filtering=False) for n in steps_grid],
        "Relief": [pk.Relief(linear_steps=n, binary_steps=5, mip_filtering=False) for n in steps_grid],
        "Parallax": [pk.Parallax(mip_filtering=False)],
        "Exact": [pk.Exact()],
        "Tessellated": [pk.Tessellated(texels_per_vertex=t, shadows="none") for t in ([1.0, 2.0, 4.0] if quick else [0.5, 1.0, 2.0, 4.0])],
    }
    preset_methods: list[pk.Method] = []
    for name, fn in presets.ALL_PRESETS.items():
        pm = fn()
        object.__setattr__(pm, "_preset", name)
        preset_methods.append(pm)
    defaults = {"POM (default)": pk.POM(shadows="none"), "Exact (default)": pk.Exact()}
    for name, dm in defaults.items():
        object.__setattr__(dm, "_preset", name)
    all_methods: list[pk.Method] = [m for ms in families.values() for m in ms] + preset_methods + list(defaults.values())

    # 1. Pareto: bricks at 60 degrees
    table = _rows(sweep(all_methods, scenes=("bricks",), angles=(60.0,), settings=dict(size=size), repeats=reps,
                        progress=True))
    for row in table:
        row["chart"] = "pareto"
    fig, ax = plt.subplots(figsize=(7, 5))
    pts = [(row["gpu_ms"], max(row["uv_p95"], 1e-4)) for row in table]
    for fam in families:
        rs = [row for row in table if row["method"] == fam]
        ax.plot([x["gpu_ms"] for x in rs], [max(x["uv_p95"], 1e-4) for x in rs], "o-", label=fam)
    for row in table:
        if row["method"] in presets.ALL_PRESETS or "default" in row["method"]:
            ax.plot(row["gpu_ms"], max(row["uv_p95"], 1e-4), "k*" if "default" in row["method"] else "s", ms=10)
            ax.annotate(row["method"], (row["gpu_ms"], max(row["uv_p95"], 1e-4)), fontsize=7, xytext=(4, 4), textcoords="offset points")
    front = pareto_front(pts)
    fp = sorted(pts[i] for i in front)
    ax.step([p[0] for p in fp], [p[1] for p in fp], "k--", where="post", lw=0.8, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"GPU time per {size}² frame (ms, {table[0]['timing']})")
    ax.set_ylabel("uv error p95 (texels, vs exact oracle)")
    ax.set_title("Speed against accuracy: bricks, 60°")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(outdir / "pareto.png", dpi=120)
    plt.close(fig)
    front_names = [table[i]["params"] for i in front]

    # 2. error against view angle
    angles = [0.0, 30.0, 60.0, 75.0, 85.0, 89.5] if quick else [0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 80.0, 85.0, 88.0, 89.5]
    angle_methods: list[pk.Method] = [pk.Parallax(), pk.SteepParallax(), pk.POM(shadows="none"), pk.Relief(), pk.Exact()]
    at = _rows(sweep(angle_methods, scenes=("bricks",), angles=angles, settings=dict(size=128), repeats=1))
    for row in at:
        row["chart"] = "angle"
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for m in angle_methods:
        rs = [x for x in at if x["method"] == m.name]
        ax.plot([x["angle"] for x in rs], [max(x["uv_p95"], 1e-4) for x in rs], "o-", label=m.name)
    ax.set_yscale("log")
    ax.set_xlabel("view angle from the normal (degrees)")
    ax.set_ylabel("uv p95 (texels)")
    ax.set_title("Stability against view angle (bricks, default settings)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(outdir / "angle.png", dpi=120)
    plt.close(fig)

    # 3. error against height-map frequency
    freqs = [1, 2, 4, 8, 16, 32] if not quick else [1, 4, 16, 32]
    ft = _rows(sweep(angle_methods, scenes=[f"sine{f}" for f in freqs] + ["spikes"], angles=(60.0,), settings=dict(size=128), repeats=1))
    for row in ft:
        row["chart"] = "frequency"
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for m in angle_methods:
        rs = [x for x in ft if x["method"] == m.name and x["scene"].startswith("sine")]
        ax.plot([float(x["scene"][4:]) for x in rs], [max(x["uv_p95"], 1e-4) for x in rs], "o-", label=m.name)
        sp = [x for x in ft if x["method"] == m.name and x["scene"] == "spikes"]
        ax.plot([64], [max(sp[0]["uv_p95"], 1e-4)], "x", color=ax.lines[-1].get_color())
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("sine frequency per tile (x at 64: spikes)")
    ax.set_ylabel("uv p95 (texels)")
    ax.set_title("Stability against height-map frequency (60°)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(outdir / "frequency.png", dpi=120)
    plt.close(fig)

    # 4. cost against tiling (Chen & Chang fig. 6)
    tiling_rows: list[dict] = []
    for tiling in (1, 2, 4, 8):
        sc = plane_scene(pk.textures.bricks(256 if quick else 512), 60.0, size, tiling=float(tiling))
        trow: dict = dict(chart="tiling", tiling=tiling)
        timed: tuple[tuple[str, pk.Method], ...] = (("POM", pk.POM(shadows="none")), ("Exact", pk.Exact()),
                                                    ("Tessellated", pk.Tessellated(texels_per_vertex=1.0, shadows="none")))
        for name, tm in timed:
            trow[name + "_ms"] = time_method(r, sc, tm, repeats=reps)["ms"]
        trow["Tessellated/POM"] = trow["Tessellated_ms"] / trow["POM_ms"]
        trow["Tessellated/Exact"] = trow["Tessellated_ms"] / trow["Exact_ms"]
        tiling_rows.append(trow)
        print(f"  tiling {tiling}x: POM {trow['POM_ms']:.1f} ms, Exact {trow['Exact_ms']:.1f} ms, Tessellated {trow['Tessellated_ms']:.1f} ms"
              f"  (x{trow['Tessellated/POM']:.1f} / x{trow['Tessellated/Exact']:.1f})")
    fig, ax = plt.subplots(figsize=(6, 4))
    for name in ("POM", "Exact", "Tessellated"):
        ax.plot([x["tiling"] for x in tiling_rows], [x[name + "_ms"] for x in tiling_rows], "o-", label=name)
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("tiling (map repeats per side)")
    ax.set_ylabel("ms per frame")
    ax.set_title("Cost against tiling (Chen & Chang fig. 6)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(outdir / "tiling.png", dpi=120)
    plt.close(fig)

    # 5. temporal stability (swimming)
    swim: list[dict] = []
    hs = pk.textures.bricks(256)
    for m in [pk.Parallax(), pk.SteepParallax(), pk.POM(shadows="none"), pk.Relief(), pk.Exact()]:
        v = swimming(m, hs, frames=8 if quick else 16)
        swim.append(dict(chart="swimming", method=m.name, swim_texels=v))
        print(f"  swimming {m.name:14s} {v:.4f} texels/frame")
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.bar([x["method"] for x in swim], [x["swim_texels"] for x in swim])
    ax.set_ylabel("mean |Δuv - Δuv_exact| per frame (texels)")
    ax.set_title("Swimming over a 0.5°/frame camera path (bricks)")
    fig.tight_layout()
    fig.savefig(outdir / "swimming.png", dpi=120)
    plt.close(fig)

    # 6. the performance goals
    goals = {}
    acc_ok = [x for x in table if x["uv_p95"] <= 0.5]
    tess = [x for x in acc_ok if x["method"] == "Tessellated"]
    fast = [x for x in acc_ok if x["method"] in ("POM", "Exact", "Relief", "Exact (default)")]
    if tess and fast:
        goals["speedup_vs_tessellated_at_p95<=0.5"] = min(x["gpu_ms"] for x in tess) / min(x["gpu_ms"] for x in fast)
    dom = {}
    for p in presets.ALL_PRESETS:
        pr = next(x for x in table if x["method"] == p)
        dom[p] = {d: (dx["gpu_ms"] <= pr["gpu_ms"] and dx["uv_p95"] <= pr["uv_p95"])
                  for d in ("POM (default)", "Exact (default)") for dx in [next(x for x in table if x["method"] == d)]}
    goals["defaults_dominate_presets"] = dom
    calls = [x for x in table if x["method"] == "Exact (default)"][0]
    goals["python_overhead_pct_at_%d" % size] = 100.0 * (calls["call_ms"] - calls["gpu_ms"]) / calls["gpu_ms"]
    goals["exact_extra_memory_x_heightmap"] = _maxmip_ratio(512)
    for k, v in goals.items():
        print(f"  goal {k}: {v}")

    all_rows = table + at + ft + tiling_rows + swim
    keys = []
    for row in all_rows:
        keys += [k for k in row if k not in keys]
    with open(outdir / "bench.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(all_rows)
    with open(outdir / "goals.txt", "w") as fh:
        for k, v in goals.items():
            fh.write(f"{k}: {v}\n")
        fh.write("pareto front: " + "; ".join(front_names) + "\n")
    print(f"wrote {outdir.resolve()}/: bench.csv, goals.txt, pareto.png, angle.png, frequency.png, tiling.png, swimming.png "
          f"in {time.perf_counter() - t_start:.0f} s")
    return dict(table=table, angle=at, frequency=ft, tiling=tiling_rows, swimming=swim, goals=goals)


def _maxmip_ratio(n: int) -> float:
    """Exact's extra memory (the max pyramid, floats) over the height map's."""
    total, w = 0, n
    h = n
    while True:
        total += w * h
        if w == 1 and h == 1:
            break
        w, h = max(1, w // 2), max(1, h // 2)
    return total / (n * n)
