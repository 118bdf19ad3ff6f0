//! Meshes across the boundary: generated (plane, sphere, torus, cylinder, cube) or made from
//! arrays, and returned as their arrays by name.

use super::arrays::nd_array;
use super::handles::rows;
use crate::error::Error;
use crate::mesh::{Mesh, TangentBases};
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A mesh's arrays by name (the stub's `MeshArrays`): positions (n, 3), normals (n, 3), uvs
/// (n, 2), indices (m,), tangents (n, 4), uv_scale (n, 2), charts (c, 3).
pub(crate) fn mesh_out<'py>(py: Python<'py>, m: &Mesh) -> PyResult<Bound<'py, PyDict>> {
    let n = m.positions.len();
    let f = |v: Vec<f32>, k: usize| nd_array(py, (n, k), v);
    let d = PyDict::new(py);
    d.set_item("positions", f(m.positions.concat(), 3)?)?;
    d.set_item("normals", f(m.normals.concat(), 3)?)?;
    d.set_item("uvs", f(m.uvs.concat(), 2)?)?;
    d.set_item("indices", m.indices.clone().into_pyarray(py))?;
    d.set_item("tangents", f(m.tangents.concat(), 4)?)?;
    d.set_item("uv_scale", f(m.uv_scale.concat(), 2)?)?;
    d.set_item(
        "charts",
        nd_array(py, (m.charts.len(), 3), m.charts.concat())?,
    )?;
    Ok(d)
}

/// Validate mesh arrays and compute the tangent bases: the given `tangents`, or else `frames`
/// ("pomkit" or "mikktspace"). Returns the mesh's arrays by name (`mesh_out`) and the repairs
/// made: degenerate_uv_triangles, fallback_vertices, replaced_normals (as `normals_mode` asked:
/// "file", "recompute" or "repair", `mesh::normals`).
#[pyfunction]
#[pyo3(signature = (positions, normals, uvs, indices, tangents=None, frames="pomkit", normals_mode="file"))]
pub fn mesh_from_arrays<'py>(
    py: Python<'py>,
    positions: PyReadonlyArray2<'py, f32>,
    normals: PyReadonlyArray2<'py, f32>,
    uvs: PyReadonlyArray2<'py, f32>,
    indices: PyReadonlyArray1<'py, u32>,
    tangents: Option<PyReadonlyArray2<'py, f32>>,
    frames: &str,
    normals_mode: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let mode = crate::mesh::normals::NormalsMode::parse(normals_mode)?;
    let p = rows::<3>(&positions, "positions")?;
    let mut n = rows::<3>(&normals, "normals")?;
    let u = rows::<2>(&uvs, "uvs")?;
    let i: Vec<u32> = indices.as_array().iter().copied().collect();
    let replaced = crate::mesh::normals::apply(mode, &p, &mut n, &i, "")?;
    let t = tangents
        .as_ref()
        .map(|t| rows::<4>(t, "tangents"))
        .transpose()?;
    let frames = match (t, frames) {
        (Some(t), _) => TangentBases::Given(t),
        (None, "pomkit") => TangentBases::Pomkit,
        (None, "mikktspace") => TangentBases::MikkTSpace,
        (None, o) => {
            return Err(Error::arg(
                "tangents",
                format!(
                "unknown tangent bases {o:?}: give \"mikktspace\", \"pomkit\" or an (n, 4) array"
            ),
            )
            .into())
        }
    };
    let (mesh, rep) = py.detach(|| Mesh::from_arrays_with(p, n, u, i, frames))?;
    let d = mesh_out(py, &mesh)?;
    d.set_item("degenerate_uv_triangles", rep.degenerate_uv_triangles)?;
    d.set_item("fallback_vertices", rep.fallback_vertices)?;
    d.set_item("replaced_normals", replaced)?;
    Ok(d)
}

/// The generated base meshes (`Mesh::plane`, ...), each by its parameters' names.
#[pyfunction]
pub fn mesh_plane(py: Python<'_>, size: f64, segments: u32) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::plane(size, segments)?)
}

#[pyfunction]
pub fn mesh_sphere(
    py: Python<'_>,
    radius: f64,
    segments: u32,
    rings: u32,
) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::sphere(radius, segments, rings)?)
}

#[pyfunction]
pub fn mesh_torus(
    py: Python<'_>,
    major: f64,
    minor: f64,
    segments: u32,
    tube_segments: u32,
) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::torus(major, minor, segments, tube_segments)?)
}

#[pyfunction]
pub fn mesh_cylinder(
    py: Python<'_>,
    radius: f64,
    height: f64,
    segments: u32,
    rings: u32,
) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::cylinder(radius, height, segments, rings)?)
}

#[pyfunction]
pub fn mesh_cube(py: Python<'_>, size: f64, segments: u32) -> PyResult<Bound<'_, PyDict>> {
    mesh_out(py, &Mesh::cube(size, segments)?)
}
