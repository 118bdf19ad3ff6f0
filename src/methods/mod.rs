//! The methods: one enum of typed parameter structs, and per method one `spec` that says
//! everything the renderer needs to run it: its shader (a `march` module for the surface pass,
//! or a pass of its own), its shader defs, its geometry, the resources it reads and its uniform
//! block. Each method is one unit: `src/methods/<name>.rs` beside `src/methods/<name>.wgsl`, or,
//! for a method that brings its own data (geometry, resources and the passes that build them),
//! the folder `src/methods/<name>/`; plus its Python dataclass (which holds the user-facing
//! defaults and ranges) and one line in `Method` below. The renderer binds what a method's
//! `Spec` declares (src/contract.rs) and knows no method by name.
//!
//! The core checks only what it needs for safety (bounded loops, memory): see `Method::validate`.

mod bump;
pub mod cone_step;
pub mod curved_relief;
mod custom;
pub mod distance_mapping;
mod exact;
mod flat;
pub mod hybrid;
pub mod ncs;
mod parallax;
mod pom;
pub mod prism;
mod relief;
mod steep;
pub mod tessellated;
pub mod walk;

pub use bump::Bump;
pub use cone_step::{ConeStep, Cones, Refine};
pub use curved_relief::CurvedRelief;
pub use custom::Custom;
pub use distance_mapping::DistanceMapping;
pub use exact::Exact;
pub use flat::Flat;
pub use ncs::Ncs;
pub use parallax::Parallax;
pub use pom::Pom;
pub use prism::Prism;
pub use prism::{PRISM_BYTES, PRISM_VERTEX_BYTES};
pub use relief::Relief;
pub use steep::SteepParallax;
pub use tessellated::Tessellated;
pub use walk::WALK_BYTES_PER_TRIANGLE;

pub use crate::contract::{
    check_finite, check_range, flag, Fields, Filtering, FromFields, Geometry, Pass, PerPixel,
    ShaderUnit, Shadows, Spec, Unit, MAX_STEPS_LIMIT,
};
use crate::error::{Error, Result};
use std::sync::Arc;
use tessellated::Pattern;

/// The registry: one line per method, `Variant(ParamStruct) = "python _kind"`. It generates the
/// `Method` enum, its dispatch and its reading from `Fields` (the pyo3 layer's dataclasses).
macro_rules! registry {
    ($($variant:ident($ty:ty) = $kind:literal,)*) => {
        /// A method with its parameters and the per-pixel options (shadows, AO, filtering).
        #[derive(Clone, Debug, PartialEq)]
        pub enum Method {
            $($variant($ty, PerPixel),)*
        }

        impl Method {
            pub fn spec(&self) -> Spec {
                match self {
                    $(Method::$variant(m, o) => m.spec(o),)*
                }
            }
            fn unit_validate(&self) -> Result<()> {
                match self {
                    $(Method::$variant(m, _) => m.validate(),)*
                }
            }
            /// The Python dataclass's `_kind`.
            pub fn kind(&self) -> &'static str {
                match self {
                    $(Method::$variant(..) => $kind,)*
                }
            }
        }

        /// Every registered method's examples (`Unit::examples`), each per-pixel one in every
        /// shadow mode and filtering (with AO): the shader variants the tests compose,
        /// translate to every backend and check against the backends' limits.
        pub fn builtin_variants() -> Vec<Method> {
            let mut out = Vec::new();
            $(for m in <$ty as Unit>::examples() {
                if <$ty as Unit>::PER_PIXEL {
                    for s in Shadows::NAMES {
                        for f in Filtering::NAMES {
                            let o = PerPixel {
                                shadows: Shadows::parse(s).expect("a listed value"),
                                filtering: Filtering::parse(f).expect("a listed value"),
                                ao_directions: 4,
                                ..PerPixel::off()
                            };
                            out.push(Method::$variant(m.clone(), o));
                        }
                    }
                } else {
                    out.push(Method::$variant(m, PerPixel::off()));
                }
            })*
            out
        }

        /// Per method, its Python `_kind` and the fields the core reads from its dataclass: its
        /// own, then the per-pixel options where it takes them.
        pub fn method_fields() -> Vec<(&'static str, Vec<&'static str>)> {
            vec![$((
                $kind,
                <$ty>::FIELDS
                    .iter()
                    .chain(if <$ty as Unit>::PER_PIXEL { PerPixel::FIELDS } else { &[] })
                    .copied()
                    .collect(),
            ),)*]
        }

        /// The method whose (Python dataclass's) `_kind` is `kind`, its parameters read field
        /// by field from `fields` (and its per-pixel options when it takes them). None: unknown
        /// kind.
        pub fn from_fields(kind: &str, fields: &dyn Fields) -> Option<Result<Method>> {
            match kind {
                $($kind => Some((|| {
                    let o = if <$ty as Unit>::PER_PIXEL { PerPixel::from_fields(fields)? } else { PerPixel::off() };
                    Ok(Method::$variant(<$ty as FromFields>::from_fields(fields)?, o))
                })()),)*
                _ => None,
            }
        }
    };
}

