"""Speed against accuracy.

`sweep(...)` renders methods x scenes x angles, times them (GPU timestamps where the adapter has
them, else wall time) and measures them against a reference; `python -m pomkit bench [--quick]`
(pomkit/apps/pareto.py) runs the standard sweep and writes the table (CSV) and the charts into
./pomkit-out/bench/.
"""

from __future__ import annotations

from ._errors import ArgumentError, ArgumentTypeError
import csv
import math
import time
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Optional, Union

import numpy as np

from . import _frame, _methods, _render, _scene, textures
from . import _validate as _v
from . import metrics, oracle
from ._motion import PATHS, camera_path, motion  # noqa: F401 (pk.bench's API)
from ._methods import label  # noqa: F401 (pk.bench's API)

__all__ = ["sweep", "SweepSettings", "variants", "plane_scene", "time_methods", "swimming", "pareto_front", "label",
           "method_name", "write_csv", "TIMING_COLUMNS"]


def plane_scene(height, theta_deg: float, size: int, depth: float = 0.08, tiling: float = 1.0,
                lights=None) -> _scene.Scene:
    """The bench scene: `pk.scenes.tilted_plane` with a 2° light from the side by default."""
    from .scenes import tilted_plane
    return tilted_plane(height, theta_deg, size, depth=depth, tiling=tiling,
                        lights=[_scene.DirectionalLight((-0.4, -1.0, -0.3), 3.0, 2.0)] if lights is None else lights)


def _stats(xs: list[float]) -> dict:
    q25, q50, q75 = np.percentile(xs, [25, 50, 75])
    return dict(median=float(q50), p25=float(q25), p75=float(q75))


def time_methods(r: _render.Renderer, scene: _scene.Scene, methods: list, aovs: tuple[_frame.AovName, ...] = ("color",), min_repeats: int = 5,
                 max_repeats: int = 25, rel_tol: float = 0.02, baseline: bool = True,
                 method_aovs: Optional[list] = None) -> list[dict]:
    """Time `methods` on one scene: one warm-up render each (pipelines, uploads), then rounds in
    which every method renders once, in an order rotated each round (interleaved, so that the
    machine's drift falls on all of them alike). After `min_repeats` rounds, rounds continue
    until no method's median moves by more than `rel_tol` between rounds, or `max_repeats`.

    Returns per method: `ms` (the median), `ms_p25`, `ms_p75` (GPU timestamps where the adapter
    has them, else wall time), `call_ms` (median wall time of the Python call), `march_ms` (median cost above
    Flat timed in the same rounds; `baseline=False` skips Flat), `over_first` (the median of
    per-round ratios to the first method: steadier than a ratio of medians on a noisy machine),
    `repeats`, `timing` and `times` (the ms of each round, for ratios of one's own).
    `method_aovs`: the AOVs of each method, when they differ (e.g. one method with colour alone
    and with every AOV); else `aovs` for all."""
    ms = list(methods) + ([_methods.Flat()] if baseline else [])
    per = list(method_aovs) if method_aovs is not None else [aovs] * len(methods)
    if len(per) != len(methods):
        raise ArgumentError("method_aovs: one entry per method")
    per += [aovs] * (len(ms) - len(per))
    for m, a in zip(ms, per):
        r.render(scene, m, aovs=a)
    times: list[list[float]] = [[] for _ in ms]
    calls: list[list[float]] = [[] for _ in ms]
    timing = "gpu"
    prev = None
    for k in range(max_repeats):
        n = len(ms)
        for j in range(n):
            i = (j + k) % n
            t0 = time.perf_counter()
            f = r.render(scene, ms[i], aovs=per[i])
            calls[i].append((time.perf_counter() - t0) * 1e3)
            times[i].append(f.time_ms or 0.0)
            timing = f.timing
        med = [float(np.median(t)) for t in times]
        if k + 1 >= min_repeats and prev is not None and all(
                abs(a - b) <= rel_tol * max(b, 1e-9) for a, b in zip(med, prev)):
            break
        prev = med
    flat = float(np.median(times[-1])) if baseline else float("nan")
    first = np.array(times[0])
    out = []
    for i in range(len(methods)):
        st = _stats(times[i])
        out.append(dict(ms=st["median"], ms_p25=st["p25"], ms_p75=st["p75"], march_ms=st["median"] - flat,
                        over_first=float(np.median(np.array(times[i]) / np.maximum(first, 1e-9))),
                        call_ms=float(np.median(calls[i])), repeats=len(times[i]), timing=timing,
                        times=list(times[i])))
    return out


