"""Long-run check: N renders of 128^2 frames with varying scenes, materials and methods; prints
the resident memory every N/10 renders. Usage: python tools/soak.py [N]"""

import resource
import sys
import time

import numpy as np

import pomkit as pk


def rss_mb() -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def main(n: int = 10_000) -> None:
    r = pk.Renderer()
    rng = np.random.default_rng(0)
    methods = [pk.Flat(), pk.Bump(), pk.POM(), pk.Relief(shadows="hard"), pk.Exact(shadows="exact"), pk.SteepParallax(),
               pk.Parallax(), pk.POM(shadows="horizon", ao_directions=4), pk.Tessellated(texels_per_vertex=2.0)]
    meshes = [pk.Mesh.plane(), pk.Mesh.sphere(segments=32, rings=16), pk.Mesh.torus(segments=32, tube_segments=16)]
    t0 = time.perf_counter()
    samples = []
    for i in range(n):
        # a new height map every render (a new upload each time: the cache must stay bounded)
        h = rng.random((64, 64)).astype(np.float32) if i % 2 else pk.textures.sine(64, 1 + i % 7)
        a = rng.random((8, 8, 3)).astype(np.float32) if i % 3 == 0 else None
        scene = pk.Scene(mesh=meshes[i % 3], material=pk.Material(h, depth=0.05 + 0.01 * (i % 5), albedo=a),
                         camera=pk.Camera.look_at((0.3, 1.5, 2.5), width=128, height=128),
                         lights=[pk.DirectionalLight((-0.4, -1, -0.3), 2.0, 1.0)], ambient=0.1)
        r.render(scene, methods[i % len(methods)])
        if i % (n // 10) == 0 or i == n - 1:
            samples.append(rss_mb())
            print(f"{i:6d} renders  RSS {samples[-1]:8.1f} MB  {time.perf_counter() - t0:7.1f} s", flush=True)
    first_tenth = samples[1]
    print(f"RSS after 10%: {first_tenth:.1f} MB, at the end: {samples[-1]:.1f} MB, growth {samples[-1] - first_tenth:+.1f} MB")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10_000)
