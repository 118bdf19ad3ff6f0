"""The speed side of `scripts/gpu_check.sh`: pomkit's methods timed on this machine's adapter
(GPU timestamps where it has them), at 512² and at 1920x1080, over the cost model's quick suite
(bricks at 45° on a plane, cobblestones on a torus); the cost model fitted there; and a table
written to docs/tables/gpu/<adapter>.md with its numbers as JSON beside it.

It needs the installed pomkit wheel, numpy and scipy (the `bench` extra): no Rust toolchain. The rank correlation
against llvmpipe reads docs/tables/gpu/llvmpipe*-vulkan.json (this script's output on llvmpipe's
Vulkan), when there is one.

Usage: python scripts/gpu_check.py [--out docs/tables/gpu] [--rounds 3]"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import time
from pathlib import Path

import numpy as np

import pomkit as pk
from pomkit import bench

SIZES = {"512²": (512, 512), "1920x1080": (1920, 1080)}


def _commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip()
    except Exception:
        return "unknown"


def _sized(scene: pk.Scene, wh: tuple[int, int]) -> pk.Scene:
    cam = scene.camera
    return scene.replace(camera=pk.Camera(eye=cam.eye, target=cam.target, up=cam.up, fov_y=cam.fov_y,
                                          width=wh[0], height=wh[1]))


def measure(rounds: int) -> dict:
    r = pk.Renderer()
    info = r.info
    scenes, methods = bench.cost_model_suite(256, quick=True)
    out: dict = dict(adapter=f"{info['name']} ({info['backend']})", driver=info["driver"], commit=_commit(), sizes={})
    for size_name, wh in SIZES.items():
        t0 = time.perf_counter()
        sized = {k: _sized(v, wh) for k, v in scenes.items()}
        rows = bench.cost_rows(r, sized, methods, min_repeats=2, max_repeats=rounds)
        fits = {k: bench.fit_model(rows, t) for k, t in bench.COST_MODELS.items()}
        per: dict[str, list[float]] = {}
        for row in rows:
            per.setdefault(row["label"], []).append(row["gpu_ms"])
        out["sizes"][size_name] = dict(ms={k: float(np.median(v)) for k, v in per.items()},
                                       rows=[{k: v for k, v in row.items() if k != "times"} for row in rows],
                                       fits=fits, timing=rows[0]["timing"] if rows else "none",
                                       seconds=time.perf_counter() - t0)
        print(f"[gpu_check] {size_name}: {len(rows)} timings in {time.perf_counter() - t0:.0f} s", flush=True)
    return out


def _find(ms: dict, prefix: str) -> float:
    for k, v in ms.items():
        if k == prefix or k.startswith(prefix + "(") or k.startswith(prefix + " "):
            return v
    return float("nan")


def spearman(a: dict, b: dict) -> tuple[float, int]:
    keys = sorted(set(a) & set(b))
    if len(keys) < 3:
        return float("nan"), len(keys)
    from scipy.stats import spearmanr
    rho = spearmanr([a[k] for k in keys], [b[k] for k in keys]).statistic
    return float(rho), len(keys)


def table(res: dict, base: dict | None) -> str:
    lines = [f"# {res['adapter']}", "",
             f"Written by `scripts/gpu_check.sh` at commit {res['commit']}. GPU ms are medians over the cost "
             "model's quick suite (bricks 45° on a plane; cobblestones, two tiles, on a torus), shadows off, "
             "interleaved rounds after a warm-up (`pomkit.bench.time_methods`).", ""]
    for size_name, s in res["sizes"].items():
        ms = s["ms"]
        pom, flat = _find(ms, "POM"), _find(ms, "Flat")
        tess = next((v for k, v in ms.items() if k.startswith("Tessellated") and "texels_per_vertex=1.0" in k
                     and "grid" not in k), _find(ms, "Tessellated"))
        lines += [f"## {size_name} ({s['timing']} timing)", "",
                  "| method | ms | / POM | / Flat | / Tessellated(1) |", "|---|---|---|---|---|"]
        for k, v in sorted(ms.items(), key=lambda kv: kv[1]):
            lines.append(f"| {k} | {v:.3f} | {v / pom:.2f} | {v / flat:.2f} | {v / tess:.2f} |")
        lines.append("")
        for name, f in s["fits"].items():
            coef = ", ".join(f"{t} {c:.3g}" for t, c in f["coef"].items())
            lines.append(f"- cost model ({name}): a = {f['a']:.3g} ms, {coef}; R² {f['r2']:.3f}, median relative "
                         f"error {f['med_rel_err']:.2f} over {f['n']} rows")
        if base and size_name in base.get("sizes", {}):
            rho, n = spearman(ms, base["sizes"][size_name]["ms"])
            lines.append(f"- rank correlation (Spearman) of the methods' ms against llvmpipe's (commit "
                         f"{base.get('commit', '?')}): {rho:.3f} over {n} methods")
        lines.append("")
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="docs/tables/gpu")
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    res = measure(a.rounds)
    slug = re.sub(r"[^A-Za-z0-9]+", "-", res["adapter"]).strip("-")
    (out / f"{slug}.json").write_text(json.dumps(res, indent=1, default=float))
    # the CPU rasteriser's Vulkan run at this commit, the baseline of the rank correlation
    bases = [p for p in sorted(out.glob("llvmpipe*-vulkan.json")) if p.stem != slug]
    base = json.loads(bases[0].read_text()) if bases else None
    (out / f"{slug}.md").write_text(table(res, base) + "\n")
    print(f"[gpu_check] wrote {out / (slug + '.md')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
