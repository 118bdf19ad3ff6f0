"""A fuzzer over meshes and files, not only over height maps: the defects real assets carry
(zero, NaN and flipped normals; degenerate and duplicate triangles; T-junctions; non-manifold
edges; mirrored charts; charts without gutters; huge and tiny scales; depth 0 and depths past the
curvature radius) and glTF node graphs with cycles and deep nesting.

For any such input every call returns in bounded time, with a frame or a clear pk.Error that
names the argument; where `check_asset` finds none of the defects that change the surface, the
methods that end the surface where the mesh does (Tessellated, Prism, NCS) cover the oracle's
pixels to within the outline band. `make test` runs POMKIT_ASSET_FUZZ_EXAMPLES (default 25)
examples; set it higher to search further (with POMKIT_HYPOTHESIS_RANDOM=1 for fresh ones)."""

from __future__ import annotations

import json
import os
import time

import numpy as np
from hypothesis import HealthCheck, event, given, note, settings
from hypothesis import strategies as st
from scipy import ndimage

import pomkit as pk
from test_surface import _gltf, _quad

EXAMPLES = int(os.environ.get("POMKIT_ASSET_FUZZ_EXAMPLES", "25"))
#: seconds any one call may take on this machine's llvmpipe at the fuzzer's 32^2 (measured: under 2)
BOUND_S = 30.0
DEFECTS = ("zero_normals", "nan_normals", "flipped_normals", "degenerate", "duplicate", "t_junction",
           "nonmanifold", "mirrored", "no_gutter")


def _base(kind: str):
    m = {"plane": lambda: pk.Mesh.plane(segments=3), "sphere": lambda: pk.Mesh.sphere(segments=12, rings=6),
         "torus": lambda: pk.Mesh.torus(segments=12, tube_segments=6), "cube": lambda: pk.Mesh.cube()}[kind]()
    return (np.array(m.positions, np.float64), np.array(m.normals, np.float64), np.array(m.uvs, np.float64),
            np.array(m.indices, np.int64).reshape(-1, 3))