def variants(cls, **grid) -> list:
    """Every combination of the given parameter lists: variants(_methods.POM, max_steps=[8, 16])."""
    keys = list(grid)
    out: list[dict] = [{}]
    for k in keys:
        out = [dict(d, **{k: v}) for d in out for v in grid[k]]
    return [cls(**d) for d in out]


def method_name(m) -> str:
    """The family a method belongs to in tables and charts: its class's name, a Custom method's
    name."""
    return m.label if isinstance(m, _methods.Custom) else m.name


def _square_spp(name: str, v) -> int:
    n = _v.integer(name, v, 1, 256, strict=True)
    if math.isqrt(n) ** 2 != n:
        raise ArgumentError(f"{name}: must be a square number of samples per pixel (1, 4, 9, 16, ...), got {n}")
    return n


@dataclass(frozen=True)
class SweepSettings:
    """What every (scene, angle) of a `sweep` is rendered and measured at. Fields are checked at
    construction; a bad one raises `pk.ArgumentError` (or `pk.ArgumentTypeError`) naming it."""

    size: int = 256
    """The frames' width and height in pixels (the tilted plane's camera; a (name, Scene) pair
    keeps its own camera)."""
    depth: float = 0.08
    """The plane's displacement depth (`Material.depth`), in object units."""
    tiling: float = 1.0
    """Repetitions of the map over the plane (`Material.tiling`)."""
    spp: int = 64
    """Mitsuba's samples per pixel for reference="mitsuba" (a square, 1 to 256)."""
    frame_spp: int = 1
    """The frames' samples per pixel (`Renderer.render(spp=)`, a square, 1 to 256); the colour
    reference of "oracle" and "tessellated" takes the same."""
    flip: bool = True
    """Score the frames' colour with FLIP against the colour reference (the flip columns; False
    leaves them NaN and renders no colour reference)."""

    def __post_init__(self) -> None:
        checked = dict(size=_v.integer("size", self.size, 1, 1 << 30),
                       depth=_v.number("depth", self.depth, 0.0, 1e30),
                       tiling=_v.number("tiling", self.tiling, 0.0, 1e6, lo_open=True),
                       spp=_square_spp("spp", self.spp),
                       frame_spp=_square_spp("frame_spp", self.frame_spp),
                       flip=_v.boolean("flip", self.flip))
        for k, v in checked.items():
            object.__setattr__(self, k, v)


def _settings(settings) -> SweepSettings:
    """`sweep`'s settings as a SweepSettings."""
    if settings is None:
        return SweepSettings()
    if isinstance(settings, SweepSettings):
        return settings
    if isinstance(settings, dict):
        raise ArgumentTypeError(f"settings: expected a pomkit.bench.SweepSettings; write pk.bench.SweepSettings(**{settings!r})")
    raise ArgumentTypeError(f"settings: expected a pomkit.bench.SweepSettings, got {type(settings).__name__}")


def _named(methods: Iterable) -> list[tuple[Optional[str], _methods.Method]]:
    """`sweep`'s methods as (name or None, method) pairs."""
    out: list[tuple[Optional[str], _methods.Method]] = []
    for m in methods:
        if isinstance(m, _methods.Method):
            out.append((None, m))
        elif isinstance(m, tuple) and len(m) == 2 and isinstance(m[1], _methods.Method):
            if not isinstance(m[0], str) or not m[0]:
                raise ArgumentError(f"methods: a (name, method) pair's name must be a non-empty string, got {m[0]!r}")
            out.append((m[0], m[1]))
        else:
            raise ArgumentTypeError("methods: expected pomkit methods such as pomkit.POM() or (name, method) pairs, "
                                    f"got {type(m).__name__}")
    return out


def _scene_for(name_or_height, angle, size, depth, tiling):
    if isinstance(name_or_height, tuple) and isinstance(name_or_height[1], _scene.Scene):
        return name_or_height  # (name, a scene of one's own, e.g. several objects): used as given
    if isinstance(name_or_height, str):
        if name_or_height.startswith("sine"):
            freq = float(name_or_height[4:] or 4)
            h = textures.sine(256, freq)
        else:
            h = textures.ALL[name_or_height](256)
        name = name_or_height
    else:
        name, h = name_or_height
    return name, plane_scene(h, angle, size, depth=depth, tiling=tiling)


