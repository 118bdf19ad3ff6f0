"""The speed side of `scripts/gpu_check.sh`: pomkit's methods timed on this machine's adapter
(GPU timestamps where it has them), at 512² and at 1920x1080, over the cost model's quick suite
(bricks at 45° on a plane, cobblestones on a torus), in both pipelines (raster, and the
visibility pass plus compute); the cost model fitted there; Flat and POM against the chip's write
and fetch bounds on the chips it knows; and a table written to docs/tables/gpu/<adapter>.md with
its numbers as JSON beside it.

It needs the installed pomkit wheel, numpy and scipy (the `bench` extra) and the checkout's
tools/ (the cost model's fitting, tools/costfit.py): no Rust toolchain. The rank correlation
against llvmpipe reads docs/tables/gpu/llvmpipe*-vulkan.json (this script's output on llvmpipe's
Vulkan), when there is one.

Usage: python scripts/gpu_check.py [--out docs/tables/gpu] [--rounds 3]"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import pomkit as pk

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))
import costfit  # noqa: E402
from provenance import record  # noqa: E402

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


#: the chips whose bounds the table states: memory bandwidth (bytes/s) and texel rate (texels/s)
#: from the vendors' data sheets (H100 SXM5: 3.35 TB/s, 528 texture units at 1.98 GHz; H200:
#: 4.8 TB/s, the same units)
CHIPS = {"H200": (4.8e12, 528 * 1.98e9), "H100": (3.35e12, 528 * 1.98e9)}
#: bytes a frame writes a pixel in the targets of every AOV but the counters (two Rgba32Uint, R32Uint)
BYTES_PER_PIXEL = 16 + 16 + 4


def measure(rounds: int) -> dict:
    """Both pipelines' timings: every method in each (the compute pipeline draws no prisms: Prism
    is timed in the raster pipeline only), the counts from the raster pipeline."""
    raster = pk.Renderer(pipeline="raster")
    info = raster.info
    scenes, methods = costfit.cost_model_suite(256, quick=True)
    out: dict = dict(adapter=f"{info['name']} ({info['backend']})", driver=info["driver"], commit=_commit(),
                     provenance=record(info), auto=info["auto_pipeline"], pipelines={})
    pipelines = {"raster": (raster, methods)}
    if not any(f.startswith("compute pipeline") and not ok for f, ok, _ in info["features"]):
        pipelines["compute"] = (pk.Renderer(pipeline="compute"), [m for m in methods if m.name != "Prism"])
    for pname, (r, ms) in pipelines.items():
        sizes: dict = {}
        for size_name, wh in SIZES.items():
            t0 = time.perf_counter()
            sized = {k: _sized(v, wh) for k, v in scenes.items()}
            rows = costfit.cost_rows(r, sized, ms, min_repeats=2, max_repeats=rounds, counter=raster)
            fits = {k: costfit.fit_model(rows, t) for k, t in costfit.COST_MODELS.items()}
            per: dict[str, list[float]] = {}
            for row in rows:
                per.setdefault(row["label"], []).append(row["gpu_ms"])
            sizes[size_name] = dict(ms={k: float(np.median(v)) for k, v in per.items()},
                                    rows=[{k: v for k, v in row.items() if k != "times"} for row in rows],
                                    fits=fits, timing=rows[0]["timing"] if rows else "none",
                                    pixels=wh[0] * wh[1], seconds=time.perf_counter() - t0)
            print(f"[gpu_check] {pname} {size_name}: {len(rows)} timings in {time.perf_counter() - t0:.0f} s", flush=True)
        out["pipelines"][pname] = sizes
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


def _bounds(res: dict, size: dict) -> list[str]:
    """Flat against its write bound, POM against its fetch bound, on a chip of CHIPS."""
    chip = next((c for c in CHIPS if c in res["adapter"]), None)
    if chip is None:
        return []
    bw, texels = CHIPS[chip]
    lines = []
    for pname, s in size.items():
        flat, pom = _find(s["ms"], "Flat"), _find(s["ms"], "POM")
        write_ms = BYTES_PER_PIXEL * s["pixels"] / bw * 1e3
        fetches = np.median([row["fetches"] for row in s["rows"] if row["label"].startswith("POM") and "min_steps" not in row["label"]])
        fetch_ms = fetches / texels * 1e3
        lines.append(f"- {pname}: Flat {flat:.3f} ms = {flat / write_ms:.1f}x its write bound ({write_ms:.4f} ms: "
                     f"{BYTES_PER_PIXEL} B a pixel at {bw / 1e12:.2f} TB/s); POM {pom:.3f} ms = {pom / fetch_ms:.1f}x "
                     f"its fetch bound ({fetch_ms:.4f} ms: {fetches:.3g} texels at {texels / 1e12:.2f} Ttexel/s)")
    return lines


def table(res: dict, base: dict | None) -> str:
    lines = [f"# {res['adapter']}", "", res["provenance"]["line"], "",
             "GPU ms are medians over the cost "
             "model's quick suite (bricks 45° on a plane; cobblestones, two tiles, on a torus), shadows off, "
             "interleaved rounds after a warm-up (`pomkit.bench.time_methods`), in both pipelines "
             "(`pk.Renderer(pipeline=\"raster\")` and `\"compute\"`; the compute pipeline draws no prisms). "
             f"\"auto\" picks the {res['auto']} pipeline here.", ""]
    pipes = res["pipelines"]
    for size_name in SIZES:
        per = {p: s[size_name] for p, s in pipes.items() if size_name in s}
        if not per:
            continue
        r = per["raster"]["ms"]
        c = per.get("compute", {}).get("ms", {})
        pom, flat = _find(r, "POM"), _find(r, "Flat")
        cpom = _find(c, "POM") if c else float("nan")
        tess = next((v for k, v in r.items() if k.startswith("Tessellated") and "texels_per_vertex=1.0" in k
                     and "grid" not in k), _find(r, "Tessellated"))
        lines += [f"## {size_name} ({per['raster']['timing']} timing)", "",
                  "| method | raster ms | compute ms | raster / compute | raster / POM | compute / compute POM | raster / Flat | raster / Tessellated(1) |",
                  "|---|---|---|---|---|---|---|---|"]
        for k, v in sorted(r.items(), key=lambda kv: kv[1]):
            cv = c.get(k, float("nan"))
            lines.append(f"| {k} | {v:.3f} | {cv:.3f} | {v / cv:.2f} | {v / pom:.2f} | {cv / cpom:.2f} | {v / flat:.2f} | {v / tess:.2f} |")
        lines.append("")
        lines += _bounds(res, per)
        for pname, s in per.items():
            for name, f in s["fits"].items():
                coef = ", ".join(f"{t} {c:.3g}" for t, c in f["coef"].items())
                lines.append(f"- {pname}, cost model ({name}): a = {f['a']:.3g} ms, {coef}; R² {f['r2']:.3f}, median "
                             f"relative error {f['med_rel_err']:.2f} over {f['n']} rows")
        if base:
            b = base.get("pipelines", {}).get("raster", base.get("sizes", {})).get(size_name)
            if b:
                rho, n = spearman(r, b["ms"])
                lines.append(f"- rank correlation (Spearman) of the raster pipeline's ms against llvmpipe's (commit "
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
