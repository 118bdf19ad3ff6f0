"""Speed against accuracy.

`sweep(...)` renders methods x scenes x angles, times them (GPU timestamps where the adapter has
them, else wall time) and measures them against a reference; `python -m pomkit bench [--quick]`
runs the standard sweep and writes the table (CSV) and the charts into ./pomkit-out/bench/.
"""

from __future__ import annotations

import csv
import math
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Iterable, Optional

import numpy as np

import pomkit as pk
from . import metrics

__all__ = ["sweep", "variants", "plane_scene", "time_method", "run_bench", "swimming"]


def plane_scene(height, theta_deg: float, size: int, depth: float = 0.08, tiling: float = 1.0,
                lights=None) -> pk.Scene:
    """A size-2 plane seen at `theta_deg` from its normal from 1.6 units away (the bench scene)."""
    t = np.radians(theta_deg)
    return pk.Scene(
        mesh=pk.Mesh.plane(2.0),
        material=pk.Material(height, depth=depth, tiling=tiling),
        camera=pk.Camera.look_at(eye=(0.0, 1.6 * np.cos(t), 1.6 * np.sin(t)), target=(0, 0, 0), up=(0, 0, -1),
                                 fov_y=40.0, width=size, height=size),
        lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0, 2.0)] if lights is None else lights,
    )


def uv_error_texels(frame: pk.Frame, ref: pk.Frame, scene: pk.Scene) -> np.ndarray:
    m = frame.mask & ref.mask
    h, w = scene.material.height.shape
    d = (frame.uv[m] - ref.uv[m]) * np.array([w, h]) * scene.material.tiling
    return np.linalg.norm(d, axis=-1)


def time_method(r: pk.Renderer, scene: pk.Scene, method, repeats: int = 5) -> dict:
    """Median, min and max time of `repeats` renders after a warm-up (pipeline creation and
    uploads happen in the warm-up)."""
    r.render(scene, method)
    ts, walls, calls = [], [], []
    f = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        f = r.render(scene, method)
        calls.append((time.perf_counter() - t0) * 1e3)
        ts.append(f.time_ms)
        walls.append(f.wall_ms)
    return dict(ms=float(np.median(ts)), ms_min=float(np.min(ts)), ms_max=float(np.max(ts)), timing=f.timing,
                call_ms=float(np.median(calls)), steps=float(f.steps[f.mask].mean()) if f.mask.any() else 0.0, frame=f)


def variants(cls, **grid) -> list:
    """Every combination of the given parameter lists: variants(pk.POM, max_steps=[8, 16])."""
    keys = list(grid)
    out = [{}]
    for k in keys:
        out = [dict(d, **{k: v}) for d in out for v in grid[k]]
    return [cls(**d) for d in out]


def _label(m) -> str:
    """The method with only the fields that differ from its defaults: POM(max_steps=16); a
    Custom method by its name and parameters."""
    from dataclasses import fields
    if isinstance(m, pk.Custom):
        return f"{m.name}({', '.join(f'{k}={v:g}' for k, v in m.params.items())})"
    try:
        default = type(m)()
    except Exception:
        return repr(m)
    diff = [f"{f.name}={getattr(m, f.name)!r}" for f in fields(m) if getattr(m, f.name) != getattr(default, f.name)]
    return f"{m.name}({', '.join(diff)})"


def _method_name(m) -> str:
    return getattr(m, "_preset", None) or (m.label if isinstance(m, pk.Custom) else m.name)


def _mitsuba_job(args):
    scene, spp = args
    from . import reference
    reference.render_mitsuba(scene, spp=spp)  # fills the on-disk cache
    return True


def _scene_for(name_or_height, angle, size, depth, tiling):
    if isinstance(name_or_height, str):
        if name_or_height.startswith("sine"):
            freq = float(name_or_height[4:] or 4)
            h = pk.textures.sine(256, freq)
        else:
            h = pk.textures.ALL[name_or_height](256)
        name = name_or_height
    else:
        name, h = name_or_height
    return name, plane_scene(h, angle, size, depth=depth, tiling=tiling)


