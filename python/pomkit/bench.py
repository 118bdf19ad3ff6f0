"""Speed against accuracy. `python -m pomkit bench` renders each method at 512^2 and measures its
time (GPU timestamps where the adapter has them) and its uv error against the exact oracle."""

from __future__ import annotations

import csv
import time
from pathlib import Path

import numpy as np

import pomkit as pk


def plane_scene(height, theta_deg: float, size: int, depth: float = 0.08, tiling: float = 1.0) -> pk.Scene:
    t = np.radians(theta_deg)
    return pk.Scene(
        mesh=pk.Mesh.plane(2.0),
        material=pk.Material(height, depth=depth, tiling=tiling),
        camera=pk.Camera.look_at(eye=(0.0, 1.6 * np.cos(t), 1.6 * np.sin(t)), target=(0, 0, 0), up=(0, 0, -1),
                                 fov_y=40.0, width=size, height=size),
        lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0, 2.0)],
    )


def uv_error_texels(frame: pk.Frame, ref: pk.Frame, scene: pk.Scene) -> np.ndarray:
    m = frame.mask & ref.mask
    h, w = scene.material.height.shape
    d = (frame.uv[m] - ref.uv[m]) * np.array([w, h]) * scene.material.tiling
    return np.linalg.norm(d, axis=-1)


def time_method(r: pk.Renderer, scene: pk.Scene, method, repeats: int = 5) -> dict:
    r.render(scene, method)  # warm-up: pipeline creation and upload
    ts = []
    walls = []
    for _ in range(repeats):
        f = r.render(scene, method)
        ts.append(f.time_ms)
        walls.append(f.wall_ms)
    return dict(ms=float(np.median(ts)), ms_min=float(np.min(ts)), ms_max=float(np.max(ts)), timing=f.timing,
                steps=float(f.steps[f.mask].mean()))


def run_bench(out: str = "pomkit-out/bench", quick: bool = False) -> list[dict]:
    outdir = Path(out)
    outdir.mkdir(parents=True, exist_ok=True)
    r = pk.Renderer()
    print(f"pomkit bench on {r.info['name']} ({r.info['backend']}), timestamps={r.info['timestamps']}")
    rows = []
    h = pk.textures.bricks(512)
    methods = {"Flat": pk.Flat(), "Bump": pk.Bump(), "POM": pk.POM(), "POM(no shadows)": pk.POM(shadows="none")}
    size = 256 if quick else 512
    scene = plane_scene(h, 60.0, size)
    base = None
    for name, m in methods.items():
        t = time_method(r, scene, m, repeats=3 if quick else 7)
        base = base or t["ms"]
        rows.append(dict(kind="time", method=name, angle=60.0, size=size, **t, ratio_to_flat=t["ms"] / base))
        print(f"  {name:16s} {t['ms']:8.2f} ms  ({t['timing']})  x{t['ms'] / base:5.2f} of Flat")
    esize = 128 if quick else 192
    for angle in (30.0, 60.0, 80.0):
        s = plane_scene(h, angle, esize)
        o = pk.exact_uv(s)
        f = r.render(s, pk.POM(shadows="none"))
        e = uv_error_texels(f, o, s)
        rows.append(dict(kind="accuracy", method="POM", angle=angle, size=esize,
                         uv_p50=float(np.percentile(e, 50)), uv_p95=float(np.percentile(e, 95)),
                         uv_p99=float(np.percentile(e, 99)), steps=float(f.steps[f.mask].mean())))
        print(f"  POM vs exact at {angle:4.0f} deg: p50 {rows[-1]['uv_p50']:.3f}  p95 {rows[-1]['uv_p95']:.3f}  p99 {rows[-1]['uv_p99']:.3f} texels")
    keys = sorted({k for row in rows for k in row})
    with open(outdir / "bench.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {outdir.resolve()}/bench.csv")
    return rows
