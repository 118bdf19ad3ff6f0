"""`pk.choose`: the cheapest method and settings that meet an error bound in the worst case over
the content and angles a user gives, on this adapter.

For each family of methods with a quality knob (a step count), the error is monotone in the knob
(more layers, more steps: never a worse worst case, up to the noise of a few texels that the
bound absorbs), so the smallest step count that meets the bound is found by bisection over
[lo, hi], not by a grid. Families without a knob (Parallax, Exact) are measured once. Every
measurement (a setting on one case: worst uv p95 against the float64 oracle, FLIP against the
noise-free exact image, unshadowed, or the tessellated mesh on a curved scene, mean texel
fetches, GPU ms) is cached on disk, keyed by the scene's hash and
the method, so a second call with a looser bound re-measures nothing. Each case is one task of
an executor when one is given (a Dask `client.get_executor()`, a process pool): the sweep's
machinery.
"""

from __future__ import annotations

from ._errors import ArgumentError, ArgumentTypeError
import json
import math
import time
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Optional, Sequence

import numpy as np

from . import _files, _frame, _methods, _render, _scene, oracle

__all__ = ["choose", "Choice", "FAMILIES", "report"]


@dataclass(frozen=True)
class Family:
    """A method family: `make(n)` is the setting at knob n (None: no knob), bisected in [lo, hi]."""
    name: str
    make: Callable[[Optional[int]], _methods.Method]
    lo: Optional[int] = None
    hi: Optional[int] = None


FAMILIES: dict[str, Family] = {f.name: f for f in [
    Family("Parallax", lambda n: _methods.Parallax()),
    Family("SteepParallax", lambda n: _methods.SteepParallax().with_steps(n or 16), 2, 256),
    Family("POM", lambda n: _methods.POM(shadows="none", lod_threshold=1000.0).with_steps(n or 32), 2, 256),
    Family("Relief", lambda n: _methods.Relief().with_steps(n or 16), 2, 256),
    Family("ConeStep", lambda n: _methods.ConeStep().with_steps(n or 32), 2, 256),
    Family("Exact", lambda n: _methods.Exact()),
    # the coarse lattice's density as the knob: 64 / n texels a vertex, Exact marching the rest
    Family("Hybrid", lambda n: _methods.Hybrid(coarse=_methods.Tessellated(texels_per_vertex=64.0 / (n or 8)),
                                               fine=_methods.Exact()), 1, 64),
]}


@dataclass
class Choice:
    """What `choose` found. `method` and `settings` are the cheapest that meet the bound
    (None when nothing does: then `closest` is the setting with the smallest worst-case error);
    `runner_up` the next family's cheapest; `table` every setting measured (one row per setting:
    family, label, worst uv p95, worst FLIP, mean fetches, mean GPU ms, whether it meets)."""
    method: Optional[_methods.Method]
    met: bool
    bound: dict
    cost: str
    runner_up: Optional[_methods.Method] = None
    closest: Optional[_methods.Method] = None
    table: list[dict] = field(default_factory=list)
    seconds: float = 0.0

    def __str__(self) -> str:
        from .bench import label

        def flip(r: dict, fmt: str) -> str:  # FLIP only where it was measured (a max_flip bound)
            return "" if math.isnan(r["flip"]) else f", {'worst ' if fmt == '.4f' else ''}FLIP {r['flip']:{fmt}}"

        b = ", ".join(f"{k} <= {v:g}" for k, v in self.bound.items())
        if not self.met:
            row = next((r for r in self.table if r["method"] is self.closest), None)
            worst = f" (worst uv p95 {row['uv_p95']:.3g}{flip(row, '.3g')})" if row else ""
            return f"no method meets {b}; the closest: {label(self.closest)}{worst}"
        row = next(r for r in self.table if r["method"] is self.method)
        s = (f"{label(self.method)}: {row['gpu_ms']:.2f} GPU ms, {row['fetches']:.1f} fetches/px, worst uv p95 "
             f"{row['uv_p95']:.3f}{flip(row, '.4f')} (bound {b}; cheapest by {self.cost})")
        if self.runner_up is not None:
            r2 = next(r for r in self.table if r["method"] is self.runner_up)
            s += f"\nrunner-up: {label(self.runner_up)}: {r2['gpu_ms']:.2f} ms, {r2['fetches']:.1f} fetches/px"
        return s

    def markdown(self) -> str:
        lines = ["| family | setting | worst uv p95 (texels) | worst FLIP | fetches/px | GPU ms | meets |",
                 "|---|---|---|---|---|---|---|"]
        for r in sorted(self.table, key=lambda r: (r["family"], r["gpu_ms"])):
            fl = "not measured" if math.isnan(r["flip"]) else f"{r['flip']:.4f}"
            lines.append(f"| {r['family']} | {r['label']} | {r['uv_p95']:.3f} | {fl} | {r['fetches']:.1f} | "
                         f"{r['gpu_ms']:.2f} | {'yes' if r['meets'] else 'no'} |")
        return "\n".join(lines)


