#!/usr/bin/env python
"""The oracle on curved meshes against the planar one (issue 49's goal: within 3x): a 256²
frame, a 4096² bricks map at depth 0.06, the sphere and the torus (48 x 24) against the plane,
for `pk.oracle.hits` and `pk.oracle.image(spp=spp)` (4 unless given; its own default
is 16) unshadowed, with a sharp light and ambient occlusion, and with a 2° light and ambient
occlusion. Best of `repeats` runs in one process, in turn; docs/oracle.md ("The oracle on any
mesh") holds the table.

    .venv/bin/python tools/oracle_time.py [hits,img,sharp,disk] [repeats] [spp]
"""

from __future__ import annotations

import sys
import time

import pomkit as pk

_HM: list = []


def height():
    """The 4096² bricks map (made once; tools/oracle_instructions.py puts its own in)."""
    if not _HM:
        _HM.append(pk.textures.bricks(4096))
    return _HM[0]


SHARP = [pk.DirectionalLight((-0.4, -1, -0.3), 3.0)]
DISK = [pk.DirectionalLight((-0.4, -1, -0.3), 3.0, angular_diameter=2.0)]
MESHES = {"plane": pk.Mesh.plane(2.0), "sphere": pk.Mesh.sphere(segments=48, rings=24),
          "torus": pk.Mesh.torus(segments=48, tube_segments=24)}


def scene(name: str, lights, ambient: float, size: int = 256) -> pk.Scene:
    eye = (0.0, 1.2, 1.2) if name == "plane" else (0.0, 1.0, 2.8)
    return pk.Scene(mesh=MESHES[name], material=pk.Material(height(), depth=0.06), lights=lights, ambient=ambient,
                    camera=pk.Camera.look_at(eye, fov_y=40, width=size, height=size))


def best(f, repeats: int) -> float:
    out = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        out = min(out, time.perf_counter() - t0)
    return out


def main(cases: list[str], repeats: int, spp: int) -> None:
    for case in cases:
        lights = DISK if case == "disk" else SHARP
        scenes = {name: scene(name, lights, 0.0 if case in ("hits", "img") else 0.1) for name in MESHES}
        if case == "hits":
            run = {name: (lambda s=s: pk.oracle.hits(s)) for name, s in scenes.items()}
        else:
            run = {name: (lambda s=s: pk.oracle.image(s, spp=spp, shadows=case != "img", cache=False))
                   for name, s in scenes.items()}
        row = {name: float("inf") for name in MESHES}
        for _ in range(repeats):
            for name, f in run.items():
                row[name] = min(row[name], best(f, 1))
        print(f"{case:6s}", "  ".join(f"{k} {v:.3f} s" for k, v in row.items()),
              f"  ratios {row['sphere'] / row['plane']:.2f} {row['torus'] / row['plane']:.2f}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1].split(",") if len(sys.argv) > 1 else ["hits", "img", "sharp", "disk"],
         int(sys.argv[2]) if len(sys.argv) > 2 else 2, int(sys.argv[3]) if len(sys.argv) > 3 else 4)
