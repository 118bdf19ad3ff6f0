#!/usr/bin/env python
"""Render the demo page's Mitsuba references (needs the `reference` and `test` extras) into
python/pomkit/data/demo/: <name>.png (sRGB8, box-filtered, 64 spp) and <name>.json (the scene's
hash, so that the demo uses a reference only for the scene it was made for). First it writes the
asset the page loads: tests/zoo.py's rock as rock.glb (through trimesh, v up as trimesh holds it)
and its baked height map as rock_height.png (16 bits).

    .venv/bin/python scripts/make_demo_refs.py [name ...]   # planar, curved, asset (default: all)
"""

import json
import sys
from pathlib import Path

import numpy as np
from PIL import Image

from pomkit import reference as R
from pomkit._cache import scene_hash
from pomkit.apps.page import ASSET, ASSET_HEIGHT, asset_scene, curved_scene, planar_scene

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

# the repository's copy (the package's data, shipped in the wheel)
REFS = Path(__file__).resolve().parent.parent / "python" / "pomkit" / "data" / "demo"

SPP = 64



def write_asset() -> None:
    import trimesh
    import zoo

    mesh, h = zoo.rock()
    uv = np.stack([mesh.uvs[:, 0], 1.0 - mesh.uvs[:, 1].astype(np.float64)], 1)
    tm = trimesh.Trimesh(np.asarray(mesh.positions, np.float64), np.asarray(mesh.indices).reshape(-1, 3),
                         vertex_normals=np.asarray(mesh.normals, np.float64),
                         visual=trimesh.visual.TextureVisuals(uv=uv), process=False)
    ASSET.write_bytes(tm.export(file_type="glb"))
    Image.fromarray(np.round(np.clip(h, 0.0, 1.0) * 65535.0).astype(np.uint16)).save(ASSET_HEIGHT)


if __name__ == "__main__":
    REFS.mkdir(parents=True, exist_ok=True)
    write_asset()
    scenes = {"planar": planar_scene, "curved": curved_scene, "asset": asset_scene}
    for name in sys.argv[1:] or list(scenes):
        scene = scenes[name]()
        ref = R.render_mitsuba(scene, spp=SPP)
        Image.fromarray(ref.to_srgb8()).save(REFS / f"{name}.png")
        h = scene_hash(scene, kind="mitsuba", spp=SPP, seed=0, variant=None, resolution=2.0)
        (REFS / f"{name}.json").write_text(json.dumps({"hash": h, "spp": SPP}) + "\n")
        print(f"{name}: {REFS / (name + '.png')} ({np.asarray(ref.mask).mean():.2f} covered)")