_RENDERER: list[_render.Renderer] = []
_REFS: dict[tuple[str, bool], tuple[_frame.Frame, _frame.Frame | None]] = {}


def _renderer() -> _render.Renderer:
    """One renderer per process (its pipelines and resident maps are reused by every
    measurement; an executor's worker makes its own)."""
    if not _RENDERER:
        _RENDERER.append(_render.Renderer())
    return _RENDERER[0]


def _refs(scene: _scene.Scene, want_flip: bool) -> tuple[_frame.Frame, _frame.Frame | None]:
    """A case's references, made once whatever the settings measured on it: the oracle, and
    the noise-free exact image (unshadowed) when FLIP is bounded."""
    from ._cache import scene_hash
    key = (scene_hash(scene, kind="refs"), want_flip)
    if key not in _REFS:
        if len(_REFS) > 64:
            _REFS.clear()
        cref = None
        if want_flip:
            # the noise-free colour reference, unshadowed as the settings measured are
            cref = oracle.image(scene, spp=1, shadows=False)
        _REFS[key] = (oracle.hits(scene), cref)
    return _REFS[key]


def _measure_case(job: tuple) -> dict:
    """One setting on one case (cached on disk): uv p95 against the oracle, FLIP against the
    mesh, mean fetches, GPU ms (median of interleaved rounds with Flat)."""
    scene, method, want_flip, rounds = job
    from ._cache import cached, scene_hash
    from . import metrics
    from .bench import time_methods
    r = _renderer()
    key = scene_hash(scene, kind="choose", method=repr(method), flip=want_flip, colour_ref="oracle_image", rounds=rounds, adapter=f"{r.info['name']} {r.info['backend']} {r.info['driver']}")

    def compute() -> dict:
        ref, cref = _refs(scene, want_flip)
        f = r.render(scene, method, aovs=("color", "uv", "mask", "fetches"))
        uv = metrics.uv_error(f, ref, scene)["p95"]
        fl = metrics.flip(f, cref) if cref is not None else float("nan")
        fetches = float(f.fetches[f.mask].mean()) if f.mask.any() else 0.0
        t = time_methods(r, scene, [method], min_repeats=rounds, max_repeats=rounds)[0]
        return dict(v=np.array([uv, fl, fetches, t["ms"]], np.float64))

    v = cached("choose", key, compute)["v"]
    return dict(uv_p95=float(v[0]), flip=float(v[1]), fetches=float(v[2]), gpu_ms=float(v[3]))


def _cases(heights, scenes, angles, resolution) -> list[_scene.Scene]:
    from .bench import plane_scene
    if scenes is not None:
        out = list(scenes)
        if not out or not all(isinstance(s, _scene.Scene) for s in out):
            raise ArgumentTypeError("scenes: expected a non-empty list of pomkit.Scene")
        return out
    if heights is None:
        raise ArgumentError("heights or scenes: give the height maps (arrays or files) or the scenes to choose for")
    hs = []
    for h in (heights if isinstance(heights, (list, tuple)) else [heights]):
        hs.append(_files.load_height(h) if isinstance(h, str) else np.asarray(h, np.float32))
    angles = list(angles)
    if not angles:
        raise ArgumentError("angles: give at least one view angle in degrees, e.g. (30, 60, 80)")
    return [plane_scene(h, float(a), int(resolution)) for h in hs for a in angles]


