//! A method the user writes: a WGSL module defining `fn march(r: Ray) -> Hit`, run by the
//! surface pass like the built-in marches (docs/custom_methods.md). Its named parameters become
//! the uniform block `params` (all f32, in the given order).
use crate::contract::{check_finite, PerPixel, ShaderUnit, Spec, Unit};
use crate::error::{Error, Result};
use std::hash::{Hash, Hasher};

#[derive(Clone, Debug, PartialEq)]
pub struct Custom {
    /// an identifier: names the module in error messages and labels
    pub name: String,
    pub wgsl: String,
    pub params: Vec<(String, f32)>,
    /// its march searches the Ray's window (from `r.s` at `r.top` down to `r.floor`), so that
    /// `Hybrid` can take it as its fine method
    pub windowed: bool,
}

impl crate::contract::FromFields for Custom {
    fn from_fields(f: &dyn crate::contract::Fields) -> Result<Self> {
        Ok(Custom {
            name: f.str("name")?,
            wgsl: f.str("wgsl")?,
            params: f.f32_map("params")?,
            windowed: f.bool("windowed")?,
        })
    }
}

fn is_ident(s: &str) -> bool {
    let mut c = s.chars();
    matches!(c.next(), Some(ch) if ch.is_ascii_alphabetic() || ch == '_')
        && c.all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
        && !s.starts_with("__")
}

impl Custom {
    /// The fields the core reads, by name.
    pub const FIELDS: &'static [&'static str] = &["name", "wgsl", "params", "windowed"];

    /// The import path: the name plus a hash of everything that shapes the module, so that a
    /// changed source or parameter list is a new module.
    pub fn module_path(&self) -> String {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.wgsl.hash(&mut h);
        for (k, _) in &self.params {
            k.hash(&mut h);
        }
        format!("pomkit::custom::{}_{:016x}", self.name, h.finish())
    }
}

impl Unit for Custom {
    fn spec(&self, o: &PerPixel) -> Spec {
        let unit = ShaderUnit {
            path: self.module_path(),
            file: format!("{}.wgsl", self.name),
            source: self.wgsl.clone().into(),
            deps: Vec::new(),
        };
        let params: Vec<(&str, f32)> = self.params.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        Spec {
            // a compile error is in the user's source
            shader_arg: "wgsl",
            ..Spec::surface(unit, o, &params)
        }
    }

    fn validate(&self) -> Result<()> {
        if !is_ident(&self.name) {
            return Err(Error::arg(
                "name",
                format!(
                    "must be a WGSL identifier (letters, digits, _), got {:?}",
                    self.name
                ),
            ));
        }
        if self.params.len() > 64 {
            return Err(Error::arg(
                "params",
                format!("at most 64 parameters, got {}", self.params.len()),
            ));
        }
        for (k, v) in &self.params {
            if !is_ident(k) {
                return Err(Error::arg(
                    "params",
                    format!("parameter names must be WGSL identifiers, got {k:?}"),
                ));
            }
            check_finite("params", *v)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::contract::Unit;

    #[test]
    fn a_compile_error_names_the_argument_and_the_line() {
        let lib = crate::shaders::ShaderLib::new().unwrap();
        let m = super::Custom {
            name: "broken".into(),
            wgsl: "#import pomkit::march::{Ray, Hit}\n\nfn march(r: Ray) -> Hit {\n    let x: f32 = undefined_thing;\n}\n".into(),
            params: vec![],
            windowed: false,
        };
        let e = lib
            .compose(
                &m.spec(&crate::contract::PerPixel::off()),
                crate::contract::Filtering::Hardware,
                Default::default(),
                "wgsl",
            )
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("wgsl:"), "{e}");
        assert!(e.contains("broken.wgsl") && e.contains(":4:"), "{e}");
    }
}
