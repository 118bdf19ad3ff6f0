//! The CPU oracle across the boundary: its frame (`oracle_hits`) and its image
//! (`oracle_image`), as dicts of numpy arrays, with the shells it keeps between calls
//! (`Shells`, owned by the caller); the reference shading's normals and sample directions for
//! `pk.reference`.

use super::arrays::nd_array;
use super::scene_args::scene_from_py;
use crate::error::Error;
use crate::oracle::Shells;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The shells the oracle keeps between calls (its objects' prisms and bounding volumes, the
/// latest four by mesh content and depth). pk.oracle holds one for the process.
#[pyclass(name = "Shells", frozen)]
#[derive(Default)]
pub struct PyShells(Shells);

#[pymethods]
impl PyShells {
    #[new]
    fn new() -> Self {
        Self::default()
    }

    /// How many shells are kept.
    fn __len__(&self) -> usize {
        self.0.len()
    }
}

/// The caller's shells, or a fresh set that keeps nothing past the call.
fn shells_or<'a>(shells: Option<&'a Bound<'_, PyShells>>, fresh: &'a Shells) -> &'a Shells {
    shells.map_or(fresh, |s| &s.get().0)
}

/// The CPU float64 oracle: dict with uv (H, W, 2) f64, depth (H, W) f64, mask, cells, and the
/// first directional light's visibility (H, W) f64. `shells` keeps the objects' shells for later
/// calls (None: built for this call only).
#[pyfunction]
#[pyo3(signature = (scene, light_bias=0.0, shells=None))]
pub fn oracle_hits<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    light_bias: f64,
    shells: Option<&Bound<'py, PyShells>>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(scene)?;
    let fresh = Shells::default();
    let shells = shells_or(shells, &fresh);
    let o =
        super::errors::interruptible(py, move || crate::oracle::hits(&scene, light_bias, shells))?;
    let d = PyDict::new(py);
    hits_into(&d, o)?;
    Ok(d)
}

/// The oracle's frame into `d`: uv, depth, mask, cells, visibility.
fn hits_into(d: &Bound<'_, PyDict>, o: crate::oracle::OracleHits) -> PyResult<()> {
    let py = d.py();
    let (h, w) = (o.height as usize, o.width as usize);
    d.set_item("uv", nd_array(py, (h, w, 2), o.uv)?)?;
    d.set_item("depth", nd_array(py, (h, w), o.depth)?)?;
    d.set_item("mask", nd_array(py, (h, w), o.mask)?)?;
    d.set_item("cells", nd_array(py, (h, w), o.cells)?)?;
    d.set_item("visibility", nd_array(py, (h, w), o.visibility)?)?;
    d.set_item("object", nd_array(py, (h, w), o.object)?)?;
    Ok(())
}

/// The oracle's image (`oracle/image.rs`): dict with color (H, W, 3) f32 and coverage (H, W) f32
/// from k x k exact samples per pixel shaded with the reference shading, and the oracle's frame
/// at the pixel centres (as `oracle_hits` at light bias 0: uv, depth, mask, cells, visibility).
/// `shells` as for `oracle_hits`.
#[pyfunction]
#[pyo3(signature = (scene, spp, shadows=true, shells=None))]
pub fn oracle_image<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    spp: u32,
    shadows: bool,
    shells: Option<&Bound<'py, PyShells>>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(scene)?;
    let fresh = Shells::default();
    let shells = shells_or(shells, &fresh);
    let o = super::errors::interruptible(py, move || {
        crate::oracle::image::render(&scene, spp, shadows, shells)
    })?;
    let (h, w) = (o.height as usize, o.width as usize);
    let d = PyDict::new(py);
    d.set_item("color", nd_array(py, (h, w, 3), o.color)?)?;
    d.set_item("coverage", nd_array(py, (h, w), o.coverage)?)?;
    hits_into(&d, o.centres)?;
    Ok(d)
}

fn columns<const N: usize>(
    a: &PyReadonlyArray2<'_, f64>,
    name: &str,
    rows: usize,
) -> PyResult<Vec<[f64; N]>> {
    let v = a.as_array();
    if v.shape() != [rows, N] {
        return Err(Error::arg(
            name,
            format!("expected shape ({rows}, {N}), got {:?}", v.shape()),
        )
        .into());
    }
    Ok(v.outer_iter()
        .map(|r| std::array::from_fn(|k| r[k]))
        .collect())
}

/// The reference shading normal (docs/conventions.md) at hits found by a ray cast on object
/// `object`'s displaced mesh: uvs (N, 2) mesh uv, and the base mesh's basis interpolated at each hit
/// from `tessellate`'s base_normals (N, 3), tangents (N, 4) and uv_scale (N, 2). (N, 3) f64.
#[pyfunction]
#[pyo3(signature = (scene, object, uvs, base_normals, tangents, uv_scale))]
pub fn reference_normals<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    object: usize,
    uvs: PyReadonlyArray2<'py, f64>,
    base_normals: PyReadonlyArray2<'py, f64>,
    tangents: PyReadonlyArray2<'py, f64>,
    uv_scale: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = scene_from_py(scene)?;
    let obj = scene.object(object)?;
    let n = uvs.as_array().shape()[0];
    let (uv, bn) = (
        columns::<2>(&uvs, "uvs", n)?,
        columns::<3>(&base_normals, "base_normals", n)?,
    );
    let (tg, sc) = (
        columns::<4>(&tangents, "tangents", n)?,
        columns::<2>(&uv_scale, "uv_scale", n)?,
    );
    let normals =
        py.detach(|| crate::oracle::shading::shading_normals(&obj.material, &uv, &bn, &tg, &sc));
    let out: Vec<f64> = normals.iter().flat_map(|v| v.to_array()).collect();
    nd_array(py, (n, 3), out)
}

/// The directions each sample traces (`oracle::image::sample_directions_of`): for sample i, about
/// the unit axes[i] with tan_r[i] (> 0 a light's disk, 0 the axis alone, < 0 the cosine set about
/// a normal), its share as sample q[i] of n. Returns (directions (M, 3) f64, owner (M,) u32).
#[pyfunction]
#[pyo3(signature = (axes, tan_r, q, n))]
pub fn reference_directions<'py>(
    py: Python<'py>,
    axes: PyReadonlyArray2<'py, f64>,
    tan_r: PyReadonlyArray1<'py, f64>,
    q: PyReadonlyArray1<'py, u32>,
    n: u32,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let rows = q.as_array().len();
    let ax = columns::<3>(&axes, "axes", rows)?;
    let (tr, qs) = (tan_r.as_array(), q.as_array());
    if tr.len() != rows {
        return Err(
            Error::arg("tan_r", format!("expected {rows} values, got {}", tr.len())).into(),
        );
    }
    if n == 0 {
        return Err(Error::arg("n", "must be at least 1").into());
    }
    let (tr, qs): (Vec<f64>, Vec<u32>) = (tr.to_vec(), qs.to_vec());
    let (dirs, owner) =
        py.detach(|| crate::oracle::image::sample_directions_of(&ax, &tr, &qs, n as usize));
    let dirs: Vec<f64> = dirs.iter().flat_map(|v| v.to_array()).collect();
    let m = owner.len();
    Ok((nd_array(py, (m, 3), dirs)?, nd_array(py, m, owner)?))
}
