"""The oracle on large meshes: `pk.oracle.hits` on UV spheres of 262k and 1M triangles, first call
(the shell built: prisms, adjacency, bounding volumes) and later calls (kept by mesh content and
depth), and the process's peak memory.

    .venv/bin/python tools/oracle_scale.py
"""

from __future__ import annotations

import resource
import time

import pomkit as pk


def main() -> None:
    for seg, rings in [(512, 256), (1024, 512)]:
        m = pk.Mesh.sphere(segments=seg, rings=rings)
        for size in (64, 256):
            sc = pk.Scene(mesh=m, material=pk.Material(height=pk.textures.bricks(256), depth=0.05),
                          camera=pk.Camera.look_at(eye=(0.0, 0.8, 2.6), target=(0, 0, 0), fov_y=40.0, width=size, height=size))
            times = []
            for _ in range(3):
                t = time.perf_counter()
                pk.oracle.hits(sc)
                times.append(time.perf_counter() - t)
            print(f"{m.indices.size // 3:8d} triangles, {size}^2: " + ", ".join(f"{x:.2f} s" for x in times))
        print(f"peak memory {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6:.2f} GB")


if __name__ == "__main__":
    main()