registry! {
    Flat(Flat) = "Flat",
    Bump(Bump) = "Bump",
    Parallax(Parallax) = "Parallax",
    SteepParallax(SteepParallax) = "SteepParallax",
    Pom(Pom) = "POM",
    Relief(Relief) = "Relief",
    Exact(Exact) = "Exact",
    ConeStep(ConeStep) = "ConeStep",
    Ncs(Ncs) = "NCS",
    Prism(Prism) = "Prism",
    Tessellated(Tessellated) = "Tessellated",
    Custom(Custom) = "Custom",
    CurvedRelief(CurvedRelief) = "CurvedRelief",
    DistanceMapping(DistanceMapping) = "DistanceMapping",
    Hybrid(Hybrid) = "Hybrid",
}

/// The methods whose search honours the Ray's window (`floor`, `top`): `Hybrid`'s fine methods
/// (and a `Custom` that says its march does: `windowed`).
pub const WINDOWED: &[&str] = &["POM", "SteepParallax", "Relief", "Exact", "ConeStep"];

/// A coarse mesh displaced at its vertices (hybrid/: Tessellated's lattice) and a per-pixel
/// method that marches only the rest, the residual, in the window each coarse triangle bounds
/// it to: engines' vertex displacement plus parallax. `coarse` None: a flat coarse mesh (the
/// base mesh, the window [0, 1]), the fine method as it runs alone.
#[derive(Clone, Debug, PartialEq)]
pub struct Hybrid {
    /// (texels_per_vertex, pattern) of the coarse lattice
    pub coarse: Option<(f64, Pattern)>,
    pub fine: Box<Method>,
}

impl Hybrid {
    /// The fields the core reads, by name.
    pub const FIELDS: &'static [&'static str] = &["coarse", "fine"];
}

impl FromFields for Hybrid {
    fn from_fields(f: &dyn Fields) -> Result<Self> {
        let (ck, cf) = f.object("coarse")?;
        let coarse = match ck.as_str() {
            "Tessellated" => {
                let t = <Tessellated as FromFields>::from_fields(&*cf)?;
                Some((t.texels_per_vertex, t.pattern))
            }
            "Flat" => None,
            o => {
                return Err(Error::arg(
                    "coarse",
                    format!("must be a pk.Tessellated (the coarse mesh) or pk.Flat() (no coarse displacement), got {o}"),
                ))
            }
        };
        let (fk, ff) = f.object("fine")?;
        let windowed_custom = fk == "Custom" && ff.bool("windowed")?;
        if !WINDOWED.contains(&fk.as_str()) && !windowed_custom {
            return Err(Error::arg(
                "fine",
                format!("must be one of {}, or a Custom with windowed=True (a search that marches a window of the shell), got {fk}", WINDOWED.join(", ")),
            ));
        }
        let fine = from_fields(&fk, &*ff).expect("a registered kind")?;
        Ok(Hybrid {
            coarse,
            fine: Box::new(fine),
        })
    }
}

