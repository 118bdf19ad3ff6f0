#!/usr/bin/env python
"""The cost model over every method (issue 33): writes docs/tables/cost_model.md.

`costfit.cost_model` (tools/costfit.py) times every built-in method (shadows off) on three
planar scenes and a torus and a sphere at 256², counts each frame's fetches, bytes, fragments,
steps and primitives, and fits GPU ms = a + sum(c_t * count_t) by least squares, per pixel and
per SIMD group (docs/cost.md). The table lists each row with the model's prediction, the fits, and
Prism's and the safe methods' ratios to POM on each scene.

    .venv/bin/python tools/cost_model.py [--quick] [--out docs/tables/cost_model.md]
"""

from __future__ import annotations

import argparse
from pathlib import Path


import pomkit as pk
from pomkit import bench as B

import costfit
from provenance import stamp

OUT = Path(__file__).resolve().parent.parent / "docs" / "tables" / "cost_model.md"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="two scenes, fewer rounds")
    ap.add_argument("--out", default=str(OUT))
    a = ap.parse_args()
    r = pk.Renderer()
    cm = costfit.cost_model(r, quick=a.quick)
    rows, fits = cm["rows"], cm["fits"]
    fit = fits["per pixel"]
    lines = ["# The cost model over every method", "", stamp(r.info), "",
             "GPU ms (timestamps, median of interleaved rounds after a warm-up) at 256², shadows off, and each frame's "
             "totals of the counters (docs/cost.md). The fits are over every row, with non-negative coefficients, each row "
             "weighted by 1/sqrt(ms) (`fit_model` of tools/costfit.py).", "",
             "| model | a (ms) | coefficients (ns per unit) | R² | median row off by | worst row off by |", "|---|---|---|---|---|---|"]
    for name, f in fits.items():
        co = ", ".join(f"{t} {v * 1e6:.3g}" for t, v in f["coef"].items())
        lines.append(f"| {name} | {f['a']:.2f} | {co} | {f['r2']:.3f} | {100 * f['med_rel_err']:.0f}% | {100 * f['max_rel_err']:.0f}% |")
    lines += ["", "| scene | method | GPU ms | predicted (per pixel) | fetches/px | bytes/px | fragments/px | quads/px | primitives | steps/px |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for x in rows:
        p = fit["a"] + sum(fit["coef"][t] * x[t] for t in fit["coef"])
        n = x["pixels"]
        lines.append(f"| {x['scene']} | {x['label']} | {x['gpu_ms']:.2f} | {p:.2f} | {x['fetches'] / n:.1f} | {x['bytes'] / n:.0f} | "
                     f"{x['fragments'] / n:.2f} | {x['quads'] / n:.2f} | {x['primitives']:.0f} | {x['steps'] / n:.1f} |")
    lines += ["", "Ratios to POM(shadows='none') on each scene (the same rounds; Tessellated(1) is the two-triangle grid, "
              "the mesh of the bench's Prism goal):", "",
              "| scene | Prism | Prism(exact) | Exact | ConeStep | Tessellated(1) | Prism / Tessellated(1) |", "|---|---|---|---|---|---|---|"]
    off = costfit.shadows_off
    keys = {k: B.label(m) for k, m in (("pom", off(pk.POM)), ("prism", off(pk.Prism)), ("prism_x", off(pk.Prism, exact=True)),
                                       ("exact", off(pk.Exact)), ("cone", off(pk.ConeStep)),
                                       ("tess", off(pk.Tessellated, texels_per_vertex=1.0, pattern="grid")))}
    for sc in dict.fromkeys(x["scene"] for x in rows):
        by = {x["label"]: x["gpu_ms"] for x in rows if x["scene"] == sc}
        t = {k: by[v] for k, v in keys.items()}
        lines.append(f"| {sc} | {t['prism'] / t['pom']:.2f} | {t['prism_x'] / t['pom']:.2f} | {t['exact'] / t['pom']:.2f} | "
                     f"{t['cone'] / t['pom']:.2f} | {t['tess'] / t['pom']:.2f} | {t['prism'] / t['tess']:.2f} |")
    Path(a.out).write_text("\n".join(lines) + "\n")
    print("\n".join(lines[:10]))
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
