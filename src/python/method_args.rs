//! Method dataclasses (pomkit/_methods.py) read into the core's typed `Method`: the core names
//! and types each field (`fields::Fields`, `params!`), this layer only reads attributes and
//! converts them. The class attribute `_kind` picks the variant.

use super::fields::PyFields;
use crate::methods::{from_fields, Method};
use pyo3::prelude::*;

impl<'a, 'py> FromPyObject<'a, 'py> for Method {
    type Error = PyErr;
    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let ob = ob.to_owned();
        let kind: String = ob
            .getattr("_kind")
            .map_err(|_| {
                crate::python::errors::argument_error(
                    "method: expected a pomkit method such as pomkit.POM()",
                )
            })?
            .extract()?;
        match from_fields(&kind, &PyFields::new(ob, "a pomkit method dataclass")) {
            Some(m) => Ok(m?),
            None => Err(crate::python::errors::argument_error(format!(
                "method: unknown method kind {kind:?}"
            ))),
        }
    }
}
