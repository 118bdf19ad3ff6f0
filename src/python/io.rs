//! Image files across the boundary: the core decodes them (`imageio.rs`), this returns arrays.

use super::arrays::nd_array;
use crate::imageio::{load_albedo, load_height, Pixels};
use pyo3::prelude::*;
use std::path::PathBuf;

/// Decode an image file: kind "height" -> ((H, W) float32, bits), "albedo" -> ((H, W, 3)
/// float32, bits). Integer files are scaled to [0, 1]; float files keep their values.
#[pyfunction]
pub fn load_image<'py>(
    py: Python<'py>,
    path: PathBuf,
    kind: &str,
) -> PyResult<(Bound<'py, PyAny>, u32)> {
    let load: fn(&std::path::Path) -> crate::Result<Pixels> = match kind {
        "height" => load_height,
        "albedo" => load_albedo,
        o => {
            return Err(crate::python::errors::argument_error(format!(
                "kind: 'height' or 'albedo', got {o:?}"
            )))
        }
    };
    let p = py.detach(|| load(&path))?;
    let (h, w) = (p.height as usize, p.width as usize);
    let a = if p.channels == 1 {
        nd_array(py, (h, w), p.data)?
    } else {
        nd_array(py, (h, w, p.channels), p.data)?
    };
    Ok((a, p.bits))
}
