//! Assets across the boundary: glTF nodes (`load_gltf`) and the asset report (`check_asset`).

use super::handles::{PyHeightData, PyMeshData};
use super::scene_args::mesh_out;
use crate::assets::{self, TangentSource};
use crate::mesh::normals::NormalsMode;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

/// Every mesh node of a glTF 2.0 file (.gltf, .glb): a list of dicts with the mesh's arrays
/// (`MeshArrays`), `name`, `transform` (16 numbers, row-major, the node's world transform),
/// `tangent_source` ("file" or "mikktspace"), `flat_normals` (primitives given flat normals) and
/// `replaced_normals` (normals recomputed as `normals` asked: "file", "recompute" or "repair").
#[pyfunction]
#[pyo3(signature = (path, normals="file"))]
pub fn load_gltf<'py>(
    py: Python<'py>,
    path: PathBuf,
    normals: &str,
) -> PyResult<Bound<'py, PyList>> {
    let mode = NormalsMode::parse(normals)?;
    let nodes = super::errors::interruptible(py, || assets::load_gltf(&path, mode))?;
    let out = PyList::empty(py);
    for n in nodes {
        let d = mesh_out(py, &n.mesh)?;
        d.set_item("name", n.name)?;
        d.set_item(
            "transform",
            n.transform.transpose().to_cols_array().to_vec(),
        )?;
        d.set_item(
            "tangent_source",
            match n.tangents {
                TangentSource::File => "file",
                TangentSource::MikkTSpace => "mikktspace",
            },
        )?;
        d.set_item("flat_normals", n.flat_normals)?;
        d.set_item("replaced_normals", n.replaced_normals)?;
        out.append(d)?;
    }
    Ok(out)
}

/// The asset report of a mesh, with its height map (and the material's tiling) when given: a
/// dict of `crate::assets::report::AssetReport`'s fields (the stub's `AssetReportDict`).
#[pyfunction]
#[pyo3(signature = (mesh, height=None, tiling=1.0, depth=None))]
pub fn check_asset<'py>(
    py: Python<'py>,
    mesh: &Bound<'py, PyMeshData>,
    height: Option<&Bound<'py, PyHeightData>>,
    tiling: f64,
    depth: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let m = mesh.get().0.clone();
    let h = height.map(|h| h.get().0.clone());
    let r = py.detach(|| assets::report::check_asset(&m, h.as_ref().map(|k| &***k), tiling, depth));
    let d = PyDict::new(py);
    d.set_item("vertices", r.vertices)?;
    d.set_item("triangles", r.triangles)?;
    d.set_item("welded_vertices", r.welded_vertices)?;
    d.set_item("charts", r.charts)?;
    d.set_item("mirrored_charts", r.mirrored_charts)?;
    d.set_item("mirrored_triangles", r.mirrored_triangles)?;
    d.set_item("degenerate_uv_triangles", r.degenerate_uv_triangles)?;
    d.set_item("degenerate_triangles", r.degenerate_triangles)?;
    d.set_item("seam_edges", r.seam_edges)?;
    d.set_item("mirror_edges", r.mirror_edges)?;
    d.set_item("mirror_shared_edges", r.mirror_shared_edges)?;
    d.set_item("open_edges", r.open_edges)?;
    d.set_item("open_length", r.open_length)?;
    d.set_item("hard_edges", r.hard_edges)?;
    d.set_item("nonmanifold_edges", r.nonmanifold_edges)?;
    d.set_item("uvs_outside_unit_square", r.uvs_outside_unit_square)?;
    d.set_item("seam_height_max", r.seam_height_max)?;
    d.set_item("seam_height_mean", r.seam_height_mean)?;
    d.set_item("overlapping_texels", r.overlapping_texels)?;
    d.set_item("min_chart_gap_texels", r.min_chart_gap_texels)?;
    d.set_item("max_clean_mip", r.max_clean_mip)?;
    d.set_item("normals_off_faces", r.normals_off_faces)?;
    d.set_item("normals_flipped", r.normals_flipped)?;
    d.set_item("folded_prisms", r.folded_prisms)?;
    let ex = PyList::empty(py);
    for (what, p) in r.examples {
        ex.append((what, p.to_vec()))?;
    }
    d.set_item("examples", ex)?;
    Ok(d)
}

/// (flipped normals, folded prisms) of a mesh at `depth`: what makes the shell methods (Prism,
/// NCS, CurvedRelief) leave the oracle, for the render-time warning.
#[pyfunction]
pub fn shell_findings(py: Python<'_>, mesh: &Bound<'_, PyMeshData>, depth: f64) -> (usize, usize) {
    let m = mesh.get().0.clone();
    py.detach(|| assets::report::shell_findings(&m, depth))
}
