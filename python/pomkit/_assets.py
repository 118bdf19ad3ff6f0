"""Users' assets: glTF 2.0 loaded as the file says (read by the core), other formats through
trimesh, and the asset report.

`load_mesh(path)` gives one `Mesh`; `load_objects(path, material)` one `Object` per primitive and
material of each mesh node, with its world transform and the file's base colour. glTF keeps positions, normals, TEXCOORD_0 and TANGENT as stored (glTF's uv
origin is pomkit's; a file's tangent handedness w becomes pomkit's, -w); a file without tangents
gets MikkTSpace ones, as the glTF specification asks.
"""

from __future__ import annotations

from ._errors import ArgumentError, ArgumentTypeError, MissingExtraError
import os
import warnings
import dataclasses
from dataclasses import field
from typing import TYPE_CHECKING, Any, Union

import numpy as np

from . import _core
from ._scene import Material, Mesh, NormalsMode, Object

__all__ = ["load_mesh", "load_objects", "check_asset", "AssetReport"]

PathLike = Union[str, "os.PathLike[str]"]
GLTF = (".gltf", ".glb")


def _path(path: PathLike) -> str:
    if not isinstance(path, (str, os.PathLike)):
        raise ArgumentTypeError(f"path: expected a file path, got {type(path).__name__}")
    p = os.fspath(path)
    if not os.path.isfile(p):
        raise ArgumentError(f"path: {p}: no such file")
    return p


def _read(path: str, normals: NormalsMode = "repair") -> "_core.GltfFile":
    """The core's reading of a glTF file (`_core.load_gltf`), with the warnings a user needs: the
    normals repaired, the primitives left out or drawn undisplaced, the textures not read."""
    if normals not in _core.NORMALS_MODES:
        raise ArgumentError(f"normals: expected one of {', '.join(map(repr, _core.NORMALS_MODES))}, got {normals!r}")
    f = _core.load_gltf(path, normals)
    replaced = sum(p["replaced_normals"] for n in f["nodes"] for p in n["parts"])
    if replaced and normals == "repair":
        warnings.warn(f"{path}: {replaced} unusable normal(s) recomputed from the faces (normals=\"repair\")",
                      RuntimeWarning, stacklevel=3)
    for n in f["nodes"]:
        if n["skipped"]:
            what = ", ".join(f"primitive {i} ({why})" for i, why in n["skipped"])
            warnings.warn(f"{path}: mesh {n['name']!r}: {what} left out: no surface to draw",
                          RuntimeWarning, stacklevel=3)
    for mi, why in f["texture_errors"]:
        warnings.warn(f"{path}: material {mi}: baseColorTexture not read ({why}); its baseColorFactor alone is the albedo",
                      RuntimeWarning, stacklevel=3)
    return f


def _uvless(path: str, node: "_core.GltfNode", part: "_core.GltfPart", what: str) -> None:
    tris = len(part["indices"]) // 3
    prims = ", ".join(map(str, part["primitives"]))
    warnings.warn(f"{path}: mesh {node['name']!r}, primitive(s) {prims}: {tris} triangles have no TEXCOORD_0 (or only "
                  f"degenerate uvs), so no parameterisation to displace: {what}", RuntimeWarning, stacklevel=3)


def _transform(node: "_core.GltfNode") -> np.ndarray:
    return np.asarray(node["transform"], np.float64).reshape(4, 4)


def _merge(meshes: "list[tuple[Any, np.ndarray]]") -> dict:
    """Several parts' arrays in one space (each one's transform applied)."""
    pos, nrm, uv, tan, idx = [], [], [], [], []
    base = 0
    for a, m in meshes:
        lin = m[:3, :3]
        p = np.asarray(a["positions"], np.float64) @ lin.T + m[:3, 3]
        n = np.asarray(a["normals"], np.float64) @ np.linalg.inv(lin)
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
        t = np.asarray(a["tangents"], np.float64).copy()
        t[:, :3] = t[:, :3] @ lin.T
        t[:, :3] /= np.maximum(np.linalg.norm(t[:, :3], axis=1, keepdims=True), 1e-30)
        if np.linalg.det(lin) < 0:  # a mirroring transform flips the handedness
            t[:, 3] = -t[:, 3]
        pos.append(p)
        nrm.append(n)
        uv.append(np.asarray(a["uvs"]))
        tan.append(t)
        idx.append(np.asarray(a["indices"], np.int64) + base)
        base += len(p)
    return dict(positions=np.concatenate(pos), normals=np.concatenate(nrm), uvs=np.concatenate(uv),
                tangents=np.concatenate(tan), indices=np.concatenate(idx))


