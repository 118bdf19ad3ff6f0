//! Normal-based curved silhouettes (Chen & Chang 2008): ncs.wgsl, reading the texture-space
//! frame maps (texspace.rs).
use super::{check_range, PerPixel, ShaderUnit, Spec, Unit, MAX_STEPS_LIMIT};
use crate::error::{Error, Result};

#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "python", derive(pyo3::FromPyObject))]
pub struct Ncs {
    /// c of P_{i+1} = P_i + c * delta * S * TBN * V (the paper's 2.5)
    pub step_scale: f32,
    pub max_steps: u32,
    /// steps of at least POM's layer density (by the local N.V), up to one shell depth long
    pub adaptive: bool,
}

impl Unit for Ncs {
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = ShaderUnit::builtin(
            "pomkit::methods::ncs",
            "src/methods/ncs.wgsl",
            include_str!("ncs.wgsl"),
        );
        let mut s = Spec::surface(
            wgsl,
            o,
            &[
                ("step_scale", self.step_scale),
                ("max_steps", self.max_steps as f32),
                ("adaptive", super::flag(self.adaptive)),
            ],
        );
        s.frame_maps = true;
        s
    }
    fn validate(&self) -> Result<()> {
        if !(self.step_scale.is_finite() && self.step_scale > 0.0) {
            return Err(Error::arg(
                "step_scale",
                format!("must be a positive number, got {}", self.step_scale),
            ));
        }
        check_range("max_steps", self.max_steps, 1, MAX_STEPS_LIMIT)
    }
}
