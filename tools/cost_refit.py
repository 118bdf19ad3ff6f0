"""The cost model refitted with latency: the timings of `scripts/gpu_check.sh` (its JSON in
docs/tables/gpu/) joined with the chain of dependent fetches (AOV `chain`, counted here: counts
are the same on every adapter), and every model of `costfit.COST_MODELS` (tools/costfit.py)
fitted to each adapter's timings, with its R² and its leave-one-method-out R² (`costfit.loo_r2`).

A table's rows keep their own fetch, byte, fragment and quad counts (those of the code that was
timed); only `chain` and `chain_group` are counted here, on the same scenes at the same sizes.

Usage: python tools/cost_refit.py [--tables docs/tables/gpu] [--out docs/tables/cost_refit.md]"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import pomkit as pk
from pomkit import bench

import costfit
from provenance import stamp
from quads import group_total

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
from gpu_check import SIZES, _sized  # noqa: E402


def chains() -> dict[tuple[str, str, str], tuple[float, float]]:
    """(size, scene, label) -> (chain, chain_group) over the quick cost suite."""
    r = pk.Renderer(pipeline="raster")
    scenes, methods = costfit.cost_model_suite(256, quick=True)
    out = {}
    for size_name, wh in SIZES.items():
        for sname, sc in scenes.items():
            sized = _sized(sc, wh)
            for m in methods:
                f = r.render(sized, m, aovs=("mask", "chain"))
                out[(size_name, sname, bench.label(m))] = (float(f.chain.sum(dtype=np.float64)), group_total(f.chain))
    return out


def timed(table: dict) -> dict[str, dict[str, list[dict]]]:
    """pipeline -> size -> rows of a gpu_check JSON (the older form without pipelines: raster)."""
    if "pipelines" in table:
        return {p: {k: v["rows"] for k, v in s.items()} for p, s in table["pipelines"].items()}
    return {"raster": {k: v["rows"] for k, v in table["sizes"].items()}}


def refit(tables: list[Path]) -> str:
    ch = chains()
    lines = ["# The cost model, refitted with latency", "",
             stamp(pk.Renderer(pipeline="raster").info) + " The adapter is the one that counted `chain`; each "
             "adapter's timings carry their own commit below.", "",
             "Each adapter's timings are `scripts/gpu_check.sh`'s (its JSON in "
             "docs/tables/gpu/: the quick suite, bricks 45° on a plane and cobblestones on a torus, 18 methods); "
             "`chain` and `chain_group` (the longest chain of dependent fetches, summed over the pixels and over "
             "SIMD groups of 32) are counted at this commit, the other counts are the table's own. R² is the fit's; "
             "LOMO is leave-one-method-out: each method predicted by the model fitted without it.", ""]
    for path in tables:
        t = json.loads(path.read_text())
        for pipe, sizes in timed(t).items():
            lines += [f"## {t['adapter']}, {pipe} pipeline (commit {t.get('commit', '?')})", "",
                      "| size | model | terms | R² | LOMO R² | median rel. error |", "|---|---|---|---|---|---|"]
            for size_name, rows in sizes.items():
                rows = [dict(x) for x in rows]
                for x in rows:
                    x["chain"], x["chain_group"] = ch.get((size_name, x["scene"], x["label"]), (np.nan, np.nan))
                rows = [x for x in rows if np.isfinite(x["chain"])]
                for name, terms in costfit.COST_MODELS.items():
                    fit = costfit.fit_model(rows, terms)
                    loo = costfit.loo_r2(rows, terms)
                    lines.append(f"| {size_name} | {name} | {', '.join(terms)} | {fit['r2']:.3f} | {loo:.3f} | "
                                 f"{fit['med_rel_err']:.2f} |")
            lines.append("")
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--tables", default="docs/tables/gpu")
    ap.add_argument("--out", default="docs/tables/cost_refit.md")
    a = ap.parse_args()
    tables = sorted(p for p in Path(a.tables).glob("*-vulkan.json"))
    text = refit(tables)
    Path(a.out).write_text(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
