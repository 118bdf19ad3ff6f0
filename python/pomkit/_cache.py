"""On-disk cache of reference renders, keyed by a hash of the scene and the settings.

Location: $POMKIT_CACHE, else ~/.cache/pomkit. Each entry is an .npz holding the arrays plus the
sha256 of their bytes; an entry whose content does not match its hash (truncated, corrupted) is
deleted and recomputed, never trusted.
"""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
import os
from pathlib import Path
from typing import Callable

import numpy as np

from . import _schema

#: the hash's format, part of every key: a new format leaves the old entries unread
FORMAT = 3


def cache_dir() -> Path:
    d = Path(os.environ.get("POMKIT_CACHE") or Path.home() / ".cache" / "pomkit")
    d.mkdir(parents=True, exist_ok=True)
    return d


def canonical(x):
    """A value as the hash reads it: floats to 12 significant digits (0 below 1e-12 in
    magnitude), so that a parameter computed on another CPU or numpy (a camera placed with
    np.cos of an angle) hashes the same; tuples, lists and arrays element by element; other
    values as they are."""
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        v = float(x)
        if not np.isfinite(v):
            return repr(v)
        return 0.0 if abs(v) < 1e-12 else float(f"{v:.12g}")
    if isinstance(x, np.ndarray):
        return [canonical(v) for v in x.tolist()]
    if isinstance(x, (list, tuple)):
        return [canonical(v) for v in x]
    if isinstance(x, dict):
        return {str(k): canonical(v) for k, v in x.items()}
    return x


def _json(x) -> bytes:
    return json.dumps(canonical(x), sort_keys=True, default=str).encode()


def _array(h, name: str, a: np.ndarray) -> None:
    """Hash an array's content: its dtype, shape and little-endian bytes."""
    a = np.ascontiguousarray(a)
    a = a.astype(a.dtype.newbyteorder("<"), copy=False)
    h.update(name.encode() + a.dtype.str.encode() + str(a.shape).encode() + a.tobytes())


def _declared(x) -> tuple[dict, list]:
    """A schema class's (camera, material, light) declared fields but pomkit's own renderer's
    settings (`_schema.settings`): the values by name, and the arrays as (name, array) in their
    declared order (an absent one left out)."""
    skip = _schema.settings(x._schema)
    values, arrays = {}, []
    for name, kind, *_ in _schema.fields(x._schema):
        v = getattr(x, name)
        if name in skip or (kind in _schema.ARRAY_KINDS and v is None):
            continue
        if kind in _schema.ARRAY_KINDS:
            arrays.append((name, v))
        else:
            values[name] = v
    return values, arrays


def scene_hash(scene, **settings) -> str:
    """sha256 over every array and parameter that changes a render, the same on every machine:
    every declared field of the scene's classes (`_declared`) and every field of its objects,
    parameters canonical (`canonical`), built-in meshes by their recipe (their vertices come
    from the platform's sinf), arrays by their little-endian bytes. Height maps and albedos are
    hashed as the float32 arrays the scene holds: pomkit makes those from exactly rounded
    operations (textures.py, _color.py), so they too are the same everywhere."""
    from ._scene import Mesh
    h = hashlib.sha256()
    lights = [dict(_declared(light)[0], kind=light._schema) for light in scene.lights]
    h.update(_json(dict(camera=_declared(scene.camera)[0], lights=lights, ambient=scene.ambient)))
    for i, o in enumerate(scene.objects):
        values: dict = {}
        arrays: list = []
        meshes = []
        for f in dataclasses.fields(o):
            v = getattr(o, f.name)
            if isinstance(v, Mesh):
                meshes.append(v)
            elif hasattr(v, "_schema"):
                vals, arrs = _declared(v)
                values.update(vals)
                arrays += arrs
            else:
                values[f.name] = v
        h.update(f"object{i}".encode() + _json(values))
        for mesh in meshes:
            if mesh.recipe is not None:
                h.update(b"mesh recipe" + _json(mesh.recipe))
            else:
                # the displaced mesh of a mesh from arrays welds its shared edges (seams, hard edges)
                h.update(b"mesh arrays, welded edges")
                a = mesh._arrays()
                for k in sorted(a):
                    _array(h, k, a[k])
        for k, a in arrays:
            _array(h, k, a)
    h.update(_json(settings))
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
        # a name of this process's own: test workers may compute the same key at once
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_bytes(buf.getvalue())
        tmp.replace(path)
    return arrays
