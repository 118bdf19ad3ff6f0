"""The demo page's loops: short videos of a method beside the oracle's image and their error,
side by side, along a camera path (`pk.bench.camera_path`), with the motion table of that path
(`pk.bench.motion`) beside each. WebM (VP9, by PyAV: the demo extra) in a looping, muted
<video>; without PyAV, an animated WebP (Pillow) in an <img>."""

from __future__ import annotations

import html
from pathlib import Path

import numpy as np

import pomkit as pk
from pomkit._heatmap import heat

FPS = 8
#: the error panel's scale: |Δ| of linear colour, per pixel, averaged over RGB
ERROR_MAX = 0.25


def encode(frames: list[np.ndarray], path: Path, fps: int = FPS) -> tuple[Path, str]:
    """Write `frames` (uint8 (H, W, 3), even sizes) as a looping video at `path` with the
    format's suffix: (its path, "video" or "img", how a page shows it)."""
    try:
        import av
    except ImportError:
        from PIL import Image
        p = path.with_suffix(".webp")
        ims = [Image.fromarray(f) for f in frames]
        ims[0].save(p, save_all=True, append_images=ims[1:], duration=int(1000 / fps), loop=0, lossless=True)
        return p, "img"
    p = path.with_suffix(".webm")
    with av.open(str(p), "w") as c:
        s = c.add_stream("libvpx-vp9", rate=fps)
        s.width, s.height, s.pix_fmt = frames[0].shape[1], frames[0].shape[0], "yuv420p"
        s.options = {"crf": "24", "b": "0"}
        for f in frames:
            for packet in s.encode(av.VideoFrame.from_ndarray(np.ascontiguousarray(f), format="rgb24")):
                c.mux(packet)
        for packet in s.encode():
            c.mux(packet)
    return p, "video"


def clip(r: pk.Renderer, scene: pk.Scene, method: pk.Method, path: str, frames: int, spp: int) -> list[np.ndarray]:
    """The loop's frames: the method | the oracle's image shaded as it is | their error."""
    shadows = getattr(method, "shadows", "none") != "none"
    out = []
    for s in pk.bench.camera_path(scene, path, frames):
        f = r.render(s, method, aovs=("color", "mask"), spp=spp)
        o = pk.oracle.image(s, spp=spp, shadows=shadows)
        err = np.abs(f.color - o.color).mean(-1)
        out.append(np.concatenate([f.to_srgb8(), o.to_srgb8(), heat(err, ERROR_MAX, f.mask | o.mask)], axis=1))
    return out


def section(r: pk.Renderer, outdir: Path, clips: list[tuple[str, pk.Scene, str, list[pk.Method]]],
            frames: int = 12, spp: int = 1) -> str:
    """The page's "In motion" section: per (name, scene, path, methods), a loop of the first
    method and the motion table of all of them along that path."""
    parts = [f"<h2>In motion</h2><p>Each loop: the method | <code>pk.oracle.image</code> shaded as the method is | "
             f"their error (0–{ERROR_MAX:g} linear), {frames} frames at {spp} spp along a camera path "
             "(<code>pk.bench.camera_path</code>). Beside it, <code>pk.bench.motion</code> on that path: "
             "ColorVideoVDP JOD against the oracle's video (10: no visible difference), flicker (the error's "
             "change frame to frame), swimming (texels) and GPU ms. docs/tables/motion.md holds the full table.</p>"]
    for name, scene, path, methods in clips:
        w, h = scene.camera.width, scene.camera.height
        if w % 2 or h % 2:
            raise ValueError(f"clips: {name}'s frame is {w}x{h}; the video needs even sizes")
        file, how = encode(clip(r, scene, methods[0], path, frames, spp), outdir / f"loop_{name}_{path}")
        media = (f'<video src="{file.name}" autoplay loop muted playsinline width="{3 * w}" height="{h}"></video>'
                 if how == "video" else f'<img src="{file.name}" width="{3 * w}" height="{h}" style="max-width:none">')
        rows = pk.bench.motion(methods, scene, path, frames=frames, spp=spp, renderer=r)
        table = "".join(
            f"<tr><td>{html.escape(x['label'])}</td><td>{x['jod']:.2f}</td><td>{x['flicker']:.4f}</td>"
            f"<td>{x['swimming']:.3f}</td><td>{x['gpu_ms']:.2f}</td></tr>" for x in rows)
        parts.append(f"<h3>{html.escape(name)}, {html.escape(path)}: {html.escape(pk.bench.PATHS[path])}</h3>"
                     f"<table><tr><td>{media}<br><small>{html.escape(rows[0]['label'])} | oracle | error</small></td>"
                     "<td><table><tr><th>method</th><th>JOD</th><th>flicker</th><th>swimming</th><th>GPU ms</th></tr>"
                     f"{table}</table></td></tr></table>")
    return "".join(parts)
