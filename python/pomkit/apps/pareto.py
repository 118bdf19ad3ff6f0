"""`python -m pomkit bench [--quick]`: the standard sweep, its table (CSV) and charts.

The library it drives is `pomkit.bench` (sweep, interleaved timing, Pareto front). Every timing
is a median over interleaved rounds after a warm-up, with its interquartile range; "march ms" is
a method's cost above Flat timed in the same rounds. The project's own goals over suites of
scenes are measured outside the package, by tools/goals.py (`make bench`).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

import pomkit as pk
from pomkit import presets
from pomkit.bench import SweepSettings, pareto_front, plane_scene, sweep, swimming, time_methods, write_csv

#: what the bench needs beyond the library (the `bench` extra)
NEEDS = ("matplotlib", "pandas", "tqdm", "skimage", "scipy")


def missing_extra() -> list[str]:
    import importlib.util
    return [m for m in NEEDS if importlib.util.find_spec(m) is None]


def _rows(t) -> list[dict]:
    return t.to_dict("records") if hasattr(t, "to_dict") else list(t)


def families(quick: bool) -> dict[str, list[pk.Method]]:
    grid = [4, 8, 16, 32, 64] if quick else [4, 8, 16, 32, 64, 128]
    return {
        "POM": [pk.POM(shadows="none", lod_threshold=1000.0, mip_filtering=False).with_steps(n) for n in grid],
        "SteepParallax": [pk.SteepParallax(mip_filtering=False).with_steps(n) for n in grid],
        "Relief": [pk.Relief(binary_steps=5, mip_filtering=False).with_steps(n) for n in grid],
        "Parallax": [pk.Parallax(mip_filtering=False)],
        "Exact": [pk.Exact()],
        "ConeStep": [pk.ConeStep(cones="relaxed", refine="binary").with_steps(n) for n in grid],
        "Tessellated": [pk.Tessellated(texels_per_vertex=t, shadows="none") for t in ([1.0, 2.0, 4.0] if quick else [0.5, 1.0, 2.0, 4.0])],
        # the coarse mesh plus POM(16) (the POM family's 16-step setting): its taps and GPU ms beside
        # POM alone at equal taps
        "Hybrid": [pk.Hybrid(coarse=pk.Tessellated(texels_per_vertex=t),
                             fine=pk.POM(shadows="none", lod_threshold=1000.0, mip_filtering=False).with_steps(16))
                   for t in ([16.0, 4.0] if quick else [16.0, 4.0, 1.0])],
    }


def _pareto_chart(plt, table: list[dict], fams: dict, size: int, out: Path, x: str = "gpu_ms") -> list[int]:
    """uv p95 against cost: GPU ms (x="gpu_ms", with IQR bars) or mean texel fetches per pixel
    (x="fetches_mean": a cost that carries over to other hardware)."""
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    y = lambda r: max(r["uv_p95"], 1e-4)  # noqa: E731
    xv = lambda r: max(r[x], 0.5) if x == "fetches_mean" else r[x]  # noqa: E731
    def err(rs: list[dict]) -> Any:
        if x != "gpu_ms":
            return None
        return np.array([[r["gpu_ms"] - r["gpu_ms_p25"] for r in rs], [r["gpu_ms_p75"] - r["gpu_ms"] for r in rs]])
    for fam in fams:
        rs = [r for r in table if r["method"] == fam]
        safe = rs and rs[0]["safety"] == "safe"
        ax.errorbar([xv(r) for r in rs], [y(r) for r in rs], xerr=err(rs), fmt="o-" if not safe else "D-",
                    mfc="white" if not safe else None, capsize=2, label=f"{fam} ({rs[0]['safety'] if rs else ''})")
    for r in table:
        if r["method"] in presets.ALL_PRESETS or "default" in r["method"]:
            ax.errorbar([xv(r)], [y(r)], xerr=err([r]), fmt="k*" if "default" in r["method"] else "s", ms=9, capsize=2)
            ax.annotate(f"{r['method']} ({r['safety']})", (xv(r), y(r)), fontsize=7, xytext=(4, 4),
                        textcoords="offset points")
    pts = [(xv(r), y(r)) for r in table]
    front = pareto_front(pts)
    fp = sorted(pts[i] for i in front)
    ax.step([p[0] for p in fp], [p[1] for p in fp], "k--", where="post", lw=0.8, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    if x == "gpu_ms":
        ax.set_xlabel(f"GPU time per {size}² frame (ms, {table[0]['timing']}; median, bars: IQR)")
    else:
        ax.set_xlabel("mean texel fetches per pixel of the search (AOV `fetches`; 0 drawn at 0.5)")
    ax.set_ylabel("uv error p95 (texels, vs exact oracle)")
    ax.set_title("Speed against accuracy: bricks, 60° (hollow: approximate, filled: safe)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return front


def _line_chart(plt, rows, methods, x, xlabel, title, out: Path, xlog=False) -> None:
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for name in methods:
        rs = [r for r in rows if r["method"] == name]
        ax.plot([x(r) for r in rs], [max(r["uv_p95"], 1e-4) for r in rs], "o-", label=name)
    if xlog:
        ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("uv p95 (texels)")
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def run_bench(out: str = "pomkit-out/bench", quick: bool = False, spp: int = 1) -> dict:
    """The bench. `spp`: the Pareto sweep's frames (and its colour reference) at that many samples
    per pixel, so that FLIP scores carry no aliasing; timings are of the one-sample frames."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t_start = time.perf_counter()
    outdir = Path(out)
    outdir.mkdir(parents=True, exist_ok=True)
    r = pk.Renderer()
    print(f"pomkit bench on {r.info['name']} ({r.info['backend']}), timestamps={r.info['timestamps']}")
    size = 256 if quick else 512
    fams = families(quick)
    preset_methods = [(name, fn()) for name, fn in presets.ALL_PRESETS.items()]
    defaults = [("POM (default)", pk.POM(shadows="none")), ("Exact (default)", pk.Exact()),
                ("ConeStep (default)", pk.ConeStep())]
    all_methods: list[pk.Method | tuple[str, pk.Method]] = [m for ms in fams.values() for m in ms]
    all_methods += preset_methods + defaults

    # 1. Pareto: bricks at 60 degrees
    table = _rows(sweep(all_methods, maps=("bricks",), angles=(60.0,), settings=SweepSettings(size=size, flip=not quick, frame_spp=spp),
                        repeats=3 if quick else 5, progress=True))
    for row in table:
        row["chart"] = "pareto"
    front = _pareto_chart(plt, table, fams, size, outdir / "pareto.png")
    front_labels = [table[i]["label"] for i in front]
    # by fetches, the per-pixel methods only: a mesh's cost is its triangles, which fetch nothing
    searched = [x for x in table if x["method"] != "Tessellated"]
    front_f = _pareto_chart(plt, searched, {k: v for k, v in fams.items() if k != "Tessellated"}, size,
                            outdir / "pareto_fetches.png", x="fetches_mean")
    front_fetch_labels = [searched[i]["label"] for i in front_f]

    # 2. error against view angle, 3. against height-map frequency (accuracy only: one round)
    angle_methods: list[pk.Method] = [pk.Parallax(), pk.SteepParallax(), pk.POM(shadows="none"), pk.Relief(), pk.Exact()]
    names = [m.name for m in angle_methods]
    angles = [0.0, 30.0, 60.0, 75.0, 85.0, 89.5] if quick else [0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 80.0, 85.0, 88.0, 89.5]
    at = _rows(sweep(angle_methods, maps=("bricks",), angles=angles, settings=SweepSettings(size=128, flip=False), repeats=1,
                     progress=False))
    for row in at:
        row["chart"] = "angle"
    _line_chart(plt, at, names, lambda x: x["angle"], "view angle from the normal (degrees)",
                "Stability against view angle (bricks, default settings)", outdir / "angle.png")
    freqs = [1, 4, 16, 32] if quick else [1, 2, 4, 8, 16, 32]
    ft = _rows(sweep(angle_methods, maps=[f"sine{f}" for f in freqs], angles=(60.0,), settings=SweepSettings(size=128, flip=False),
                     repeats=1, progress=False))
    for row in ft:
        row["chart"] = "frequency"
    _line_chart(plt, ft, names, lambda x: float(x["scene"][4:]), "sine frequency per tile",
                "Stability against height-map frequency (60°)", outdir / "frequency.png", xlog=True)

    # 4. cost against tiling (Chen & Chang fig. 6), on the plane
    tiling_rows: list[dict] = []
    tiled: list[pk.Method] = [pk.POM(shadows="none"), pk.Exact(),
                              pk.Tessellated(texels_per_vertex=1.0, shadows="none", pattern="grid")]
    for tiling in ((1, 4) if quick else (1, 2, 4, 8)):
        sc = plane_scene(pk.textures.bricks(256 if quick else 512), 60.0, size, tiling=float(tiling))
        ts = time_methods(r, sc, tiled, min_repeats=3)
        for m, t in zip(tiled, ts):
            tiling_rows.append(dict(chart="tiling", method=m.name, label=m.name, safety=m.safety, scene="bricks",
                                    tiling=tiling, gpu_ms=t["ms"], gpu_ms_p25=t["ms_p25"], gpu_ms_p75=t["ms_p75"],
                                    march_ms=t["march_ms"], timing=t["timing"]))
        print(f"  tiling {tiling}x: " + ", ".join(f"{m.name} {t['ms']:.1f} ms" for m, t in zip(tiled, ts)))
    fig, ax = plt.subplots(figsize=(6, 4))
    for m in tiled:
        rs = [x for x in tiling_rows if x["method"] == m.name]
        ax.plot([x["tiling"] for x in rs], [x["gpu_ms"] for x in rs], "o-", label=m.name)
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("tiling (map repeats per side)")
    ax.set_ylabel("ms per frame (median)")
    ax.set_title("Cost against tiling (Chen & Chang fig. 6)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(outdir / "tiling.png", dpi=120)
    plt.close(fig)

    # 5. temporal stability (swimming)
    swim: list[dict] = []
    hs = pk.textures.bricks(256)
    for m in angle_methods:
        v = swimming(m, hs, frames=6 if quick else 16)
        swim.append(dict(chart="swimming", method=m.name, label=m.name, safety=m.safety, swim_texels=v))
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.bar([str(x["method"]) for x in swim], [float(x["swim_texels"]) for x in swim])
    ax.set_ylabel("mean |Δuv - Δuv_exact| per frame (texels)")
    ax.set_title("Swimming over a 0.5°/frame camera path (bricks)")
    fig.tight_layout()
    fig.savefig(outdir / "swimming.png", dpi=120)
    plt.close(fig)

    write_csv(table + at + ft + tiling_rows + swim, outdir / "bench.csv")
    print(f"wrote {outdir.resolve()}/: bench.csv, pareto.png, pareto_fetches.png, angle.png, frequency.png, tiling.png, "
          f"swimming.png in {time.perf_counter() - t_start:.0f} s")
    return dict(table=table, searched=searched, front=front_labels, front_fetches=front_fetch_labels, angle=at,
                frequency=ft, tiling=tiling_rows, swimming=swim, size=size)