def _defect(name: str, p, n, uv, tri, rng):
    """Apply one defect to the arrays; returns them."""
    k = rng.integers(len(tri))
    if name == "zero_normals":
        n[tri[k]] = 0.0
    elif name == "nan_normals":
        n[tri[k][0]] = np.nan
    elif name == "flipped_normals":
        n[tri[k]] = -n[tri[k]]
    elif name == "degenerate":
        a = tri[k]
        tri = np.vstack([tri, [a[0], a[0], a[1]]])
    elif name == "duplicate":
        tri = np.vstack([tri, tri[k]])
    elif name == "t_junction":
        a, b, c = tri[k]
        m = len(p)
        p = np.vstack([p, 0.5 * (p[a] + p[b])])
        n = np.vstack([n, n[a] + n[b]])
        uv = np.vstack([uv, 0.5 * (uv[a] + uv[b])])
        tri = np.vstack([np.delete(tri, k, 0), [a, m, c], [m, b, c]])
    elif name == "nonmanifold":
        a, b, _ = tri[k]
        m = len(p)
        p = np.vstack([p, p[a] + n[a] * 0.1 + 0.05])
        n = np.vstack([n, n[a]])
        uv = np.vstack([uv, uv[a] + 0.01])
        tri = np.vstack([tri, [a, b, m]])
    elif name == "mirrored":
        half = tri[: len(tri) // 2].reshape(-1)
        m = len(p)
        p, n = np.vstack([p, p[half]]), np.vstack([n, n[half]])
        uv = np.vstack([uv, np.c_[1.0 - uv[half, 0], uv[half, 1]]])
        tri = np.vstack([np.arange(m, m + len(half)).reshape(-1, 3), tri[len(tri) // 2:]])
    elif name == "no_gutter":
        uv = np.clip(uv * 1.02 - 0.01, 0.0, 1.0)
    return p, n, uv, tri


@st.composite
def assets(draw):
    kind = draw(st.sampled_from(["plane", "sphere", "torus", "cube"]))
    defects = draw(st.lists(st.sampled_from(DEFECTS), max_size=3, unique=True))
    scale = 10.0 ** draw(st.sampled_from([-4, -1, 0, 0, 2, 4]))
    depth = draw(st.sampled_from([0.0, 0.02, 0.1, 1.5]))  # 1.5: past the sphere's and torus's radii
    seed = draw(st.integers(0, 2 ** 16))
    mode = draw(st.sampled_from(["file", "repair", "recompute"]))
    method = draw(st.sampled_from(["POM", "NCS", "CurvedRelief", "Prism", "Tessellated"]))
    return kind, tuple(defects), scale, depth, seed, mode, method


def _timed(f, *a, **k):
    t = time.perf_counter()
    out = f(*a, **k)
    assert time.perf_counter() - t < BOUND_S, f"{f.__name__} took {time.perf_counter() - t:.1f} s"
    return out


def _clean(r) -> bool:
    """check_asset finds nothing that changes the surface the methods see (degenerate triangles,
    as at a sphere's poles, and hard edges have their rules)."""
    return not (r.nonmanifold_edges or r.normals_flipped or r.normals_off_faces or r.folded_prisms
                or r.mirror_shared_edges)


@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
@given(a=assets())
def test_any_defective_asset_answers_with_a_frame_or_a_clear_error(renderer, a):
    kind, defects, scale, depth, seed, mode, method = a
    note(f"{kind} {defects} scale={scale} depth={depth} normals={mode} {method}")
    rng = np.random.default_rng(seed)
    p, n, uv, tri = _base(kind)
    for d in defects:
        p, n, uv, tri = _defect(d, p, n, uv, tri, rng)
    p = p * scale
    try:
        with _quiet():
            mesh = _timed(pk.Mesh.from_arrays, p, n, uv, tri, normals_mode=mode)
    except pk.Error as e:
        assert str(e).split(":")[0] in ("normals", "uvs", "indices", "positions", "mesh", "tangents"), str(e)
        event(f"mesh refused: {str(e).split(':')[0]}")
        return
    h = pk.textures.bricks(32)
    mat = pk.Material(height=h, depth=depth * scale)
    r = _timed(pk.check_asset, mesh, mat)
    c = 0.5 * (p.min(0) + p.max(0))
    rad = 0.5 * float(np.linalg.norm(p.max(0) - p.min(0)))
    cam = pk.Camera.look_at(eye=tuple(c + rad * np.array([0.9, 1.6, 2.2])), target=tuple(c), fov_y=45.0, width=32, height=32)
    sc = pk.Scene(mesh=mesh, material=mat, camera=cam)
    m = {"POM": pk.POM(), "NCS": pk.NCS(), "CurvedRelief": pk.CurvedRelief(), "Prism": pk.Prism(),
         "Tessellated": pk.Tessellated(texels_per_vertex=2)}[method]
    try:
        with _quiet():  # the render-time warnings of folds and flipped normals are expected here
            f = _timed(renderer.render, sc, m, aovs=("mask", "uv"))
        o = _timed(pk.oracle.hits, sc)
    except pk.Error as e:
        # a refusal must name what to change
        assert ":" in str(e) and len(str(e)) > 20, str(e)
        event(f"render refused: {str(e).split(':')[0]}")
        return
    event(f"rendered ({'clean' if _clean(r) else 'reported'})")
    assert np.isfinite(f.uv[f.mask]).all()
    if _clean(r) and method in ("Tessellated", "Prism", "NCS") and depth * scale > 0 and depth < 1.0:
        band = ndimage.binary_dilation(o.mask, iterations=2) & ~ndimage.binary_erosion(o.mask, iterations=2)
        event("coverage checked against the oracle")
        off = (f.mask != o.mask) & ~band
        assert off.sum() <= 2, f"{method}: {int(off.sum())} pixels off the oracle's coverage beyond the outline band"


class _quiet:
    def __enter__(self):
        import warnings
        self._w = warnings.catch_warnings()
        self._w.__enter__()
        warnings.simplefilter("ignore")

    def __exit__(self, *e):
        self._w.__exit__(*e)


@st.composite
def node_graphs(draw):
    """glTF node lists: random children (cycles, self-loops, shared children), or deep chains."""
    kind = draw(st.sampled_from(["random", "chain", "self"]))
    if kind == "chain":
        depth = draw(st.sampled_from([2, 64, 4096]))
        nodes = [{"children": [i + 1]} for i in range(depth - 1)] + [{"mesh": 0}]
        if draw(st.booleans()):
            nodes[-1]["children"] = [0]  # the chain closes into a cycle
        return nodes
    if kind == "self":
        return [{"mesh": 0, "children": [0]}]
    count = draw(st.integers(1, 12))
    nodes = []
    for i in range(count):
        kids = draw(st.lists(st.integers(0, count - 1), max_size=3, unique=True))
        node = {"children": kids} if kids else {}
        if draw(st.booleans()) or i == 0:
            node["mesh"] = 0
        nodes.append(node)
    return nodes


@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
@given(nodes=node_graphs())
def test_any_node_graph_loads_or_is_refused_at_once(tmp_path_factory, nodes):
    note(json.dumps(nodes)[:300])
    p, n, uv, i = _quad()
    path = _gltf(tmp_path_factory.mktemp("g") / "graph.gltf", p, n, uv, i, nodes=nodes)
    t = time.perf_counter()
    try:
        mesh = pk.load_mesh(path)
        assert mesh.indices.size % 3 == 0
    except pk.Error as e:
        assert str(e).startswith("path:") and ("node" in str(e) or "mesh" in str(e)), str(e)
    assert time.perf_counter() - t < 5.0
