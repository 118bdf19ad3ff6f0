"""The cost model's fitting (docs/cost.md): GPU ms of every method over the cost model's scenes
with each frame's counts (`cost_rows`), the non-negative weighted fits of `COST_MODELS`
(`fit_model`), their leave-one-method-out R² (`loo_r2`), the line of ms against fetches over a
sweep's rows (`fit_cost`) and horizon AO's share of the frame (`ao_cost`). Used by goals.py,
cost_model.py, cost_refit.py and scripts/gpu_check.py; it needs scipy (the `bench` extra)."""

from __future__ import annotations

import inspect
from typing import Iterable, Optional

import numpy as np

import pomkit as pk
from pomkit.bench import label, plane_scene, time_methods

if __package__:  # imported as tools.costfit
    from .quads import group_total, triangle_counts
else:  # a script of tools/ (its folder on sys.path)
    from quads import group_total, triangle_counts


def fit_cost(rows: list[dict], x: str = "fetches_mean", y: str = "gpu_ms") -> dict:
    """The least-squares line y = a + b * x over `rows` (e.g. a sweep's rows: ms against mean
    fetches per pixel) and how well it predicts: R² (1: the fetches explain every difference in
    time; 0: no better than the mean). Returns a, b, r2, n."""
    xs = np.array([float(r[x]) for r in rows])
    ys = np.array([float(r[y]) for r in rows])
    ok = np.isfinite(xs) & np.isfinite(ys)
    xs, ys = xs[ok], ys[ok]
    if len(xs) < 3 or np.ptp(xs) == 0:
        return dict(a=float("nan"), b=float("nan"), r2=float("nan"), n=int(len(xs)))
    b, a = np.polyfit(xs, ys, 1)
    res = ys - (a + b * xs)
    r2 = 1.0 - float(np.sum(res ** 2)) / float(np.sum((ys - ys.mean()) ** 2))
    return dict(a=float(a), b=float(b), r2=r2, n=int(len(xs)))


#: the per-frame counts the cost model fits GPU ms with (shaders/cost.wgsl; `quads`;
#: docs/cost.md). `primitives` and `rasterised` are counted beside them but are not terms: once
#: the quads a triangle touches are counted, the triangles themselves earned no cost of their own
#: (a non-negative coefficient of 0)
COST_TERMS = ("fetches", "bytes", "fragments", "quads")


def cost_rows(r: pk.Renderer, scenes: dict, methods: list, min_repeats: int = 3,
              max_repeats: int = 9, counter: Optional[pk.Renderer] = None) -> list[dict]:
    """Per scene and method: GPU ms (`time_methods`: warm-up, interleaved rounds, median) and
    the frame's totals of fetches, bytes, the chain of dependent fetches, fragments and steps (one
    render that counts them, not timed), the search's counts per SIMD group (`group_total`) and its
    primitives. `counter`:
    the renderer that counts (default `r`; the compute pipeline counts no fragments, so its rows
    take their counts from a raster renderer's)."""
    rows = []
    counter = counter or r
    for sname, sc in scenes.items():
        ts = time_methods(r, sc, methods, min_repeats=min_repeats, max_repeats=max_repeats)
        for m, t in zip(methods, ts):
            f = counter.render(sc, m, aovs=("mask", "fetches", "bytes", "chain", "fragments", "steps"))
            submitted, facing, nquads = triangle_counts(sc, m)
            rows.append(dict(chart="cost_model", scene=sname, method=m.name, label=label(m), gpu_ms=t["ms"],
                             gpu_ms_p25=t["ms_p25"], gpu_ms_p75=t["ms_p75"], march_ms=t["march_ms"], timing=t["timing"],
                             fetches=float(f.fetches.sum(dtype=np.float64)),
                             fragments=float(f.fragments.sum(dtype=np.float64)),
                             steps=float(f.steps.sum(dtype=np.float64)), primitives=float(submitted),
                             rasterised=float(facing), quads=nquads,
                             bytes=float(f.bytes.sum(dtype=np.float64)),
                             fetches_group=group_total(f.fetches), steps_group=group_total(f.steps),
                             bytes_group=group_total(f.bytes), chain=float(f.chain.sum(dtype=np.float64)),
                             chain_group=group_total(f.chain),
                             pixels=int(f.mask.size)))
    return rows