def _sweep_scene(job: tuple) -> list[dict]:
    """The rows of one (scene, angle): runs where it is sent (an executor's worker opens its own
    device on its first render)."""
    scene_spec, angle, named, cfg, reference, repeats = job
    methods = [m for _, m in named]
    sname, scene = _scene_for(scene_spec, angle, cfg.size, cfg.depth, cfg.tiling)
    r = _render.Renderer()
    flip = cfg.flip
    fspp = cfg.frame_spp
    floor: dict = {}
    if reference == "oracle":
        ref = oracle.hits(scene)
        cref = None
        if flip:
            # the noise-free colour reference at the frames' spp (its floor is 0: a score is the
            # method's error), shadowed for the methods that cast shadows, else not
            from . import reference as R
            crefs = {sh: oracle.image(scene, spp=fspp, shadows=sh) for sh in (False, True)}
            cref = crefs[False]
            floor = dict(flip_floor=0.0)
    elif reference == "tessellated":
        ref = cref = r.render(scene, _methods.Tessellated(texels_per_vertex=0.5), spp=fspp)
    else:
        from . import reference as R
        ref = cref = R.render_mitsuba(scene, spp=cfg.spp)
        if flip:
            # the floor: the exact geometry (the mesh) against Mitsuba at the frames' spp
            try:
                fc = metrics.compare(r.render(scene, _methods.Tessellated(texels_per_vertex=0.5), spp=fspp), ref, scene)
                floor = dict(flip_floor=fc["flip"], flip_floor_interior=fc["flip_interior"],
                             flip_floor_silhouette=fc["flip_silhouette"])
            except ImportError:
                pass
    aovs: tuple[_frame.AovName, ...] = ("color", "uv", "mask", "steps", "fetches", "bytes") if flip else \
        ("uv", "mask", "steps", "fetches", "bytes")
    if len(scene.objects) > 1:
        aovs += ("object",)  # uv error is measured per object
    times = time_methods(r, scene, methods, aovs=("color",), min_repeats=repeats)
    mpix = scene.camera.width * scene.camera.height / 1e6
    rows = []
    for (name, m), t in zip(named, times):
        f = r.render(scene, m, aovs=aovs, spp=fspp)
        e = metrics.uv_error(f, ref, scene)
        fl = fl_in = fl_sil = float("nan")
        if flip and cref is not None:
            try:
                cr = crefs[getattr(m, "shadows", "none") != "none"] if reference == "oracle" else cref
                c = metrics.compare(f, cr, scene)
                fl, fl_in, fl_sil = c["flip"], c["flip_interior"], c["flip_silhouette"]
            except ImportError:
                pass
        steps = float(f.steps[f.mask].mean()) if f.mask.any() else 0.0
        fetches = f.fetches[f.mask] if f.mask.any() else np.zeros(1)
        nbytes = f.bytes[f.mask] if f.mask.any() else np.zeros(1)
        shadow = _shadow_columns(r, scene, m, ref if reference == "oracle" else None)
        rows.append(dict(method=name or method_name(m), label=name or label(m), safety=m.safety, scene=sname,
                         angle=angle, size=cfg.size, gpu_ms=t["ms"], gpu_ms_p25=t["ms_p25"], gpu_ms_p75=t["ms_p75"],
                         march_ms=t["march_ms"], call_ms=t["call_ms"], repeats=t["repeats"], timing=t["timing"],
                         ms_per_mpix=t["ms"] / mpix, mean_steps=steps, fetches_mean=float(fetches.mean()),
                         fetches_p99=float(np.percentile(fetches, 99)), bytes_mean=float(nbytes.mean()), uv_p50=e["p50"], uv_p95=e["p95"],
                         uv_p99=e["p99"], mask_iou=e["mask_iou"], flip=fl, flip_interior=fl_in,
                         flip_silhouette=fl_sil, frame_spp=fspp, **floor, **shadow))
    return rows


def _shadow_columns(r: _render.Renderer, scene: _scene.Scene, method, oracle) -> dict:
    """shadow_iou and shadow_vis_error of the method's self-shadowing against the exact oracle's
    visibility (metrics.shadow_error); NaN where the reference is not the oracle, the method
    casts no shadows or the scene has no directional light."""
    nan = dict(shadow_iou=float("nan"), shadow_vis_error=float("nan"))
    if oracle is None or getattr(method, "shadows", "none") == "none" or not oracle.has("visibility") \
            or not np.isfinite(oracle.visibility).any():
        return nan
    e = metrics.shadow_error(r.render_visibility(scene, method), oracle, scene)
    return dict(shadow_iou=e["iou"], shadow_vis_error=e["vis_error"])


#: the columns that hold timings (they differ between runs; the rest is deterministic)
TIMING_COLUMNS = ("gpu_ms", "gpu_ms_p25", "gpu_ms_p75", "march_ms", "call_ms", "repeats", "ms_per_mpix", "timing")