def sweep(methods: Iterable, scenes: Iterable = ("bricks",), angles: Iterable[float] = (60.0,),
          settings: Optional[dict] = None, reference: str = "exact", repeats: int = 3,
          csv_path: Optional[str] = None, progress: bool = True, workers: int = 0):
    """Render, time and measure every (method, scene, angle).

    methods: Method instances (see `variants` and `pomkit.presets`); scenes: texture names from
    `pk.textures.ALL`, "sineF" for a sine of frequency F, or (name, height array) pairs;
    settings: size (256), depth (0.08), tiling (1.0), spp (64, Mitsuba);
    reference: "exact" (the CPU oracle; FLIP then against Tessellated(0.5) colour), "tessellated"
    or "mitsuba" (rendered first, through a process pool of `workers` processes when > 0, and
    cached on disk).
    Rows: method, params, scene, angle, gpu_ms (median) with min/max, ms_per_mpix, call_ms, mean
    steps, uv p50/p95/p99 (texels), mask IoU, FLIP. Returns a pandas DataFrame when pandas is
    installed, else a list of dicts; writes CSV to `csv_path` when given."""
    if reference not in ("exact", "tessellated", "mitsuba"):
        raise ValueError(f"reference: must be 'exact', 'tessellated' or 'mitsuba', got {reference!r}")
    cfg = dict(size=256, depth=0.08, tiling=1.0, spp=64)
    cfg.update(settings or {})
    methods = list(methods)
    jobs = [(s, a) for s in scenes for a in angles]
    r = pk.Renderer()
    built = {(str(s if isinstance(s, str) else s[0]), a): _scene_for(s, a, cfg["size"], cfg["depth"], cfg["tiling"])
             for s, a in jobs}
    if reference == "mitsuba" and workers > 0:
        with ProcessPoolExecutor(workers) as ex:
            list(ex.map(_mitsuba_job, [(sc, cfg["spp"]) for _, sc in built.values()]))
    bar = None
    if progress:
        try:
            from tqdm.auto import tqdm
            bar = tqdm(total=len(built) * len(methods), desc="pomkit sweep", leave=False)
        except ImportError:
            bar = None
    rows = []
    for (sname, angle), (_, scene) in built.items():
        if reference == "exact":
            ref = pk.exact_uv(scene)
            cref = r.render(scene, pk.Tessellated(texels_per_vertex=0.5))
        elif reference == "tessellated":
            ref = cref = r.render(scene, pk.Tessellated(texels_per_vertex=0.5))
        else:
            from . import reference as R
            ref = cref = R.render_mitsuba(scene, spp=cfg["spp"])
        for m in methods:
            t = time_method(r, scene, m, repeats=repeats)
            f = t.pop("frame")
            e = metrics.uv_error(f, ref, scene)
            try:
                fl = metrics.flip(f, cref)
            except ImportError:
                fl = float("nan")
            mpix = scene.camera.width * scene.camera.height / 1e6
            rows.append(dict(method=_method_name(m), params=_label(m), scene=sname, angle=angle, size=cfg["size"],
                             gpu_ms=t["ms"], gpu_ms_min=t["ms_min"], gpu_ms_max=t["ms_max"], timing=t["timing"],
                             ms_per_mpix=t["ms"] / mpix, call_ms=t["call_ms"], mean_steps=t["steps"],
                             uv_p50=e["p50"], uv_p95=e["p95"], uv_p99=e["p99"], mask_iou=e["mask_iou"], flip=fl))
            if bar is not None:
                bar.update(1)
    if bar is not None:
        bar.close()
    if csv_path:
        Path(csv_path).parent.mkdir(parents=True, exist_ok=True)
        with open(csv_path, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    try:
        import pandas as pd
        return pd.DataFrame(rows)
    except ImportError:
        return rows


def swimming(method, scene_height, frames: int = 16, step_deg: float = 0.5, start_deg: float = 55.0, size: int = 128) -> float:
    """Temporal stability: over a camera path (`frames` views, `step_deg` apart), the mean over
    pixels of |frame-to-frame change of the hit uv - the change the exact oracle predicts|, in
    texels. 0 means the surface moves exactly as the true surface would."""
    r = pk.Renderer()
    prev = None
    acc = []
    for k in range(frames):
        sc = plane_scene(scene_height, start_deg + step_deg * k, size)
        f = r.render(sc, method)
        o = pk.exact_uv(sc)
        if prev is not None:
            pf, po = prev
            m = f.mask & o.mask & pf.mask & po.mask
            d = ((f.uv - pf.uv) - (o.uv - po.uv))[m] * np.array(sc.material.height.shape[::-1])
            acc.append(float(np.linalg.norm(d, axis=-1).mean()))
        prev = (f, o)
    return float(np.mean(acc))


# ------------------------------------------------------------------ the standard bench

def _rows(t):
    return t.to_dict("records") if hasattr(t, "to_dict") else list(t)


def pareto_front(points):
    """Indices of the points not dominated in (time, error), both minimised."""
    idx = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in idx:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def run_bench(out: str = "pomkit-out/bench", quick: bool = False) -> dict:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from . import presets

    t_start = time.perf_counter()
    outdir = Path(out)
    outdir.mkdir(parents=True, exist_ok=True)
    r = pk.Renderer()
    print(f"pomkit bench on {r.info['name']} ({r.info['backend']}), timestamps={r.info['timestamps']}")
    size = 256 if quick else 512
    reps = 3 if quick else 5
    steps_grid = [4, 8, 16, 32, 64] if quick else [4, 8, 16, 32, 64, 128]
    lvl0 = dict(mip_filtering=False)
    families = {
        "POM": [pk.POM(min_steps=max(1, n // 4), max_steps=n, shadows="none", lod_threshold=1000.0, **lvl0) for n in steps_grid],
        "SteepParallax": [pk.SteepParallax(steps=n, **lvl0) for n in steps_grid],
        "Relief": [pk.Relief(linear_steps=n, binary_steps=5, **lvl0) for n in steps_grid],
        "Parallax": [pk.Parallax(**lvl0)],
        "Exact": [pk.Exact()],
        "Tessellated": [pk.Tessellated(texels_per_vertex=t, shadows="none") for t in ([1.0, 2.0, 4.0] if quick else [0.5, 1.0, 2.0, 4.0])],
    }
    preset_methods = []
    for name, fn in presets.ALL_PRESETS.items():
        m = fn()
        object.__setattr__(m, "_preset", name)
        preset_methods.append(m)
    defaults = {"POM (default)": pk.POM(shadows="none"), "Exact (default)": pk.Exact()}
    for name, m in defaults.items():
        object.__setattr__(m, "_preset", name)
    all_methods = [m for ms in families.values() for m in ms] + preset_methods + list(defaults.values())

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
    angle_methods = [pk.Parallax(), pk.SteepParallax(), pk.POM(shadows="none"), pk.Relief(), pk.Exact()]
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
    tiling_rows = []
    for tiling in (1, 2, 4, 8):
        sc = plane_scene(pk.textures.bricks(256 if quick else 512), 60.0, size, tiling=float(tiling))
        row = dict(chart="tiling", tiling=tiling)
        for name, m in (("POM", pk.POM(shadows="none")), ("Exact", pk.Exact()), ("Tessellated", pk.Tessellated(texels_per_vertex=1.0, shadows="none"))):
            row[name + "_ms"] = time_method(r, sc, m, repeats=reps)["ms"]
        row["Tessellated/POM"] = row["Tessellated_ms"] / row["POM_ms"]
        row["Tessellated/Exact"] = row["Tessellated_ms"] / row["Exact_ms"]
        tiling_rows.append(row)
        print(f"  tiling {tiling}x: POM {row['POM_ms']:.1f} ms, Exact {row['Exact_ms']:.1f} ms, Tessellated {row['Tessellated_ms']:.1f} ms"
              f"  (x{row['Tessellated/POM']:.1f} / x{row['Tessellated/Exact']:.1f})")
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
    swim = []
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
