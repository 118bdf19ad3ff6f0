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
    let mut d = ReportDict {
        d: PyDict::new(py),
        err: None,
    };
    r.visit(&mut d);
    match d.err {
        Some(e) => Err(e),
        None => Ok(d.d),
    }
}

/// The report's fields into a dict, as `AssetReport::visit` hands them over.
struct ReportDict<'py> {
    d: Bound<'py, PyDict>,
    err: Option<PyErr>,
}

impl ReportDict<'_> {
    fn set<'a, T: pyo3::IntoPyObject<'a>>(&mut self, name: &str, v: T)
    where
        Self: 'a,
    {
        if self.err.is_none() {
            self.err = self.d.set_item(name, v).err();
        }
    }
}

impl assets::report::ReportVisitor for ReportDict<'_> {
    fn count(&mut self, name: &'static str, v: Option<i64>) {
        self.set(name, v);
    }
    fn real(&mut self, name: &'static str, v: Option<f64>) {
        self.set(name, v);
    }
    fn flag(&mut self, name: &'static str, v: bool) {
        self.set(name, v);
    }
    fn places(&mut self, name: &'static str, v: &[(String, [f32; 3])]) {
        let places: Vec<(String, (f32, f32, f32))> =
            v.iter().map(|(w, p)| (w.clone(), (p[0], p[1], p[2]))).collect();
        self.set(name, places);
    }
}

/// `AssetReport::FIELDS`: (name, Python type, doc) per field of the asset report.
pub fn report_fields() -> Vec<(&'static str, &'static str, &'static str)> {
    assets::report::AssetReport::FIELDS
        .iter()
        .map(|(n, t, d)| (*n, *t, d.trim()))
        .collect()
}

/// (flipped normals, folded prisms) of a mesh at `depth`: what makes the shell methods (Prism,
/// NCS, CurvedRelief) leave the oracle, for the render-time warning.
#[pyfunction]
pub fn shell_findings(py: Python<'_>, mesh: &Bound<'_, PyMeshData>, depth: f64) -> (usize, usize) {
    let m = mesh.get().0.clone();
    py.detach(|| assets::report::shell_findings(&m, depth))
}