def load_mesh(path: PathLike, *, tangents: Any = None, normals: NormalsMode = "repair") -> Mesh:
    """One mesh from a file. glTF 2.0 (.gltf, .glb) is read by pomkit's core as the file says:
    positions, normals, TEXCOORD_0 and TANGENT bit for bit (the tangent's w as pomkit's
    handedness, minus glTF's), MikkTSpace tangents where the file has none, flat normals where it
    has none (as glTF asks). A file of several mesh nodes and primitives is merged into one mesh
    in the scene's space (their transforms applied; `load_objects` keeps them apart, with their
    materials). A primitive without TEXCOORD_0 has nothing to displace: one mesh has one
    material, so it is left out here with a warning that names it (`load_objects` keeps it,
    drawn undisplaced); points and lines are left out too. Other formats (OBJ, PLY, ...) load
    through trimesh (`Mesh.from_trimesh`, v flipped to pomkit's convention).

    tangents: None keeps the file's (or MikkTSpace); "mikktspace", "pomkit" or an (n, 4) array
    replace them (see `Mesh.from_arrays`).
    normals: "repair" (the default, as engines' importers do: an unusable normal, NaN, Inf or zero
    length, defines no surface, so only those are recomputed from the faces, with a warning that
    counts them), "file" (what the file says; an unusable normal is refused with the mesh,
    primitive and vertex named) or "recompute" (all of them; hard edges over 60 degrees kept). A node graph that is not a tree
    (a cycle) is refused at once."""
    p = _path(path)
    if not p.lower().endswith(GLTF):
        try:
            import trimesh
        except ImportError:
            raise MissingExtraError(f"path: {p}: formats other than glTF load through trimesh; pip install trimesh (or pomkit[reference])") from None
        tm = trimesh.load(p, force="mesh", process=False)
        return Mesh.from_trimesh(tm, tangents="mikktspace" if tangents is None else tangents, normals_mode=normals)
    f = _read(p, normals)
    parts = []
    for n in f["nodes"]:
        for part in n["parts"]:
            if part["has_uvs"]:
                parts.append((n, part))
    if parts:
        for n in f["nodes"]:
            for part in n["parts"]:
                if not part["has_uvs"]:
                    _uvless(p, n, part, "left out of the mesh (pk.load_objects keeps it, drawn undisplaced)")
    if not parts:
        # nothing has uvs: the whole mesh with its uvs projected per triangle (each triangle a chart)
        parts = [(n, part) for n in f["nodes"] for part in n["parts"]]
        warnings.warn(f"{p}: no primitive has usable TEXCOORD_0: the mesh's uvs are projected per triangle (each "
                      "triangle its own chart, so a map displaces each one apart); unwrap it (e.g. with xatlas) for a "
                      "parameterisation to displace", RuntimeWarning, stacklevel=2)
    n0, a0 = parts[0]
    as_stored = len(parts) == 1 and np.array_equal(_transform(n0), np.eye(4))
    if as_stored and tangents is None:
        return Mesh._from_core(a0, "arrays")
    a = a0 if as_stored else _merge([(part, _transform(n)) for n, part in parts])
    t = a["tangents"] if tangents is None else tangents
    return Mesh.from_arrays(a["positions"], a["normals"], a["uvs"], a["indices"], tangents=t)


