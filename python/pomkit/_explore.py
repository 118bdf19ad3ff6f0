"""`pk.explore(scene)`: a notebook widget (anywidget) to orbit a scene live and compare methods
against the reference.

Drag to orbit about the camera's target, scroll to zoom; pick the method, its main parameter
(its step count), the view (colour, reference, uv error, FLIP, steps, fetches, LOD, shadow
error) and a comparison with the reference (a split, or the reference alone). Beside the frame:
GPU ms, texel fetches, uv p95 and FLIP. While dragging, frames render at half the resolution and
skip the reference; references are cached per pose. Traits: `method` (a name), `view`,
`compare`, `steps`, `azimuth`, `elevation` (degrees), `distance` (scene units), `size`, `image`
(the PNG shown) and `stats` (a dict). Works wherever anywidget does (JupyterLab, Notebook 7,
VS Code, Colab); the `notebooks` extra installs it.

The reference: "oracle" is `pk.oracle.image` (noise-free, any mesh) with the float64
oracle for uv and shadows; with reference="tessellated", the mesh itself (`Tessellated(1.0)`, the default fan: as close to the field as the two-triangle grid at
0.5 texels per vertex, at a third of its time on a cobbled torus at 256²).
"""

from __future__ import annotations

from ._errors import ArgumentError, ArgumentTypeError

import io
import math
import time
from collections import OrderedDict
from typing import Any, Optional, Sequence

import numpy as np

from . import _methods, metrics, oracle
from ._heatmap import heat
from ._frame import Frame
from ._render import Renderer
from ._scene import Camera, Scene

__all__ = ["explore", "VIEWS", "METHOD_STEPS"]

#: what the frame shows
VIEWS: tuple[str, ...] = ("color", "reference", "uv_error", "flip", "steps", "fetches", "lod", "shadow_error")
#: each method's main parameter, the field the `steps` trait sets: the method's own `steps_knob`
METHOD_STEPS: dict[str, Optional[str]] = {c.__name__: c.steps_knob for c in _methods.ALL_METHODS}

_ESM = r"""
function render({ model, el }) {
  const root = document.createElement("div");
  root.className = "pomkit-explore";
  const bar = document.createElement("div");
  const pick = (name, options) => {
    const s = document.createElement("select");
    s.title = name;
    for (const o of options) { const e = document.createElement("option"); e.value = o; e.textContent = o; s.appendChild(e); }
    s.value = model.get(name);
    s.addEventListener("change", () => { model.set(name, s.value); model.save_changes(); });
    model.on("change:" + name, () => { s.value = model.get(name); });
    bar.appendChild(s);
    return s;
  };
  pick("method", model.get("methods"));
  pick("view", model.get("views"));
  pick("compare", ["off", "split", "reference"]);
  const steps = document.createElement("input");
  steps.type = "number"; steps.min = 0; steps.max = 512; steps.title = "steps (0: the method's default)";
  steps.value = model.get("steps");
  steps.addEventListener("change", () => { model.set("steps", parseInt(steps.value || "0")); model.save_changes(); });
  bar.appendChild(steps);
  const img = document.createElement("img");
  img.draggable = false;
  img.style.cursor = "grab";
  const stats = document.createElement("pre");
  const show = () => {
    const v = model.get("image");
    if (v && v.byteLength) {
      const url = URL.createObjectURL(new Blob([v], { type: "image/png" }));
      img.onload = () => URL.revokeObjectURL(url);
      img.src = url;
    }
    stats.textContent = Object.entries(model.get("stats")).map(([k, x]) => k + ": " + x).join("\n");
  };
  model.on("change:image", show);
  model.on("change:stats", show);
  let last = null;
  img.addEventListener("pointerdown", (e) => {
    last = [e.clientX, e.clientY];
    img.setPointerCapture(e.pointerId);
    model.set("dragging", true); model.save_changes();
  });
  img.addEventListener("pointermove", (e) => {
    if (!last) return;
    const dx = e.clientX - last[0], dy = e.clientY - last[1];
    if (Math.abs(dx) + Math.abs(dy) < 2) return;
    last = [e.clientX, e.clientY];
    model.set("azimuth", model.get("azimuth") - dx * 0.5);
    model.set("elevation", Math.max(-89, Math.min(89, model.get("elevation") + dy * 0.5)));
    model.save_changes();
  });
  const up = () => { if (last) { last = null; model.set("dragging", false); model.save_changes(); } };
  img.addEventListener("pointerup", up);
  img.addEventListener("pointercancel", up);
  img.addEventListener("wheel", (e) => {
    e.preventDefault();
    model.set("distance", model.get("distance") * Math.pow(1.1, Math.sign(e.deltaY)));
    model.save_changes();
  }, { passive: false });
  root.appendChild(bar);
  const row = document.createElement("div");
  row.style.display = "flex"; row.style.gap = "12px";
  row.appendChild(img); row.appendChild(stats);
  root.appendChild(row);
  el.appendChild(root);
  show();
}
export default { render };
"""


