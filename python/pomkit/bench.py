"""Speed against accuracy.

`sweep(...)` renders methods x scenes x angles, times them (GPU timestamps where the adapter has
them, else wall time) and measures them against a reference; `python -m pomkit bench [--quick]`
(pomkit/apps/bench.py) runs the standard sweep and writes the table (CSV) and the charts into
./pomkit-out/bench/.
"""

from __future__ import annotations

import csv
import math
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Iterable, Optional

import numpy as np

import pomkit as pk
from . import metrics

__all__ = ["sweep", "variants", "plane_scene", "time_method", "swimming", "pareto_front"]


def plane_scene(height, theta_deg: float, size: int, depth: float = 0.08, tiling: float = 1.0,
                lights=None) -> pk.Scene:
    """A size-2 plane seen at `theta_deg` from its normal from 1.6 units away (the bench scene)."""
    t = np.radians(theta_deg)
    return pk.Scene(
        mesh=pk.Mesh.plane(2.0),
        material=pk.Material(height, depth=depth, tiling=tiling),
        camera=pk.Camera.look_at(eye=(0.0, 1.6 * np.cos(t), 1.6 * np.sin(t)), target=(0, 0, 0), up=(0, 0, -1),
                                 fov_y=40.0, width=size, height=size),
        lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0, 2.0)] if lights is None else lights,
    )


def time_method(r: pk.Renderer, scene: pk.Scene, method, repeats: int = 5) -> dict:
    """Median, min and max time of `repeats` renders after a warm-up (pipeline creation and
    uploads happen in the warm-up)."""
    f = r.render(scene, method)
    ts: list[float] = []
    walls: list[float] = []
    calls: list[float] = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        f = r.render(scene, method)
        calls.append((time.perf_counter() - t0) * 1e3)
        ts.append(f.time_ms or 0.0)
        walls.append(f.wall_ms or 0.0)
    return dict(ms=float(np.median(ts)), ms_min=float(np.min(ts)), ms_max=float(np.max(ts)), timing=f.timing,
                call_ms=float(np.median(calls)), steps=float(f.steps[f.mask].mean()) if f.mask.any() else 0.0, frame=f)


def variants(cls, **grid) -> list:
    """Every combination of the given parameter lists: variants(pk.POM, max_steps=[8, 16])."""
    keys = list(grid)
    out: list[dict] = [{}]
    for k in keys:
        out = [dict(d, **{k: v}) for d in out for v in grid[k]]
    return [cls(**d) for d in out]


def _label(m) -> str:
    """The method with only the fields that differ from its defaults: POM(max_steps=16); a
    Custom method by its name and parameters."""
    from dataclasses import fields
    if isinstance(m, pk.Custom):
        return f"{m.name}({', '.join(f'{k}={v:g}' for k, v in m.params.items())})"
    try:
        default = type(m)()
    except Exception:
        return repr(m)
    diff = [f"{f.name}={getattr(m, f.name)!r}" for f in fields(m) if getattr(m, f.name) != getattr(default, f.name)]
    return f"{m.name}({', '.join(diff)})"


def _method_name(m) -> str:
    return getattr(m, "_preset", None) or (m.label if isinstance(m, pk.Custom) else m.name)


def _mitsuba_job(args):
    scene, spp = args
    from . import reference
    reference.render_mitsuba(scene, spp=spp)  # fills the on-disk cache
    return True


def _scene_for(name_or_height, angle, size, depth, tiling):
    if isinstance(name_or_height, str):
        if name_or_height.startswith("sine"):
            freq = float(name_or_height[4:] or 4)
            h = pk.textures.sine(256, freq)
        else:
            h = pk.textures.ALL[name_or_height](256)
        name = name_or_height
    else:
        name, h = name_or_height
    return name, plane_scene(h, angle, size, depth=depth, tiling=tiling)


