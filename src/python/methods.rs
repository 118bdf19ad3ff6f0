//! Method dataclasses (pomkit/_methods.py) extracted straight into the core's typed `Method`:
//! each field read by name, no flattening and no re-parsing of defaults. The class attribute
//! `_kind` picks the variant.

use crate::methods::*;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The string options, parsed by the core (which names the argument in its errors).
macro_rules! from_str_option {
    ($($t:ty),*) => {$(
        impl<'a, 'py> FromPyObject<'a, 'py> for $t {
            type Error = PyErr;
            fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
                Ok(<$t>::parse(&ob.extract::<String>()?)?)
            }
        }
    )*};
}

from_str_option!(Shadows, Filtering, Cones, Refine);

impl<'a, 'py> FromPyObject<'a, 'py> for Flat {
    type Error = PyErr;
    fn extract(_: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        Ok(Flat {})
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for Custom {
    type Error = PyErr;
    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let mut params = Vec::new();
        for item in ob.getattr("params")?.call_method0("items")?.try_iter()? {
            let (k, v): (String, f64) = item?.extract()?;
            params.push((k, v as f32));
        }
        Ok(Custom {
            name: ob.getattr("name")?.extract()?,
            wgsl: ob.getattr("wgsl")?.extract()?,
            params,
        })
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for Method {
    type Error = PyErr;
    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let ob = ob.to_owned();
        let kind: String = ob
            .getattr("_kind")
            .map_err(|_| {
                PyValueError::new_err("method: expected a pomkit method such as pomkit.POM()")
            })?
            .extract()?;
        from_python(&kind, &ob).unwrap_or_else(|| {
            Err(PyValueError::new_err(format!(
                "method: unknown method kind {kind:?}"
            )))
        })
    }
}
