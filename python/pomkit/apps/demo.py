"""`python -m pomkit demo`: the page of every method (apps/page.py) and the several-objects scene."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

import pomkit as pk


def _label(img: np.ndarray, text: str) -> np.ndarray:
    from PIL import Image, ImageDraw
    im = Image.fromarray(img)
    d = ImageDraw.Draw(im)
    d.rectangle([0, 0, 8 + 7 * len(text), 16], fill=(0, 0, 0))
    d.text((4, 2), text, fill=(255, 255, 255))
    return np.asarray(im)


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
        ref = R.render_mitsuba(scene, spp=16)  # matched: Mitsuba's ray casts shaded by the definition
        fl = pk.metrics.flip(frame, ref)
    except ImportError as e:
        print(f"  (no Mitsuba reference: {e})")
    else:
        tiles.append(_label(ref.to_srgb8(), "Mitsuba (matched) 16 spp"))
        both = frame.mask & ref.mask
        agree = float((frame.object == ref.object)[both].mean())
        lines.append(f"objects: Prism (exact) vs Mitsuba: FLIP {fl:.4f}, object agreement {agree:.4f}")
        print("  " + lines[-1])
    Image.fromarray(np.concatenate(tiles, 1)).save(outdir / "objects.png")
    return lines


def run_demo(out: str = "pomkit-out", size: int = 256) -> Path:
    """The page (index.html: every method on a plane and a torus beside Mitsuba, heat maps, the
    speed/accuracy chart, a pk.choose answer, the LOD view; apps/page.py), objects.png and
    report.txt."""
    from .page import run_page

    t0 = time.perf_counter()
    outdir = Path(out)
    outdir.mkdir(parents=True, exist_ok=True)
    r = pk.Renderer()
    print(f"pomkit {pk.__version__} on {r.info['name']} ({r.info['backend']})")
    page = run_page(outdir, size)
    lines = objects_demo(r, outdir)
    (outdir / "report.txt").write_text("\n".join([f"adapter: {r.info['name']} ({r.info['backend']})"] + lines) + "\n")
    print(f"wrote {page.resolve()} (open it in a browser), objects.png, report.txt")
    print(f"done in {time.perf_counter() - t0:.1f} s")
    return outdir
