//! A Python object's attributes as the core's `Fields`: how the methods' dataclasses and the
//! scene's schema classes cross the boundary. The core names and types each field; this only
//! converts, and names the field (and the object it belongs to) in its errors.

use super::handles::{PyAlbedoData, PyHeightData};
use crate::error::{Error, Result};
use crate::fields::{Fields, FromFields, Handle};
use pyo3::prelude::*;
use pyo3::types::PyDict;

pub(crate) struct PyFields<'py> {
    ob: Bound<'py, PyAny>,
    /// what the object should be, for errors ("a pomkit.Camera")
    what: &'static str,
}

impl<'py> PyFields<'py> {
    pub(crate) fn new(ob: Bound<'py, PyAny>, what: &'static str) -> Self {
        PyFields { ob, what }
    }

    fn attr(&self, name: &str) -> Result<Bound<'py, PyAny>> {
        attr(&self.ob, name, self.what)
    }

    fn get<T: for<'a> FromPyObjectOwned<'a>>(&self, name: &str, expected: &str) -> Result<T> {
        let v = self.attr(name)?;
        v.extract::<T>()
            .map_err(|_| Error::wrong_type(name, format!("expected {expected}, got {v}")))
    }
}

impl Fields for PyFields<'_> {
    fn object(&self, name: &str) -> Result<(String, Box<dyn Fields + '_>)> {
        let v = self.attr(name)?;
        let kind: String = v
            .getattr("_kind")
            .and_then(|k| k.extract())
            .map_err(|_| Error::wrong_type(name, format!("expected a pomkit method, got {v}")))?;
        Ok((kind, Box::new(PyFields::new(v, "a pomkit method dataclass"))))
    }
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
    fn vec3(&self, name: &str) -> Result<[f64; 3]> {
        self.get(name, "three numbers")
    }
    fn rgb(&self, name: &str) -> Result<[f32; 3]> {
        self.get(name, "three numbers (linear RGB)")
    }
    fn handle(&self, name: &str) -> Result<Option<Handle>> {
        // the object makes (once) and keeps the core's data of its field
        let h = self
            .ob
            .call_method1("_handle_of", (name,))
            .map_err(|e| Error::wrong_type(name, format!("expected {}: {e}", self.what)))?;
        if h.is_none() {
            return Ok(None);
        }
        if let Ok(d) = h.cast::<PyHeightData>() {
            return Ok(Some(d.get().0.clone() as Handle));
        }
        if let Ok(d) = h.cast::<PyAlbedoData>() {
            return Ok(Some(d.get().0.clone() as Handle));
        }
        Err(Error::wrong_type(name, format!("expected {}", self.what)))
    }
    fn f32_map(&self, name: &str) -> Result<Vec<(String, f32)>> {
        let v = self.attr(name)?;
        let d = v
            .cast::<PyDict>()
            .map_err(|_| Error::wrong_type(name, "expected a dict of name -> number"))?;
        d.iter()
            .map(|(k, v)| {
                Ok((
                    k.extract::<String>()
                        .map_err(|_| Error::wrong_type(name, "names must be strings"))?,
                    v.extract::<f64>()
                        .map_err(|_| Error::wrong_type(name, "values must be numbers"))?
                        as f32,
                ))
            })
            .collect()
    }
}

/// Attribute `name` of `ob`, or an error naming it and what `ob` should be ("a pomkit.Scene").
pub(crate) fn attr<'py>(
    ob: &Bound<'py, PyAny>,
    name: &str,
    what: &str,
) -> Result<Bound<'py, PyAny>> {
    ob.getattr(name)
        .map_err(|_| Error::arg(name, format!("missing: expected {what}")))
}

/// A schema struct read from a Python object's attributes; errors name `what` and the field.
pub(crate) fn read<T: FromFields>(ob: &Bound<'_, PyAny>, what: &'static str) -> Result<T> {
    T::from_fields(&PyFields::new(ob.clone(), what))
}