def fit_model(rows: list[dict], terms: Iterable[str] = COST_TERMS, y: str = "gpu_ms") -> dict:
    """`y = a + sum(c_t * t)` over `rows` (per-frame totals) with every coefficient and `a`
    non-negative (a count can only add time), each row weighted by 1 / sqrt(y): between least
    squares on the milliseconds, where the 100 ms mesh rows set every coefficient and gave a
    fetch a negative cost, and on relative error, where the 1 ms rows do. Returns a, the
    coefficients by term (ms per unit), r2 (of the milliseconds, unweighted), the median and
    worst relative error of a row (med_rel_err, max_rel_err), n."""
    from scipy.optimize import nnls
    terms = list(terms)
    rows = [x for x in rows if np.isfinite(x.get(y, np.nan)) and float(x[y]) > 0]
    X = np.array([[1.0] + [float(x[t]) for t in terms] for x in rows])
    Y = np.array([float(x[y]) for x in rows])
    if len(rows) <= len(terms) + 1:
        return dict(a=float("nan"), coef={t: float("nan") for t in terms}, r2=float("nan"), med_rel_err=float("nan"),
                    max_rel_err=float("nan"), n=len(rows))
    w = 1.0 / np.sqrt(Y)
    # scale the columns so that the solve is well conditioned, then undo it
    s = np.maximum(np.abs(X).max(0), 1e-30)
    c, _ = nnls((X / s) * w[:, None], Y * w)
    c = c / s
    pred = X @ c
    r2 = 1.0 - float(np.sum((Y - pred) ** 2)) / float(np.sum((Y - Y.mean()) ** 2))
    rel = np.abs(pred - Y) / Y
    return dict(a=float(c[0]), coef={t: float(v) for t, v in zip(terms, c[1:])}, r2=r2,
                med_rel_err=float(np.median(rel)), max_rel_err=float(np.max(rel)), n=len(rows))


def shadows_off(cls, **kw):
    """`cls(**kw)` with shadows="none" where the method casts shadows and `kw` does not say."""
    if "shadows" in inspect.signature(cls).parameters:
        kw.setdefault("shadows", "none")
    return cls(**kw)


def cost_model_suite(size: int = 256, quick: bool = False) -> tuple[dict, list]:
    """The cost model's scenes and methods: planar maps at 45-70° (bricks, the gravel
    photograph tiled twice, the terrain DEM) and a torus and a sphere with two tiles of
    cobblestones; every built-in method with shadows off, Tessellated at three lattices (and the grid at one), Prism
    both ways, POM at two step budgets."""
    def plane(h, theta, tiling=1.0):
        return plane_scene(h, theta, size, depth=0.08, tiling=tiling)

    def curved(mesh):
        m = pk.Mesh.torus(segments=48, tube_segments=24) if mesh == "torus" else pk.Mesh.sphere(segments=48, rings=24)
        return pk.Scene(mesh=m, material=pk.Material(pk.textures.cobblestones(256, cells=8), depth=0.06, tiling=2.0),
                        camera=pk.Camera.look_at((0.4, 1.6, 2.8), fov_y=40, width=size, height=size))

    T = pk.textures
    scenes = {"bricks 45°": plane(T.bricks(256), 45.0), "gravel 70°": plane(T.real("gravel", 256), 70.0, 2.0),
              "terrain 60°": plane(T.real("terrain", 256), 60.0), "torus": curved("torus"), "sphere": curved("sphere")}
    if quick:
        scenes = {k: scenes[k] for k in ("bricks 45°", "torus")}
    off = shadows_off
    methods = [off(pk.Flat), off(pk.Bump), off(pk.Parallax), off(pk.SteepParallax, steps=16), off(pk.POM),
               off(pk.POM, min_steps=16, max_steps=64), off(pk.Relief), off(pk.ConeStep), off(pk.Exact), off(pk.DistanceMapping),
               off(pk.NCS), off(pk.CurvedRelief), off(pk.Prism), off(pk.Prism, exact=True),
               off(pk.Tessellated, texels_per_vertex=1.0), off(pk.Tessellated, texels_per_vertex=0.5),
               off(pk.Tessellated, texels_per_vertex=2.0), off(pk.Tessellated, texels_per_vertex=1.0, pattern="grid")]
    return scenes, methods


