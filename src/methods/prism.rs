//! Prism POM (Dachsbacher & Tatarchuk 2007): a pass of its own (prism.wgsl) over the prisms
//! extruded from the base mesh (geometry::prisms).
use super::{check_range, flag, Geometry, Pass, PerPixel, ShaderUnit, Spec, Unit, MAX_STEPS_LIMIT};
use crate::error::Result;

#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "python", derive(pyo3::FromPyObject))]
pub struct Prism {
    pub min_steps: u32,
    pub max_steps: u32,
    /// the shell above the base mesh (the paper's set-up) instead of below it
    pub outward: bool,
    /// march each segment with the max-mip traversal
    pub exact: bool,
}

impl Unit for Prism {
    fn spec(&self, o: &PerPixel) -> Spec {
        let shader = ShaderUnit::builtin(
            "pomkit::methods::prism",
            "src/methods/prism.wgsl",
            include_str!("prism.wgsl"),
        );
        let mut s = Spec::surface(
            shader.clone(),
            o,
            &[
                ("min_steps", self.min_steps as f32),
                ("max_steps", self.max_steps as f32),
                ("exact", flag(self.exact)),
            ],
        );
        s.pass = Pass::Own {
            shader,
            vs: "vs_prism",
            fs: "fs_prism",
            shadow_vs: "vs_prism_shadow",
            shadow_fs: "fs_prism_shadow",
        };
        s.defs.clear();
        s.geometry = Geometry::Prisms {
            outward: self.outward,
        };
        s
    }
    fn validate(&self) -> Result<()> {
        check_range("min_steps", self.min_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("max_steps", self.max_steps, 1, MAX_STEPS_LIMIT)
    }
}
