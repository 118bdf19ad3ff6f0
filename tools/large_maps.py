#!/usr/bin/env python
"""Large height maps with every method (issue 31): the first render's wall time (the map's
upload, its pyramids and the method's own build included) and the process's peak host RSS
(lavapipe keeps GPU memory in host RAM), each case in a fresh process so that nothing is shared,
at 128² frames. Writes a Markdown table to stdout (docs/assets.md holds one).

    .venv/bin/python tools/large_maps.py [--sizes 4096 8192 16384] [--methods POM Exact ...]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

CASE = r"""
import json, resource, sys, time
import numpy as np
import pomkit as pk
size, name, mesh = int(sys.argv[1]), sys.argv[2], sys.argv[3]
t0 = time.perf_counter()
small = pk.textures.noise(256, seed=3)
big = np.kron(small, np.ones((size // 256, size // 256), np.float32))
big *= 0.98
big += 0.02 * np.random.default_rng(0).random(big.shape, dtype=np.float32)
t_map = time.perf_counter() - t0
rss_map = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
m = {"plane": pk.Mesh.plane(2.0), "sphere": pk.Mesh.sphere(), "torus": pk.Mesh.torus()}[mesh]
eye = (0.0, 1.2, 1.2) if mesh == "plane" else (0.0, 1.6, 2.4)
scene = pk.Scene(mesh=m, material=pk.Material(big, depth=0.06, tiling=1.0),
                 camera=pk.Camera.look_at(eye, fov_y=40.0, width=128, height=128),
                 lights=[pk.DirectionalLight((-0.3, -1.0, -0.2), 3.0)])
r = pk.Renderer()
note = ""
if name == "oracle.hits":
    render = lambda: pk.oracle.hits(scene)
else:
    method = eval("pk." + name)
    render = lambda: r.render(scene, method, aovs=("uv", "mask"))
t1 = time.perf_counter()
try:
    f = render()
    ok = bool(f.mask.any() and np.isfinite(f.uv[f.mask]).all())
except ValueError as e:
    ok, note = False, str(e)[:160]
first = time.perf_counter() - t1
t2 = time.perf_counter()
if ok:
    render()
again = time.perf_counter() - t2
print(json.dumps(dict(size=size, method=name, mesh=mesh, ok=ok, note=note, map_s=t_map, first_s=first, again_s=again,
                      rss_map_gb=rss_map, rss_peak_gb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20)))
"""

PLANAR = ["Flat()", "Bump()", "Parallax()", "SteepParallax()", "POM()", "Relief()", "Exact()", "ConeStep()",
          "DistanceMapping()", "Prism()", "NCS()", "CurvedRelief()", "oracle.hits"]
CURVED = ["Prism()", "NCS()"]


def tessellated(size: int) -> str:
    # the least texels per vertex under the core's 40M-vertex limit
    for tpv in (1, 1.5, 2, 3, 4, 6, 8):
        # the default fan: a lattice point and a quad centre each (tessellate.rs's vertex limit)
        if 2 * (size / tpv + 2) ** 2 < 40_000_000:
            return f"Tessellated(texels_per_vertex={tpv})"
    return "Tessellated(texels_per_vertex=8)"


def run(size: int, method: str, mesh: str, cache: str) -> dict:
    env = dict(os.environ, POMKIT_CACHE=cache)
    p = subprocess.run([sys.executable, "-c", CASE, str(size), method, mesh], env=env, capture_output=True, text=True)
    if p.returncode != 0:
        return dict(size=size, method=method, mesh=mesh, ok=False, note=p.stderr.strip().splitlines()[-1][:160])
    return json.loads(p.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[4096, 8192, 16384])
    ap.add_argument("--methods", nargs="+", default=None, help="method expressions, e.g. POM() 'Exact()'")
    a = ap.parse_args()
    print("| map | mesh | method | first render (s) | again (s) | peak RSS (GB) | note |")
    print("|---|---|---|---|---|---|---|")
    for size in a.sizes:
        cases = [(m, "plane") for m in (a.methods or PLANAR + [tessellated(size)])]
        if a.methods is None and size == 8192:
            cases += [(m, mesh) for m in CURVED for mesh in ("sphere", "torus")]
        for method, mesh in cases:
            with tempfile.TemporaryDirectory() as cache:  # a cold disk cache for each case
                r = run(size, method, mesh, cache)
                extra = ""
                if method == "ConeStep()" and r.get("ok"):
                    warm = run(size, method, mesh, cache)  # a fresh process: the kept cone map
                    extra = f"first render in a new process, the cone map read from disk: {warm['first_s']:.1f} s"
            print(f"| {size}² | {mesh} | {method} | {r.get('first_s', float('nan')):.1f} | {r.get('again_s', float('nan')):.2f} | "
                  f"{r.get('rss_peak_gb', float('nan')):.2f} | {'' if r.get('ok') else 'refused: ' + r.get('note', '')}{extra} |",
                  flush=True)


if __name__ == "__main__":
    main()