#: the model's two forms: the counts themselves, and with the search's counts taken per SIMD
#: group (a group waits for its longest lane)
COST_MODELS = {"per pixel": COST_TERMS,
               "per SIMD group": ("fetches_group", "bytes_group", "fragments", "quads"),
               # latency: a SIMD group waits a fetch's latency once a round of its longest chain
               "latency": ("fetches_group", "chain_group", "fragments", "quads")}


def loo_r2(rows: list[dict], terms: Iterable[str], y: str = "gpu_ms", key: str = "method") -> float:
    """Leave-one-method-out R²: each method's rows predicted by the model fitted on every other
    method's (`fit_model`), R² of those predictions. A model that only memorises the methods it
    was fitted on scores low; one whose terms explain time carries over to a method it has not
    seen."""
    terms = list(terms)
    rows = [x for x in rows if np.isfinite(x.get(y, np.nan)) and float(x[y]) > 0]
    pred, obs = [], []
    for m in sorted({x[key] for x in rows}):
        fit = fit_model([x for x in rows if x[key] != m], terms, y)
        if not np.isfinite(fit["a"]):
            continue
        for x in rows:
            if x[key] == m:
                pred.append(fit["a"] + sum(fit["coef"][t] * float(x[t]) for t in terms))
                obs.append(float(x[y]))
    if len(obs) < 3:
        return float("nan")
    p, o = np.array(pred), np.array(obs)
    return 1.0 - float(np.sum((o - p) ** 2)) / float(np.sum((o - o.mean()) ** 2))


def cost_model(r: pk.Renderer, size: int = 256, quick: bool = False) -> dict:
    """GPU ms of every method over `cost_model_suite`, and the least-squares fits of
    `COST_MODELS` (docs/cost.md): rows and fits by name."""
    scenes, methods = cost_model_suite(size, quick)
    rows = cost_rows(r, scenes, methods, min_repeats=2 if quick else 3, max_repeats=4 if quick else 9)
    return dict(rows=rows, fits={k: fit_model(rows, t) for k, t in COST_MODELS.items()})


def ao_cost(r: pk.Renderer, size: int = 256, quick: bool = False) -> list[dict]:
    """Dachsbacher & Tatarchuk 2007's one figure, reproduced: the cost of horizon AO with 4 and 8
    directions over the same frame without it. Prism and POM with horizon shadows (DT07's set-up:
    a directional light and ambient), on planar scenes and the torus, GPU ms of interleaved rounds.
    Per scene and method: the frame's ms at 0, 4 and 8 directions and the AO's share of the frame
    with it, (ms_k - ms_0) / ms_k (the paper: about 35 % of the frame rate)."""
    light = [pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)]

    def plane(h, theta):
        return plane_scene(h, theta, size, depth=0.08).replace(lights=light, ambient=0.2)

    torus = pk.Scene(mesh=pk.Mesh.torus(segments=48, tube_segments=24),
                     material=pk.Material(pk.textures.cobblestones(256, cells=8), depth=0.06, tiling=2.0),
                     camera=pk.Camera.look_at((0.4, 1.6, 2.8), fov_y=40, width=size, height=size), lights=light, ambient=0.2)
    scenes = {"bricks 45°": plane(pk.textures.bricks(256), 45.0), "terrain 60°": plane(pk.textures.real("terrain", 256), 60.0),
              "torus": torus}
    if quick:
        scenes = {"bricks 45°": scenes["bricks 45°"]}
    rows = []
    for name, sc in scenes.items():
        for cls in (pk.Prism, pk.POM):
            ms = [cls(shadows="horizon", ao_directions=k) for k in (0, 4, 8)]
            t = time_methods(r, sc, ms, min_repeats=3 if quick else 5, max_repeats=5 if quick else 15, baseline=False)
            base = np.array(t[0]["times"])
            row = dict(chart="ao_cost", scene=name, method=cls.__name__, ms_0=t[0]["ms"], ms_4=t[1]["ms"], ms_8=t[2]["ms"],
                       timing=t[0]["timing"])
            for k, tk in ((4, t[1]), (8, t[2])):
                # the share per round (the same round's frames), then the median: steadier than
                # a ratio of medians on a noisy machine
                tt = np.array(tk["times"])
                row[f"ao_share_{k}"] = float(np.median((tt - base) / np.maximum(tt, 1e-9)))
            rows.append(row)
    return rows
