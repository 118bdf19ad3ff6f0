"""pytest helpers for your own test suite: a plugin you opt into, with
`pytest_plugins = ["pomkit.testing"]` in your top-level conftest.py or `pytest -p pomkit.testing`
(it is not registered on install, so that a pytest run that does not ask never imports pomkit).

    def test_my_method(oracle_frame):
        ref = oracle_frame(scene, kind="image", spp=16)   # the oracle: noise-free, cached on disk
        frame = pk.Renderer().render(scene, pk.POM(), spp=16)
        pk.testing.assert_close(frame, ref, scene=scene, uv_p95=0.5, flip_interior=0.02)

`assert_close` fails with the measured numbers and writes a side-by-side image (frame | ref |
error) to $POMKIT_DIFF_DIR (default ./pomkit-out/diffs), named after the test that failed.
A FLIP tolerance below the reference's own noise (`Frame.noise_floor`: 0 for `pk.oracle.image`,
the seed-against-seed FLIP for Mitsuba when measured) is refused: it could only pass by luck.
"""

from __future__ import annotations

from ._errors import ArgumentError
import os
from pathlib import Path
from typing import Optional

import numpy as np
import pytest

from ._frame import Frame
from ._scene import Scene

__all__ = ["assert_close", "oracle_frame", "reference_frame"]


