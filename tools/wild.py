#!/usr/bin/env python
"""The corpus of other people's models (issue 73): every file of scripts/wild_manifest.toml,
fetched by scripts/wild.py into the cache, loaded with pomkit's defaults and measured against the
oracle. `make wild` runs it on the whole corpus and writes docs/tables/wild.md; tests/test_wild.py
runs the manifest's fixed sample.

Per file: loaded or refused (the reason), triangles, charts, `check_asset`'s findings; then at
three views (two from above, one from below) at 96², each method against `pk.oracle.hits`: mask
IoU, interior holes (pixels inside the oracle's outline, eroded by 3 pixels, that the method
misses) and interior uv p95 in texels. Heights are each object's own base-colour texture's
luminance (stretched to [0, 1]) where it has one, else a field baked over its uvs; depth 1% of the
model's bounding diagonal (in world units: each object's depth is divided by its node's scale). Each file runs in a worker process with a time limit, so that one that
crashes or hangs is reported as such.

    .venv/bin/python tools/wild.py [--sample] [--every N] [--limit N] [--only NAME,...] [--files-timeout S] [--out docs/tables/wild.md]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import multiprocessing as mp
import os
import subprocess
import sys
import time
import traceback
import warnings
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
import zoo  # noqa: E402  (interior_holes: the zoo's measure of holes)

FETCHER = ROOT / "scripts" / "wild.py"
SIZE = 96
#: the methods measured, by the name the table gives them
METHOD_NAMES = ("Flat", "Parallax", "SteepParallax", "POM", "Relief", "Exact", "ConeStep", "Prism", "Prism(exact)",
                "NCS", "CurvedRelief", "DistanceMapping", "Tessellated(1)")
#: the methods that draw silhouettes: none may cover less than POM (the base mesh's outline)
SILHOUETTE = ("Prism", "Prism(exact)", "NCS", "CurvedRelief")
#: check_asset's findings under which a method is not held to the oracle (it says so)
FLAGS = ("normals_flipped", "normals_off_faces", "folded_prisms", "nonmanifold_edges", "mirror_shared_edges")


def methods() -> dict[str, Any]:
    import pomkit as pk
    return {"Flat": pk.Flat(), "Parallax": pk.Parallax(), "SteepParallax": pk.SteepParallax(), "POM": pk.POM(shadows="none"),
            "Relief": pk.Relief(), "Exact": pk.Exact(), "ConeStep": pk.ConeStep(), "Prism": pk.Prism(),
            "Prism(exact)": pk.Prism(exact=True), "NCS": pk.NCS(), "CurvedRelief": pk.CurvedRelief(),
            "DistanceMapping": pk.DistanceMapping(), "Tessellated(1)": pk.Tessellated(texels_per_vertex=1)}


def corpus(sample: bool) -> list[dict]:
    """The index of the fetched corpus (fetching what is missing), only the sample's files with
    `sample`."""
    args = [sys.executable, str(FETCHER), "fetch"] + (["--sample"] if sample else [])
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
    listed = subprocess.run([sys.executable, str(FETCHER), "list"] + (["--sample"] if sample else []),
                            check=True, capture_output=True, text=True).stdout.split()
    cache = Path(os.environ.get("POMKIT_WILD_CACHE", Path.home() / ".cache" / "pomkit" / "wild"))
    index = json.loads((cache / "index.json").read_text())
    ids = set(listed)
    return [e for e in index if e["id"] in ids] if sample else index


def _luminance(albedo: np.ndarray) -> np.ndarray:
    import pomkit as pk
    lum = albedo[..., :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    lum = pk.textures.fit(lum, min(256, max(lum.shape)))
    if float(lum.max() - lum.min()) < 1e-3:
        return np.full(lum.shape, 0.5, np.float32)
    return pk.textures.normalize(lum)


def _cells(scale: float):
    def f(p: np.ndarray) -> np.ndarray:
        q = p / scale
        g = np.abs(q - np.floor(q) - 0.5).max(-1)
        return np.clip(2.5 * (0.45 - g), 0.0, 1.0)
    return f


def scene_objects(glb: str):
    """The file's objects with pomkit's defaults (`load_objects`), each with its height: its own
    texture's luminance, or cells baked over its uvs; depth 1% of the bounding diagonal. Also the
    world bounds and the warnings the load gave."""
    import pomkit as pk
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        objs = pk.load_objects(glb, pk.Material(pk.textures.constant(8, 1.0), depth=1.0))
    pts = []
    for o in objs:
        p = np.asarray(o.mesh.positions, np.float64)
        if o.transform is not None:
            m = np.asarray(o.transform, np.float64)
            p = p @ m[:3, :3].T + m[:3, 3]
        pts.append(p)
    allp = np.concatenate(pts)
    lo, hi = allp.min(0), allp.max(0)
    diag = float(np.linalg.norm(hi - lo))
    out = []
    for o in objs:
        mat = o.material
        albedo = mat.albedo
        if albedo is not None and albedo.shape[0] * albedo.shape[1] > 4:
            h = _luminance(np.asarray(albedo))
        else:
            scale = max(float(np.linalg.norm(np.ptp(o.mesh.positions, 0))), 1e-9) / 4.0
            h = pk.textures.bake(o.mesh, _cells(scale), 128)
        # 1% of the world's diagonal, in the object's units (depth is in object space: a node
        # scaled 10x would otherwise sink 10% of the diagonal); load_objects puts primitives
        # without uvs at 0
        scale = 1.0 if o.transform is None else float(np.abs(np.linalg.det(np.asarray(o.transform, np.float64)[:3, :3]))) ** (1.0 / 3.0)
        depth = 0.0 if mat.depth == 0.0 else 0.01 * diag / max(scale, 1e-30)
        out.append(dataclasses.replace(o, material=dataclasses.replace(mat, height=h, depth=depth)))
    return out, (lo, hi), [str(w.message) for w in caught]


def views(lo, hi, size: int = SIZE, fov: float = 35.0):
    """Three cameras on the bounding sphere: two from 35° above, one from 30° below."""
    import pomkit as pk
    c = 0.5 * (lo + hi)
    r = max(0.5 * float(np.linalg.norm(hi - lo)), 1e-9)
    d = r / np.sin(np.radians(fov) / 2.0) * 1.05
    out = []
    for a, e in ((0.4, 35.0), (0.4 + 2.0 * np.pi / 3, 35.0), (0.4 + 4.0 * np.pi / 3, -30.0)):
        e = np.radians(e)
        eye = c + d * np.array([np.cos(e) * np.cos(a), np.sin(e), np.cos(e) * np.sin(a)])
        out.append(pk.Camera.look_at(tuple(eye), tuple(c), fov_y=fov, width=size, height=size))
    return out


def findings(objs) -> dict[str, int]:
    import pomkit as pk
    tot: dict[str, int] = {}
    for o in objs:
        r = pk.check_asset(o.mesh, o.material)
        for k in ("triangles", "charts", "seam_edges", "open_edges", "hard_edges", "mirrored_charts") + FLAGS:
            tot[k] = tot.get(k, 0) + int(getattr(r, k) or 0)
    return tot


def measure(entry: dict, renderer=None) -> dict:
    """One file's row: load, findings and, per view and method, IoU, interior holes, uv p95."""
    import pomkit as pk
    row: dict[str, Any] = dict(id=entry["id"], package=entry["package"], triangles=entry.get("triangles"))
    t0 = time.perf_counter()
    try:
        objs, (lo, hi), warned = scene_objects(entry["glb"])
    except Exception as e:  # a refusal: its reason is the row
        row.update(loaded=False, reason=str(e).replace(entry["glb"], "<file>"))
        return row
    row.update(loaded=True, warnings=len(warned), objects=len(objs),
               textured=sum(o.material.albedo is not None and o.material.albedo.shape[0] > 2 for o in objs))
    row["findings"] = findings(objs)
    row["flagged"] = any(row["findings"][k] for k in FLAGS)
    r = renderer or pk.Renderer()
    res: dict[str, list] = {m: [] for m in METHOD_NAMES}
    for cam in views(lo, hi):
        s = pk.Scene(objects=objs, camera=cam, lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)], ambient=0.1)
        ref = pk.oracle.hits(s)
        if ref.mask.sum() < 50:
            continue
        for name, m in methods().items():
            try:
                f = r.render(s, m, aovs=("uv", "mask", "object"))
            except Exception as e:
                res[name].append(dict(error=str(e)[:200]))
                continue
            u = pk.metrics.uv_error(f, ref, s)
            res[name].append(dict(iou=float(u["mask_iou"]), holes=zoo.interior_holes(f.mask, ref.mask),
                                  uv_p95=float(u["p95"]) if u["n"] else float("nan")))
    row["methods"] = res
    row["seconds"] = time.perf_counter() - t0
    return row