def _orbit(cam: Camera) -> tuple[float, float, float]:
    """The camera's (azimuth, elevation, distance) about its target (degrees, scene units)."""
    d = np.subtract(cam.eye, cam.target)
    r = float(np.linalg.norm(d))
    return math.degrees(math.atan2(d[0], d[2])), math.degrees(math.asin(max(-1.0, min(1.0, d[1] / r)))), r


def _configured(methods: Optional[Sequence[Any]]) -> dict[str, _methods.Method]:
    """Each entry of `methods` (a method's name, or a configured method such as
    `pk.POM(min_steps=12)`) under the label the widget lists it by: the name, or the method's repr."""
    items = list(methods) if methods is not None else [m.__name__ for m in _methods.ALL_METHODS]
    out: dict[str, _methods.Method] = {}
    for m in items:
        if isinstance(m, str):
            if m not in METHOD_STEPS:
                raise ArgumentError(f"methods: {m!r} is not a pomkit method; one of {', '.join(METHOD_STEPS)}, or a configured method such as pk.POM(min_steps=12)")
            out[m] = getattr(_methods, m)()
        elif isinstance(m, _methods.Method):
            out[repr(m)] = m
        else:
            raise ArgumentTypeError(f"methods: expected method names or pomkit methods, got {type(m).__name__}")
    if not out:
        raise ArgumentError("methods: give at least one method")
    return out


