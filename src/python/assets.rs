//! Assets across the boundary: glTF nodes (`load_gltf`) and the asset report (`check_asset`).

use super::handles::{PyHeightData, PyMeshData};
use super::arrays::nd_array;
use super::mesh_args::mesh_out;
use crate::assets::{self, TangentSource};
use crate::mesh::normals::NormalsMode;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;

/// A glTF 2.0 file (.gltf, .glb) as a dict: `nodes`, every mesh node (`name`, `transform`: 16
/// numbers, row-major, the node's world transform; `skipped`: (primitive, why) of the points, lines and
/// arealess primitives left out; `parts`: per material and uv presence the primitives' mesh arrays
/// (`MeshArrays`) with `material` (glTF index or None), `has_uvs` (False: no TEXCOORD_0, drawn
/// undisplaced), `primitives`, `tangent_source` ("file" or "mikktspace"), `flat_normals` and
/// `replaced_normals`); `materials` (`name`, `base_color_factor`, `base_color_texture`: None or
/// `rgba` (H, W, 4) uint8 sRGB, `wrap` (s, t), `tex_coord`); `texture_errors`: (material, why).
#[pyfunction]
#[pyo3(signature = (path, normals="file"))]
pub fn load_gltf<'py>(
    py: Python<'py>,
    path: PathBuf,
    normals: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let mode = NormalsMode::parse(normals)?;
    let file = super::errors::interruptible(py, || assets::load_gltf(&path, mode))?;
    let nodes = PyList::empty(py);
    for n in file.nodes {
        let d = PyDict::new(py);
        d.set_item("name", n.name)?;
        d.set_item(
            "transform",
            n.transform.transpose().to_cols_array().to_vec(),
        )?;
        d.set_item("skipped", n.skipped)?;
        let parts = PyList::empty(py);
        for p in n.parts {
            let pd = mesh_out(py, &p.mesh)?;
            pd.set_item("material", p.material)?;
            pd.set_item("has_uvs", p.uvs)?;
            pd.set_item("primitives", p.primitives)?;
            pd.set_item(
                "tangent_source",
                match p.tangents {
                    TangentSource::File => "file",
                    TangentSource::MikkTSpace => "mikktspace",
                },
            )?;
            pd.set_item("flat_normals", p.flat_normals)?;
            pd.set_item("replaced_normals", p.replaced_normals)?;
            parts.append(pd)?;
        }
        d.set_item("parts", parts)?;
        nodes.append(d)?;
    }
    let materials = PyList::empty(py);
    for m in file.materials {
        let d = PyDict::new(py);
        d.set_item("name", m.name)?;
        d.set_item("base_color_factor", m.base_color_factor.to_vec())?;
        match m.base_color_texture {
            Some(t) => {
                let td = PyDict::new(py);
                td.set_item(
                    "rgba",
                    nd_array(py, (t.height as usize, t.width as usize, 4), t.rgba)?,
                )?;
                td.set_item("wrap", (t.wrap[0], t.wrap[1]))?;
                td.set_item("tex_coord", t.tex_coord)?;
                d.set_item("base_color_texture", td)?;
            }
            None => d.set_item("base_color_texture", py.None())?,
        }
        materials.append(d)?;
    }
    let out = PyDict::new(py);
    out.set_item("nodes", nodes)?;
    out.set_item("materials", materials)?;
    out.set_item("texture_errors", file.texture_errors)?;
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
