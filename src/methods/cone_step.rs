//! Cone step mapping (Dummer 2006; relaxed cones: Policarpo & Oliveira 2007; conservative under
//! bilinear interpolation: Ban & Valasek 2024): cone_step.wgsl, over a cone map built on the GPU
//! from the max-mip pyramid (conemap.rs).
use super::{check_range, PerPixel, ShaderUnit, Spec, Unit, MAX_STEPS_LIMIT};
pub use crate::conemap::Cones;
use crate::error::{Error, Result};

/// How the march ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Refine {
    /// the max-mip walk with the exact patch intersection, from where the cones stop
    Exact,
    /// a binary search between the last point above and the first below the surface
    Binary,
    /// the raw cone march
    None,
}

impl Cones {
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "conservative" => Ok(Cones::Conservative),
            "relaxed" => Ok(Cones::Relaxed),
            o => Err(Error::arg(
                "cones",
                format!("must be 'conservative' or 'relaxed', got {o:?}"),
            )),
        }
    }
}

impl Refine {
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "exact" => Ok(Refine::Exact),
            "binary" => Ok(Refine::Binary),
            "none" => Ok(Refine::None),
            o => Err(Error::arg(
                "refine",
                format!("must be 'exact', 'binary' or 'none', got {o:?}"),
            )),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "python", derive(pyo3::FromPyObject))]
pub struct ConeStep {
    pub cones: Cones,
    pub refine: Refine,
    /// cone steps before the refinement takes over (or the march stops, flagged)
    pub max_steps: u32,
    /// bisections of `refine = Binary`
    pub binary_steps: u32,
    /// bound of the max-mip walk of `refine = Exact`
    pub max_iterations: u32,
}

impl Unit for ConeStep {
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = ShaderUnit::builtin(
            "pomkit::methods::cone_step",
            "src/methods/cone_step.wgsl",
            include_str!("cone_step.wgsl"),
        );
        let mut s = Spec::surface(
            wgsl,
            o,
            &[
                ("max_steps", self.max_steps as f32),
                ("binary_steps", self.binary_steps as f32),
            ],
        );
        s.defs.push(match self.refine {
            Refine::Exact => "REFINE_EXACT",
            Refine::Binary => "REFINE_BINARY",
            Refine::None => "REFINE_NONE",
        });
        s.cone_map = Some(self.cones);
        s.max_iterations = self.max_iterations;
        s
    }
    fn validate(&self) -> Result<()> {
        check_range("max_steps", self.max_steps, 1, MAX_STEPS_LIMIT)?;
        check_range("binary_steps", self.binary_steps, 0, 64)?;
        check_range("max_iterations", self.max_iterations, 1, 1 << 24)
    }
}