def _diff_image(frame: Frame, ref: Frame, name: str) -> Path:
    from PIL import Image
    a = frame.to_srgb8() if frame.has("color") else np.zeros(frame.mask.shape + (3,), np.uint8)
    b = ref.to_srgb8() if ref.has("color") else np.zeros(ref.mask.shape + (3,), np.uint8)
    d = np.abs(a.astype(np.int16) - b.astype(np.int16)).max(-1)
    d = np.clip(d.astype(np.float32) * 4, 0, 255).astype(np.uint8)
    err = np.stack([d, d // 3, 255 - d], -1) * (d[..., None] > 0)
    out = Path(os.environ.get("POMKIT_DIFF_DIR", "pomkit-out/diffs"))
    out.mkdir(parents=True, exist_ok=True)
    p = out / f"{name}.png"
    Image.fromarray(np.concatenate([a, b, err.astype(np.uint8)], 1)).save(p)
    return p


def assert_close(frame: Frame, ref: Frame, scene: Optional[Scene] = None, *, uv_p95: Optional[float] = None,
                 uv_p99: Optional[float] = None, flip: Optional[float] = None, iou: Optional[float] = None,
                 objects: Optional[float] = None, flip_interior: Optional[float] = None,
                 flip_silhouette: Optional[float] = None, name: Optional[str] = None) -> dict:
    """Check a frame against a reference. Each given tolerance is asserted (uv in texels, needs
    `scene`; in a scene of several objects, per object where both frames hit the same one);
    `objects` is the least fraction of the pixels both cover where the two `object` AOVs agree
    (interpenetration). `flip_interior` and `flip_silhouette` bound FLIP over the interior and the
    silhouette band of `metrics.compare` (a planar method's outline error apart from its
    displacement error). The returned dict holds every measured number. On failure the message lists them
    all and names the side-by-side diff image."""
    from . import metrics

    if name is None:  # the running test's id, so that two failures do not share one image
        test = os.environ.get("PYTEST_CURRENT_TEST", "assert_close").split(" ")[0]
        name = "".join(c if c.isalnum() or c in "-_." else "_" for c in test.split("::", 1)[-1])
    floor = getattr(ref, "noise_floor", None)
    for k, tol in (("flip", flip), ("flip_interior", flip_interior), ("flip_silhouette", flip_silhouette)):
        if tol is not None and floor is not None and tol < floor:
            raise ArgumentError(f"{k}: a tolerance of {tol} is below the reference's own noise (noise_floor "
                             f"{floor:.4f}, its FLIP against itself at another seed): it would pass or fail by "
                             f"chance; use a tolerance above it, or the noise-free pk.oracle.image")
    got: dict = {"mask_iou": metrics.mask_iou(frame, ref)}
    if floor is not None:
        got["flip_floor"] = float(floor)
    fails = []
    if uv_p95 is not None or uv_p99 is not None:
        if scene is None:
            raise ArgumentError("scene: uv tolerances need the scene (for the map size and tiling)")
        e = metrics.uv_error(frame, ref, scene)
        got.update(uv_p50=e["p50"], uv_p95=e["p95"], uv_p99=e["p99"], uv_max=e["max"])
        if uv_p95 is not None and not e["p95"] <= uv_p95:
            fails.append(f"uv p95 {e['p95']:.4f} > {uv_p95}")
        if uv_p99 is not None and not e["p99"] <= uv_p99:
            fails.append(f"uv p99 {e['p99']:.4f} > {uv_p99}")
    if flip is not None:
        got["flip"] = metrics.flip(frame, ref)
        if not got["flip"] <= flip:
            fails.append(f"FLIP {got['flip']:.4f} > {flip}")
    if flip_interior is not None or flip_silhouette is not None:
        c = metrics.compare(frame, ref, scene) if scene is not None else None
        if c is None:
            raise ArgumentError("scene: region tolerances need the scene")
        got.update(flip_interior=c["flip_interior"], flip_silhouette=c["flip_silhouette"])
        if flip_interior is not None and not c["flip_interior"] <= flip_interior:
            fails.append(f"FLIP interior {c['flip_interior']:.4f} > {flip_interior}")
        if flip_silhouette is not None and not c["flip_silhouette"] <= flip_silhouette:
            fails.append(f"FLIP silhouette {c['flip_silhouette']:.4f} > {flip_silhouette}")
    if objects is not None or (frame.has("object") and ref.has("object")):
        both = frame.mask & ref.mask
        got["objects"] = float((frame.object == ref.object)[both].mean()) if both.any() else float("nan")
        if objects is not None and not got["objects"] >= objects:
            fails.append(f"object agreement {got['objects']:.4f} < {objects}")
    if iou is not None and not got["mask_iou"] >= iou:
        fails.append(f"mask IoU {got['mask_iou']:.4f} < {iou}")
    if fails:
        p = _diff_image(frame, ref, name)
        measured = ", ".join(f"{k}={v:.4g}" for k, v in got.items())
        raise AssertionError(f"{name}: {'; '.join(fails)} (measured: {measured}); diff image: {p}")
    return got


_ORACLE_KINDS = {"oracle_image": "image", "oracle_hits": "hits", "render_exact": "image", "exact": "hits"}


def _reference(scene: Scene, kind: str = "mitsuba", **kw) -> Frame:
    from . import reference
    if kind in _ORACLE_KINDS:
        raise ArgumentError(f"kind: the oracle is not a reference; use the oracle_frame fixture: "
                            f"oracle_frame(scene, kind={_ORACLE_KINDS[kind]!r})")
    if kind == "mitsuba":
        return reference.render_mitsuba(scene, **kw)
    if kind == "pyrender":
        return reference.render_pyrender(scene, **kw)
    if kind == "cycles":
        return reference.render_cycles(scene, **kw)
    raise ArgumentError(f"kind: must be 'mitsuba', 'pyrender' or 'cycles', got {kind!r}")


def _oracle(scene: Scene, kind: str = "image", **kw) -> Frame:
    from . import oracle
    if kind == "image":
        return oracle.image(scene, **kw)
    if kind == "hits":
        return oracle.hits(scene, **kw)
    raise ArgumentError(f"kind: must be 'image' or 'hits', got {kind!r}")


@pytest.fixture
def reference_frame():
    """A function (scene, kind="mitsuba", **settings) -> Frame, cached on disk by scene hash: an
    independent renderer's frame, "mitsuba" (`pk.reference.render_mitsuba`), "pyrender" or
    "cycles". The ground truth itself is the `oracle_frame` fixture."""
    return _reference


@pytest.fixture
def oracle_frame():
    """A function (scene, kind="image", **settings) -> Frame: the float64 oracle, "image"
    (`pk.oracle.image`, the noise-free colour, cached on disk by scene hash) or "hits"
    (`pk.oracle.hits`: uv, depth, mask, object, visibility)."""
    return _oracle
