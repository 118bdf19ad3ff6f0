//! The scene's user-facing classes declared once: each `schema!` struct is the core's type, the
//! reader of its fields by name (`fields::FromFields`, which the pyo3 layer feeds from Python
//! attributes), and the table (`FIELDS`) that pomkit's Python classes of the same name are
//! built from (python/pomkit/_schema.py: the fields, their order, defaults, ranges and docs).

/// How Python validates and converts a field's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// three finite numbers (float64)
    Vec3,
    /// linear RGB: three finite numbers >= 0, or one for grey (float32)
    Rgb,
    /// a finite number in [lo, hi]
    Real { lo: f64, hi: f64 },
    /// a whole number in [lo, hi]
    Integer { lo: u32, hi: u32 },
    /// True or False
    Bool,
    /// a height map: a 2-D array in [0, 1] (float, uint8 or uint16), shared as `HeightMap`
    Height,
    /// an albedo: (H, W, 3) sRGB uint8 or linear float, or None; shared as `Albedo`
    Albedo,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Vec3 => "vec3",
            Kind::Rgb => "rgb",
            Kind::Real { .. } => "real",
            Kind::Integer { .. } => "integer",
            Kind::Bool => "bool",
            Kind::Height => "height",
            Kind::Albedo => "albedo",
        }
    }
    /// The inclusive range of a number (None for the others).
    pub fn range(self) -> Option<(f64, f64)> {
        match self {
            Kind::Real { lo, hi } => Some((lo, hi)),
            Kind::Integer { lo, hi } => Some((lo as f64, hi as f64)),
            _ => None,
        }
    }
}

/// One field of a schema class.
#[derive(Clone, Copy, Debug)]
pub struct Field {
    pub name: &'static str,
    pub kind: Kind,
    /// the default as a Python literal; None where the field is required
    pub default: Option<&'static str>,
    /// A setting of pomkit's own renderer (marked `@ setting`): it changes no reference render
    /// (the oracle's, Mitsuba's, Cycles'), so reference caches do not hash it.
    pub setting: bool,
    pub doc: &'static str,
}

/// A field's value checked against its kind (the same rules Python applies when it builds the
/// class): finite vectors, colours >= 0, numbers within their range.
pub trait CheckValue {
    fn check(&self, name: &str, kind: Kind) -> crate::error::Result<()>;
}

fn out_of(name: &str, v: f64, kind: Kind) -> crate::error::Result<()> {
    match kind.range() {
        Some((lo, hi)) if !(v >= lo && v <= hi) => Err(crate::error::Error::arg(
            name,
            format!("must lie in [{lo}, {hi}], got {v}"),
        )),
        _ => Ok(()),
    }
}

impl CheckValue for f64 {
    fn check(&self, name: &str, kind: Kind) -> crate::error::Result<()> {
        out_of(name, *self, kind)
    }
}

impl CheckValue for f32 {
    fn check(&self, name: &str, kind: Kind) -> crate::error::Result<()> {
        out_of(name, *self as f64, kind)
    }
}

impl CheckValue for u32 {
    fn check(&self, name: &str, kind: Kind) -> crate::error::Result<()> {
        out_of(name, *self as f64, kind)
    }
}

impl CheckValue for bool {
    fn check(&self, _: &str, _: Kind) -> crate::error::Result<()> {
        Ok(())
    }
}

impl CheckValue for [f64; 3] {
    fn check(&self, name: &str, _: Kind) -> crate::error::Result<()> {
        if self.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(crate::error::Error::arg(name, "must be finite"))
        }
    }
}

impl CheckValue for [f32; 3] {
    fn check(&self, name: &str, _: Kind) -> crate::error::Result<()> {
        if self.iter().all(|x| x.is_finite() && *x >= 0.0) {
            Ok(())
        } else {
            Err(crate::error::Error::arg(name, "must be finite and >= 0"))
        }
    }
}

/// Height maps and albedos are checked when they are shared (`shared`).
impl<T> CheckValue for super::Shared<T> {
    fn check(&self, _: &str, _: Kind) -> crate::error::Result<()> {
        Ok(())
    }
}