def _albedo(path: str, mat: "_core.GltfMaterial") -> np.ndarray:
    """A glTF material's albedo: baseColorTexture (sRGB, decoded to linear) times
    baseColorFactor's RGB, or the factor alone as a constant map."""
    from ._color import srgb_to_linear
    factor = np.asarray(mat["base_color_factor"][:3], np.float32)
    tex = mat["base_color_texture"]
    if tex is None:
        return np.broadcast_to(factor, (2, 2, 3)).astype(np.float32)
    if tuple(tex["wrap"]) != ("repeat", "repeat"):
        warnings.warn(f"{path}: material {mat['name']!r}: its baseColorTexture's sampler wraps {tex['wrap']}; pomkit "
                      "samples every map with repeat, so uvs outside [0, 1] read the texture tiled", RuntimeWarning, stacklevel=4)
    if tex["tex_coord"] != 0:
        warnings.warn(f"{path}: material {mat['name']!r}: baseColorTexture reads TEXCOORD_{tex['tex_coord']}; pomkit "
                      "reads TEXCOORD_0 for every map", RuntimeWarning, stacklevel=4)
    rgb = srgb_to_linear(np.asarray(tex["rgba"])[..., :3])
    return np.ascontiguousarray(rgb * factor, dtype=np.float32)


def load_objects(path: PathLike, material: Material, *, normals: NormalsMode = "repair") -> list[Object]:
    """One `pk.Object` per primitive and material of each mesh node of a glTF 2.0 file (a node's
    primitives that share a material are one object), with the node's world transform:
    positions, normals, uvs and tangents as the file stores them (see `load_mesh`).

    Each object takes `material` (its height, depth, tiling), with the file's base colour as its
    albedo unless `material.albedo` is set: baseColorTexture (sRGB, decoded) times
    baseColorFactor, or the factor alone. A primitive without TEXCOORD_0 is kept as an object of
    its own at depth 0 (drawn undisplaced, as Flat draws), with a warning that names it and
    counts its triangles. `normals` as `load_mesh` takes it. Give each object its own material with `dataclasses.replace`; what the
    file's materials hold beyond the base colour is ignored (docs/assets.md)."""
    if not isinstance(material, Material):
        raise ArgumentTypeError(f"material: expected a pk.Material, got {type(material).__name__}")
    p = _path(path)
    if not p.lower().endswith(GLTF):
        raise ArgumentError(f"path: {p}: load_objects reads glTF 2.0 (.gltf, .glb); use load_mesh for other formats")
    f = _read(p, normals)
    albedos: dict[int, np.ndarray] = {}
    out = []
    for n in f["nodes"]:
        m = _transform(n)
        for part in n["parts"]:
            mat = material
            mi = part["material"]
            if material.albedo is None and mi is not None:
                if mi not in albedos:
                    albedos[mi] = _albedo(p, f["materials"][mi])
                mat = dataclasses.replace(mat, albedo=albedos[mi])
            if not part["has_uvs"]:
                _uvless(p, n, part, "kept at depth 0, drawn undisplaced")
                mat = dataclasses.replace(mat, depth=0.0)
            out.append(Object(Mesh._from_core(part, "arrays"), mat, transform=None if np.array_equal(m, np.eye(4)) else m))
    return out


#: what each finding changes, for the report's text
_MEANING = {
    "open border": "the displaced surface ends there (no method adds a skirt)",
    "seam": "uvs split: each side samples its own texels; the displaced surface is one surface across it",
    "seam heights disagree": "the two sides of a seam read different heights (the bake's mismatch): the surface steps there, and a wall along the seam closes the step (the oracle, the mesh); the texture-space marches (POM, Exact, ...) leave the step open",
    "mirror axis": "the tangent basis's handedness flips across it",
    "vertex shared across a mirror axis": "one tangent serves both handednesses: the frame collapses in the triangles beside it (split the vertex, as glTF exporters do)",
    "mirrored chart": "a chart whose uvs are mirrored (handedness w = +1)",
    "hard edge": "split normals: the sides displace along different normals; the reference welds them at their mean",
    "non-manifold edge": "more than two triangles share the edge",
    "degenerate uv triangle": "zero uv area: no tangent basis of its own (a fallback frame)",
    "degenerate triangle": "zero area",
    "overlapping charts": "two charts map the same texels",
    "normal far from its face": "a vertex normal more than 60 degrees from its face (averaged across a thin part or a sharp edge): Prism's shell and the NCS/CurvedRelief walks lean far from the surface there (remedy: split or recompute the normals, normals=\"recompute\")",
    "flipped normal": "a vertex normal more than 90 degrees from its face: the shell turns inside out there, and Prism, NCS and CurvedRelief lose the surface; shading follows the normals the file gives (remedy: recompute the normals, normals=\"recompute\")",
    "folded shell": "at the material's depth the prism's bottom turns over (depth past the local radius of curvature, or normals that cross): Prism, NCS and CurvedRelief are not held to the oracle there (remedy: lower the depth, or recompute the normals)",
}


