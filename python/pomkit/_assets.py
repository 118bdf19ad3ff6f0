"""Users' assets: glTF 2.0 loaded as the file says (read by the core), other formats through
trimesh, and the asset report.

`load_mesh(path)` gives one `Mesh`; `load_objects(path, material)` one `Object` per mesh node with
its world transform. glTF keeps positions, normals, TEXCOORD_0 and TANGENT as stored (glTF's uv
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


def _nodes(path: str, normals: NormalsMode = "file") -> list:
    if normals not in _core.NORMALS_MODES:
        raise ArgumentError(f"normals: expected one of {', '.join(map(repr, _core.NORMALS_MODES))}, got {normals!r}")
    nodes = list(_core.load_gltf(path, normals))
    replaced = sum(n["replaced_normals"] for n in nodes)
    if replaced and normals == "repair":
        warnings.warn(f"{path}: {replaced} unusable normal(s) recomputed from the faces (normals=\"repair\")",
                      RuntimeWarning, stacklevel=3)
    return nodes


def _merge(meshes: list[tuple[dict, np.ndarray]]) -> dict:
    """Several nodes' arrays in one space (each node's transform applied)."""
    pos, nrm, uv, tan, idx = [], [], [], [], []
    base = 0
    for a, m in meshes:
        lin = m[:3, :3]
        p = np.asarray(a["positions"], np.float64) @ lin.T + m[:3, 3]
        n = np.asarray(a["normals"], np.float64) @ np.linalg.inv(lin)
        n /= np.linalg.norm(n, axis=1, keepdims=True)
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


def load_mesh(path: PathLike, *, tangents: Any = None, normals: NormalsMode = "file") -> Mesh:
    """One mesh from a file. glTF 2.0 (.gltf, .glb) is read by pomkit's core as the file says:
    positions, normals, TEXCOORD_0 and TANGENT bit for bit (the tangent's w as pomkit's
    handedness, minus glTF's), MikkTSpace tangents where the file has none, flat normals where it
    has none (as glTF asks). A file of several mesh nodes is merged into one mesh in the scene's
    space (their transforms applied; `load_objects` keeps them apart). Other formats (OBJ, PLY,
    ...) load through trimesh (`Mesh.from_trimesh`, v flipped to pomkit's convention).

    tangents: None keeps the file's (or MikkTSpace); "mikktspace", "pomkit" or an (n, 4) array
    replace them (see `Mesh.from_arrays`).
    normals: "file" (the default: what the file says; an unusable normal, NaN, Inf or zero length,
    is refused with the mesh, primitive and vertex named), "repair" (only the unusable ones
    recomputed from the faces, with a warning that counts them: what engines' importers do) or
    "recompute" (all of them; hard edges over 60 degrees kept). A node graph that is not a tree
    (a cycle) is refused at once."""
    p = _path(path)
    if not p.lower().endswith(GLTF):
        try:
            import trimesh
        except ImportError:
            raise MissingExtraError(f"path: {p}: formats other than glTF load through trimesh; pip install trimesh (or pomkit[reference])") from None
        tm = trimesh.load(p, force="mesh", process=False)
        return Mesh.from_trimesh(tm, tangents="mikktspace" if tangents is None else tangents, normals_mode=normals)
    nodes = _nodes(p, normals)
    as_stored = len(nodes) == 1 and np.array_equal(np.asarray(nodes[0]["transform"]), np.eye(4).reshape(-1))
    if as_stored and tangents is None:
        return Mesh._from_core(nodes[0], "arrays")
    a = nodes[0] if as_stored else _merge([(n, np.asarray(n["transform"], np.float64).reshape(4, 4)) for n in nodes])
    t = a["tangents"] if tangents is None else tangents
    return Mesh.from_arrays(a["positions"], a["normals"], a["uvs"], a["indices"], tangents=t)


def load_objects(path: PathLike, material: Material) -> list[Object]:
    """One `pk.Object` per mesh node of a glTF 2.0 file, each with its node's world transform
    and the given `material`: positions, normals, uvs and tangents as the file stores them (see
    `load_mesh`). Give each object its own material with `dataclasses.replace`."""
    if not isinstance(material, Material):
        raise ArgumentTypeError(f"material: expected a pk.Material, got {type(material).__name__}")
    p = _path(path)
    if not p.lower().endswith(GLTF):
        raise ArgumentError(f"path: {p}: load_objects reads glTF 2.0 (.gltf, .glb); use load_mesh for other formats")
    out = []
    for n in _nodes(p):
        m = np.asarray(n["transform"], np.float64).reshape(4, 4)
        out.append(Object(Mesh._from_core(n, "arrays"), material, transform=None if np.array_equal(m, np.eye(4)) else m))
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
