//! Errors across the boundary: the core's `Error` as pomkit's Python exceptions, the classes of
//! `pomkit._errors` (each a `pk.Error`): `InvalidArgument` and `Limit` -> ArgumentError (a
//! ValueError), `NoAdapter` -> NoAdapterError, `Gpu` -> GpuError, `DeviceLost` -> DeviceLostError
//! (RuntimeErrors).

use crate::error::Error;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyType;

/// The exception `name` of `pomkit._errors` with `msg`; a plain ValueError or RuntimeError where
/// that module cannot be imported (the core loaded without its package).
fn pomkit_error(name: &str, msg: String, value_error: bool) -> PyErr {
    Python::attach(|py| {
        let ty = py
            .import("pomkit._errors")
            .and_then(|m| m.getattr(name))
            .and_then(|t| t.cast_into::<PyType>().map_err(PyErr::from));
        match ty {
            Ok(t) => PyErr::from_type(t, msg),
            Err(_) if value_error => PyValueError::new_err(msg),
            Err(_) => PyRuntimeError::new_err(msg),
        }
    })
}

impl From<Error> for PyErr {
    fn from(e: Error) -> PyErr {
        let name = match e {
            Error::InvalidArgument { .. } | Error::Limit { .. } => "ArgumentError",
            Error::NoAdapter(_) => "NoAdapterError",
            Error::Gpu(_) => "GpuError",
            Error::DeviceLost(_) => "DeviceLostError",
        };
        let value_error = name == "ArgumentError";
        pomkit_error(name, e.to_string(), value_error)
    }
}

/// pomkit's ArgumentError (a ValueError) with `msg`, which names the argument and the fix.
pub(crate) fn argument_error(msg: impl Into<String>) -> PyErr {
    pomkit_error("ArgumentError", msg.into(), true)
}
