//! Method dataclasses (pomkit/_methods.py) read into the core's typed `Method`: the core names
//! and types each field (`contract::Fields`, `params!`), this layer only reads attributes and
//! converts them. The class attribute `_kind` picks the variant.

use crate::contract::Fields;
use crate::error::{Error, Result};
use crate::methods::{from_fields, Method};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A dataclass's attributes as `Fields`.
struct PyFields<'py>(Bound<'py, PyAny>);

impl PyFields<'_> {
    fn get<T: for<'a> FromPyObjectOwned<'a>>(&self, name: &str, what: &str) -> Result<T> {
        let v = self
            .0
            .getattr(name)
            .map_err(|_| Error::arg(name, "missing: expected a pomkit method dataclass"))?;
        v.extract::<T>()
            .map_err(|_| Error::arg(name, format!("expected {what}, got {v}")))
    }
}

impl Fields for PyFields<'_> {
    fn u32(&self, name: &str) -> Result<u32> {
        self.get(name, "a non-negative integer")
    }
    fn f32(&self, name: &str) -> Result<f32> {
        self.get(name, "a number")
    }
    fn f64(&self, name: &str) -> Result<f64> {
        self.get(name, "a number")
    }
    fn bool(&self, name: &str) -> Result<bool> {
        self.get(name, "True or False")
    }
    fn str(&self, name: &str) -> Result<String> {
        self.get(name, "a string")
    }
    fn f32_map(&self, name: &str) -> Result<Vec<(String, f32)>> {
        let v = self
            .0
            .getattr(name)
            .map_err(|_| Error::arg(name, "missing: expected a pomkit method dataclass"))?;
        let d = v
            .cast::<PyDict>()
            .map_err(|_| Error::arg(name, "expected a dict of name -> number"))?;
        d.iter()
            .map(|(k, v)| {
                Ok((
                    k.extract::<String>()
                        .map_err(|_| Error::arg(name, "names must be strings"))?,
                    v.extract::<f64>()
                        .map_err(|_| Error::arg(name, "values must be numbers"))?
                        as f32,
                ))
            })
            .collect()
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for Method {
    type Error = PyErr;
    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let ob = ob.to_owned();
        let kind: String = ob
            .getattr("_kind")
            .map_err(|_| {
                crate::python::errors::argument_error("method: expected a pomkit method such as pomkit.POM()")
            })?
            .extract()?;
        match from_fields(&kind, &PyFields(ob)) {
            Some(m) => Ok(m?),
            None => Err(crate::python::errors::argument_error(format!(
                "method: unknown method kind {kind:?}"
            ))),
        }
    }
}