#: the report's count warnings: (field, text; {n} is the count, {depth} the material's)
_WARNINGS = [
    ("overlapping_texels", "{n} texels are mapped by two charts"),
    ("degenerate_uv_triangles", "{n} triangles have zero uv area"),
    ("mirror_shared_edges", "{n} mirror-axis edges share vertices across the axis: one tangent serves both handednesses there, and shading and the texture-space methods (NCS, CurvedRelief) go wrong beside them; split those vertices, as glTF exporters do"),
    ("nonmanifold_edges", "{n} non-manifold edges"),
    ("normals_flipped", "{n} triangles have a vertex normal more than 90 degrees from the face: the shell turns inside out there (Prism, NCS and CurvedRelief lose the surface); load with normals=\"recompute\", or recompute them in your tool"),
    ("normals_off_faces", "{n} triangles have a vertex normal more than 60 degrees from the face (averaged across a thin part or a sharp edge): Prism, NCS and CurvedRelief lean far from the surface there; split the normals at sharp edges, or load with normals=\"recompute\""),
    ("folded_prisms", "{n} prisms fold at depth {depth:g} (deeper than the local radius of curvature, or normals that cross): Prism, NCS and CurvedRelief are not held to the oracle there; lower the depth"),
]


class _AssetReportBase:
    """What `check_asset` found. Counts are over the mesh's triangles and its geometric edges
    (vertices welded by position); `examples` names up to five places (in the mesh's space) of
    each finding. The height-map fields are None without a map."""

    #: fields the report computes in Python, after the core's (`_core.ASSET_REPORT_FIELDS`)
    _PYTHON_FIELDS = (
        ("seam_world_max", "Optional[float]", "the largest height mismatch across a seam in world units (with a material's depth)", None),
        ("warnings", "list[str]", "what the findings break, and the remedy", list),
    )

    def __str__(self) -> str:
        r: AssetReport = self  # type: ignore[assignment]
        lines = [f"{r.triangles} triangles, {r.vertices} vertices ({r.welded_vertices} positions), {r.charts} chart(s)"]
        lines.append(f"seams: {r.seam_edges} edges; mirror axes: {r.mirror_edges} ({r.mirror_shared_edges} sharing vertices); mirrored charts: {r.mirrored_charts}")
        lines.append(f"open borders: {r.open_edges} edges ({r.open_length:.4g} long); hard edges: {r.hard_edges}; non-manifold: {r.nonmanifold_edges}")
        lines.append(f"degenerate: {r.degenerate_triangles} triangles, {r.degenerate_uv_triangles} in uv")
        fold = "" if r.folded_prisms is None else f"; prisms folded at the depth: {r.folded_prisms}"
        lines.append(f"normals past 60 degrees from their face: {r.normals_off_faces} triangles, past 90 (flipped): {r.normals_flipped}{fold}")
        if r.height_min is not None and r.height_max is not None:
            rd = "" if r.relief_depth is None else f"; relief depth {r.relief_depth:.4g} (depth x {r.height_max - r.height_min:.3g})"
            lines.append(f"heights used: {r.height_min:.4g}..{r.height_max:.4g} of 0..1{rd}")
        if r.seam_height_max is not None:
            w = "" if r.seam_world_max is None else f" ({r.seam_world_max:.3g} world units)"
            lines.append(f"seam height mismatch: max {r.seam_height_max:.4g}{w}, mean {r.seam_height_mean:.3g}")
        if r.overlapping_texels is not None:
            lines.append(f"overlapping texels: {r.overlapping_texels}")
        if r.min_chart_gap_texels is not None:
            mip = "none (charts touch)" if r.max_clean_mip is None else f"0..{r.max_clean_mip}"
            lines.append(f"narrowest gap between charts: {r.min_chart_gap_texels} texels; mip levels that stay inside a chart: {mip}")
        for w in r.warnings:
            lines.append(f"warning: {w}")
        for what, p in r.examples:
            lines.append(f"  {what} at ({p[0]:.4g}, {p[1]:.4g}, {p[2]:.4g}): {_MEANING.get(what, '')}")
        return "\n".join(lines)


