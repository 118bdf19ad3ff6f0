//! numpy arrays from the core's vectors.

use numpy::ndarray::Array;
use numpy::IntoPyArray;
use pyo3::prelude::*;

/// A numpy array of `shape` that takes ownership of `v` (no copy).
pub(crate) fn nd_array<'py, T: numpy::Element, D: numpy::ndarray::Dimension>(
    py: Python<'py>,
    shape: impl numpy::ndarray::IntoDimension<Dim = D>,
    v: Vec<T>,
) -> PyResult<Bound<'py, PyAny>> {
    let a = Array::from_shape_vec(shape, v)
        .map_err(|e| crate::python::errors::argument_error(e.to_string()))?;
    Ok(a.into_pyarray(py).into_any())
}
