"""A file loads as engines load it (issue 73 §2): a primitive without uvs is kept and drawn
undisplaced, unusable normals are repaired by default, and the file's base colour is the albedo."""

from __future__ import annotations

import base64
import io
import json
import warnings

import numpy as np
import pytest
from PIL import Image

import pomkit as pk


def _png(rgb: np.ndarray) -> str:
    buf = io.BytesIO()
    Image.fromarray(rgb).save(buf, format="PNG")
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode()


def _file(path, *, texture=None, factor=(1.0, 1.0, 1.0, 1.0), wrap=10497, second_without_uvs=True, normals=None):
    """A .gltf of one node: a quad with uvs and material 0 (baseColorFactor `factor`, and
    `texture` as its embedded PNG with wrap mode `wrap`), and beside it, in the same mesh, a
    triangle without TEXCOORD_0 that uses material 1 (a factor only)."""
    p = np.array([[-1, 0, -1], [1, 0, -1], [-1, 0, 1], [1, 0, 1]], np.float32)
    n = np.array(normals if normals is not None else [[0, 1, 0]] * 4, np.float32)
    uv = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], np.float32)
    idx = np.array([0, 2, 1, 1, 2, 3], np.uint32)
    tp = np.array([[0, 1, 0], [0, 1, 1], [1, 1, 0]], np.float32)
    tn = np.array([[1, 0, 0]] * 3, np.float32)
    arrays = [(p, "VEC3", 5126), (n, "VEC3", 5126), (uv, "VEC2", 5126), (idx, "SCALAR", 5125), (tp, "VEC3", 5126), (tn, "VEC3", 5126)]
    blob, views, acc = b"", [], []
    for a, kind, ct in arrays:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": a.nbytes})
        extra = {"min": a.min(0).tolist(), "max": a.max(0).tolist()} if kind == "VEC3" and a is not n and a is not tn else {}
        acc.append({"bufferView": len(views) - 1, "componentType": ct, "count": len(a), "type": kind, **extra})
        blob += a.tobytes()
    prims = [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]
    if second_without_uvs:
        prims.append({"attributes": {"POSITION": 4, "NORMAL": 5}, "material": 1})
    mat0 = {"pbrMetallicRoughness": {"baseColorFactor": list(factor)}, "name": "painted"}
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "house"}],
        "meshes": [{"primitives": prims}],
        "materials": [mat0, {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.8, 1.0]}, "name": "glass"}],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": views, "accessors": acc,
    }
    if texture is not None:
        doc["images"] = [{"uri": _png(texture)}]
        doc["samplers"] = [{"wrapS": wrap, "wrapT": 10497}]
        doc["textures"] = [{"source": 0, "sampler": 0}]
        mat0["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    path.write_text(json.dumps(doc))
    return path


def _texture():
    rng = np.random.default_rng(3)
    return rng.integers(0, 256, (8, 16, 3), dtype=np.uint8)


def test_base_color_texture_times_factor_is_the_albedo(tmp_path):
    tex = _texture()
    path = _file(tmp_path / "t.gltf", texture=tex, factor=(0.5, 1.0, 0.25, 1.0))
    with pytest.warns(RuntimeWarning, match="1 triangles have no TEXCOORD_0"):
        objs = pk.load_objects(path, pk.Material(pk.textures.constant(16, 0.5), depth=0.05))
    assert len(objs) == 2
    want = pk._color.srgb_to_linear(tex) * np.array([0.5, 1.0, 0.25], np.float32)
    np.testing.assert_allclose(objs[0].material.albedo, want, rtol=1e-6, atol=1e-7)
    # the uv-less primitive: its own object, undisplaced, with its material's factor
    assert objs[0].material.depth == 0.05 and objs[1].material.depth == 0.0
    np.testing.assert_allclose(objs[1].material.albedo[0, 0], [0.2, 0.4, 0.8], rtol=1e-6)
    # the caller's albedo wins
    own = np.full((4, 4, 3), 0.3, np.float32)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        objs = pk.load_objects(path, pk.Material(pk.textures.constant(16, 0.5), depth=0.05, albedo=own))
    assert all(np.array_equal(o.material.albedo, own) for o in objs)


def test_the_albedo_reaches_the_frame(tmp_path):
    """A red texture renders red with Flat and with the oracle's image: the file's colour is
    what the frame shows, not grey."""
    tex = np.zeros((8, 8, 3), np.uint8)
    tex[..., 0] = 255
    path = _file(tmp_path / "red.gltf", texture=tex, second_without_uvs=False)
    obj, = pk.load_objects(path, pk.Material(pk.textures.constant(16, 1.0), depth=0.02))
    s = pk.Scene(objects=[obj], camera=pk.Camera.look_at((0, 2.0, 0.5), (0, 0, 0), fov_y=40, width=32, height=32),
                 lights=[pk.DirectionalLight((0, -1, 0), 3.0)])
    f = pk.Renderer().render(s, pk.Flat())
    ref = pk.oracle.image(s, spp=1, cache=False)
    for c in (f.color[f.mask], ref.color[ref.mask]):
        assert c[:, 0].min() > 0.4 and c[:, 1:].max() < 1e-6


def test_a_clamping_sampler_is_reported(tmp_path):
    path = _file(tmp_path / "c.gltf", texture=_texture(), wrap=33071, second_without_uvs=False)
    with pytest.warns(RuntimeWarning, match="wraps"):
        pk.load_objects(path, pk.Material(pk.textures.constant(16, 0.5), depth=0.05))


def test_load_mesh_keeps_the_displaceable_part_and_names_the_rest(tmp_path):
    path = _file(tmp_path / "m.gltf")
    with pytest.warns(RuntimeWarning, match=r"mesh 'house', primitive\(s\) 1: 1 triangles have no TEXCOORD_0.*left out"):
        m = pk.load_mesh(path)
    assert len(m.indices) == 6


def test_a_file_without_any_uvs_loads_with_projected_uvs(tmp_path):
    """Every primitive without uvs: load_mesh gives the whole mesh, each triangle its own chart,
    and says so; check_asset finds no degenerate uv triangle in it."""
    path = _file(tmp_path / "n.gltf")
    doc = json.loads(path.read_text())
    del doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"]
    path.write_text(json.dumps(doc))
    with pytest.warns(RuntimeWarning, match="projected per triangle"):
        m = pk.load_mesh(path)
    assert len(m.indices) == 9 and len(m.positions) == 9
    assert pk.check_asset(m).degenerate_uv_triangles == 0


def test_unusable_normals_are_repaired_by_default(tmp_path):
    bad = [[0, 1, 0], [0, 0, 0], [float("nan"), 0, 0], [0, 1, 0]]
    path = _file(tmp_path / "z.gltf", normals=bad, second_without_uvs=False)
    with pytest.warns(RuntimeWarning, match="2 unusable normal"):
        m = pk.load_mesh(path)
    np.testing.assert_allclose(m.normals, [[0, 1, 0]] * 4, atol=1e-6)
    with pytest.raises(ValueError, match="vertex 1 has an unusable normal"):
        pk.load_mesh(path, normals="file")
