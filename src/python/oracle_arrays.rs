//! The CPU oracle across the boundary: its frame (`exact_uv`) and the exact image
//! (`render_exact`), as dicts of numpy arrays.

use super::nd_array;
use super::scene_args::scene_from_py;
use crate::oracle::exact_hits;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The CPU float64 oracle: dict with uv (H, W, 2) f64, depth (H, W) f64, mask, cells, and the
/// first directional light's visibility (H, W) f64.
#[pyfunction]
#[pyo3(signature = (scene, light_bias=0.0))]
pub fn exact_uv<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyDict>,
    light_bias: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(scene)?;
    let o = py.detach(move || exact_hits(&scene, light_bias))?;
    let (h, w) = (o.height as usize, o.width as usize);
    let d = PyDict::new(py);
    d.set_item("uv", nd_array(py, (h, w, 2), o.uv)?)?;
    d.set_item("depth", nd_array(py, (h, w), o.depth)?)?;
    d.set_item("mask", nd_array(py, (h, w), o.mask)?)?;
    d.set_item("cells", nd_array(py, (h, w), o.cells)?)?;
    d.set_item("visibility", nd_array(py, (h, w), o.visibility)?)?;
    Ok(d)
}

/// The exact image (`oracle/image.rs`): dict with color (H, W, 3) f32 and coverage (H, W) f32
/// from k x k exact samples per pixel shaded with the reference shading.
#[pyfunction]
#[pyo3(signature = (scene, spp, shadows=true))]
pub fn render_exact<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyDict>,
    spp: u32,
    shadows: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(scene)?;
    let o = py.detach(move || crate::oracle::image::render_exact(&scene, spp, shadows))?;
    let (h, w) = (o.height as usize, o.width as usize);
    let d = PyDict::new(py);
    d.set_item("color", nd_array(py, (h, w, 3), o.color)?)?;
    d.set_item("coverage", nd_array(py, (h, w), o.coverage)?)?;
    Ok(d)
}