def choose(heights: Any = None, scenes: Optional[Sequence[_scene.Scene]] = None,
           angles: Iterable[float] = (30.0, 60.0, 80.0), resolution: int = 256, *,
           max_uv_error: Optional[float] = None, max_flip: Optional[float] = None,
           methods: Optional[Sequence[str]] = None, cost: str = "gpu_ms", budget_s: Optional[float] = None,
           rounds: int = 5, executor: Optional[Executor] = None) -> Choice:
    """The cheapest method and settings whose worst case over the given content and angles meets
    the bound.

    heights: a height map (array or file path) or a list of them, seen on a plane at each of
    `angles` (degrees from the normal) at `resolution`²; or scenes: the scenes themselves.
    max_uv_error: the bound on each case's uv p95 (texels, against the float64 oracle);
    max_flip: the bound on each case's FLIP (against `pk.oracle.image(scene, shadows=False)`, noise-free); at least one.
    methods: family names from `FAMILIES` (default: all). cost: "gpu_ms" (this adapter) or
    "fetches" (texel fetches per pixel: a cost that carries over to a GPU).
    budget_s: stop searching after this many seconds (the answer is then the best found).
    executor: any concurrent.futures.Executor: each case of a setting is one task.
    """
    if max_uv_error is None and max_flip is None:
        raise ArgumentError("max_uv_error or max_flip: give at least one bound, e.g. max_uv_error=0.5 (texels)")
    if cost not in ("gpu_ms", "fetches"):
        raise ArgumentError(f"cost: 'gpu_ms' or 'fetches', got {cost!r}")
    names = list(methods) if methods is not None else list(FAMILIES)
    for n in names:
        if n not in FAMILIES:
            raise ArgumentError(f"methods: unknown family {n!r}; one of {', '.join(FAMILIES)}")
    cases = _cases(heights, scenes, angles, resolution)
    want_flip = max_flip is not None
    t0 = time.perf_counter()
    measured: dict[str, dict] = {}
    table: list[dict] = []

    from .bench import label

    def evaluate(fam: Family, n: Optional[int]) -> dict:
        m = fam.make(n)
        key = repr(m)
        if key in measured:
            return measured[key]
        jobs = [(sc, m, want_flip, rounds) for sc in cases]
        rs = list(executor.map(_measure_case, jobs)) if executor is not None else [_measure_case(j) for j in jobs]
        row = dict(family=fam.name, label=label(m), method=m, knob=n,
                   uv_p95=max(r["uv_p95"] for r in rs), flip=max(r["flip"] for r in rs),
                   fetches=float(np.mean([r["fetches"] for r in rs])), gpu_ms=float(np.mean([r["gpu_ms"] for r in rs])))
        row["meets"] = bool((max_uv_error is None or row["uv_p95"] <= max_uv_error) and
                            (max_flip is None or row["flip"] <= max_flip))
        measured[key] = row
        table.append(row)
        return row

    def out_of_time() -> bool:
        return budget_s is not None and time.perf_counter() - t0 > budget_s

    for name in names:
        fam = FAMILIES[name]
        if fam.lo is None or fam.hi is None:
            evaluate(fam, None)
            continue
        lo, hi = fam.lo, fam.hi
        if not evaluate(fam, hi)["meets"]:
            continue  # the most steps tried do not meet it: no setting of this family does
        if evaluate(fam, lo)["meets"]:
            continue
        # invariant: lo fails, hi meets; bisect in log space (the error falls roughly as 1/n)
        while hi - lo > max(1, lo // 8) and not out_of_time():
            mid = int(round(np.sqrt(lo * hi)))
            mid = min(max(mid, lo + 1), hi - 1)
            if evaluate(fam, mid)["meets"]:
                hi = mid
            else:
                lo = mid
        if out_of_time():
            break

    ok = sorted((r for r in table if r["meets"]), key=lambda r: r[cost])
    best = ok[0] if ok else None
    runner = next((r for r in ok if best is not None and r["family"] != best["family"]), None)
    bound = {k: v for k, v in (("max_uv_error", max_uv_error), ("max_flip", max_flip)) if v is not None}

    def badness(r: dict) -> float:
        return max((r["uv_p95"] / max_uv_error) if max_uv_error else 0.0, (r["flip"] / max_flip) if max_flip else 0.0)

    closest = min(table, key=badness)["method"] if table else None
    return Choice(method=best["method"] if best else None, met=best is not None, bound=bound, cost=cost,
                  runner_up=runner["method"] if runner else None, closest=None if best else closest,
                  table=table, seconds=time.perf_counter() - t0)


def parse_angles(text: str) -> list[float]:
    """'30:80' (3 angles from 30 to 80), '30:80:5' or '30,60,80'."""
    try:
        if ":" in text:
            parts = [float(x) for x in text.split(":")]
            n = int(parts[2]) if len(parts) > 2 else 3
            return [float(x) for x in np.linspace(parts[0], parts[1], n)]
        return [float(x) for x in text.split(",")]
    except (ValueError, IndexError):
        raise ArgumentError(f"angles: 'a:b', 'a:b:n' or 'a,b,c' in degrees, got {text!r}") from None


def report(choice: Choice, out) -> None:
    """choice.md (the answer and the table) and choice.png (worst error against cost, the bound
    dashed, the answer starred) into the folder `out`."""
    from pathlib import Path
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "choice.md").write_text(f"# pk.choose\n\n{choice}\n\n{choice.markdown()}\n\nsearched in {choice.seconds:.1f} s\n")
    (out / "choice.json").write_text(json.dumps([{k: v for k, v in r.items() if k != "method"} for r in choice.table],
                                                indent=1))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    err = "uv_p95" if "max_uv_error" in choice.bound else "flip"
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for fam in dict.fromkeys(r["family"] for r in choice.table):
        rs = sorted((r for r in choice.table if r["family"] == fam), key=lambda r: r[choice.cost])
        ax.plot([r[choice.cost] for r in rs], [max(r[err], 1e-4) for r in rs], "o-", label=fam)
    bound = choice.bound.get("max_uv_error" if err == "uv_p95" else "max_flip")
    if bound is not None:
        ax.axhline(bound, color="k", ls="--", lw=0.8, label="bound")
    if choice.method is not None:
        r = next(r for r in choice.table if r["method"] is choice.method)
        ax.plot([r[choice.cost]], [max(r[err], 1e-4)], "k*", ms=14, label="choice")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("mean GPU ms" if choice.cost == "gpu_ms" else "mean texel fetches per pixel")
    ax.set_ylabel(f"worst {err} over the cases")
    ax.set_title("pk.choose: every setting measured")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "choice.png", dpi=110)
    plt.close(fig)
