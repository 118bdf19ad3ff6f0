"""The same bits on every machine (issue 31): generated maps, real maps through `fit`, the sRGB
tables and the built-in scenes' hashes, held against tests/data/hashes.json.

A hash that moved with the CPU broke the disk cache, the demo's shipped references and mixed Dask
clusters: on a CPU without AVX-512, numpy's pow (the albedo's sRGB decode) gave other last bits.
The digests are checked here in-process, in subprocesses with numpy's SIMD dispatch switched off
(NPY_DISABLE_CPU_FEATURES: AVX-512 alone, then everything above the baseline), and by `make test`
under the oldest numpy that pyproject.toml allows (scripts/numpy_floor.sh runs this file as a
script there). Any change to a map or to the hash's format is a deliberate one: regenerate with

    .venv/bin/python tests/test_hashes.py --update

and say why in the commit.
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

try:
    import pytest
    slow = pytest.mark.slow
except ImportError:  # scripts/numpy_floor.sh runs this file with numpy and the wheel alone
    def slow(f):
        return f

DATA = Path(__file__).resolve().parent / "data" / "hashes.json"
# maps made by pomkit: `text` is left out (Pillow's font rasteriser draws its glyphs)
GENERATED = ("bricks", "cobblestones", "pyramids", "sine", "noise", "spikes", "constant")


def _digest(a) -> str:
    a = np.ascontiguousarray(a)
    a = a.astype(a.dtype.newbyteorder("<"), copy=False)
    return hashlib.sha256(a.dtype.str.encode() + str(a.shape).encode() + a.tobytes()).hexdigest()[:24]


def _scenes():
    import pomkit as pk
    from pomkit.apps import page

    t = np.radians(50.0)
    yield "demo planar", page.planar_scene()
    yield "demo curved", page.curved_scene()
    yield "sunk sphere", pk.scenes.sunk_sphere(64)
    yield "sine sphere, a camera by cos and sin", pk.Scene(
        mesh=pk.Mesh.sphere(), material=pk.Material(pk.textures.sine(64, freq=3.0), depth=0.05, tiling=2.0),
        camera=pk.Camera.look_at((0.0, 2.5 * np.cos(t), 2.5 * np.sin(t)), fov_y=40, width=64, height=48),
        lights=[pk.DirectionalLight((-0.3, -1.0, -0.2), (2.0, 1.5, 1.0), angular_diameter=3.0)], ambient=0.1)
    rng = np.random.default_rng(7)
    yield "arrays mesh, uint8 albedo, rotated", pk.Scene(
        objects=[pk.Object(pk.Mesh.from_arrays([[0, 0, 0], [1, 0, 0], [0, 0, 1]], [[0, 1, 0]] * 3,
                                               [[0, 0], [1, 0], [0, 1]], [0, 2, 1]),
                           pk.Material(pk.textures.noise(32), depth=0.1,
                                       albedo=rng.integers(0, 256, (32, 32, 3), dtype=np.uint8)),
                           pk.scenes.rotate((0, 1, 0), 30.0))],
        camera=pk.Camera.look_at((0.3, 1.0, 1.5), width=32, height=32), lights=[pk.SphereLight((0, 1, 0), 0.1, 2.0)])


def compute(real: bool = True) -> dict:
    """Every digest this file holds; `real=False` leaves out the maps that need matplotlib and
    scikit-image (the numpy-floor run installs neither)."""
    import pomkit as pk
    from pomkit import _color
    from pomkit._cache import scene_hash

    out: dict = {}
    for name in GENERATED:
        for size in (1, 7, 128):
            out[f"textures.{name}({size})"] = _digest(getattr(pk.textures, name)(size))
    ramp = np.add.outer(np.arange(403.0) ** 2, np.arange(344.0) * 3.0) % 1013.0
    out["textures.fit(ramp 403x344, 128)"] = _digest(pk.textures.fit(ramp, 128))
    out["textures.fit(ramp 403x344, 57)"] = _digest(pk.textures.fit(ramp, 57))
    if real:
        for name in pk.textures.REAL:
            out[f"textures.real({name!r})"] = _digest(pk.textures.real(name, 128))
    out["srgb8 table"] = _digest(_color.srgb8_table())
    out["srgb16 table"] = _digest(_color.srgb16_table())
    out["linear_to_srgb8(ramp)"] = _digest(_color.linear_to_srgb8(np.linspace(0.0, 1.0, 100003)))
    for name, scene in _scenes():
        out[f"scene_hash({name})"] = scene_hash(scene, kind="test", spp=4)
    return out


def _held() -> dict:
    return json.loads(DATA.read_text())


def _check(got: dict, where: str) -> None:
    held = _held()
    diff = [f"{k}: {got[k]} != {held.get(k)}" for k in got if got[k] != held.get(k)]
    assert not diff, f"{where}: digests moved (run tests/test_hashes.py --update only for a deliberate change):\n" + "\n".join(diff)


def test_every_digest_is_held():
    got = compute()
    assert set(got) == set(_held()), "tests/data/hashes.json lists other digests: regenerate it"
    _check(got, "in-process")


def _simd_off(level: str) -> str:
    """The features to switch off: the AVX-512 family, or everything numpy dispatches above its
    baseline."""
    try:
        from numpy._core import _multiarray_umath as mu  # type: ignore[attr-defined]
    except ImportError:  # numpy < 2
        from numpy.core import _multiarray_umath as mu  # type: ignore[attr-defined,no-redef]
    dispatch = [f for f in mu.__cpu_dispatch__ if f not in mu.__cpu_baseline__]
    if level == "avx512":
        dispatch = [f for f in dispatch if f.startswith("AVX512") or f == "X86_V4"]
    return " ".join(dispatch)


@slow
def test_the_same_digests_without_simd():
    """The CPU the issue's machine had: numpy's dispatch without AVX-512, and without anything
    above the baseline. Each run in a fresh interpreter (the dispatch is chosen at import)."""
    for level in ("avx512", "baseline"):
        env = dict(os.environ, NPY_DISABLE_CPU_FEATURES=_simd_off(level))
        r = subprocess.run([sys.executable, __file__, "--print"], env=env, capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr[-3000:]
        _check(json.loads(r.stdout.strip().splitlines()[-1]), f"NPY_DISABLE_CPU_FEATURES={env['NPY_DISABLE_CPU_FEATURES']}")


def test_the_demo_references_are_keyed_by_these_hashes():
    """The shipped Mitsuba renders are used only for the scene they were made for: their keys
    are the demo scenes' hashes computed here (and so on any machine the digests hold on)."""
    from pomkit._cache import scene_hash
    from pomkit.apps import page

    for name, make in (("planar", page.planar_scene), ("curved", page.curved_scene)):
        meta = json.loads((page.REFS / f"{name}.json").read_text())
        assert meta["hash"] == scene_hash(make(), kind="mitsuba", spp=meta["spp"], seed=0, variant=None, resolution=2.0), name


if __name__ == "__main__":
    if "--update" in sys.argv:
        DATA.write_text(json.dumps(compute(), indent=1, sort_keys=True) + "\n")
        print(f"wrote {DATA}")
    elif "--print" in sys.argv:
        print(json.dumps(compute()))
    elif "--check-floor" in sys.argv:
        # the oldest numpy (scripts/numpy_floor.sh): without the real maps' dependencies
        got = compute(real=False)
        _check(got, f"numpy {np.__version__}")
        print(f"numpy {np.__version__}: {len(got)} digests as held")
    else:
        sys.exit("usage: tests/test_hashes.py --update | --print | --check-floor")