def _worker(conn) -> None:
    import pomkit as pk
    r = pk.Renderer()
    while True:
        entry = conn.recv()
        if entry is None:
            return
        try:
            conn.send(measure(entry, r))
        except Exception:
            conn.send(dict(id=entry["id"], package=entry["package"], loaded=False,
                           reason="error: " + traceback.format_exc(limit=2).strip().splitlines()[-1]))


def run(entries: list[dict], timeout: float) -> list[dict]:
    """Each entry measured in a worker process, restarted after a crash or `timeout` seconds."""
    ctx = mp.get_context("spawn")
    rows, proc, conn = [], None, None
    for k, e in enumerate(entries):
        if not e.get("glb") or e.get("error") or not os.path.exists(e["glb"]):
            rows.append(dict(id=e["id"], package=e["package"], loaded=False, converted=False,
                             reason="not converted: " + str(e.get("error") or "no glb")[:120]))
            continue
        if proc is None:
            conn, child = ctx.Pipe()
            proc = ctx.Process(target=_worker, args=(child,), daemon=True)
            proc.start()
        assert conn is not None
        conn.send(e)
        if conn.poll(timeout):
            try:
                rows.append(conn.recv())
            except EOFError:
                rows.append(dict(id=e["id"], package=e["package"], loaded=False, reason="crashed"))
                proc = None
        else:
            rows.append(dict(id=e["id"], package=e["package"], loaded=False, reason=f"hung (over {timeout:g} s)"))
            proc.kill()
            proc = None
        if proc is not None and not proc.is_alive():
            rows[-1] = dict(id=e["id"], package=e["package"], loaded=False, reason="crashed")
            proc = None
        print(f"[wild] {k + 1}/{len(entries)} {e['id']}: {'loaded' if rows[-1].get('loaded') else rows[-1].get('reason', '')[:60]}",
              flush=True)
    if proc is not None and conn is not None:
        conn.send(None)
        proc.join(5)
    return rows


