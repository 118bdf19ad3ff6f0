"""The zoo's table (docs/assets.md, "On users' assets"): every curved method and the mesh on
each asset of tests/zoo.py, without shadows, against `render_mitsuba(spp=4, shadows=False)`, at the
reference's spp.

    .venv/bin/python tools/zoo_table.py [--size 128] [--views 2] [--depth 0.04]

Per method and asset, over the views: silhouette IoU, pixels missed 3 pixels inside Mitsuba's
outline (interior holes), interior FLIP, and wall ms a frame (llvmpipe here; timings of a CPU
rasteriser, for scale only). Mitsuba renders are cached on disk by scene hash.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import pomkit as pk  # noqa: E402
import zoo  # noqa: E402

# without shadows, as the reference renders
METHODS = {
    "Tessellated(0.5)": pk.Tessellated(texels_per_vertex=0.5, shadows="none"),
    "Prism": pk.Prism(shadows="none"),
    "Prism(exact)": pk.Prism(exact=True, shadows="none"),
    "NCS": pk.NCS(shadows="none"),
    "CurvedRelief": pk.CurvedRelief(shadows="none"),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--views", type=int, default=2)
    ap.add_argument("--depth", type=float, default=0.04)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--assets", nargs="*", default=list(zoo.ZOO))
    a = ap.parse_args()
    r = pk.Renderer()
    rows = []
    for name in a.assets:
        mesh, _ = zoo.ZOO[name]()
        cells: dict[str, list] = {m: [] for m in METHODS}
        for cam in zoo.views(mesh, a.views, size=a.size):
            scene = zoo.scene(name, cam, depth=a.depth)
            ref = pk.reference.render_mitsuba(scene, spp=a.spp, shadows=False)
            for label, m in METHODS.items():
                r.render(scene, m, spp=a.spp)  # resources and pipelines built outside the timing
                t = time.perf_counter()
                f = r.render(scene, m, spp=a.spp)
                ms = 1e3 * (time.perf_counter() - t)
                c = pk.metrics.compare(f, ref, scene)
                cells[label].append((c["mask_iou"], zoo.interior_holes(f.mask, ref.mask), c["flip_interior"], ms))
        rows.append((name, len(mesh.indices) // 3, cells))
        print(name, flush=True)
    print()
    print("| asset | " + " | ".join(METHODS) + " |")
    print("|---|" + "---|" * len(METHODS))
    rng = lambda v, f: f.format(min(v)) if f.format(min(v)) == f.format(max(v)) else f"{f.format(min(v))}-{f.format(max(v))}"  # noqa: E731
    for name, ntri, cells in rows:
        out = []
        for label in METHODS:
            v = cells[label]
            out.append(f"{rng([x[0] for x in v], '{:.4f}')}, {max(x[1] for x in v)}, {rng([x[2] for x in v], '{:.4f}')}, {rng([x[3] for x in v], '{:.0f}')} ms")
        print(f"| {name} ({ntri} tris) | " + " | ".join(out) + " |")


if __name__ == "__main__":
    main()
