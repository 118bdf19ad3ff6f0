#!/usr/bin/env python
"""Render the demo page's Mitsuba references (needs the `reference` extra) into
python/pomkit/data/demo/: <name>.png (sRGB8, box-filtered, 64 spp) and <name>.json (the scene's
hash, so that the demo uses a reference only for the scene it was made for).

    .venv/bin/python scripts/make_demo_refs.py
"""

import json
from pathlib import Path

import numpy as np
from PIL import Image

from pomkit import reference as R
from pomkit._cache import scene_hash
from pomkit.apps.page import curved_scene, planar_scene

# the repository's copy (the package's data, shipped in the wheel)
REFS = Path(__file__).resolve().parent.parent / "python" / "pomkit" / "data" / "demo"

SPP = 64

if __name__ == "__main__":
    REFS.mkdir(parents=True, exist_ok=True)
    for name, scene in (("planar", planar_scene()), ("curved", curved_scene())):
        ref = R.render_mitsuba(scene, spp=SPP)
        Image.fromarray(ref.to_srgb8()).save(REFS / f"{name}.png")
        h = scene_hash(scene, kind="mitsuba", spp=SPP, seed=0, variant=None, resolution=2.0)
        (REFS / f"{name}.json").write_text(json.dumps({"hash": h, "spp": SPP}) + "\n")
        print(f"{name}: {REFS / (name + '.png')} ({np.asarray(ref.mask).mean():.2f} covered)")