def _worst(rows: list[dict], name: str) -> dict:
    vals = [v for r in rows if r.get("methods") for v in r["methods"][name] if "iou" in v]
    errs = sum(1 for r in rows if r.get("methods") for v in r["methods"][name] if "error" in v)
    if not vals:
        return dict(n=0, errors=errs)
    p95 = [v["uv_p95"] for v in vals if np.isfinite(v["uv_p95"])]
    return dict(n=len(vals), errors=errs, iou_min=min(v["iou"] for v in vals),
                iou_mean=float(np.mean([v["iou"] for v in vals])), holes=sum(v["holes"] for v in vals),
                holed=sum(v["holes"] > 0 for v in vals), uv_p95_median=float(np.median(p95)) if p95 else float("nan"))


def below_pom(rows: list[dict], name: str, slack: float = 0.0) -> int:
    """Views where a silhouette method covers less of the oracle than POM (IoU below POM's)."""
    n = 0
    for r in rows:
        for a, b in zip(r.get("methods", {}).get(name, []), r.get("methods", {}).get("POM", [])):
            if "iou" in a and "iou" in b and a["iou"] < b["iou"] - slack:
                n += 1
    return n


def summary(rows: list[dict]) -> str:
    conv = [r for r in rows if r.get("converted", True)]
    loaded = [r for r in conv if r.get("loaded")]
    tris = sum(r.get("triangles") or 0 for r in loaded)
    holes = {m: sum(v.get("holes", 0) > 0 for r in loaded if not r.get("flagged") for v in r["methods"][m]) for m in METHOD_NAMES}
    holed = ", ".join(f"{m} {n}" for m, n in holes.items() if n) or "none"
    below = ", ".join(f"{m} {below_pom(loaded, m, 0.002)}" for m in SILHOUETTE)
    pk_count = len({r["package"] for r in rows})
    return (f"{len(loaded)} of {len(conv)} converted files from {pk_count} packages load with pomkit's defaults "
            f"({tris} triangles); views with interior holes on files check_asset does not flag: {holed}; "
            f"views where a silhouette method's IoU is more than 0.002 below POM's: {below}")


