//! Reading a typed struct field by field from a source that names its fields (a Python
//! object's attributes, through the pyo3 layer): the methods' parameters (`params!`) and the
//! scene's schema classes (`schema!`). At the bottom of the crate, beside `error`.

use crate::error::{Error, Result};

/// Where a struct's fields come from, by name: the pyo3 layer reads a Python object through
/// it. The core names the fields and types them; a binding layer only converts values (and
/// names the field in its errors).
pub trait Fields {
    fn u32(&self, name: &str) -> Result<u32>;
    fn f32(&self, name: &str) -> Result<f32>;
    fn f64(&self, name: &str) -> Result<f64>;
    fn bool(&self, name: &str) -> Result<bool>;
    fn str(&self, name: &str) -> Result<String>;
    /// a mapping of names to numbers, in its order (a custom method's `params`)
    fn f32_map(&self, name: &str) -> Result<Vec<(String, f32)>>;
    /// three numbers (a point or a direction)
    fn vec3(&self, name: &str) -> Result<[f64; 3]> {
        Err(Error::arg(name, "expected three numbers"))
    }
    /// linear RGB
    fn rgb(&self, name: &str) -> Result<[f32; 3]> {
        Err(Error::arg(name, "expected linear RGB"))
    }
    /// a nested object (a method inside a method): its `_kind` and its fields
    fn object(&self, name: &str) -> Result<(String, Box<dyn Fields + '_>)> {
        Err(Error::arg(name, "expected a nested object"))
    }
    /// shared core data made once for the field's value (a height map, an albedo), None where
    /// the value is None; the reader downcasts it to the type it expects
    fn handle(&self, name: &str) -> Result<Option<Handle>> {
        Err(Error::arg(name, "expected shared core data"))
    }
}

/// Shared core data of any type (`Fields::handle`).
pub type Handle = std::sync::Arc<dyn std::any::Any + Send + Sync>;

/// A parameter's type, read from `Fields` by name.
pub trait FieldValue: Sized {
    fn get(f: &dyn Fields, name: &str) -> Result<Self>;
}

macro_rules! field_values {
    ($($t:ty => $get:ident),*) => {$(
        impl FieldValue for $t {
            fn get(f: &dyn Fields, name: &str) -> Result<Self> {
                f.$get(name)
            }
        }
    )*};
}

field_values!(u32 => u32, f32 => f32, f64 => f64, bool => bool, [f64; 3] => vec3, [f32; 3] => rgb);

/// A method's parameters, read from `Fields`.
pub trait FromFields: Sized {
    fn from_fields(f: &dyn Fields) -> Result<Self>;
}
