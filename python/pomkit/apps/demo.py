"""`python -m pomkit demo`: a small gallery on bricks at a grazing angle (Flat, Bump, POM with hard
and soft shadows), the LOD tint view, and POM's uv error against the exact oracle."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

import pomkit as pk


def lod_tint(frame: pk.Frame, threshold: float) -> np.ndarray:
    """Colour tinted by the mip level: green where full POM runs, yellow in the blend band,
    red where bump mapping takes over; sRGB uint8."""
    base = frame.to_srgb8().astype(np.float32) / 255.0
    lod = np.nan_to_num(frame.lod, nan=0.0)
    t = np.clip(lod - (threshold - 1.0), 0.0, 1.0)[..., None]
    tint = np.where(lod[..., None] <= threshold - 1.0, [0.2, 1.0, 0.2], (1 - t) * np.array([1.0, 1.0, 0.1]) + t * np.array([1.0, 0.2, 0.2]))
    out = np.where(frame.mask[..., None], 0.55 * base + 0.45 * tint * base.mean(-1, keepdims=True) * 1.6, base)
    return (np.clip(out, 0, 1) * 255).astype(np.uint8)


def _label(img: np.ndarray, text: str) -> np.ndarray:
    from PIL import Image, ImageDraw
    im = Image.fromarray(img)
    d = ImageDraw.Draw(im)
    d.rectangle([0, 0, 8 + 7 * len(text), 16], fill=(0, 0, 0))
    d.text((4, 2), text, fill=(255, 255, 255))
    return np.asarray(im)


def brick_albedo(h: np.ndarray, seed: int = 1) -> np.ndarray:
    """sRGB uint8 albedo for a bricks height map: brick reds on the tops, grey mortar below."""
    rng = np.random.default_rng(seed)
    t = np.clip((h - 0.45) / 0.3, 0.0, 1.0)[..., None]
    grain = 1.0 + 0.08 * (rng.random(h.shape)[..., None] - 0.5)
    brick = np.array([170.0, 74.0, 52.0]) * (0.85 + 0.3 * (h[..., None] - 0.9))
    mortar = np.array([150.0, 146.0, 138.0])
    return np.clip((mortar * (1 - t) + brick * t) * grain, 0, 255).astype(np.uint8)


def demo_scene(size: int = 384, theta_deg: float = 72.0) -> pk.Scene:
    t = np.radians(theta_deg)
    h = pk.textures.bricks(512)
    return pk.Scene(
        mesh=pk.Mesh.plane(size=2.0),
        material=pk.Material(height=h, depth=0.06, tiling=2.0, albedo=brick_albedo(h)),
        camera=pk.Camera.look_at(eye=(0.0, 1.5 * np.cos(t), 1.5 * np.sin(t)), target=(0, 0, -0.1), up=(0, 1, 0),
                                 fov_y=40.0, width=size, height=size),
        lights=[pk.DirectionalLight(direction=(-0.6, -0.55, -0.3), irradiance=3.0, angular_diameter=4.0)],
        ambient=0.08,
    )


def objects_demo(r: "pk.Renderer", outdir: Path, size: int = 256) -> list[str]:
    """Several objects: a displaced sphere sunk into a displaced brick floor, casting its shadow
    onto the bricks (`pk.scenes.sunk_sphere`), rendered with Prism (exact) and POM, with the Mitsuba
    reference beside them when the reference extra is installed. Writes objects.png."""
    from PIL import Image

    scene = pk.scenes.sunk_sphere(size)
    tiles, lines = [], []
    # Prism without its own shadow march (on curved meshes it speckles; the cast map shadows the
    # sphere and the floor), POM with its hard self-shadows
    frames = {label: r.render(scene, m) for label, m in (("Prism (exact)", pk.Prism(exact=True, shadows="none")),
                                                          ("POM", pk.POM(shadows="hard")))}
    for label, f in frames.items():
        tiles.append(_label(f.to_srgb8(), f"{label}  {f.time_ms:.0f} ms"))
        lines.append(f"objects ({size}², cast shadows): {label} {f.time_ms:.1f} ms ({f.timing})")
        print("  " + lines[-1])
    frame = frames["Prism (exact)"]
    try:
        # the reference extra: Mitsuba (a cached render needs none) and FLIP
        from .. import reference as R
        ref = R.render_mitsuba(scene, spp=64)
        fl = pk.metrics.flip(frame, ref)
    except ImportError as e:
        print(f"  (no Mitsuba reference: {e})")
    else:
        tiles.append(_label(ref.to_srgb8(), "Mitsuba 64 spp"))
        both = frame.mask & ref.mask
        agree = float((frame.object == ref.object)[both].mean())
        lines.append(f"objects: Prism (exact) vs Mitsuba: FLIP {fl:.4f}, object agreement {agree:.4f}")
        print("  " + lines[-1])
    Image.fromarray(np.concatenate(tiles, 1)).save(outdir / "objects.png")
    return lines


def run_demo(out: str = "pomkit-out", size: int = 384) -> Path:
    from PIL import Image

    t0 = time.perf_counter()
    outdir = Path(out)
    outdir.mkdir(parents=True, exist_ok=True)
    r = pk.Renderer()
    print(f"pomkit {pk.__version__} on {r.info['name']} ({r.info['backend']})")
    scene = demo_scene(size)
    methods = {
        "flat": pk.Flat(),
        "bump": pk.Bump(),
        "pom_hard": pk.POM(shadows="hard", shadow_steps=16),
        "pom_soft": pk.POM(shadows="soft", shadow_steps=16),
    }
    tiles = []
    frames = {}
    for name, m in methods.items():
        r.render(scene, m)  # the first render of a method builds its pipeline: time the second
        f = r.render(scene, m)
        frames[name] = f
        f.save(outdir / f"{name}.png")
        tiles.append(_label(f.to_srgb8(), f"{name}  {f.time_ms:.1f} ms"))
        print(f"  {name:9s} {f.time_ms:8.2f} ms ({f.timing})  mean steps {f.steps[f.mask].mean():6.1f}")
    thr = 4.0
    tint = lod_tint(frames["pom_soft"], thr)
    Image.fromarray(tint).save(outdir / "lod_tint.png")
    tiles.append(_label(tint, "LOD: green POM, yellow blend, red bump"))
    gallery = np.concatenate([np.concatenate(tiles[:3], 1), np.concatenate(tiles[3:] + [np.zeros_like(tiles[0])] * (6 - len(tiles)), 1)], 0)
    Image.fromarray(gallery).save(outdir / "gallery.png")

    # accuracy against the CPU oracle (exact first hit against the bilinear field)
    small = scene.replace(camera=pk.Camera.look_at(scene.camera.eye, scene.camera.target, fov_y=40.0, width=160, height=160))
    oracle = pk.exact_uv(small)
    h, w = small.single.material.height.shape
    lines = []
    for label, m in (("POM (default: level-0 march)", pk.POM(shadows="none")),
                     ("POM, mip-filtered march", pk.POM(shadows="none", mip_filtering=True)),
                     ("ConeStep (conservative, exact)", pk.ConeStep()),
                     ("Exact (max-mip)", pk.Exact())):
        f = r.render(small, m)
        e = pk.metrics.uv_error(f, oracle, small)
        lines.append(f"{label} vs exact_uv at 72 deg: uv error p50 {e['p50']:.3f}, p95 {e['p95']:.3f} texels")
        print("  " + lines[-1])
    lines += objects_demo(r, outdir)
    line = "\n".join(lines)
    (outdir / "report.txt").write_text(
        "\n".join([f"adapter: {r.info['name']} ({r.info['backend']})"]
                  + [f"{k}: {v.time_ms:.2f} ms ({v.timing})" for k, v in frames.items()] + [line]) + "\n")
    print(f"wrote {outdir.resolve()}/: gallery.png, {', '.join(n + '.png' for n in methods)}, lod_tint.png, objects.png, "
          "report.txt")
    print(f"done in {time.perf_counter() - t0:.1f} s")
    return outdir