def table(rows: list[dict]) -> str:
    out = [summary(rows), "", "| method | views | errors | IoU min | IoU mean | views with holes | hole pixels | uv p95 median |",
           "|---|---|---|---|---|---|---|---|"]
    loaded = [r for r in rows if r.get("loaded")]
    for m in METHOD_NAMES:
        w = _worst(loaded, m)
        if not w["n"]:
            out.append(f"| {m} | 0 | {w['errors']} | | | | | |")
            continue
        out.append(f"| {m} | {w['n']} | {w['errors']} | {w['iou_min']:.4f} | {w['iou_mean']:.4f} | {w['holed']} | {w['holes']} | "
                   f"{w['uv_p95_median']:.3f} |")
    out += ["", "Per file (loaded: objects, textured objects, triangles, charts, findings; refused: the reason):", "",
            "| file | result | worst silhouette IoU below POM | holes (method: pixels) |", "|---|---|---|---|"]
    for r in rows:
        if not r.get("loaded"):
            out.append(f"| {r['id']} | refused: {r.get('reason', '')[:150]} | | |")
            continue
        f = r["findings"]
        found = ", ".join(f"{k} {v}" for k, v in f.items() if v and k not in ("triangles", "charts"))
        res = f"{r['objects']} obj, {r['textured']} textured, {f['triangles']} tris, {f['charts']} charts" + (f"; {found}" if found else "")
        gaps = []
        for m in SILHOUETTE:
            d = [b["iou"] - a["iou"] for a, b in zip(r["methods"][m], r["methods"]["POM"]) if "iou" in a and "iou" in b]
            if d and max(d) > 0.002:
                gaps.append(f"{m} {max(d):.3f}")
        holes = [f"{m}: {sum(v.get('holes', 0) for v in r['methods'][m])}" for m in METHOD_NAMES
                 if any(v.get("holes", 0) for v in r["methods"][m])]
        out.append(f"| {r['id']} | {res} | {', '.join(gaps)} | {', '.join(holes)} |")
    return "\n".join(out) + "\n"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sample", action="store_true")
    ap.add_argument("--limit", type=int, default=0)
    ap.add_argument("--every", type=int, default=1, help="every n-th file of the index (a spread subset)")
    ap.add_argument("--only", default="", help="comma-separated parts of file ids: measure only the files whose id holds one")
    ap.add_argument("--files-timeout", type=float, default=300.0)
    ap.add_argument("--out", default=str(ROOT / "docs" / "tables" / "wild.md"))
    ap.add_argument("--json", default=str(ROOT / "pomkit-out" / "wild.json"))
    a = ap.parse_args(argv)
    entries = corpus(a.sample)
    if a.only:
        parts = [p for p in a.only.split(",") if p]
        entries = [e for e in entries if any(p in e["id"] for p in parts)]
    entries = entries[:: max(a.every, 1)]
    if a.limit:
        entries = entries[: a.limit]
    rows = run(entries, a.files_timeout)
    Path(a.json).parent.mkdir(parents=True, exist_ok=True)
    Path(a.json).write_text(json.dumps(rows, default=float))
    sys.path.insert(0, str(ROOT / "tools"))
    import pomkit as pk
    from provenance import stamp
    body = table(rows)
    Path(a.out).write_text(f"# Assets from the wild\n\n{stamp(pk.Renderer().info)}\n\n{body}")
    print(summary(rows))


if __name__ == "__main__":
    main()
