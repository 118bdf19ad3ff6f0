//! Frames across the boundary: the core's Frame as a dict of numpy arrays (moved, not copied);
//! the AOVs the frame does not hold are None.

use super::nd_array;
use crate::render::{Aovs, Frame};
use numpy::ndarray::{Dimension, IntoDimension};
use numpy::Element;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `aovs=` from Python: None or "all" for every AOV, else a sequence of names.
pub fn aovs_from_py(aovs: Option<&Bound<'_, PyAny>>) -> PyResult<Aovs> {
    let Some(a) = aovs else {
        return Ok(Aovs::ALL);
    };
    if let Ok(s) = a.extract::<String>() {
        return if s == "all" {
            Ok(Aovs::ALL)
        } else {
            Ok(Aovs::parse(&[s])?)
        };
    }
    let names: Vec<String> = a.extract().map_err(|_| {
        PyValueError::new_err(
            "aovs: expected 'all' or a sequence of AOV names, e.g. (\"color\", \"uv\")",
        )
    })?;
    Ok(Aovs::parse(&names)?)
}

/// A numpy array of `shape` owning `v`, or None when the frame does not hold it.
fn array<'py, T: Element, D: Dimension>(
    py: Python<'py>,
    shape: impl IntoDimension<Dim = D>,
    v: Vec<T>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    if v.is_empty() {
        return Ok(None);
    }
    nd_array(py, shape, v).map(Some)
}

pub fn frame_to_py<'py>(py: Python<'py>, f: Frame) -> PyResult<Bound<'py, PyDict>> {
    let (h, w) = (f.height as usize, f.width as usize);
    let d = PyDict::new(py);
    let mask = if f.aovs.has("mask") {
        f.mask
    } else {
        Vec::new()
    };
    d.set_item("color", array(py, (h, w, 3), f.color)?)?;
    d.set_item("uv", array(py, (h, w, 2), f.uv)?)?;
    d.set_item("depth", array(py, (h, w), f.depth)?)?;
    d.set_item("mask", array(py, (h, w), mask)?)?;
    d.set_item("steps", array(py, (h, w), f.steps)?)?;
    d.set_item("lod", array(py, (h, w), f.lod)?)?;
    d.set_item("flags", array(py, (h, w), f.flags)?)?;
    d.set_item("object", array(py, (h, w), f.object)?)?;
    d.set_item("gpu_ms", f.gpu_ms)?;
    d.set_item("wall_ms", f.wall_ms)?;
    Ok(d)
}
