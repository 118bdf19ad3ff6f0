//! Frames across the boundary: the core's Frame as numpy arrays by AOV name (moved, not
//! copied), following the AOV table; the AOVs the frame does not hold are None.

use super::arrays::nd_array;
use crate::render::aovs::{AovData, AOVS};
use crate::render::{Aovs, Frame};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `aovs=` from Python: None or "all" for every AOV but the cost counters, else a sequence of
/// names.
pub fn aovs_from_py(aovs: Option<&Bound<'_, PyAny>>) -> PyResult<Aovs> {
    let Some(a) = aovs else {
        return Ok(Aovs::STANDARD);
    };
    if let Ok(s) = a.extract::<String>() {
        return if s == "all" {
            Ok(Aovs::STANDARD)
        } else {
            Ok(Aovs::parse(&[s])?)
        };
    }
    let names: Vec<String> = a.extract().map_err(|_| {
        crate::python::errors::argument_error(
            "aovs: expected 'all' or a sequence of AOV names, e.g. (\"color\", \"uv\")",
        )
    })?;
    Ok(Aovs::parse(&names)?)
}

/// A rendered frame as it crosses the boundary: its arrays by AOV name and its timings
/// (`pomkit.Frame` wraps it).
#[pyclass(name = "RenderedFrame", module = "pomkit._core", frozen)]
pub struct PyRenderedFrame {
    /// numpy arrays by AOV name (the AOV table's, render/aovs.rs), None for those not asked for
    #[pyo3(get)]
    arrays: Py<PyDict>,
    /// GPU time of the passes by timestamp queries, None where the adapter has none
    #[pyo3(get)]
    gpu_ms: Option<f64>,
    /// wall time of the render call
    #[pyo3(get)]
    wall_ms: f64,
}

/// The frame's arrays as the AOV table (render/aovs.rs) says: shape (H, W) or (H, W, comps),
/// its dtype. The arrays are moved, not copied.
pub fn frame_to_py<'py>(py: Python<'py>, f: Frame) -> PyResult<Bound<'py, PyRenderedFrame>> {
    let (h, w) = (f.height as usize, f.width as usize);
    let d = PyDict::new(py);
    for (a, data) in AOVS.iter().zip(f.data) {
        let arr: Option<Bound<'py, PyAny>> = match data {
            None => None,
            Some(data) => Some(match (a.comps, data) {
                (1, AovData::F32(v)) => nd_array(py, (h, w), v)?,
                (c, AovData::F32(v)) => nd_array(py, (h, w, c), v)?,
                (_, AovData::U32(v)) => nd_array(py, (h, w), v)?,
                (_, AovData::U8(v)) => nd_array(py, (h, w), v)?,
                (_, AovData::I32(v)) => nd_array(py, (h, w), v)?,
                (_, AovData::Bool(v)) => nd_array(py, (h, w), v)?,
            }),
        };
        d.set_item(a.name, arr)?;
    }
    Bound::new(
        py,
        PyRenderedFrame {
            arrays: d.unbind(),
            gpu_ms: f.gpu_ms,
            wall_ms: f.wall_ms,
        },
    )
}
