"""Render the cross-backend scenes with the backend of this process (POMKIT_BACKEND) and save
every frame's AOVs to an .npz: `python tests/backend_frames.py out.npz`. Run once per backend
by tests/test_backends.py, which compares the files frame to frame."""

from __future__ import annotations

import dataclasses
import os
import sys
import tempfile

import numpy as np

os.environ.setdefault("XDG_RUNTIME_DIR", tempfile.mkdtemp(prefix="pomkit-xdg-"))

import pomkit as pk  # noqa: E402

SIZE = 64
LIGHT = pk.DirectionalLight((-0.4, -0.8, -0.3), 3.0, angular_diameter=2.0)


def scenes() -> dict:
    t = np.radians(60.0)
    plane = pk.Scene(mesh=pk.Mesh.plane(2.0), material=pk.Material(pk.textures.bricks(128), depth=0.08),
                     camera=pk.Camera.look_at((0.0, 1.6 * np.cos(t), 1.6 * np.sin(t)), (0, 0, 0), up=(0, 0, -1),
                                              fov_y=40.0, width=SIZE, height=SIZE),
                     lights=[LIGHT], ambient=0.1)
    torus = pk.Scene(mesh=pk.Mesh.torus(segments=32, tube_segments=16),
                     material=pk.Material(pk.textures.cobblestones(128), depth=0.05),
                     camera=pk.Camera.look_at((1.6, 1.5, 2.2), width=SIZE, height=SIZE), lights=[LIGHT], ambient=0.1)
    return {"plane": plane, "torus": torus}


def methods() -> dict:
    """Every method at its defaults, the mip-filtered marches, and each with exact filtering
    (the GL backend cannot filter float32: its "hardware" filtering is exact filtering)."""
    out: dict = {
        "Flat": pk.Flat(), "Bump": pk.Bump(), "Parallax": pk.Parallax(), "SteepParallax": pk.SteepParallax(),
        "POM": pk.POM(), "POM-mip": pk.POM(mip_filtering=True), "Relief": pk.Relief(), "Exact": pk.Exact(shadows="exact"),
        "ConeStep": pk.ConeStep(), "ConeStep-relaxed": pk.ConeStep(cones="relaxed", refine="binary"), "NCS": pk.NCS(),
        "Prism": pk.Prism(), "Prism-exact": pk.Prism(exact=True), "Tessellated": pk.Tessellated(),
        "POM-horizon-ao": pk.POM(shadows="horizon", ao_directions=4),
    }
    for name in ("Bump", "Parallax", "SteepParallax", "POM", "POM-mip", "Relief", "NCS", "Prism", "POM-horizon-ao"):
        out[name + "/exactf"] = dataclasses.replace(out[name], filtering="exact")
    return out


def main(path: str) -> None:
    r = pk.Renderer()
    arrays = {"_backend": np.array(r.info["backend"]), "_float32_filterable": np.array(r.info["float32_filterable"])}
    for sname, sc in scenes().items():
        for mname, m in methods().items():
            f = r.render(sc, m)
            for a in ("color", "uv", "depth", "mask", "steps", "flags"):
                arrays[f"{sname}|{mname}|{a}"] = getattr(f, a)
    np.savez_compressed(path, **arrays)


if __name__ == "__main__":
    main(sys.argv[1])