def sweep(methods: Iterable[Union[_methods.Method, tuple[str, _methods.Method]]], maps: Iterable = ("bricks",),
          angles: Iterable[float] = (60.0,), settings: Optional[SweepSettings] = None, reference: str = "oracle",
          repeats: int = 5, csv_path: Optional[str] = None, progress: bool = True, executor: Optional[Executor] = None) -> list[dict]:
    """Render, time and measure every (method, map, angle) on the tilted plane.

    methods: Method instances (see `variants`), or (name, method) pairs, whose name stands in
    the rows' method and label columns (the presets by their names: `[(name, fn()) for name,
    fn in pk.presets.ALL_PRESETS.items()]`); maps: texture names from `pk.textures.ALL`,
    "sineF" for a sine of frequency F, or (name, height array) pairs, each on a plane (a (name,
    Scene) pair is taken as it is);
    settings: a `SweepSettings` (frame size, depth, tiling, Mitsuba's spp, the frames' spp,
    FLIP; None: its defaults);
    reference: "oracle" (`pk.oracle.hits` for the geometry, FLIP against `pk.oracle.image`,
    noise-free, unshadowed for the methods without shadows),
    "tessellated" or "mitsuba" (cached on disk);
    repeats: the least number of interleaved timing rounds (see `time_methods`);
    executor: any `concurrent.futures.Executor` (a process pool, Dask's `client.get_executor()`,
    Ray's): each (scene, angle) is one task, rendered, timed and measured where it is sent; each
    worker opens its own device. Timings from workers that share a machine's cores compete.

    Rows: method, label, safety ("safe": never misses a feature of the bilinear field;
    "approximate"), scene, angle, size, gpu_ms (median) with its p25/p75, march_ms (cost above
    Flat), call_ms, repeats, timing, ms_per_mpix, mean_steps, fetches_mean and fetches_p99 (texel
    fetches per pixel of the search: the AOV `fetches`), bytes_mean, uv p50/p95/p99 (texels),
    mask IoU, FLIP over the frame, its interior and its silhouette band (`metrics.compare`),
    frame_spp, and with reference="mitsuba" the aliasing floor beside them: flip_floor,
    flip_floor_interior, flip_floor_silhouette (Tessellated(0.5), the exact geometry, against
    Mitsuba at the same frame_spp). Returns the rows, a list of dicts (`pandas.DataFrame(rows)`
    makes a table of them); writes CSV to `csv_path` when given."""
    if reference not in ("oracle", "tessellated", "mitsuba"):
        raise ArgumentError(f"reference: must be 'oracle', 'tessellated' or 'mitsuba', got {reference!r}")
    cfg = _settings(settings)
    named = _named(methods)
    jobs = [(s, a, named, cfg, reference, repeats) for s in maps for a in angles]
    bar = None
    if progress:
        try:
            from tqdm.auto import tqdm
            bar = tqdm(total=len(jobs), desc="pomkit sweep", leave=False)
        except ImportError:
            bar = None
    rows: list[dict] = []
    if executor is None:
        results: Iterable[list[dict]] = map(_sweep_scene, jobs)
    else:
        results = (f.result() for f in [executor.submit(_sweep_scene, j) for j in jobs])
    for rs in results:
        rows += rs
        if bar is not None:
            bar.update(1)
    if bar is not None:
        bar.close()
    if csv_path:
        write_csv(rows, csv_path)
    return rows


def write_csv(rows: list[dict], path) -> None:
    """Rows with possibly different keys, as one CSV (missing cells empty). Every row also
    records the machine (adapter, backend, driver, pomkit and wgpu versions, OS: `pk.info`), so
    that CSVs from different machines can be pooled."""
    from ._info import machine
    m = machine()
    rows = [{**row, **{k: v for k, v in m.items() if k not in row}} for row in rows]
    keys: list[str] = []
    for row in rows:
        keys += [k for k in row if k not in keys]
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)


def swimming(method, scene_height, frames: int = 16, step_deg: float = 0.5, start_deg: float = 55.0, size: int = 128) -> float:
    """Temporal stability: over a camera path (`frames` views, `step_deg` apart), the mean over
    pixels of |frame-to-frame change of the hit uv - the change the exact oracle predicts|, in
    texels. 0 means the surface moves exactly as the true surface would."""
    r = _render.Renderer()
    prev = None
    acc = []
    for k in range(frames):
        sc = plane_scene(scene_height, start_deg + step_deg * k, size)
        f = r.render(sc, method, aovs=("uv", "mask"))
        o = oracle.hits(sc)
        if prev is not None:
            pf, po = prev
            m = f.mask & o.mask & pf.mask & po.mask
            d = ((f.uv - pf.uv) - (o.uv - po.uv))[m] * np.array(sc.single.material.height.shape[::-1])
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

