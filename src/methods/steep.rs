//! Steep parallax mapping (McGuire & McGuire 2005): steep.wgsl.
use crate::contract::{check_range, PerPixel, Spec, Unit, MAX_STEPS_LIMIT};
use crate::error::Result;

crate::params! {
    pub struct SteepParallax {
        pub steps: u32,
    }
}

impl Unit for SteepParallax {
    fn examples() -> Vec<Self> {
        vec![SteepParallax { steps: 32 }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("steep");
        Spec::surface(wgsl, o, &[("steps", self.steps as f32)])
    }
    fn validate(&self) -> Result<()> {
        check_range("steps", self.steps, 1, MAX_STEPS_LIMIT)
    }
}
