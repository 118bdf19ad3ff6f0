"""Golden frames: every built-in method (and its option variants) on small stability scenes,
saved once from a known-good build and compared against by tests/test_golden.py.

They pin the renderer's arithmetic across refactors (issue 10: "frames bit-identical to before
the change"). Regenerate only on purpose, with the reason in the commit message:

    .venv/bin/python tests/golden.py        # writes tests/data/golden.npz
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

import numpy as np

os.environ.setdefault("XDG_RUNTIME_DIR", tempfile.mkdtemp(prefix="pomkit-xdg-"))

import pomkit as pk  # noqa: E402

PATH = Path(__file__).parent / "data" / "golden.npz"
SIZE = 48
MAP = 128
ANGLES = (0.0, 60.0, 85.0)


# Tessellated's shadow-map size when the frames were saved (the default became 1024 with issue 13)
SHADOW_MAP = 2048

def _plane(height, theta):
    return pk.scenes.tilted_plane(height, theta, SIZE, ambient=0.1,
                                  lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0, 2.0, shadow_map_size=SHADOW_MAP)])


def _curved(mesh):
    return pk.Scene(
        mesh=mesh, material=pk.Material(pk.textures.bricks(MAP), depth=0.06),
        camera=pk.Camera.look_at((1.6, 1.5, 2.2), width=SIZE, height=SIZE),
        lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0, 2.0, shadow_map_size=SHADOW_MAP)], ambient=0.1)


def planar_methods():
    return {
        "flat": pk.Flat(), "bump": pk.Bump(), "bump_exactf": pk.Bump(filtering="exact"),
        # the mip-filtered field these were saved with (level 0 became the default with issue 26)
        "parallax": pk.Parallax(mip_filtering=True), "parallax_nolimit": pk.Parallax(offset_limiting=False, scale=0.8, bias=0.01, mip_filtering=True),
        "steep": pk.SteepParallax(mip_filtering=True), "steep_hard": pk.SteepParallax(steps=12, shadows="hard", mip_filtering=True),
        "pom": pk.POM(mip_filtering=True), "pom_none": pk.POM(shadows="none", mip_filtering=True), "pom_fixed": pk.POM(adaptive=False, min_steps=8, max_steps=8, shadows="hard", mip_filtering=True),
        "pom_level0": pk.POM(mip_filtering=False, shadows="horizon", ao_directions=4), "pom_exactf": pk.POM(filtering="exact", mip_filtering=True),
        "relief": pk.Relief(mip_filtering=True), "relief_bias": pk.Relief(depth_bias=True, shadows="soft", mip_filtering=True),
        "exact": pk.Exact(), "exact_shadow": pk.Exact(shadows="exact", ao_directions=8),
        "tess": pk.Tessellated(), "tess_none": pk.Tessellated(shadows="none"),
        # the full shell these were saved with (the tight shell became the default with issue 33)
        "prism": pk.Prism(tight=False), "prism_exact": pk.Prism(exact=True, shadows="none", tight=False),
        "prism_tight": pk.Prism(), "prism_tight_exact": pk.Prism(exact=True, shadows="none"),
    }


def curved_methods():
    return {
        "pom": pk.POM(mip_filtering=True), "ncs": pk.NCS(), "ncs_c1": pk.NCS(step_scale=1.0, max_steps=32, shadows="hard"),
        "prism": pk.Prism(tight=False), "prism_out": pk.Prism(outward=True, shadows="horizon", tight=False),
        "prism_exact": pk.Prism(exact=True, tight=False),
        "prism_tight": pk.Prism(), "prism_tight_out": pk.Prism(outward=True, shadows="horizon"),
        "prism_tight_exact": pk.Prism(exact=True),
        "tess": pk.Tessellated(),
    }


def cases():
    """(key, scene, method) for every golden frame."""
    out = []
    for tex in ("bricks", "spikes"):
        h = pk.textures.ALL[tex](MAP)
        for a in ANGLES:
            sc = _plane(h, a)
            for name, m in planar_methods().items():
                out.append((f"{tex}-{a:g}-{name}", sc, m))
    for mesh in ("torus", "sphere"):
        sc = _curved(getattr(pk.Mesh, mesh)())
        for name, m in curved_methods().items():
            out.append((f"{mesh}-{name}", sc, m))
    return out


AOVS = ("color", "uv", "depth", "mask", "steps", "lod", "flags")


def adapter(r) -> str:
    """The adapter and backend a frame is rendered on, as the pins record it (`meta/adapter`):
    bit-identical frames hold on that adapter and driver only."""
    return f"{r.info['name']} ({r.info['backend']}; {r.info['driver']})"


def main(only: str = "", path: Path = PATH) -> None:
    """Save the golden frames; with `only`, re-pin just the frames whose key contains it (a
    method whose algorithm changed by design) and keep the others as they are. With another
    `path`, every frame as this adapter renders it, for comparing adapters; the pins stay."""
    r = pk.Renderer()
    arrays = dict(np.load(path)) if only else {}
    here = adapter(r)
    if only and str(arrays.get("meta/adapter")) != here:
        sys.exit(f"the frames were pinned on {arrays.get('meta/adapter')}; this is {here}: re-pin them all there, or all here")
    arrays["meta/adapter"] = np.array(here)
    for key, sc, m in cases():
        if only not in key:
            continue
        f = r.render(sc, m)
        for a in AOVS:
            arrays[f"{key}/{a}"] = getattr(f, a)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(path, **arrays)
    print(f"wrote {(len(arrays) - 1) // len(AOVS)} frames to {path} ({path.stat().st_size / 1e6:.1f} MB)", file=sys.stderr)


if __name__ == "__main__":
    # python golden.py [substring]: re-pin; python golden.py --out FILE: this adapter's frames to FILE
    if sys.argv[1:2] == ["--out"]:
        main("", Path(sys.argv[2]))
    else:
        main(sys.argv[1] if len(sys.argv) > 1 else "")