def _build_report() -> Any:
    """`AssetReport`, the frozen dataclass of the core's declared fields (src/assets/report.rs's
    `report!`) and then the Python ones, on `_AssetReportBase`."""
    specs: list[Any] = [(name, Any) for name, _t, _doc in _core.ASSET_REPORT_FIELDS]
    for name, _t, _doc, default in _AssetReportBase._PYTHON_FIELDS:
        specs.append((name, Any, field(default_factory=default) if callable(default) else field(default=default)))
    lines = [" ".join((_AssetReportBase.__doc__ or "").split()), ""]
    lines += [f"{name}: {' '.join(doc.split())}" for name, _t, doc in _core.ASSET_REPORT_FIELDS if doc]
    cls = dataclasses.make_dataclass("AssetReport", specs, bases=(_AssetReportBase,), frozen=True,
                                     namespace={"__doc__": "\n".join(lines)})
    cls.__module__ = __name__
    return cls


if TYPE_CHECKING:
    from ._schema_classes import AssetReport
else:
    AssetReport = _build_report()


def check_asset(mesh: Mesh, height: Any = None) -> AssetReport:
    """A report on `mesh` (and its height map) to read before trusting a comparison: charts,
    seams and how far the height field disagrees across them, mirrored charts and mirror axes,
    degenerate triangles, open borders, hard edges (split normals), non-manifold edges; with a
    map, overlapping charts and the narrowest gap between charts against the mip levels a method
    samples (a bilinear footprint at level k reaches 2^k texels: a chart with g texels of gutter
    on its side stays clean up to level log2(g)); vertex normals far from their faces (past 60
    degrees, and past 90 as flipped) and, with a material, the prisms that fold at its depth: each
    warning names the methods it breaks and the remedy.

    height: None, a height map (2-D array), or a `pk.Material` (its height, depth and tiling:
    the mismatch is then also given in world units)."""
    if not isinstance(mesh, Mesh):
        raise ArgumentTypeError(f"mesh: expected a pk.Mesh, got {type(mesh).__name__}")
    depth, tiling, hd = None, 1.0, None
    if isinstance(height, Material):
        depth, tiling = height.depth, height.tiling
        hd = height._height_data()
    elif height is not None:
        hd = Material(height=height)._height_data()
    r = _core.check_asset(mesh._core_data(), hd, float(tiling), None if depth is None else float(depth))
    d: dict[str, Any] = dict(r)
    seam = r["seam_height_max"]
    d["seam_world_max"] = None if (depth is None or seam is None) else seam * depth
    d["examples"] = [(w, tuple(p)) for w, p in r["examples"]]
    warn: list[str] = []
    if d["mirrored_triangles"] > 0.75 * d["triangles"]:
        warn.append(f"{d['mirrored_triangles']} of {d['triangles']} triangles are mirrored: the uvs probably have v pointing up (trimesh's, xatlas's and OBJ's convention); pomkit's v points down (use pk.Mesh.from_trimesh or v -> 1 - v)")
    if d["seam_height_max"] is not None and d["seam_height_max"] > 2.0 / 255.0:
        warn.append(f"heights disagree across seams by up to {d['seam_height_max']:.3g}: the displaced surface steps there, closed by a wall along the seam; the texture-space marches (POM, Exact, ...) leave the step open")
    lo, hi = d["height_min"], d["height_max"]
    if lo is not None and hi is not None and hi - lo < 0.75:
        keep = "" if depth is None else f" and depth {depth * (hi - lo):.4g} (depth x {hi - lo:.3g})"
        warn.append(f"the height map holds only {lo:.3g}..{hi:.3g} of 0..1: every march steps through the whole shell, "
                    f"{1.0 / max(hi - lo, 1e-9):.3g}x coarser on the relief than it could; pk.textures.normalize(h){keep} "
                    f"give the same relief with its top moved up to the mesh by depth x {1.0 - hi:.3g} "
                    f"(normalize(h, base=...) keeps a zero level of your choosing on the mesh instead)")
    if d["min_chart_gap_texels"] is not None and d["max_clean_mip"] is None:
        warn.append("charts touch (no gutter): filtered samples bleed between them at every mip level")
    for key, text in _WARNINGS:
        if d[key]:
            warn.append(text.format(n=d[key], depth=depth))
    return AssetReport(**d, warnings=warn)
