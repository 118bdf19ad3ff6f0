"""The oracle against Blender's Cycles (pk.reference.render_cycles) on the sphere, a plane and
the asset zoo: uv error away from chart borders, and coverage; the table of docs/tables/cycles.md.

    cd tests && PYTHONPATH=. ../.venv/bin/python ../tools/cycles_agreement.py > ../docs/tables/cycles.md
"""

from __future__ import annotations

import numpy as np

import pomkit as pk
import zoo
from provenance import stamp
from test_cycles import _charts_apart, _outline


def measure(label: str, sc, dicing: float = 0.25, px: int = 1) -> None:
    c = pk.reference.render_cycles(sc, spp=1, shadows=False, dicing=dicing)
    ref = pk.oracle.hits(sc)
    h = sc.material.height
    tex = np.array([h.shape[1], h.shape[0]], np.float64) * sc.material.tiling
    both = c.mask & ref.mask & ~_charts_apart(ref, tex, px)
    err = np.linalg.norm((c.uv.astype(np.float64) - ref.uv) * tex, axis=-1)[both]
    d = c.mask != ref.mask
    print(f"| {label} | {dicing} | {np.percentile(err, 95):.4f} | {np.percentile(err, 99):.4f} | "
          f"{int((c.mask & ~ref.mask).sum())} | {int((ref.mask & ~c.mask).sum())} | {int((d & ~_outline(ref.mask)).sum())} | "
          f"{int(ref.mask.sum())} |", flush=True)


def main() -> None:
    print("# Blender's Cycles against the oracle\n")
    print(stamp(None, "tools/cycles_agreement.py") + " Cycles renders on Blender's CPU device and the oracle is "
          "pomkit's float64 CPU code: no GPU adapter takes part.\n")
    print("`pk.reference.render_cycles` (bpy 5.0.1, true displacement, simple adaptive subdivision) against")
    print("`pk.oracle.hits` at pixel centres; uv error in texels away from chart borders (within 1 pixel, 4 on")
    print("the crate, whose hard edges Cycles leaves split); coverage in pixels. Written by")
    print("tools/cycles_agreement.py.\n")
    print("| scene | dicing (px) | uv p95 (texel) | uv p99 | Cycles only (px) | oracle only (px) | off the outline band | oracle's pixels |")
    print("|---|---|---|---|---|---|---|---|")
    for tex in ["bricks", "noise"]:
        sc = pk.Scene(mesh=pk.Mesh.sphere(), material=pk.Material(height=pk.textures.ALL[tex](128), depth=0.05),
                      camera=pk.Camera.look_at(eye=(0.0, 0.8, 2.6), target=(0, 0, 0), fov_y=40.0, width=128, height=128))
        measure(f"sphere, {tex} 128², 128² frame", sc)
    measure("plane (size 2), bricks 128², 60°", pk.scenes.tilted_plane(pk.textures.bricks(128), 60.0, 128))
    for name, dicing, px in [("rock", 0.25, 1), ("terrain", 0.25, 1), ("mirrored_slab", 0.1, 1), ("crate", 0.25, 4),
                             ("big", 0.25, 1)]:
        mesh, h = zoo.ZOO[name](128 if name == "big" else 64)
        for i, cam in enumerate(zoo.views(mesh, n=3, size=128)):
            measure(f"zoo {name}, view {i}", pk.Scene(mesh=mesh, material=pk.Material(height=h, depth=0.04), camera=cam),
                    dicing, px)


if __name__ == "__main__":
    main()
