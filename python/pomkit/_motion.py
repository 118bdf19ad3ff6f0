"""Stability in motion: each method's video along a camera path against the oracle's video
(`pk.oracle.image` at every frame, shaded as the method is), judged perceptually by
ColorVideoVDP (JOD, the Rust core's `colorvideovdp`) and measured geometrically (flicker,
swimming, the grazing slide), with the method's GPU time per frame. `pk.bench.motion` and
`pk.bench.camera_path`."""

from __future__ import annotations

import math
from typing import Iterable

import numpy as np

from . import _render, metrics, oracle
from ._errors import ArgumentError, ArgumentTypeError
from ._frame import Frame
from ._methods import Method, label
from ._scene import Camera, Scene

__all__ = ["PATHS", "camera_path", "motion"]

#: the camera paths: an orbit about the world's y axis through the target (pomkit's planes face
#: +y), a dolly of the view towards grazing (to 85° from the axis), and a pull-back that
#: minifies the map (the eye 6x farther at the end), each from the scene's own camera
PATHS: dict[str, str] = {
    "orbit": "the eye turns 24° about the y axis through the target",
    "dolly": "the eye tilts from its own angle to 85° from the y axis, at its distance",
    "pullback": "the eye moves away along its ray to 6x its distance (the map minified)",
}


def _rotate(v: np.ndarray, axis: np.ndarray, deg: float) -> np.ndarray:
    a = axis / np.linalg.norm(axis)
    t = math.radians(deg)
    return v * math.cos(t) + np.cross(a, v) * math.sin(t) + a * np.dot(a, v) * (1 - math.cos(t))


def camera_path(scene: Scene, path: str = "orbit", frames: int = 12) -> list[Scene]:
    """`frames` copies of `scene`, its camera moved along `path` (one of `PATHS`)."""
    if not isinstance(scene, Scene):
        raise ArgumentTypeError(f"scene: expected a pomkit.Scene, got {type(scene).__name__}")
    if path not in PATHS:
        raise ArgumentError(f"path: one of {', '.join(PATHS)}, got {path!r}")
    if not isinstance(frames, int) or frames < 2:
        raise ArgumentError(f"frames: at least 2 frames make a path, got {frames!r}")
    cam = scene.camera
    eye, target = np.array(cam.eye, np.float64), np.array(cam.target, np.float64)
    rel = eye - target
    y = np.array([0.0, 1.0, 0.0])
    out = []
    for k in range(frames):
        s = k / (frames - 1)
        if path == "orbit":
            e = target + _rotate(rel, y, -12.0 + 24.0 * s)
        elif path == "dolly":
            start = math.degrees(math.acos(np.clip(np.dot(rel, y) / np.linalg.norm(rel), -1, 1)))
            side = np.cross(y, rel)
            side = side if np.linalg.norm(side) > 1e-9 else np.array([1.0, 0.0, 0.0])
            e = target + _rotate(rel, side, (85.0 - start) * s)
        else:
            e = target + rel * (1.0 + 5.0 * s)
        out.append(scene.replace(camera=Camera(eye=tuple(e), target=cam.target, up=cam.up, fov_y=cam.fov_y,
                                               width=cam.width, height=cam.height)))
    return out


def _shadowed(method: Method) -> bool:
    return getattr(method, "shadows", "none") != "none"


def motion(methods: Iterable[Method], scene: Scene, path: str = "orbit", frames: int = 12, fps: float = 30.0,
           spp: int = 4, display: str = "standard_4k", renderer: _render.Renderer | None = None) -> list[dict]:
    """Render each method and the oracle's image along `path` (`camera_path`) and score each
    method's video against the oracle's, shaded as the method is (its self-shadows or none).

    Rows, one per method: method, label, path, frames, fps, spp, shading ("self-shadowed" or
    "unshadowed": what the method and its reference computed), and
    - jod: ColorVideoVDP's JOD of the video against the oracle's (10: no visible difference);
    - error_rms: the colour error's RMS over the frames (its spatial energy);
    - flicker: the RMS of the error's change from frame to frame (its temporal energy: 0 for an
      error that holds still, however large);
    - swimming: the mean |frame-to-frame change of the hit uv - the oracle's change| in texels;
    - slide: how far the hit's uv error moves per degree of view change, in texels a degree
      (NaN on the pull-back, whose view does not turn);
    - gpu_ms: the median time of the method's frames.
    The method renders at `spp` samples per pixel like the oracle, so aliasing is not scored."""
    methods = list(methods)
    for m in methods:
        if not isinstance(m, Method):
            raise ArgumentTypeError(f"methods: expected pomkit methods such as pomkit.POM(), got {type(m).__name__}")
    scenes = camera_path(scene, path, frames)
    r = renderer or _render.Renderer()
    texels = np.array(scene.single.material.height.shape[::-1], np.float64) * scene.single.material.tiling
    turn = [math.degrees(math.acos(np.clip(np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b)), -1, 1)))
            for a, b in ((np.subtract(p.camera.eye, p.camera.target), np.subtract(q.camera.eye, q.camera.target))
                         for p, q in zip(scenes, scenes[1:]))]
    # the oracle's frames and video, once per shading
    refs: dict[bool, tuple[list[Frame], np.ndarray]] = {}
    rows = []
    for m in methods:
        sh = _shadowed(m)
        if sh not in refs:
            frames_sh = [oracle.image(s, spp=spp, shadows=sh) for s in scenes]
            refs[sh] = (frames_sh, metrics._linear_video(frames_sh, "reference"))
        ref, vr = refs[sh]
        fs = [r.render(s, m, aovs=("color", "uv", "mask"), spp=spp) for s in scenes]
        vm = metrics._linear_video(fs, "frames")
        err = vm.astype(np.float64) - vr
        both = [f.mask & o.mask for f, o in zip(fs, ref)]
        swim, slide = [], []
        for k in range(1, frames):
            w = both[k] & both[k - 1]
            if not w.any():
                continue
            d = ((fs[k].uv - fs[k - 1].uv) - (ref[k].uv - ref[k - 1].uv))[w] * texels
            swim.append(float(np.linalg.norm(d - np.round(d / texels) * texels, axis=-1).mean()))
            if turn[k - 1] > 1e-3:  # degrees: the pull-back's view does not turn
                e0, e1 = (fs[k - 1].uv - ref[k - 1].uv)[w] * texels, (fs[k].uv - ref[k].uv)[w] * texels
                slide.append(float(np.linalg.norm(e1 - e0, axis=-1).mean()) / turn[k - 1])
        rows.append(dict(
            method=m.name, label=label(m), path=path, frames=frames, fps=fps, spp=spp,
            shading="self-shadowed" if sh else "unshadowed",
            jod=metrics.jod(vm, vr, fps=fps, display=display),
            error_rms=float(np.sqrt(np.mean(err ** 2))),
            flicker=float(np.sqrt(np.mean(np.diff(err, axis=0) ** 2))),
            swimming=float(np.mean(swim)) if swim else float("nan"),
            slide=float(np.mean(slide)) if slide else float("nan"),
            gpu_ms=float(np.median([f.time_ms or 0.0 for f in fs]))))
    return rows