impl<T> CheckValue for Option<super::Shared<T>> {
    fn check(&self, _: &str, _: Kind) -> crate::error::Result<()> {
        Ok(())
    }
}

/// A class declared by `schema!`: its name and fields, in order.
pub trait Schema {
    const CLASS: &'static str;
    const DOC: &'static str;
    const FIELDS: &'static [Field];
}

/// A kind by its name in `schema!`.
#[macro_export]
macro_rules! schema_kind {
    (Vec3) => {
        $crate::scene::schema::Kind::Vec3
    };
    (Rgb) => {
        $crate::scene::schema::Kind::Rgb
    };
    (Bool) => {
        $crate::scene::schema::Kind::Bool
    };
    (Height) => {
        $crate::scene::schema::Kind::Height
    };
    (Albedo) => {
        $crate::scene::schema::Kind::Albedo
    };
    (Real($lo:expr, $hi:expr)) => {
        $crate::scene::schema::Kind::Real { lo: $lo, hi: $hi }
    };
    (Integer($lo:expr, $hi:expr)) => {
        $crate::scene::schema::Kind::Integer { lo: $lo, hi: $hi }
    };
}

/// A schema struct: `field: Type = Kind(range) [= "python default"],` per user-facing field,
/// each with its doc comment; `internal { name: Type = value, }` for fields the core sets itself.
#[macro_export]
macro_rules! schema {
    (
        $(#[doc = $doc:literal])*
        pub struct $name:ident {
            $(
                $(#[doc = $fdoc:literal])*
                pub $f:ident : $t:ty = $kind:ident $(($lo:expr, $hi:expr))? $(, $default:literal)? $(@ $setting:ident)?;
            )*
        }
        $(internal {
            $($(#[$im:meta])* pub $x:ident : $xt:ty = $xv:expr;)*
        })?
    ) => {
        $(#[doc = $doc])*
        #[derive(Clone, Debug)]
        pub struct $name {
            $($(#[doc = $fdoc])* pub $f: $t,)*
            $($($(#[$im])* pub $x: $xt,)*)?
        }

        impl $crate::fields::FromFields for $name {
            fn from_fields(src: &dyn $crate::fields::Fields) -> $crate::error::Result<Self> {
                Ok($name {
                    $($f: <$t as $crate::fields::FieldValue>::get(src, stringify!($f))?,)*
                    $($($x: $xv,)*)?
                })
            }
        }

        impl $name {
            /// Each field against its kind and range (the table's; rules across fields are
            /// the type's own `validate`).
            pub fn check_fields(&self) -> $crate::error::Result<()> {
                $(
                    $crate::scene::schema::CheckValue::check(
                        &self.$f,
                        stringify!($f),
                        $crate::schema_kind!($kind $(($lo, $hi))?),
                    )?;
                )*
                Ok(())
            }
        }

        impl $crate::scene::schema::Schema for $name {
            const CLASS: &'static str = stringify!($name);
            const DOC: &'static str = concat!($($doc, "\n",)*);
            const FIELDS: &'static [$crate::scene::schema::Field] = &[$(
                $crate::scene::schema::Field {
                    name: stringify!($f),
                    kind: $crate::schema_kind!($kind $(($lo, $hi))?),
                    default: $crate::schema_default!($($default)?),
                    setting: $crate::schema_setting!($($setting)?),
                    doc: concat!($($fdoc, "\n",)*),
                },
            )*];
        }
    };
}

/// Whether a field is marked `@ setting`.
#[macro_export]
macro_rules! schema_setting {
    () => {
        false
    };
    (setting) => {
        true
    };
}

#[macro_export]
macro_rules! schema_default {
    () => {
        None
    };
    ($d:literal) => {
        Some($d)
    };
}

impl crate::fields::FieldValue for super::Shared<super::HeightMap> {
    fn get(f: &dyn crate::fields::Fields, name: &str) -> crate::error::Result<Self> {
        f.handle(name)?
            .and_then(|h| h.downcast().ok())
            .ok_or_else(|| crate::error::Error::arg(name, "expected a height map"))
    }
}

impl crate::fields::FieldValue for Option<super::Shared<super::Albedo>> {
    fn get(f: &dyn crate::fields::Fields, name: &str) -> crate::error::Result<Self> {
        match f.handle(name)? {
            None => Ok(None),
            Some(h) => h
                .downcast()
                .map(Some)
                .map_err(|_| crate::error::Error::arg(name, "expected an albedo")),
        }
    }
}

/// Every schema class, in the order Python builds them.
pub fn classes() -> Vec<(&'static str, &'static str, &'static [Field])> {
    fn one<T: Schema>() -> (&'static str, &'static str, &'static [Field]) {
        (T::CLASS, T::DOC, T::FIELDS)
    }
    vec![
        one::<super::Camera>(),
        one::<super::Material>(),
        one::<super::DirectionalLight>(),
        one::<super::SphereLight>(),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::{Error, Result};
    use crate::fields::{Fields, FromFields};

    /// Fields from (name, value) pairs: what the pyo3 layer does from attributes.
    struct Pairs(Vec<(&'static str, f64)>);
    impl Pairs {
        fn v(&self, name: &str) -> Result<f64> {
            self.0
                .iter()
                .find(|(n, _)| *n == name)
                .map(|(_, v)| *v)
                .ok_or_else(|| Error::arg(name, "missing"))
        }
    }
    impl Fields for Pairs {
        fn u32(&self, name: &str) -> Result<u32> {
            Ok(self.v(name)? as u32)
        }
        fn f32(&self, name: &str) -> Result<f32> {
            Ok(self.v(name)? as f32)
        }
        fn f64(&self, name: &str) -> Result<f64> {
            self.v(name)
        }
        fn bool(&self, name: &str) -> Result<bool> {
            Ok(self.v(name)? != 0.0)
        }
        fn str(&self, name: &str) -> Result<String> {
            Err(Error::arg(name, "no strings here"))
        }
        fn f32_map(&self, name: &str) -> Result<Vec<(String, f32)>> {
            Err(Error::arg(name, "no maps here"))
        }
        fn vec3(&self, name: &str) -> Result<[f64; 3]> {
            Ok([self.v(name)?; 3])
        }
        fn rgb(&self, name: &str) -> Result<[f32; 3]> {
            Ok([self.v(name)? as f32; 3])
        }
    }

    #[test]
    fn a_light_reads_every_field_of_its_table_and_names_a_missing_one() {
        let names: Vec<&str> = super::super::SphereLight::FIELDS
            .iter()
            .map(|f| f.name)
            .collect();
        let all = Pairs(names.iter().map(|n| (*n, 0.5)).collect());
        let l = super::super::SphereLight::from_fields(&all).unwrap();
        assert_eq!(l.radius, 0.5);
        assert_eq!(l.position, [0.5; 3]);
        let short = Pairs(vec![("position", 1.0)]);
        let e = super::super::SphereLight::from_fields(&short).unwrap_err();
        assert!(e.to_string().contains("radius"), "{e}");
    }

    #[test]
    fn the_core_checks_fields_by_the_same_table() {
        let mut l = super::super::SphereLight {
            position: [0.0, 1.0, 0.0],
            radius: 0.05,
            intensity: [1.0; 3],
            color: [1.0, -0.5, 0.0],
        };
        let e = super::super::Light::Sphere(l.clone())
            .validate()
            .unwrap_err();
        assert!(e.to_string().contains("color"), "{e}");
        l.color = [1.0; 3];
        l.radius = f64::NAN;
        let e = super::super::Light::Sphere(l).validate().unwrap_err();
        assert!(e.to_string().contains("radius"), "{e}");
    }

    #[test]
    fn every_field_has_a_doc_and_defaults_follow_required_fields() {
        for (class, doc, fields) in classes() {
            assert!(!doc.trim().is_empty(), "{class}");
            let mut defaulted = false;
            for f in fields {
                assert!(!f.doc.trim().is_empty(), "{class}.{}", f.name);
                assert!(
                    !(defaulted && f.default.is_none()),
                    "{class}.{}: a required field after a default",
                    f.name
                );
                defaulted |= f.default.is_some();
            }
        }
    }
}
