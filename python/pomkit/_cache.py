"""On-disk cache of reference renders, keyed by a hash of the scene and the settings.

Location: $POMKIT_CACHE, else ~/.cache/pomkit. Each entry is an .npz holding the arrays plus the
sha256 of their bytes; an entry whose content does not match its hash (truncated, corrupted) is
deleted and recomputed, never trusted.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
from pathlib import Path
from typing import Callable

import numpy as np

FORMAT = 1


def cache_dir() -> Path:
    d = Path(os.environ.get("POMKIT_CACHE") or Path.home() / ".cache" / "pomkit")
    d.mkdir(parents=True, exist_ok=True)
    return d


def scene_hash(scene, **settings) -> str:
    """sha256 over every array and parameter that changes a render."""
    h = hashlib.sha256()
    # the scene's parameters as `Scene._describe` gives them, without making the core's copies
    # of the arrays (they are hashed here from the arrays themselves). A one-object scene without
    # a transform hashes as scenes did before objects existed, so that cached references stay.
    lights = []
    for l in scene.lights:
        ld = l._describe()
        # pomkit's own shadow settings do not change a reference render
        ld.pop("cast_shadows", None)
        ld.pop("shadow_map_size", None)
        lights.append(ld)
    first = scene.objects[0]
    d = dict(depth=first.material.depth, tiling=first.material.tiling, camera=scene.camera._describe(),
             lights=lights, ambient=scene.ambient)
    for i, o in enumerate(scene.objects):
        m = o.material
        if i > 0 or not o.is_identity:
            h.update(f"object{i}:v2".encode() + np.ascontiguousarray(o.transform).tobytes())
            h.update(json.dumps(dict(depth=m.depth, tiling=m.tiling)).encode())
        mesh = o.mesh._arrays()
        for k in sorted(mesh):
            a = np.ascontiguousarray(mesh[k])
            h.update(k.encode() + str(a.dtype).encode() + str(a.shape).encode() + a.tobytes())
        for k, a in (("height", m.height), ("albedo", m.albedo)):
            if a is not None:
                a = np.ascontiguousarray(a)
                h.update(k.encode() + str(a.shape).encode() + a.tobytes())
    h.update(json.dumps(d, sort_keys=True, default=str).encode())
    h.update(json.dumps(settings, sort_keys=True, default=str).encode())
    h.update(f"format{FORMAT}".encode())
    return h.hexdigest()[:32]


def _digest(arrays: dict) -> str:
    h = hashlib.sha256()
    for k in sorted(arrays):
        a = np.ascontiguousarray(arrays[k])
        h.update(k.encode() + str(a.dtype).encode() + str(a.shape).encode() + a.tobytes())
    return h.hexdigest()


def cached(kind: str, key: str, compute: Callable[[], dict], use_cache: bool = True) -> dict:
    """Return the arrays for (kind, key), computing and storing them on a miss."""
    path = cache_dir() / f"{kind}-{key}.npz"
    if use_cache and path.exists():
        try:
            with np.load(path, allow_pickle=False) as z:
                arrays = {k: z[k] for k in z.files if k != "__digest__"}
                digest = str(z["__digest__"])
            if digest == _digest(arrays):
                return arrays
        except Exception:
            pass
        path.unlink(missing_ok=True)  # corrupt: recompute
    arrays = compute()
    if use_cache:
        buf = io.BytesIO()
        np.savez_compressed(buf, __digest__=np.array(_digest(arrays)), **arrays)
        tmp = path.with_suffix(".tmp")
        tmp.write_bytes(buf.getvalue())
        tmp.replace(path)
    return arrays