impl Unit for Hybrid {
    const PER_PIXEL: bool = false;
    fn examples() -> Vec<Self> {
        vec![
            Hybrid {
                coarse: Some((8.0, Pattern::Fan)),
                fine: Box::new(Method::pom(PerPixel::off())),
            },
            Hybrid {
                coarse: Some((4.0, Pattern::Grid)),
                fine: Box::new(Method::Exact(
                    Exact {
                        max_iterations: 4096,
                    },
                    PerPixel::off(),
                )),
            },
        ]
    }
    fn spec(&self, _: &PerPixel) -> Spec {
        let mut s = self.fine.spec();
        s.geometry = Geometry::Own(Arc::new(hybrid::WindowMesh {
            texels_per_vertex: self.coarse.map(|c| c.0),
            pattern: self.coarse.map_or(Pattern::Fan, |c| c.1),
        }));
        s.defs.push("WINDOW");
        s.defs.push("VERTEX_EXTRA");
        s
    }
    fn validate(&self) -> Result<()> {
        if let Some((tpv, _)) = self.coarse {
            if !(tpv.is_finite() && (1.0 / 64.0..=1024.0).contains(&tpv)) {
                return Err(Error::arg(
                    "coarse",
                    format!("texels_per_vertex must lie in [1/64, 1024], got {tpv}"),
                ));
            }
        }
        self.fine.validate()
    }
}

impl Method {
    /// The safety checks: bounded loops and sizes. (Ranges a user should see live in Python.)
    pub fn validate(&self) -> Result<()> {
        self.spec().pixel.validate()?;
        self.unit_validate()
    }

    /// The method "auto"'s pipeline probe times (src/render/choice.rs): POM with the paper's
    /// defaults, no shadows, the per-pixel search most frames draw.
    pub fn auto_probe() -> Self {
        Method::pom(PerPixel::off())
    }

    /// POM with the paper's defaults (8..50 samples, LOD threshold 4) and the given options:
    /// for the core's own tests and examples.
    pub fn pom(pixel: PerPixel) -> Self {
        Method::Pom(
            Pom {
                min_steps: 8,
                max_steps: 50,
                lod_threshold: 4.0,
                adaptive: true,
            },
            pixel,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;
    use std::collections::HashMap;

    /// Fields from a map of strings: the core reads methods with no binding layer.
    struct MapFields(HashMap<&'static str, &'static str>);

    impl Fields for MapFields {
        fn u32(&self, n: &str) -> Result<u32> {
            self.str(n)?
                .parse()
                .map_err(|_| Error::arg(n, "not an integer"))
        }
        fn f32(&self, n: &str) -> Result<f32> {
            self.str(n)?
                .parse()
                .map_err(|_| Error::arg(n, "not a number"))
        }
        fn f64(&self, n: &str) -> Result<f64> {
            self.str(n)?
                .parse()
                .map_err(|_| Error::arg(n, "not a number"))
        }
        fn bool(&self, n: &str) -> Result<bool> {
            self.str(n)?
                .parse()
                .map_err(|_| Error::arg(n, "not a bool"))
        }
        fn str(&self, n: &str) -> Result<String> {
            self.0
                .get(n)
                .map(|s| s.to_string())
                .ok_or_else(|| Error::arg(n, "missing"))
        }
        fn f32_map(&self, _: &str) -> Result<Vec<(String, f32)>> {
            Ok(Vec::new())
        }
    }

    #[test]
    fn methods_read_from_fields() {
        let per_pixel = [
            ("shadows", "exact"),
            ("shadow_steps", "8"),
            ("filtering", "hardware"),
            ("mip_filtering", "false"),
            ("ao_directions", "0"),
            ("horizon_samples", "8"),
        ];
        let mut f: HashMap<&str, &str> = per_pixel.into();
        f.extend([("linear_steps", "32"), ("binary_steps", "6")]);
        let m = from_fields("CurvedRelief", &MapFields(f.clone()))
            .unwrap()
            .unwrap();
        assert_eq!(m.kind(), "CurvedRelief");
        assert_eq!(m.spec().pixel.shadows, Shadows::Exact);
        assert!(from_fields("NoSuchMethod", &MapFields(f.clone())).is_none());
        // a missing or bad field is an error that names it
        f.insert("shadows", "bogus");
        let e = from_fields("CurvedRelief", &MapFields(f))
            .unwrap()
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("shadows:"), "{e}");
    }
}