def explore(scene: Scene, methods: Optional[Sequence[Any]] = None, reference: str = "oracle", size: int = 256) -> Any:
    """A widget that orbits `scene` live with any of `methods` (names of pomkit methods, or
    configured methods such as `pk.POM(min_steps=12)`, listed by their repr; default: every method
    by name) against `reference` ("oracle" or "tessellated"). The steps slider, when set, replaces
    the method's main step count (METHOD_STEPS). See the module's doc."""
    import anywidget
    import traitlets as t

    configured = _configured(methods)
    names = list(configured)
    if reference not in ("oracle", "tessellated"):
        raise ArgumentError(f"reference: 'oracle' or 'tessellated', got {reference!r}")
    if not isinstance(scene, Scene):
        raise ArgumentTypeError(f"scene: expected a pomkit.Scene, got {type(scene).__name__}")

    class Explorer(anywidget.AnyWidget):
        _esm = _ESM
        method = t.Unicode(names[0] if "POM" not in names else "POM").tag(sync=True)
        methods = t.List(t.Unicode()).tag(sync=True)
        views = t.List(t.Unicode()).tag(sync=True)
        view = t.Unicode("color").tag(sync=True)
        compare = t.Unicode("off").tag(sync=True)
        steps = t.Int(0).tag(sync=True)
        azimuth = t.Float(0.0).tag(sync=True)
        elevation = t.Float(30.0).tag(sync=True)
        distance = t.Float(2.0).tag(sync=True)
        size = t.Int(256).tag(sync=True)
        dragging = t.Bool(False).tag(sync=True)
        image = t.Bytes(b"").tag(sync=True)
        stats = t.Dict().tag(sync=True)

        def __init__(self, **kw: Any) -> None:
            super().__init__(**kw)
            self._scene = scene
            self._renderer = Renderer()
            self._refs: OrderedDict = OrderedDict()
            self._exact = reference == "oracle"
            self.observe(self._changed, names=["method", "view", "compare", "steps", "azimuth", "elevation",
                                               "distance", "size", "dragging"])
            self._update()

        # ---- the scene at the current pose ----
        def _camera(self, size: int) -> Camera:
            c = self._scene.camera
            az, el = math.radians(self.azimuth), math.radians(self.elevation)
            off = self.distance * np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])
            w = size
            h = max(1, round(size * c.height / c.width))
            up = c.up if abs(math.cos(el)) > 1e-3 else (0.0, 0.0, -1.0)
            return Camera.look_at(tuple(np.add(c.target, off)), c.target, up, c.fov_y, w, h)

        def _method(self) -> _methods.Method:
            if self.method not in names:
                raise ArgumentError(f"method: one of {', '.join(names)}, got {self.method!r}")
            base = configured[self.method]
            return base.with_steps(int(self.steps)) if self.steps > 0 else base

        def _reference(self, sc: Scene) -> tuple[Frame, Optional[Frame]]:
            """(colour reference, geometric oracle or None), cached per pose."""
            key = (round(self.azimuth, 3), round(self.elevation, 3), round(self.distance, 5), sc.camera.width)
            if key not in self._refs:
                if self._exact:
                    ex = oracle.image(sc, spp=1, cache=False)
                    # its uv, mask and visibility are the oracle's (pk.oracle.hits)
                    self._refs[key] = (ex, ex)
                else:
                    self._refs[key] = (self._renderer.render(sc, _methods.Tessellated(1.0)), None)
                while len(self._refs) > 16:
                    self._refs.popitem(last=False)
            return self._refs[key]

        def _changed(self, change: Any) -> None:
            self._update()

        def _update(self) -> None:
            t0 = time.perf_counter()
            size = max(16, self.size // 2) if self.dragging else self.size
            sc = self._scene.replace(camera=self._camera(size))
            m = self._method()
            f = self._renderer.render(sc, m, aovs=("color", "uv", "mask", "steps", "lod", "fetches") + (("object",) if len(sc.objects) > 1 else ()))
            stats: dict = dict(method=repr(m), gpu_ms=round(f.gpu_ms, 3) if f.gpu_ms is not None else None,
                               fetches=round(float(f.fetches[f.mask].mean()), 2) if f.mask.any() else 0.0)
            ref = oracle = None
            if not self.dragging or self.view in ("reference", "uv_error", "flip", "shadow_error") or self.compare != "off":
                ref, oracle = self._reference(sc)
                geo = oracle if oracle is not None else ref
                e = metrics.uv_error(f, geo, sc)
                stats["uv_p95"] = round(float(e["p95"]), 4)
                try:
                    fl, _ = metrics.flip(f, ref, image=True)
                    stats["flip"] = round(float(fl), 4)
                except ImportError:
                    fl = float("nan")
            img = self._view(f, ref, oracle, sc, m)
            if self.compare != "off" and ref is not None:
                r8 = ref.to_srgb8()
                if self.compare == "reference":
                    img = r8
                else:  # split: the method on the left, the reference on the right
                    img = img.copy()
                    half = img.shape[1] // 2
                    img[:, half:] = r8[:, half:]
                    img[:, half] = 255
            from PIL import Image
            buf = io.BytesIO()
            Image.fromarray(img).save(buf, format="PNG")
            stats["ms"] = round(1e3 * (time.perf_counter() - t0), 1)
            stats["size"] = f"{img.shape[1]}x{img.shape[0]}"
            self.image = buf.getvalue()
            self.stats = stats

        def _view(self, f: Frame, ref: Optional[Frame], oracle: Optional[Frame], sc: Scene, m) -> np.ndarray:
            v = self.view
            if v not in VIEWS:
                raise ArgumentError(f"view: one of {', '.join(VIEWS)}, got {v!r}")
            if v == "color" or ref is None and v in ("reference", "uv_error", "flip", "shadow_error"):
                return f.to_srgb8()
            assert ref is not None or v in ("steps", "fetches", "lod")
            if v == "reference" and ref is not None:
                return ref.to_srgb8()
            if v == "uv_error" and ref is not None:
                e = metrics.uv_error(f, oracle if oracle is not None else ref, sc)["image"]
                return heat(e, 2.0, f.mask)
            if v == "flip" and ref is not None:
                try:
                    _, emap = metrics.flip(f, ref, image=True)
                    return heat(np.asarray(emap).reshape(f.mask.shape), 0.5, np.ones_like(f.mask))
                except ImportError:
                    return f.to_srgb8()
            if v == "steps":
                return heat(f.steps.astype(np.float64), max(float(f.steps.max()), 1.0), f.mask)
            if v == "fetches":
                return heat(f.fetches.astype(np.float64), max(float(f.fetches.max()), 1.0), f.mask)
            if v == "lod":
                return heat(f.lod, max(math.log2(max(sc.material.height.shape)), 1.0) if sc.material else 8.0, f.mask)
            # shadow_error: the method's visibility of the first directional light against the oracle's
            if oracle is None or not hasattr(m, "shadows"):
                return f.to_srgb8()
            vis = self._renderer.render_visibility(sc, m)
            d = np.abs(np.nan_to_num(vis.visibility) - np.nan_to_num(oracle.visibility))
            return heat(d, 1.0, f.mask & oracle.mask)

    a, e, d = _orbit(scene.camera)
    return Explorer(methods=names, views=list(VIEWS), azimuth=a, elevation=e, distance=d, size=int(size))