def sweep(methods: Iterable, scenes: Iterable = ("bricks",), angles: Iterable[float] = (60.0,),
          settings: Optional[dict] = None, reference: str = "exact", repeats: int = 3,
          csv_path: Optional[str] = None, progress: bool = True, workers: int = 0):
    """Render, time and measure every (method, scene, angle).

    methods: Method instances (see `variants` and `pomkit.presets`); scenes: texture names from
    `pk.textures.ALL`, "sineF" for a sine of frequency F, or (name, height array) pairs;
    settings: size (256), depth (0.08), tiling (1.0), spp (64, Mitsuba);
    reference: "exact" (the CPU oracle; FLIP then against Tessellated(0.5) colour), "tessellated"
    or "mitsuba" (rendered first, through a process pool of `workers` processes when > 0, and
    cached on disk).
    Rows: method, params, scene, angle, gpu_ms (median) with min/max, ms_per_mpix, call_ms, mean
    steps, uv p50/p95/p99 (texels), mask IoU, FLIP. Returns a pandas DataFrame when pandas is
    installed, else a list of dicts; writes CSV to `csv_path` when given."""
    if reference not in ("exact", "tessellated", "mitsuba"):
        raise ValueError(f"reference: must be 'exact', 'tessellated' or 'mitsuba', got {reference!r}")
    cfg: dict = dict(size=256, depth=0.08, tiling=1.0, spp=64)
    cfg.update(settings or {})
    methods = list(methods)
    jobs = [(s, a) for s in scenes for a in angles]
    r = pk.Renderer()
    built = {(str(s if isinstance(s, str) else s[0]), a): _scene_for(s, a, cfg["size"], cfg["depth"], cfg["tiling"])
             for s, a in jobs}
    if reference == "mitsuba" and workers > 0:
        with ProcessPoolExecutor(workers) as ex:
            list(ex.map(_mitsuba_job, [(sc, cfg["spp"]) for _, sc in built.values()]))
    bar = None
    if progress:
        try:
            from tqdm.auto import tqdm
            bar = tqdm(total=len(built) * len(methods), desc="pomkit sweep", leave=False)
        except ImportError:
            bar = None
    rows = []
    for (sname, angle), (_, scene) in built.items():
        if reference == "exact":
            ref = pk.exact_uv(scene)
            cref = r.render(scene, pk.Tessellated(texels_per_vertex=0.5))
        elif reference == "tessellated":
            ref = cref = r.render(scene, pk.Tessellated(texels_per_vertex=0.5))
        else:
            from . import reference as R
            ref = cref = R.render_mitsuba(scene, spp=cfg["spp"])
        for m in methods:
            t = time_method(r, scene, m, repeats=repeats)
            f = t.pop("frame")
            e = metrics.uv_error(f, ref, scene)
            try:
                fl = metrics.flip(f, cref)
            except ImportError:
                fl = float("nan")
            mpix = scene.camera.width * scene.camera.height / 1e6
            rows.append(dict(method=_method_name(m), params=_label(m), scene=sname, angle=angle, size=cfg["size"],
                             gpu_ms=t["ms"], gpu_ms_min=t["ms_min"], gpu_ms_max=t["ms_max"], timing=t["timing"],
                             ms_per_mpix=t["ms"] / mpix, call_ms=t["call_ms"], mean_steps=t["steps"],
                             uv_p50=e["p50"], uv_p95=e["p95"], uv_p99=e["p99"], mask_iou=e["mask_iou"], flip=fl))
            if bar is not None:
                bar.update(1)
    if bar is not None:
        bar.close()
    if csv_path:
        Path(csv_path).parent.mkdir(parents=True, exist_ok=True)
        with open(csv_path, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    try:
        import pandas as pd
        return pd.DataFrame(rows)
    except ImportError:
        return rows


def swimming(method, scene_height, frames: int = 16, step_deg: float = 0.5, start_deg: float = 55.0, size: int = 128) -> float:
    """Temporal stability: over a camera path (`frames` views, `step_deg` apart), the mean over
    pixels of |frame-to-frame change of the hit uv - the change the exact oracle predicts|, in
    texels. 0 means the surface moves exactly as the true surface would."""
    r = pk.Renderer()
    prev = None
    acc = []
    for k in range(frames):
        sc = plane_scene(scene_height, start_deg + step_deg * k, size)
        f = r.render(sc, method)
        o = pk.exact_uv(sc)
        if prev is not None:
            pf, po = prev
            m = f.mask & o.mask & pf.mask & po.mask
            d = ((f.uv - pf.uv) - (o.uv - po.uv))[m] * np.array(sc.material.height.shape[::-1])
            acc.append(float(np.linalg.norm(d, axis=-1).mean()))
        prev = (f, o)
    return float(np.mean(acc))


def pareto_front(points):
    """Indices of the points not dominated in (time, error), both minimised."""
    idx = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in idx:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front
