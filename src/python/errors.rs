//! Errors across the boundary: the core's `Error` as Python exceptions (`InvalidArgument` and
//! `Limit` -> ValueError, `NoAdapter` -> NoAdapterError, `Gpu` -> GpuError, `DeviceLost` ->
//! DeviceLostError; the last three subclass RuntimeError).

use crate::error::Error;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    _core,
    GpuError,
    PyRuntimeError,
    "A wgpu validation or out-of-memory error."
);
create_exception!(
    _core,
    DeviceLostError,
    GpuError,
    "The GPU device was lost; create a new Renderer."
);
create_exception!(
    _core,
    NoAdapterError,
    PyRuntimeError,
    "No GPU adapter is available."
);

impl From<Error> for PyErr {
    fn from(e: Error) -> PyErr {
        match e {
            Error::InvalidArgument { .. } | Error::Limit { .. } => {
                PyValueError::new_err(e.to_string())
            }
            Error::NoAdapter(_) => NoAdapterError::new_err(e.to_string()),
            Error::Gpu(_) => GpuError::new_err(e.to_string()),
            Error::DeviceLost(_) => DeviceLostError::new_err(e.to_string()),
        }
    }
}
